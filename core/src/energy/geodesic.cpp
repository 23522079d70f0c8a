// SPDX-License-Identifier: MIT
#include "energy/geodesic.hpp"

#include <algorithm>

namespace depath {

GeodesicEnergy::GeodesicEnergy(const Mesh& mesh, std::vector<double> density, double smoothness)
    : Energy(mesh, smoothness), density_(std::move(density)) {
  if (density_.empty()) density_.assign(mesh.num_vertices(), 1.0);
  const bool uniform =
      std::all_of(density_.begin(), density_.end(), [&](double rho) { return rho == density_[0]; });
  if (uniform && smoothness == 0.0 && !density_.empty() && density_[0] > 0.0) length_factor_ = density_[0];
}

double GeodesicEnergy::segment_energy(const SurfacePoint& a, const SurfacePoint& b, int) const {
  const double length = (b.position(mesh_) - a.position(mesh_)).norm();
  return 0.5 * length * (a.interpolate(density_.data()) + b.interpolate(density_.data()));
}

}  // namespace depath
