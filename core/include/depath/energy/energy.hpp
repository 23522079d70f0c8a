// SPDX-License-Identifier: MIT
// The energy interface: what a path costs. One implementation per file in core/src/energy/.
//
// Inputs: a mesh and an EnergySpec (geodesic with per-vertex density, vector field,
// constant slope; optional smoothness). Outputs: the energy of any surface path, its
// per-segment terms, the density the `fmm` baseline decodes, energy-specific metrics.
// Guarantees: implementations are immutable and thread-safe; make_energy rejects a bad
// spec with Error(invalid_argument) naming the field.
// Reference: the energies of DE-Path (Ye, Liu, Zheng, Hormann, He): weighted geodesics,
// paths along a vector field, constant-slope curves on terrain.
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/mesh/surface_path.hpp"

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace depath {

/// A named figure reported next to the energy (e.g. "normalized_energy", "mean_slope_error").
struct Metric {
  std::string name;
  double value = 0.0;
};

/// Energy of a surface path: a sum of per-segment terms plus an optional smoothness
/// penalty (lambda * sum of turning angles between consecutive segments, radians,
/// measured within the surface, relative to the preferred lines where the energy has
/// them: see turning_angle).
///
/// Implementations are immutable after construction and safe to call from many threads.
class Energy {
 public:
  Energy(const Mesh& mesh, double smoothness) : mesh_(mesh), smoothness_(smoothness) {}
  virtual ~Energy() = default;

  /// "geodesic", "vector_field" or "constant_slope".
  virtual std::string_view name() const = 0;

  /// Energy of the straight segment a -> b lying in face `face` (a and b on its boundary).
  virtual double segment_energy(const SurfacePoint& a, const SurfacePoint& b, int face) const = 0;

  /// Extra figures for a final path (normalized energy, slope error, ...). Default: none.
  virtual std::vector<Metric> metrics(const SurfacePath& path) const { return {}; }

  /// The directions the integrand prefers at `point` (a point of face f): up to two unit
  /// 3D vectors in the face's plane, each standing for a line (both senses), written to
  /// `lines`; returns how many (0 where no direction is preferred). A path along them costs
  /// nothing. Used to trace guide curves (field lines, constant-slope lines) that seed the
  /// search, and by turning_angle (the smoothness penalty). Default: none (geodesic).
  virtual int preferred_lines(int face, const Vec3& point, Vec3 lines[2]) const { return 0; }

  /// Per-vertex density that the `fmm` baseline decodes (the problem's own density).
  /// Default: uniform 1 (plain geodesic distance).
  virtual std::vector<double> baseline_density() const;

  /// c > 0 if this energy is c times the path's length (segment_energy(a, b, f) is
  /// c * |b - a| and there is no smoothness term): the shortest path in a strip of faces
  /// is then known exactly, and refinement straightens it instead of searching. Default:
  /// 0 (not a length).
  virtual double length_factor() const { return 0.0; }

  /// Sum of segment energies plus the smoothness penalty.
  double evaluate(const SurfacePath& path) const;

  /// Sum of segment energies alone (what the energy-specific metrics normalise).
  double segment_sum(const SurfacePath& path) const;

  /// The smoothness penalty weight lambda (>= 0).
  double smoothness() const { return smoothness_; }

  /// The turning the smoothness penalty charges at point `i` of the path (radians, in
  /// [0, pi]; 0 at the end points).
  ///  - Energies with preferred lines (vector_field, constant_slope), at an edge point: the
  ///    turning relative to the preferred line the path follows, |wrap(dphi - dpsi)|, both
  ///    measured in the unfolding of the outgoing segment's face about the edge into the
  ///    incoming one's plane (as surface_turning does): dphi the path's signed turning, dpsi
  ///    the signed rotation (modulo pi: lines have no sense) from the preferred line at the
  ///    incoming segment's midpoint to the one at the outgoing segment's midpoint. With two
  ///    lines per face (constant slope's two branches) the lines are matched across the edge
  ///    so they rotate least, and the matched pair nearest the path is used. Summed over a
  ///    path this is the total variation of the path's angle to the line it follows: a
  ///    path along a field line or a constant-slope spiral costs (about) nothing however it
  ///    curves, a zig-zag across the lines is charged as before.
  ///  - Everywhere else (energies without preferred lines such as geodesic, vertex points,
  ///    faces that do not hold the point or are degenerate, a zero field at a midpoint): the
  ///    plain turning within the surface, surface_turning(mesh, path, i).
  /// On a flat mesh with a uniform field both are the plain angle between the segments.
  double turning_angle(const SurfacePath& path, int i) const;

  const Mesh& mesh() const { return mesh_; }

 protected:
  const Mesh& mesh_;
  double smoothness_;
};

/// Which energy a job minimises.
enum class EnergyKind { geodesic, vector_field, constant_slope };

/// Parses "geodesic" | "vector_field" | "constant_slope"; throws Error(invalid_argument).
EnergyKind parse_energy_kind(std::string_view name);
const char* energy_kind_name(EnergyKind kind);

/// Everything needed to build an energy for a mesh.
struct EnergySpec {
  EnergyKind kind = EnergyKind::geodesic;
  /// geodesic: per-vertex density (> 0, within [1e-100, 1e100]); empty means 1 everywhere.
  std::vector<double> density;
  /// vector_field: per-vertex 3D vectors (projected onto each face's plane).
  std::vector<Vec3> field;
  /// vector_field: generate the field as the gradient of the height (up axis) instead.
  bool field_from_height = false;
  /// Rotation of a generated field in the tangent plane, degrees (counter-clockwise
  /// about the face normal).
  double rotate_degrees = 0.0;
  /// constant_slope: the target slope k = dz/ds (>= 0).
  double slope = 0.0;
  /// Height axis for terrain energies and generators: 0 = x, 1 = y, 2 = z.
  int up_axis = 2;
  /// Smoothness penalty weight lambda (>= 0).
  double smoothness = 0.0;
};

/// Builds the energy; throws Error(invalid_argument) naming the problem (wrong array
/// length, density not in [1e-100, 1e100] (zero, negative, non-finite), missing field, negative slope, ...).
std::unique_ptr<Energy> make_energy(const Mesh& mesh, const EnergySpec& spec);

}  // namespace depath
