// SPDX-License-Identifier: MIT
// The energy factory: validates an EnergySpec against a mesh and builds the energy.
#include "depath/energy/energy.hpp"
#include "depath/util/error.hpp"
#include "depath/mesh/tangent_fields.hpp"
#include "energy/constant_slope.hpp"
#include "energy/geodesic.hpp"
#include "energy/vector_field.hpp"

#include <cmath>
#include <sstream>
#include <string>

namespace depath {
namespace {

void check_smoothness(double lambda) {
  if (!std::isfinite(lambda) || lambda < 0.0)
    throw Error(ErrorCode::invalid_argument,
                "smoothness must be a finite number >= 0, got " + std::to_string(lambda));
}

void check_density(const Mesh& mesh, const std::vector<double>& density) {
  if (density.empty()) return;
  if (static_cast<int>(density.size()) != mesh.num_vertices())
    throw Error(ErrorCode::invalid_argument, "density has " + std::to_string(density.size()) +
                                                 " values but the mesh has " +
                                                 std::to_string(mesh.num_vertices()) + " vertices");
  // Fast marching squares densities and multiplies them by squared edge lengths: past this
  // range arrival times overflow or vanish and every target looks unreachable ("no path").
  constexpr double kMinDensity = 1e-100, kMaxDensity = 1e100;
  for (size_t v = 0; v < density.size(); ++v) {
    const double d = density[v];
    if (std::isfinite(d) && d >= kMinDensity && d <= kMaxDensity) continue;
    std::ostringstream value;
    value << d;
    if (!std::isfinite(d) || d <= 0.0)
      throw Error(ErrorCode::invalid_argument, "density at vertex " + std::to_string(v) + " is " + value.str() +
                                                   ": densities must be finite and > 0");
    throw Error(ErrorCode::invalid_argument,
                  "density at vertex " + std::to_string(v) + " is " + value.str() +
                      ": densities must lie in [1e-100, 1e100], beyond that the arrival times overflow or "
                      "underflow (only ratios of densities matter: rescale the field)");
  }
}

void check_up_axis(int axis) {
  if (axis < 0 || axis > 2)
    throw Error(ErrorCode::invalid_argument,
                "up axis must be 0 (x), 1 (y) or 2 (z), got " + std::to_string(axis));
}

// vector_field: exactly one of a given field and a generated one; a given field has one
// finite vector per vertex; the field must not vanish everywhere (no path would be
// preferred over another).
std::vector<Vec3> vector_field_of(const Mesh& mesh, const EnergySpec& spec) {
  const bool given = !spec.field.empty();
  if (given && spec.field_from_height)
    throw Error(ErrorCode::invalid_argument,
                "vector_field: give either a field (--field FILE) or --field-from-height, not both");
  if (!given && !spec.field_from_height)
    throw Error(ErrorCode::invalid_argument,
                "vector_field needs a field: per-vertex vectors (--field FILE) or --field-from-height");
  std::vector<Vec3> field;
  if (given) {
    if (static_cast<int>(spec.field.size()) != mesh.num_vertices())
      throw Error(ErrorCode::invalid_argument, "field has " + std::to_string(spec.field.size()) +
                                                   " vectors but the mesh has " +
                                                   std::to_string(mesh.num_vertices()) + " vertices");
    for (size_t v = 0; v < spec.field.size(); ++v)
      if (!spec.field[v].allFinite())
        throw Error(ErrorCode::invalid_argument,
                    "field vector at vertex " + std::to_string(v) + " is not finite");
    field = spec.field;
  } else {
    check_up_axis(spec.up_axis);
    if (!std::isfinite(spec.rotate_degrees))
      throw Error(ErrorCode::invalid_argument, "field rotation (--rotate) must be a finite angle in degrees");
    field = height_gradient_field(mesh, spec.up_axis, spec.rotate_degrees);
  }
  bool any = false;
  for (const Vec3& v : field) any = any || v.squaredNorm() > 0.0;
  if (!any)
    throw Error(ErrorCode::invalid_argument,
                spec.field_from_height
                    ? "vector_field: the height gradient vanishes everywhere (level terrain; check --up)"
                    : "vector_field: the field vanishes everywhere");
  return field;
}

void check_slope(const EnergySpec& spec) {
  check_up_axis(spec.up_axis);
  if (!std::isfinite(spec.slope) || spec.slope < 0.0)
    throw Error(ErrorCode::invalid_argument,
                "slope (--slope) must be a finite number >= 0, got " + std::to_string(spec.slope));
}

}  // namespace

std::unique_ptr<Energy> make_energy(const Mesh& mesh, const EnergySpec& spec) {
  check_smoothness(spec.smoothness);
  switch (spec.kind) {
    case EnergyKind::geodesic:
      check_density(mesh, spec.density);
      return std::make_unique<GeodesicEnergy>(mesh, spec.density, spec.smoothness);
    case EnergyKind::vector_field:
      return std::make_unique<VectorFieldEnergy>(mesh, vector_field_of(mesh, spec), spec.smoothness);
    case EnergyKind::constant_slope:
      check_slope(spec);
      return std::make_unique<ConstantSlopeEnergy>(mesh, spec.up_axis, spec.slope, spec.smoothness);
  }
  throw Error(ErrorCode::invalid_argument,
              std::string("energy ") + energy_kind_name(spec.kind) + " is not available in this build");
}

}  // namespace depath
