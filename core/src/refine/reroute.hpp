// SPDX-License-Identifier: MIT
// Refinement step 2: changes of the path's edge sequence (dropping redundant points,
// re-routing around vertices).
#pragma once

#include "refine/common.hpp"

namespace depath::refine {

/// Drops every interior point whose two neighbours lie on a common face (the path
/// then joins them directly across that face) when that does not raise the energy.
/// Returns the number of points dropped; `energy` is updated.
int remove_redundant_points(Evaluator& eval, SurfacePath& path, double& energy);

/// Replaces runs of consecutive edge points that all lie on edges around one vertex v
/// by v itself, when that does not raise the energy. This is where a path that hugs a
/// vertex ends up (the optimum passes through v); the points only approach v
/// asymptotically under smooth optimisation, whose finite differences break down there.
/// Returns the number of runs collapsed; `energy` is updated.
int collapse_vertex_runs(Evaluator& eval, SurfacePath& path, double& energy);

/// At each interior vertex v of the path (previous point a, next point b), tries the
/// route a -> b through the fan of faces around v on either side whose surface angle
/// (from a to b, measured at v) is below pi: the path then crosses the edges (v, w) of
/// that fan instead of passing through v, initially along the straight line of the
/// unfolded fan (the shortest such route). A route is kept only if it lowers the
/// whole-path energy (after a golden-section pass on its new points when the straight
/// line alone does not). Returns the number of vertices re-routed; `energy` is updated.
int reroute_vertices(Evaluator& eval, SurfacePath& path, double& energy, const std::function<bool()>& cancelled);

}  // namespace depath::refine
