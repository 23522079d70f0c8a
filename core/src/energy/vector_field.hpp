// SPDX-License-Identifier: MIT
// The `vector_field` energy (SPEC §1): integral along the path of the acute angle between
// the path's line and the field's line.
#pragma once

#include "depath/energy/energy.hpp"

#include <array>
#include <vector>

namespace depath {

/// Inputs: a mesh, a per-vertex field (3D vectors, one per vertex, finite; the caller
/// validates) and the smoothness weight.
///
/// Definition: inside face f the field is the barycentric (linear) interpolation of the
/// corner vectors, each projected onto f's plane. The field is a line field (bidirectional):
/// the angle between a segment with direction d and the field w is
/// atan2(|d x w|, |d . w|), in [0, pi/2]. Where the field vanishes (|w| <= 1e-12 times the
/// largest vertex vector) the angle is 0: no preferred direction there.
/// A segment a -> b in face f contributes length * mean angle, the mean taken with 3-point
/// Gauss-Legendre quadrature along the segment (exact for a constant field; the angle is
/// smooth except where the field turns parallel to the segment, where its kink costs an
/// error of O(h^2) per segment). Degenerate (zero-area) faces have no plane: there the
/// field is interpolated unprojected and the angle taken in 3D.
///
/// Guarantees: deterministic; immutable after construction and thread-safe; per-face data
/// (tangent frame, corner vectors in 2D face coordinates) is precomputed so a segment costs
/// two barycentric look-ups and three atan2.
/// metrics(): "normalized_energy" = sum of segment energies / path length (the mean angle in
/// radians; the smoothness penalty is not included).
class VectorFieldEnergy final : public Energy {
 public:
  VectorFieldEnergy(const Mesh& mesh, std::vector<Vec3> field, double smoothness);

  std::string_view name() const override { return "vector_field"; }
  double segment_energy(const SurfacePoint& a, const SurfacePoint& b, int face) const override;
  std::vector<Metric> metrics(const SurfacePath& path) const override;
  /// The field's line at the point (1), or none where it vanishes or the face is degenerate.
  int preferred_lines(int face, const Vec3& point, Vec3 lines[2]) const override;

  /// Sum of segment energies (no smoothness penalty).
  double field_energy(const SurfacePath& path) const;
  const std::vector<Vec3>& field() const { return field_; }

 private:
  struct FaceData {
    Vec3 e1, e2;                          // tangent frame (zero if degenerate)
    std::array<double, 6> corner_field;   // corner vectors in (e1, e2) coordinates
    bool valid;
  };
  std::vector<Vec3> field_;
  std::vector<FaceData> faces_;
  double zero_norm2_ = 0.0;  // squared magnitude at or below which the field counts as zero
};

}  // namespace depath
