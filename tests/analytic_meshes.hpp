// SPDX-License-Identifier: MIT
// Meshes for the tests: icospheres and open cylinders (known geodesics), and the generators'
// grids with alternating diagonals.
#pragma once

#include "depath/generators/surfaces.hpp"
#include "depath/mesh/mesh.hpp"

#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace depath::test {

/// Unit icosphere: an icosahedron subdivided `levels` times, vertices on the sphere.
inline Mesh make_icosphere(int levels, double radius = 1.0) {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> p = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi}, {0, 1, phi},
                         {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& v : p) v.normalize();
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back((p[a] + p[b]).normalized());
      return mid[key] = static_cast<int>(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& t : f) {
      const int a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
      next.push_back({t[0], a, c});
      next.push_back({t[1], b, a});
      next.push_back({t[2], c, b});
      next.push_back({a, b, c});
    }
    f = std::move(next);
  }
  for (auto& v : p) v *= radius;
  return Mesh(std::move(p), std::move(f));
}

/// Open cylinder of radius r around the z axis, z in [0, height], `rings` x `sectors`
/// vertices; vertex (ring i, sector j) has id i * sectors + j at angle 2 pi j / sectors.
inline Mesh make_cylinder(double radius, double height, int rings, int sectors) {
  std::vector<Vec3> p;
  std::vector<std::array<int, 3>> f;
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < sectors; ++j) {
      const double a = 2 * M_PI * j / sectors;
      p.emplace_back(radius * std::cos(a), radius * std::sin(a), height * i / (rings - 1));
    }
  }
  for (int i = 0; i + 1 < rings; ++i) {
    for (int j = 0; j < sectors; ++j) {
      const int a = i * sectors + j, b = i * sectors + (j + 1) % sectors;
      const int c = a + sectors, d = b + sectors;
      // Alternate the diagonals so that no direction is favoured.
      if ((i + j) % 2 == 0) {
        f.push_back({a, b, d});
        f.push_back({a, d, c});
      } else {
        f.push_back({a, b, c});
        f.push_back({b, d, c});
      }
    }
  }
  return Mesh(std::move(p), std::move(f));
}

/// The generators' n x n grid over [-3, 3]^2 (vertex (i, j) = j * n + i) with alternating
/// diagonals, so that no direction is favoured: flat (geodesics are straight lines) or the
/// MATLAB peaks terrain (a curved surface where the fmm back-trace is measurably off the
/// geodesic).
inline Mesh alternating_grid(int n, GridHeight height = GridHeight::flat) {
  GridOptions o;
  o.n = n;
  o.height = height;
  o.diagonals = GridDiagonals::alternating;
  return make_grid(o);
}

/// Vertex of a mesh closest to a point.
inline int nearest_vertex(const Mesh& mesh, const Vec3& q) {
  int best = 0;
  for (int v = 1; v < mesh.num_vertices(); ++v)
    if ((mesh.position(v) - q).squaredNorm() < (mesh.position(best) - q).squaredNorm()) best = v;
  return best;
}

}  // namespace depath::test
