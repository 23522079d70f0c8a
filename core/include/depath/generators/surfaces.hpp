// SPDX-License-Identifier: MIT
// Generators for the paper's test surfaces (SPEC §4): regular n x n grids, optionally
// lifted to a height field (flat, MATLAB `peaks`), and cones.
//
// Inputs: sizes and shape options. Outputs: a Mesh with documented vertex ids (so tests and
// benchmarks can name vertices). Guarantees: deterministic; bad options throw
// Error(invalid_argument). Its own target (depath_generators): the solver never needs it.
#pragma once

#include "depath/mesh/mesh.hpp"

#include <string_view>

namespace depath {

/// Height function of a grid.
enum class GridHeight { flat, peaks };
GridHeight parse_grid_height(std::string_view name);  ///< "flat" | "peaks"; throws Error(invalid_argument)

/// How each grid cell is split into two triangles.
enum class GridDiagonals {
  uniform,      ///< every cell split along the same diagonal
  alternating,  ///< checkerboard of the two diagonals (less directional bias)
};
GridDiagonals parse_grid_diagonals(std::string_view name);  ///< "uniform" | "alternating"

/// MATLAB's peaks(x, y) = 3(1-x)^2 e^(-x^2-(y+1)^2) - 10(x/5 - x^3 - y^5) e^(-x^2-y^2)
///                        - 1/3 e^(-(x+1)^2-y^2).
double matlab_peaks(double x, double y);

struct GridOptions {
  int n = 41;                  ///< vertices per side (>= 2): n * n vertices, 2 (n-1)^2 faces
  double half_size = 3.0;      ///< the grid spans [-half_size, half_size]^2 (MATLAB peaks domain)
  GridHeight height = GridHeight::flat;
  /// Multiplies the height. `peaks` is evaluated at MATLAB coordinates 3 u / half_size and
  /// scaled by half_size / 3, so the surface is MATLAB's surf(peaks) uniformly scaled; with
  /// half_size 3 and height_scale 1 it is exactly MATLAB's.
  double height_scale = 1.0;
  GridDiagonals diagonals = GridDiagonals::uniform;
  int up_axis = 2;  ///< height axis (0 = x, 1 = y, 2 = z); the grid spans the other two
};

/// Regular grid. Vertex id of grid point (i, j) (i along the first plane axis, j along the
/// second) is j * n + i. Plane axes are the two after `up_axis` in cyclic order (z: x, y;
/// x: y, z; y: z, x), so faces are counter-clockwise seen from +up (normals point up).
/// Throws Error(invalid_argument) for n < 2, non-finite or non-positive sizes, bad axis.
Mesh make_grid(const GridOptions& options);

struct ConeOptions {
  double height = 1.0;   ///< apex height above the base plane (> 0)
  double radius = 1.0;   ///< base radius (> 0)
  int rings = 20;        ///< rings of vertices from apex to rim (>= 1), evenly spaced radii
  int sectors = 64;      ///< vertices per ring (>= 3)
  bool cap = false;      ///< close the base with a fan around a centre vertex
  int up_axis = 2;       ///< cone axis (the apex is at +height on this axis)
};

/// Cone around the up axis, base centred at the origin. Vertex 0 is the apex; ring r
/// (1..rings, radius = radius * r / rings, height = height * (1 - r / rings)) holds vertices
/// 1 + (r - 1) * sectors + j at angle 2 pi j / sectors, counter-clockwise seen from +up
/// starting on the first plane axis; the cap centre (if any) is the last vertex.
/// Outward-facing triangles. Throws Error(invalid_argument) for bad options.
Mesh make_cone(const ConeOptions& options);

/// Vertex id of the cone's ring r (1..rings), sector j (0..sectors-1).
inline int cone_vertex(const ConeOptions& options, int ring, int sector) {
  return 1 + (ring - 1) * options.sectors + sector;
}

}  // namespace depath
