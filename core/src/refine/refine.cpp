// SPDX-License-Identifier: MIT
#include "depath/refine/refine.hpp"

#include "depath/util/error.hpp"
#include "refine/common.hpp"
#include "refine/descent.hpp"
#include "refine/hops.hpp"

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

  DescentStats stats;
  double e = descend(eval, path, eval.total(path), options, options.max_sweeps, options.on_sweep, cancelled, stats);
  // Hops only from a converged descent: the sweep budget is spent otherwise.
  if (!stats.max_sweeps && !stats.cancelled && options.max_hops > 0) {
    rep.hops = hop_over_vertices(eval, path, e, options, options.max_sweeps, cancelled, stats);
  }
  rep.sweeps = stats.sweeps;
  rep.reroutes = stats.reroutes;
  if (stats.cancelled) {
    rep.stop_reason = "cancelled";
  } else if (stats.max_sweeps) {
    rep.stop_reason = "max_sweeps";
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
