// SPDX-License-Identifier: MIT
// Refinement step 3: basin hops over the vertices beside the path.
#pragma once

#include "refine/descent.hpp"

namespace depath::refine {

/// Local moves cannot carry a path across a vertex: a locally shortest path passing on
/// one side of a vertex (or through a saddle vertex, >= pi of surface angle on both
/// sides) stays in its homotopy class even when a shorter path runs just across that
/// vertex. A hop pins the path to a vertex w beside it (the run of points on edges
/// around w becomes w itself), runs the descent on the stretch between the nearest
/// vertices of the path around w (the path's other points stay put), and so lets the
/// path settle through w or on either side of it. Each round tries every vertex of every
/// face the path crosses and applies the hop that lowers the whole-path energy most,
/// then runs the descent on the whole path (at most `sweep_budget` sweeps in all, counted
/// in stats); rounds repeat until no hop helps, options.max_hops hops were made, or on
/// cancellation. Returns the number of hops made; `energy` is updated and never rises.
int hop_over_vertices(Evaluator& eval, SurfacePath& path, double& energy, const RefineOptions& options,
                      int sweep_budget, const std::function<bool()>& cancelled, DescentStats& stats);

}  // namespace depath::refine
