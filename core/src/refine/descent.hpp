// SPDX-License-Identifier: MIT
// The local descent of the refinement: sweeps of the local moves until the energy stops
// dropping. refine_path runs it on the whole path, the vertex hops on windows of it.
#pragma once

#include "depath/refine/refine.hpp"
#include "refine/common.hpp"

#include <functional>

namespace depath::refine {

/// What descents did, summed over the calls that share it.
struct DescentStats {
  int sweeps = 0;
  int reroutes = 0;
  bool max_sweeps = false;  ///< the last call stopped at its sweep limit
  bool cancelled = false;   ///< the last call stopped on cancellation
};

/// Sweeps of local moves on `path` (a surface path with valid faces whose energy is
/// `energy`): optimise the edge points along their edges, snap points that reach an edge
/// end, collapse vertex runs, drop redundant points, re-route at vertices. Stops when a
/// sweep lowers the energy by less than options.tolerance (relative) and changes no
/// vertex, after `max_sweeps` sweeps, or on cancellation. A sweep that round-off made a
/// loss is undone. The end points never move. Calls `on_sweep` (if set) after every
/// sweep, numbered on from stats.sweeps. Returns the new energy (<= `energy`).
double descend(Evaluator& eval, SurfacePath& path, double energy, const RefineOptions& options, int max_sweeps,
               const std::function<void(const RefineSweep&)>& on_sweep, const std::function<bool()>& cancelled,
               DescentStats& stats);

}  // namespace depath::refine
