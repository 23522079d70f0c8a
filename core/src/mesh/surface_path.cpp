// SPDX-License-Identifier: MIT
#include "depath/mesh/surface_path.hpp"

namespace depath {

std::vector<Vec3> path_positions(const Mesh& mesh, const SurfacePath& path) {
  std::vector<Vec3> out;
  out.reserve(path.points.size());
  for (const auto& p : path.points) out.push_back(p.position(mesh));
  return out;
}

double path_length(const Mesh& mesh, const SurfacePath& path) {
  double length = 0.0;
  for (size_t i = 1; i < path.points.size(); ++i)
    length += (path.points[i].position(mesh) - path.points[i - 1].position(mesh)).norm();
  return length;
}

}  // namespace depath
