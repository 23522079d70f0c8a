// SPDX-License-Identifier: MIT
// The vertices of a mesh bucketed in a uniform grid of cubes, for finding the vertices near
// a point or segment without testing all of them.
//
// Inputs: a mesh and the cubes' side. Outputs: for an axis-aligned box, every vertex in the
// cubes it meets (a superset of the vertices inside it, each once). Guarantees: at most
// 2^20 cubes per axis (the side grows if the mesh is larger); memory O(V); building costs
// a sort of the vertices.
#pragma once

#include "depath/mesh/mesh.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace depath {

class VertexCubes {
 public:
  /// `side` <= 0 or not finite: one cube per unit length.
  VertexCubes(const Mesh& mesh, double side);

  /// Calls f(v) for every vertex in the cubes meeting the box [lo, hi], each once, and returns
  /// true; returns false, calling nothing, if the box meets more cubes than there are
  /// vertices (scanning them all costs less then).
  template <class F>
  bool for_each_in_box(const Vec3& lo, const Vec3& hi, F&& f) const {
    int64_t a[3], b[3];
    double cubes = 1.0;
    for (int k = 0; k < 3; ++k) {
      a[k] = cube(lo[k], k);
      b[k] = cube(hi[k], k);
      cubes *= double(b[k] - a[k] + 1);
    }
    if (cubes > double(vertices_.size())) return false;
    for (int64_t z = a[2]; z <= b[2]; ++z) {
      for (int64_t y = a[1]; y <= b[1]; ++y) {
        // A row's cubes have consecutive keys.
        const uint64_t last = key(b[0], y, z);
        for (auto k = std::lower_bound(keys_.begin(), keys_.end(), key(a[0], y, z));
             k != keys_.end() && *k <= last; ++k) {
          const size_t i = static_cast<size_t>(k - keys_.begin());
          for (int j = begin_[i]; j < begin_[i + 1]; ++j) f(vertices_[j]);
        }
      }
    }
    return true;
  }

 private:
  // The cube holding coordinate x along axis k, clamped to the grid (monotone in x).
  int64_t cube(double x, int k) const;
  uint64_t key(int64_t x, int64_t y, int64_t z) const {
    return (uint64_t(z) * uint64_t(extent_[1]) + uint64_t(y)) * uint64_t(extent_[0]) + uint64_t(x);
  }

  Vec3 origin_;
  double side_ = 1.0;
  int64_t extent_[3] = {1, 1, 1};
  std::vector<uint64_t> keys_;  // the non-empty cubes, ascending
  std::vector<int> begin_;      // cube keys_[i] holds vertices_[begin_[i] .. begin_[i + 1])
  std::vector<int> vertices_;
};

}  // namespace depath
