// SPDX-License-Identifier: MIT
#include "energy/vector_field.hpp"

#include "energy/angles.hpp"
#include "depath/mesh/tangent_fields.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace depath {

namespace {

// 3-point Gauss-Legendre on [0, 1].
constexpr double kGaussNode = 0.38729833462074168852;  // sqrt(3/5) / 2
constexpr double kNodes[3] = {0.5 - kGaussNode, 0.5, 0.5 + kGaussNode};
constexpr double kWeights[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};

// Barycentric coordinates of a surface point in face f. Vertex and edge points of the face
// map exactly; a point that is not on the face (a caller's inconsistency) falls back to
// the geometric coordinates of its projection onto the face plane.
std::array<double, 3> barycentric(const Mesh& mesh, int f, const SurfacePoint& p, const Vec3& e1, const Vec3& e2,
                                  bool valid) {
  std::array<double, 3> w{0.0, 0.0, 0.0};
  const int c0 = mesh.corner_of(f, p.v0);
  if (p.is_vertex()) {
    if (c0 >= 0) {
      w[c0] = 1.0;
      return w;
    }
  } else {
    const int c1 = mesh.corner_of(f, p.v1);
    if (c0 >= 0 && c1 >= 0) {
      w[c0] += 1.0 - p.t;
      w[c1] += p.t;
      return w;
    }
  }
  if (!valid) return {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};
  const auto& t = mesh.face(f);
  const Vec3& p0 = mesh.position(t[0]);
  const Vec3 q = p.position(mesh) - p0;
  const Vec3 a = mesh.position(t[1]) - p0, b = mesh.position(t[2]) - p0;
  const double ax = a.dot(e1), ay = a.dot(e2), bx = b.dot(e1), by = b.dot(e2);
  const double qx = q.dot(e1), qy = q.dot(e2);
  const double det = ax * by - ay * bx;
  const double u = (qx * by - qy * bx) / det;
  const double v = (ax * qy - ay * qx) / det;
  return {1.0 - u - v, u, v};
}

}  // namespace

VectorFieldEnergy::VectorFieldEnergy(const Mesh& mesh, std::vector<Vec3> field, double smoothness)
    : Energy(mesh, smoothness), field_(std::move(field)) {
  double max_norm2 = 0.0;
  for (const Vec3& v : field_) max_norm2 = std::max(max_norm2, v.squaredNorm());
  zero_norm2_ = max_norm2 * 1e-24;
  faces_ = per_face_frames<FaceData>(mesh, [&](int f, const FaceFrame& frame, FaceData& d) {
    d.valid = frame.valid;
    const auto& t = mesh.face(f);
    for (int k = 0; k < 3; ++k) {
      // 2D coordinates in the face frame = projection onto the face plane.
      d.corner_field[2 * k] = field_[t[k]].dot(frame.e1);
      d.corner_field[2 * k + 1] = field_[t[k]].dot(frame.e2);
    }
  });
}

double VectorFieldEnergy::segment_energy(const SurfacePoint& a, const SurfacePoint& b, int face) const {
  const FaceData& d = faces_[face];
  const Vec3 pa = a.position(mesh_), pb = b.position(mesh_);
  const Vec3 seg = pb - pa;
  const double length = seg.norm();
  if (!(length > 0.0)) return 0.0;
  const auto ba = barycentric(mesh_, face, a, d.e1, d.e2, d.valid);
  const auto bb = barycentric(mesh_, face, b, d.e1, d.e2, d.valid);
  double mean_angle = 0.0;
  if (d.valid) {
    const double dx = seg.dot(d.e1), dy = seg.dot(d.e2);
    const auto& c = d.corner_field;
    const double wax = ba[0] * c[0] + ba[1] * c[2] + ba[2] * c[4];
    const double way = ba[0] * c[1] + ba[1] * c[3] + ba[2] * c[5];
    const double wbx = bb[0] * c[0] + bb[1] * c[2] + bb[2] * c[4];
    const double wby = bb[0] * c[1] + bb[1] * c[3] + bb[2] * c[5];
    for (int q = 0; q < 3; ++q) {
      const double s = kNodes[q];
      const double wx = (1.0 - s) * wax + s * wbx, wy = (1.0 - s) * way + s * wby;
      if (wx * wx + wy * wy <= zero_norm2_) continue;
      mean_angle += kWeights[q] * acute_angle(dx, dy, wx, wy);
    }
  } else {
    const auto& t = mesh_.face(face);
    const Vec3 wa = ba[0] * field_[t[0]] + ba[1] * field_[t[1]] + ba[2] * field_[t[2]];
    const Vec3 wb = bb[0] * field_[t[0]] + bb[1] * field_[t[1]] + bb[2] * field_[t[2]];
    for (int q = 0; q < 3; ++q) {
      const double s = kNodes[q];
      const Vec3 w = (1.0 - s) * wa + s * wb;
      if (w.squaredNorm() <= zero_norm2_) continue;
      mean_angle += kWeights[q] * first_quadrant_atan2(seg.cross(w).norm(), std::abs(seg.dot(w)));
    }
  }
  return length * mean_angle;
}

int VectorFieldEnergy::preferred_lines(int face, const Vec3& point, Vec3 lines[2]) const {
  const FaceData& d = faces_[face];
  if (!d.valid) return 0;
  const auto& t = mesh_.face(face);
  const Vec3& p0 = mesh_.position(t[0]);
  const Vec3 q = point - p0, a = mesh_.position(t[1]) - p0, b = mesh_.position(t[2]) - p0;
  const double ax = a.dot(d.e1), ay = a.dot(d.e2), bx = b.dot(d.e1), by = b.dot(d.e2);
  const double qx = q.dot(d.e1), qy = q.dot(d.e2);
  const double det = ax * by - ay * bx;
  const double u = (qx * by - qy * bx) / det, v = (ax * qy - ay * qx) / det;
  const double w[3] = {1.0 - u - v, u, v};
  const auto& c = d.corner_field;
  const double wx = w[0] * c[0] + w[1] * c[2] + w[2] * c[4], wy = w[0] * c[1] + w[1] * c[3] + w[2] * c[5];
  const double norm2 = wx * wx + wy * wy;
  if (!(norm2 > zero_norm2_)) return 0;
  lines[0] = (wx * d.e1 + wy * d.e2) / std::sqrt(norm2);
  return 1;
}

double VectorFieldEnergy::field_energy(const SurfacePath& path) const { return segment_sum(path); }

std::vector<Metric> VectorFieldEnergy::metrics(const SurfacePath& path) const {
  const double length = path_length(mesh_, path);
  return {{"normalized_energy", length > 0.0 ? field_energy(path) / length : 0.0}};
}

}  // namespace depath
