#include "depath/refine_path.hpp"

#include "depath/error.hpp"
#include "refine_common.hpp"
#include "refine_points.hpp"
#include "refine_reroute.hpp"

#include <cmath>
#include <string>

namespace depath {
namespace {

void check_path(const Mesh& mesh, const SurfacePath& path) {
  const int n = mesh.num_vertices();
  auto valid_vertex = [n](int v) { return v >= 0 && v < n; };
  for (std::size_t i = 0; i < path.points.size(); ++i) {
    const SurfacePoint& p = path.points[i];
    const bool ok = p.is_vertex() ? valid_vertex(p.v0)
                                  : valid_vertex(p.v0) && valid_vertex(p.v1) && std::isfinite(p.t) && p.t >= 0.0 &&
                                        p.t <= 1.0;
    if (!ok) throw Error(ErrorCode::invalid_argument, "refine_path: point " + std::to_string(i) + " is not on the mesh");
  }
  if (path.segment_faces.size() + 1 != path.points.size()) {
    throw Error(ErrorCode::invalid_argument, "refine_path: the path needs one segment face per segment");
  }
}

}  // namespace

SurfacePath refine_path(const Energy& energy, const SurfacePath& input, const RefineOptions& options,
                        const std::function<bool()>& cancelled, RefineReport* report) {
  using namespace refine;
  RefineReport local_report;
  RefineReport& rep = report ? *report : local_report;
  rep = RefineReport{};
  rep.stop_reason = "converged";
  if (input.points.size() < 2) return input;
  const Mesh& mesh = energy.mesh();
  check_path(mesh, input);
  const double input_energy = energy.evaluate(input);
  rep.initial_energy = rep.final_energy = input_energy;

  Evaluator eval(energy);
  SurfacePath path = input;
  if (!repair_faces(eval, path)) {
    throw Error(ErrorCode::invalid_argument, "refine_path: two consecutive points of the path share no face");
  }
  snap_and_merge(path);
  double current = eval.total(path);

  SurfacePath snapshot;
  for (int sweep = 1; sweep <= options.max_sweeps; ++sweep) {
    if (is_cancelled(cancelled)) {
      rep.stop_reason = "cancelled";
      break;
    }
    snapshot = path;
    const double start = current;
    double e = optimize_edge_points(eval, path, current, options.max_newton_iterations, cancelled);
    // Points pushed to an edge end become vertices, where re-routing can act.
    if (snap_and_merge(path)) e = eval.total(path);
    const int collapsed = collapse_vertex_runs(eval, path, e);
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
    rep.sweeps = sweep;
    rep.reroutes += rerouted;
    if (options.on_sweep) options.on_sweep(RefineSweep{sweep, current, eval.evaluations(), &path});
    const bool structural = !reverted && (removed > 0 || rerouted > 0);
    if (!structural && !(start - current > options.tolerance * std::abs(start))) break;
    if (sweep == options.max_sweeps) rep.stop_reason = "max_sweeps";
  }
  rep.evaluations = eval.evaluations();

  // The contract, checked with the energy's own evaluation (not our window sums).
  const double result_energy = energy.evaluate(path);
  if (!(result_energy <= input_energy)) {
    rep.final_energy = input_energy;
    return input;
  }
  rep.final_energy = result_energy;
  return path;
}

}  // namespace depath
