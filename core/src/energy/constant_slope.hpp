// SPDX-License-Identifier: MIT
// The `constant_slope` energy (SPEC §1): paths that climb or descend a terrain at a
// constant slope k = dz/ds.
#pragma once

#include "depath/energy/energy.hpp"

#include <vector>

namespace depath {

/// Inputs: a mesh (the terrain), the height axis (0 = x, 1 = y, 2 = z), the target slope
/// k >= 0 and the smoothness weight (the caller validates them).
///
/// Definition: inside face f the height z is linear with gradient g (in the face plane), so
/// a unit tangent direction d has slope dz/ds = g . d, s the 3D arc length. The directions
/// of slope k are the gradient direction rotated by +theta and -theta about the face normal,
/// cos theta = k / |g|. They are taken as lines (bidirectional): a path may descend at slope
/// k as well as climb, consistent with the reported error |dz/ds| - k. Where the face is too
/// flat for slope k (|g| < k) the single gradient line is the target; where the face is
/// level (|g| = 0) or degenerate no direction is preferred and the angle is 0. The target
/// lines are constant per face, so a segment of length L in f contributes exactly
/// L * min(acute angle to the +theta line, acute angle to the -theta line), in [0, pi/2].
///
/// Guarantees: deterministic, immutable after construction and thread-safe; target lines
/// are precomputed per face in 2D face coordinates (a segment costs two atan2).
/// metrics(): "normalized_energy" = segment energies / path length (mean angle, radians,
/// without the smoothness penalty); "mean_slope_error" = length-weighted mean over segments
/// of | |dz| / L - k |, dz the height difference across the segment.
class ConstantSlopeEnergy final : public Energy {
 public:
  ConstantSlopeEnergy(const Mesh& mesh, int up_axis, double slope, double smoothness);

  std::string_view name() const override { return "constant_slope"; }
  double segment_energy(const SurfacePoint& a, const SurfacePoint& b, int face) const override;
  std::vector<Metric> metrics(const SurfacePath& path) const override;
  /// The face's target lines (2, or 1 where the face is too flat for slope k; none on
  /// level or degenerate faces).
  int preferred_lines(int face, const Vec3& point, Vec3 lines[2]) const override;

  /// Sum of segment energies (no smoothness penalty).
  double slope_energy(const SurfacePath& path) const;
  /// Length-weighted mean of | |dz/ds| - k | over the path's segments (0 for an empty path).
  double mean_slope_error(const SurfacePath& path) const;
  int up_axis() const { return up_axis_; }
  double slope() const { return slope_; }

 private:
  struct FaceData {
    Vec3 e1, e2;        // tangent frame
    double u1x, u1y;    // target line 1 (unit, 2D face coordinates)
    double u2x, u2y;    // target line 2 (equal to line 1 where the face is too flat)
    bool has_target;    // false on level or degenerate faces
  };
  int up_axis_;
  double slope_;
  std::vector<FaceData> faces_;
};

}  // namespace depath
