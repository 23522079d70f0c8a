// SPDX-License-Identifier: MIT
// Geodesic energy: the integral of a per-vertex density along the path.
#pragma once

#include "depath/energy/energy.hpp"

#include <vector>

namespace depath {

/// Integral of rho along the path, rho per vertex and linear inside faces. A straight
/// segment inside a face costs length * (rho_a + rho_b) / 2, which is exact for linear rho.
/// An empty density means rho = 1 (the path length).
class GeodesicEnergy final : public Energy {
 public:
  GeodesicEnergy(const Mesh& mesh, std::vector<double> density, double smoothness);
  std::string_view name() const override { return "geodesic"; }
  double segment_energy(const SurfacePoint& a, const SurfacePoint& b, int face) const override;
  std::vector<double> baseline_density() const override { return density_; }
  const std::vector<double>& density() const { return density_; }
  /// The density when it is the same everywhere and there is no smoothness, else 0.
  double length_factor() const override { return length_factor_; }

 private:
  std::vector<double> density_;
  double length_factor_ = 0.0;
};

}  // namespace depath
