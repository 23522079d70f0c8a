// The energy factory: validates an EnergySpec against a mesh and builds the energy.
#include "depath/energy.hpp"
#include "depath/error.hpp"
#include "energies/geodesic_energy.hpp"

#include <cmath>
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
  for (size_t v = 0; v < density.size(); ++v) {
    if (!std::isfinite(density[v]) || density[v] < 0.0)
      throw Error(ErrorCode::invalid_argument, "density at vertex " + std::to_string(v) + " is " +
                                                   std::to_string(density[v]) +
                                                   ": densities must be finite and >= 0");
  }
}

}  // namespace

std::unique_ptr<Energy> make_energy(const Mesh& mesh, const EnergySpec& spec) {
  check_smoothness(spec.smoothness);
  switch (spec.kind) {
    case EnergyKind::geodesic:
      check_density(mesh, spec.density);
      return std::make_unique<GeodesicEnergy>(mesh, spec.density, spec.smoothness);
    case EnergyKind::vector_field:
    case EnergyKind::constant_slope:
      break;
  }
  throw Error(ErrorCode::invalid_argument,
              std::string("energy ") + energy_kind_name(spec.kind) + " is not available in this build");
}

}  // namespace depath
