// SPDX-License-Identifier: MIT
// Internal to the `de` method: a guide for direction energies (vector_field,
// constant_slope). From the source, the curves that follow the energy's preferred lines
// (Energy::preferred_lines: field lines, constant-slope lines) are traced across the faces;
// the one passing closest to the target becomes a channel of low density, whose decoded
// path follows the curve and then turns off to the target. It seeds the search (a winding
// zero-energy path, e.g. a spiral over more than a turn, is out of reach of perturbations
// of the uniform density) and starts the refinement. The traced curves themselves, cut
// in a face holding the other end (traced from either end), are refinement starts too
// (guide_paths).
#pragma once

#include "depath/energy/energy.hpp"
#include "depath/mesh/mesh.hpp"
#include "depath/mesh/surface_path.hpp"
#include "mesh/vertex_cubes.hpp"

#include <span>
#include <vector>

namespace depath {

/// Candidate guide channels, as per-vertex densities: kChannelDensity within 1.5 mean edge
/// lengths of a traced curve up to one of its close approaches to the target (up to 3 per
/// curve: a curve may pass near the target on another branch first), 1 elsewhere, the
/// closest approach first. Empty if the energy prefers no direction at the
/// source (geodesic energies). Deterministic; cost O(V) per candidate plus, per curve, the
/// vertices near its chords (first_close_chord).
std::vector<std::vector<double>> guide_densities(const Mesh& mesh, const Energy& energy, int source, int target);

/// Guide paths, as surface paths for the refinement to start from: from each end, the
/// traced curves (integrated inside every face, chords between their edge crossings) cut
/// where they pass through a face holding the other end, then straight to it; per end
/// the cut of least segment energy (up to 2 paths, source to target; none for energies
/// without preferred lines). A decoded channel is a fast-marching geodesic within 1.5
/// edges of the curve, whose angle energy the refinement's local moves often cannot bring
/// down to the curve's own (the integrand |angle| is kinked at 0); these start on it.
/// Deterministic; cost O(curve points) per traced direction.
std::vector<SurfacePath> guide_paths(const Mesh& mesh, const Energy& energy, int source, int target);

/// The channels' building block: per vertex, the first chord (points[i - 1], points[i]),
/// 1 <= i <= last, passing within `width` of it (3D distance), INT_MAX for none; a channel
/// ending at point i holds the vertices whose first chord is i or earlier. `cubes` buckets
/// the mesh's vertices (any side); only the vertices near each chord are tested.
std::vector<int> first_close_chord(const Mesh& mesh, const VertexCubes& cubes, std::span<const Vec3> points,
                                   int last, double width);

}  // namespace depath
