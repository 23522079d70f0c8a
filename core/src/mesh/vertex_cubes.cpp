// SPDX-License-Identifier: MIT
#include "mesh/vertex_cubes.hpp"

#include <cmath>
#include <utility>

namespace depath {

VertexCubes::VertexCubes(const Mesh& mesh, double side) : origin_(mesh.bounding_box().min) {
  const Vec3 size = mesh.bounding_box().max - origin_;
  constexpr double kMaxCubes = double(1 << 20);  // per axis: a key then fits in 64 bits
  side_ = std::isfinite(side) && side > 0.0 ? std::max(side, size.maxCoeff() / kMaxCubes) : 1.0;
  if (!std::isfinite(side_)) side_ = 1.0;
  for (int k = 0; k < 3; ++k) {
    extent_[k] = static_cast<int64_t>(std::clamp(std::floor(size[k] / side_), 0.0, kMaxCubes)) + 1;
  }
  std::vector<std::pair<uint64_t, int>> keyed(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.position(v);
    keyed[v] = {key(cube(p.x(), 0), cube(p.y(), 1), cube(p.z(), 2)), v};
  }
  std::sort(keyed.begin(), keyed.end());
  vertices_.reserve(keyed.size());
  for (size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first) {
      keys_.push_back(keyed[i].first);
      begin_.push_back(static_cast<int>(i));
    }
    vertices_.push_back(keyed[i].second);
  }
  begin_.push_back(static_cast<int>(keyed.size()));
}

int64_t VertexCubes::cube(double x, int k) const {
  const double c = std::floor((x - origin_[k]) / side_);
  return static_cast<int64_t>(std::clamp(std::isnan(c) ? 0.0 : c, 0.0, double(extent_[k] - 1)));
}

}  // namespace depath
