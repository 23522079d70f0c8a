// SPDX-License-Identifier: MIT
#include "depath/energy/energy.hpp"

#include "depath/util/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace depath {

std::vector<double> Energy::baseline_density() const { return std::vector<double>(mesh_.num_vertices(), 1.0); }

double Energy::segment_sum(const SurfacePath& path) const {
  double total = 0.0;
  for (int i = 0; i < path.num_segments(); ++i)
    total += segment_energy(path.points[i], path.points[i + 1], path.segment_faces[i]);
  return total;
}

double Energy::evaluate(const SurfacePath& path) const {
  double total = segment_sum(path);
  const int segments = path.num_segments();
  if (smoothness_ > 0.0) {
    double turning = 0.0;
    for (int i = 1; i < segments; ++i) turning += turning_angle(path, i);
    total += smoothness_ * turning;
  }
  return total;
}

EnergyKind parse_energy_kind(std::string_view name) {
  if (name == "geodesic") return EnergyKind::geodesic;
  if (name == "vector_field") return EnergyKind::vector_field;
  if (name == "constant_slope") return EnergyKind::constant_slope;
  throw Error(ErrorCode::invalid_argument,
              "unknown energy '" + std::string(name) + "': expected geodesic, vector_field or constant_slope");
}

const char* energy_kind_name(EnergyKind kind) {
  switch (kind) {
    case EnergyKind::geodesic: return "geodesic";
    case EnergyKind::vector_field: return "vector_field";
    case EnergyKind::constant_slope: return "constant_slope";
  }
  return "unknown";
}

}  // namespace depath
