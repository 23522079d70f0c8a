// SPDX-License-Identifier: MIT
#include "energy/geodesic.hpp"

namespace depath {

GeodesicEnergy::GeodesicEnergy(const Mesh& mesh, std::vector<double> density, double smoothness)
    : Energy(mesh, smoothness), density_(std::move(density)) {
  if (density_.empty()) density_.assign(mesh.num_vertices(), 1.0);
}

double GeodesicEnergy::segment_energy(const SurfacePoint& a, const SurfacePoint& b, int) const {
  const double length = (b.position(mesh_) - a.position(mesh_)).norm();
  return 0.5 * length * (a.interpolate(density_.data()) + b.interpolate(density_.data()));
}

}  // namespace depath
