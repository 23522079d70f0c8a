// SPDX-License-Identifier: MIT
// The `descent` method: local energy descent on the path (the paper's gradient-descent
// comparison), started from the `fmm` path traced both ways: from the target back in the
// source's distance field and from the source back in the target's. Round-off in the two
// fields sends them around different saddle vertices, and a path through a saddle vertex is
// locally shortest whichever side is shorter. For a length (uniform density, no
// smoothness), whose refinement is exact and cheap, detours through the corridor between
// the end points start it as well. One progress report per refinement sweep.
//
// Measured on the 84 exact-geodesic pairs of the 7 scanned shared meshes: from the first
// path alone 79 end within 0.1% of the exact length, from both 82, with the detours 84.
#include "depath/decode/path_decoder.hpp"
#include "depath/decode/trace.hpp"
#include "depath/refine/refine.hpp"
#include "solve/methods/detours.hpp"
#include "solve/methods/methods.hpp"

#include <algorithm>
#include <chrono>

namespace depath {

namespace {

// Detours: how many, through which corridor (d_s + d_t within this fraction of the
// shortest), and from how many of the lowest local optima the vertex hops then run (each
// hop chain costs about as much as all the local descents). Measured on the 84 pairs:
// 2 detours in a 2% corridor 83 within 0.1%, 4 all 84 (in 1% or 2%), 8 also 84 at 1.2x the
// time; hops from every optimum within 1% of the lowest 1.3x the time of hops from 2, from
// the lowest alone 83.
constexpr int kDetours = 4;
constexpr double kCorridorSlack = 0.02;
constexpr int kHopStarts = 2;

// The starts: the fmm path, the same traced the other way (from the source back in the
// target's field) and, for a length, the detours (then options.hop_starts is set).
std::vector<SurfacePath> starts_of(const MethodContext& ctx, RefineOptions& options) {
  std::vector<SurfacePath> starts{ctx.fmm_path};
  const int source = ctx.job.source, target = ctx.job.target;
  const std::vector<double> density = ctx.energy.baseline_density();
  SurfacePath back;
  if (!(ctx.energy.length_factor() > 0.0)) {
    PathDecoder decoder(ctx.stencils);
    if (decoder.decode(density, target, source, back)) {
      back.reverse();
      starts.push_back(std::move(back));
    }
    return starts;
  }
  // Whole marches from both ends: the corridor needs both fields everywhere near the path.
  FastMarching from_source(ctx.stencils), from_target(ctx.stencils);
  from_source.run(density, source);
  from_target.run(density, target);
  if (trace_steepest_descent(from_target, target, source, back)) {
    back.reverse();
    starts.push_back(std::move(back));
  }
  for (SurfacePath& detour : corridor_detours(from_source, from_target, source, target, starts, kDetours, kCorridorSlack)) {
    starts.push_back(std::move(detour));
  }
  options.hop_starts = kHopStarts;
  return starts;
}

}  // namespace

MethodOutcome run_descent_method(const MethodContext& ctx) {
  RefineOptions options;
  const std::vector<SurfacePath> starts = starts_of(ctx, options);
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
