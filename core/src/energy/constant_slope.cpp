// SPDX-License-Identifier: MIT
#include "energy/constant_slope.hpp"

#include "energy/angles.hpp"
#include "depath/mesh/tangent_fields.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace depath {

ConstantSlopeEnergy::ConstantSlopeEnergy(const Mesh& mesh, int up_axis, double slope, double smoothness)
    : Energy(mesh, smoothness), up_axis_(up_axis), slope_(slope) {
  const std::vector<Vec3> grads = height_gradients(mesh, up_axis);
  faces_ = per_face_frames<FaceData>(mesh, [&](int f, const FaceFrame& frame, FaceData& d) {
    d.u1x = d.u1y = d.u2x = d.u2y = 0.0;
    d.has_target = false;
    if (!frame.valid) return;
    const double gx = grads[f].dot(frame.e1), gy = grads[f].dot(frame.e2);
    const double g = std::hypot(gx, gy);
    if (!(g > 0.0)) return;
    d.has_target = true;
    const double hx = gx / g, hy = gy / g;  // unit gradient direction
    if (g <= slope) {
      d.u1x = d.u2x = hx;
      d.u1y = d.u2y = hy;
      return;
    }
    // Rotate the gradient direction by +/- theta; (-hy, hx) is n x (unit gradient).
    const double c = slope / g;
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    d.u1x = c * hx - s * hy;
    d.u1y = c * hy + s * hx;
    d.u2x = c * hx + s * hy;
    d.u2y = c * hy - s * hx;
  });
}

double ConstantSlopeEnergy::segment_energy(const SurfacePoint& a, const SurfacePoint& b, int face) const {
  const FaceData& d = faces_[face];
  if (!d.has_target) return 0.0;
  const Vec3 seg = b.position(mesh_) - a.position(mesh_);
  const double length = seg.norm();
  if (!(length > 0.0)) return 0.0;
  const double dx = seg.dot(d.e1), dy = seg.dot(d.e2);
  return length * std::min(acute_angle(dx, dy, d.u1x, d.u1y), acute_angle(dx, dy, d.u2x, d.u2y));
}

int ConstantSlopeEnergy::preferred_lines(int face, const Vec3&, Vec3 lines[2]) const {
  const FaceData& d = faces_[face];
  if (!d.has_target) return 0;
  lines[0] = d.u1x * d.e1 + d.u1y * d.e2;
  if (d.u1x == d.u2x && d.u1y == d.u2y) return 1;
  lines[1] = d.u2x * d.e1 + d.u2y * d.e2;
  return 2;
}

double ConstantSlopeEnergy::slope_energy(const SurfacePath& path) const { return segment_sum(path); }

double ConstantSlopeEnergy::mean_slope_error(const SurfacePath& path) const {
  double weighted = 0.0, total = 0.0;
  for (int i = 0; i < path.num_segments(); ++i) {
    const Vec3 seg = path.points[i + 1].position(mesh_) - path.points[i].position(mesh_);
    const double length = seg.norm();
    if (!(length > 0.0)) continue;
    // length * | |dz| / length - k |
    weighted += std::abs(std::abs(seg[up_axis_]) - slope_ * length);
    total += length;
  }
  return total > 0.0 ? weighted / total : 0.0;
}

std::vector<Metric> ConstantSlopeEnergy::metrics(const SurfacePath& path) const {
  const double length = path_length(mesh_, path);
  return {{"normalized_energy", length > 0.0 ? slope_energy(path) / length : 0.0},
          {"mean_slope_error", mean_slope_error(path)}};
}

}  // namespace depath
