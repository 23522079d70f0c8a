// SPDX-License-Identifier: MIT
#include "refine/descent.hpp"

#include "refine/points.hpp"
#include "refine/reroute.hpp"

#include <cmath>

namespace depath::refine {

double descend(Evaluator& eval, SurfacePath& path, double energy, const RefineOptions& options, int max_sweeps,
               const std::function<void(const RefineSweep&)>& on_sweep, const std::function<bool()>& cancelled,
               DescentStats& stats) {
  stats.max_sweeps = stats.cancelled = false;
  double current = energy;
  SurfacePath snapshot;
  for (int sweep = 1; sweep <= max_sweeps; ++sweep) {
    if (is_cancelled(cancelled)) {
      stats.cancelled = true;
      break;
    }
    snapshot = path;
    const double start = current;
    double e = optimize_edge_points(eval, path, current, options.max_newton_iterations, cancelled);
    // Points pushed to an edge end become vertices, where re-routing can act.
    if (snap_and_merge(path)) e = eval.total(path);
    // A length's straightening already ends a path that bends at a vertex exactly there
    // (snapped above): no run is left to collapse, and trying costs a window per point.
    const int collapsed = eval.energy().length_factor() > 0.0 ? 0 : collapse_vertex_runs(eval, path, e);
    const int removed = remove_redundant_points(eval, path, e) + collapsed;
    const int rerouted = reroute_vertices(eval, path, e, cancelled);
    if (removed > 0 || rerouted > 0) snap_and_merge(path);
    // Re-sum from scratch: the window updates above must not drift, and the guarantee
    // is about the true total.
    e = eval.total(path);
    bool reverted = false;
    if (!(e <= start)) {
      path = snapshot;  // round-off made the sweep a (tiny) loss: keep the old path
      e = start;
      reverted = true;
    }
    current = e;
    ++stats.sweeps;
    stats.reroutes += rerouted;
    if (on_sweep) on_sweep(RefineSweep{stats.sweeps, current, eval.evaluations(), &path});
    const bool structural = !reverted && (removed > 0 || rerouted > 0);
    if (!structural && !(start - current > options.tolerance * std::abs(start))) break;
    if (sweep == max_sweeps) stats.max_sweeps = true;
  }
  return current;
}

}  // namespace depath::refine
