// SPDX-License-Identifier: MIT
// How much a surface path turns within the surface (its discrete geodesic curvature): what
// a user sees of a path's bending, and the smoothness penalty of the energies that prefer
// no direction (Energy::turning_angle).
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/mesh/surface_path.hpp"

namespace depath {

/// Inputs: a mesh, a path on it and the index i of one of its points.
/// Output: the turning angle (radians, in [0, pi]) at point i (0 at the end points and at
/// a repeated point), measured within the surface, so that a path running straight on the
/// surface (a geodesic) costs nothing for the bending of the surface under it:
///  - at an edge point, the angle between the incoming segment and the outgoing one after
///    unfolding the outgoing segment's face about the edge into the incoming segment's
///    plane (exact: a path straight in the unfolding turns by 0);
///  - at a vertex, pi - min(theta_1, theta_2), theta_1 and theta_2 the surface angles at
///    the vertex on the two sides of the path (sums of corner angles); 0 where both are
///    at least pi, as for every locally shortest path; at a boundary vertex |pi - theta|
///    for the one side there is;
///  - where a point's segment faces do not hold it (not a valid surface path) or are
///    degenerate, the 3D angle between the segments.
/// On a flat mesh all three are the plain angle between consecutive segments.
/// Guarantees: deterministic, reads only the mesh and the path (thread-safe).
double surface_turning(const Mesh& mesh, const SurfacePath& path, int i);

/// Sum of surface_turning over the path's interior points.
double total_surface_turning(const Mesh& mesh, const SurfacePath& path);

}  // namespace depath
