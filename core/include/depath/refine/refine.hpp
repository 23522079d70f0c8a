// SPDX-License-Identifier: MIT
// Local refinement of a surface path: the energy-descent that `--refine` and the
// `descent` method run.
//
// Inputs: an energy, one path (or several starts) between the same end points, options.
// Outputs: a path of lower or equal energy and a report. Guarantees: never raises the
// energy, keeps the end points, returns a valid surface path; cancellable between steps.
#pragma once

#include "depath/energy/energy.hpp"
#include "depath/mesh/surface_path.hpp"

#include <cstdint>
#include <functional>
#include <span>
#include <string>

namespace depath {

/// What one refinement sweep achieved (reported through RefineOptions::on_sweep).
struct RefineSweep {
  int sweep = 0;            ///< 1-based sweep just finished
  double energy = 0.0;      ///< energy of the path after it
  int64_t evaluations = 0;  ///< segment-energy evaluations so far
  const SurfacePath* path = nullptr;  ///< the path after it (valid during the callback)
};

/// Summary of a refinement run.
struct RefineReport {
  int sweeps = 0;
  int64_t evaluations = 0;  ///< segment-energy evaluations (the unit of work)
  double initial_energy = 0.0;
  double final_energy = 0.0;
  int reroutes = 0;         ///< vertices the path was re-routed around
  int hops = 0;             ///< vertices the path was pinned to (RefineOptions::max_hops)
  std::string stop_reason;  ///< "converged", "max_sweeps" or "cancelled"
};

struct RefineOptions {
  /// Maximum sweeps over the whole path (each: optimise the points along their edges,
  /// then simplify and re-route at vertices), hops included.
  int max_sweeps = 100;
  /// Stop once a sweep lowers the energy by less than this fraction and changes no
  /// vertex the path passes through.
  double tolerance = 1e-10;
  /// Newton iterations on the points' edge parameters per sweep.
  int max_newton_iterations = 40;
  /// Maximum vertex hops once the local moves have converged (0: local moves only). A
  /// hop pins the path to a vertex beside it and lets it settle again; it is kept only if
  /// it lowers the energy. This is what carries a path across a vertex into another
  /// homotopy class (local moves never do); it costs one descent on a stretch of the path
  /// per vertex beside it, per hop.
  int max_hops = 20;
  /// refine_best_of only: the hops run from at most this many of the lowest distinct
  /// local optima (0: from every one within 1% of the lowest).
  int hop_starts = 0;
  /// Called after every sweep (on the calling thread).
  std::function<void(const RefineSweep&)> on_sweep;
};

/// Lowers the energy of `path` by local moves: every interior point slides along its
/// edge (Newton on all edge parameters at once, golden-section per point as a
/// fallback), points that reach an edge end become vertices, redundant points are
/// dropped, and at a vertex the path is re-routed through the fan of faces on the side
/// where the surface angle is below pi (changing the edge sequence). Once these local
/// moves have converged, vertex hops (RefineOptions::max_hops) try pinning the path to
/// each vertex beside it, which can move it into another homotopy class. Works for any
/// Energy through segment_energy / turning_angle; every move is kept only if it lowers
/// the energy.
///
/// Guarantees: energy.evaluate(result) <= energy.evaluate(path); the end points are
/// unchanged; the result is a valid surface path (interior points on edges or at
/// vertices, segment_faces[i] contains both ends of segment i). An empty or
/// single-segment-free path is returned as is. `cancelled` (optional) is polled between
/// steps; once true the best path so far is returned. Throws Error(invalid_argument) if
/// `path` is not a valid surface path (a segment whose ends share no face).
SurfacePath refine_path(const Energy& energy, const SurfacePath& path, const RefineOptions& options = {},
                        const std::function<bool()>& cancelled = {}, RefineReport* report = nullptr);

/// Multi-start refinement: the lowest-energy path that refinement reaches from any of
/// `starts` (paths between the same end points). The local optima of the refinement
/// differ by homotopy class, and which start reaches the best one is not visible before
/// refining it. Every start gets the local moves (no hops); then the hops, which cost
/// far more, run once from each distinct local optimum within 1% of the lowest (at most
/// options.hop_starts of them when that is set).
/// Guarantees: the result's energy is at most that of every start and of refining any
/// start without hops; the rest as for refine_path. options.on_sweep is called after
/// every sweep of every refinement, with the sweeps counted on across them and the lowest
/// energy so far (and its path). The report describes the winning start's refinement, with the evaluations of all;
/// initial_energy is the first start's energy. An empty `starts` gives an empty path.
SurfacePath refine_best_of(const Energy& energy, std::span<const SurfacePath> starts,
                           const RefineOptions& options = {}, const std::function<bool()>& cancelled = {},
                           RefineReport* report = nullptr);

}  // namespace depath
