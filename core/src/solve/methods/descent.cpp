// SPDX-License-Identifier: MIT
// The `descent` method: local energy descent on the path (the paper's gradient-descent
// comparison), started from the `fmm` path traced both ways: from the target back in the
// source's distance field and from the source back in the target's. Round-off in the two
// fields sends them around different saddle vertices, and a path through a saddle vertex is
// locally shortest whichever side is shorter: on the 84 exact-geodesic pairs of the shared
// meshes, 5 descents from the first path end 0.12-0.45% above the exact length and 4 of
// them end within 0.003% from the second. One progress report per refinement sweep.
#include "depath/decode/path_decoder.hpp"
#include "depath/refine/refine.hpp"
#include "solve/methods/methods.hpp"

#include <algorithm>
#include <chrono>

namespace depath {

MethodOutcome run_descent_method(const MethodContext& ctx) {
  std::vector<SurfacePath> starts{ctx.fmm_path};
  PathDecoder decoder(ctx.stencils);
  if (SurfacePath back; decoder.decode(ctx.energy.baseline_density(), ctx.job.target, ctx.job.source, back)) {
    back.reverse();
    starts.push_back(std::move(back));
  }
  RefineOptions options;
  // Work is reported in whole-path energy evaluations, the unit DE counts in: the
  // refinement counts segment evaluations, so divide by the path's segment count.
  const int64_t segments = std::max(1, ctx.fmm_path.num_segments());
  // Sweeps are counted on across the starts' refinements: each start's local moves, then
  // the hops from each of them at most.
  const int max_sweeps = 2 * options.max_sweeps * static_cast<int>(starts.size());
  double previous = ctx.fmm_energy;
  int sweeps = 0;
  options.on_sweep = [&](const RefineSweep& sweep) {
    const bool improved = sweep.energy < previous;
    previous = sweep.energy;
    sweeps = sweep.sweep;
    Progress figures;
    figures.generation = sweep.sweep;
    figures.max_generations = max_sweeps;
    figures.best_energy = sweep.energy;
    figures.mean_energy = sweep.energy;
    figures.evaluations = (sweep.evaluations + segments - 1) / segments;
    figures.improvements = improved ? 1 : 0;
    report_progress(ctx, figures, sweep.path);
  };
  RefineReport report;
  MethodOutcome outcome;
  outcome.path = refine_best_of(ctx.energy, starts, options, ctx.hooks.is_cancelled, &report);
  outcome.energy = report.final_energy;
  outcome.generations = sweeps;
  outcome.evaluations = (report.evaluations + segments - 1) / segments;
  outcome.stop_reason = report.stop_reason == "max_sweeps" ? "max_generations" : report.stop_reason;
  return outcome;
}

}  // namespace depath
