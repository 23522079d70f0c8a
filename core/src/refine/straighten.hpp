// SPDX-License-Identifier: MIT
// Refinement step 1 for length energies: the exact shortest path through the path's own
// strip of faces.
#pragma once

#include "depath/mesh/surface_path.hpp"

namespace depath::refine {

/// Moves the interior edge points of `path` to the shortest path through the faces it
/// crosses, for energies proportional to length (Energy::length_factor() > 0), with the
/// edge sequence fixed: what optimize_edge_points searches for numerically, found
/// exactly. Each run of edge points between two fixed points (vertices, end points) is
/// unfolded into the plane across its edges and the funnel algorithm (Lee and Preparata,
/// "Euclidean shortest paths in the presence of rectilinear barriers", Networks 14, 1984)
/// gives the shortest polyline through it; where that polyline bends, it bends at an end
/// of an edge, and the points there get t = 0 or 1 exactly (the caller snaps them to
/// vertices, where re-routing can act).
///
/// A run is left as it is when its faces do not form a strip: a point whose two segments
/// lie in one face, or a segment face that does not hold the edge on either side of it.
/// Returns the number of runs left so (0: every edge point now sits where the shortest
/// path through its strip crosses its edge). Never moves vertex points or the end points.
int straighten_runs(const Mesh& mesh, SurfacePath& path);

}  // namespace depath::refine
