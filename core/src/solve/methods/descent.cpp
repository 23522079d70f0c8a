// SPDX-License-Identifier: MIT
// The `descent` method: local energy descent on the path, started from the `fmm` path
// (the paper's gradient-descent comparison). One progress report per refinement sweep.
#include "depath/refine/refine.hpp"
#include "solve/methods/methods.hpp"

#include <algorithm>
#include <chrono>

namespace depath {

MethodOutcome run_descent_method(const MethodContext& ctx) {
  RefineOptions options;
  // Work is reported in whole-path energy evaluations, the unit DE counts in: the
  // refinement counts segment evaluations, so divide by the path's segment count.
  const int64_t segments = std::max(1, ctx.fmm_path.num_segments());
  double previous = ctx.fmm_energy;
  options.on_sweep = [&](const RefineSweep& sweep) {
    const bool improved = sweep.energy < previous;
    previous = sweep.energy;
    Progress figures;
    figures.generation = sweep.sweep;
    figures.max_generations = options.max_sweeps;
    figures.best_energy = sweep.energy;
    figures.mean_energy = sweep.energy;
    figures.evaluations = (sweep.evaluations + segments - 1) / segments;
    figures.improvements = improved ? 1 : 0;
    report_progress(ctx, figures, sweep.path);
  };
  RefineReport report;
  MethodOutcome outcome;
  outcome.path = refine_path(ctx.energy, ctx.fmm_path, options, ctx.hooks.is_cancelled, &report);
  outcome.energy = report.final_energy;
  outcome.generations = report.sweeps;
  outcome.evaluations = (report.evaluations + segments - 1) / segments;
  outcome.stop_reason = report.stop_reason == "max_sweeps" ? "max_generations" : report.stop_reason;
  return outcome;
}

}  // namespace depath
