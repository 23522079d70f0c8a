// SPDX-License-Identifier: MIT
#include "picture/camera.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace depath::picture {

OrthoCamera::OrthoCamera(const Vec3& center, const Vec3& toward_viewer, double pixels_per_unit, int width,
                         int height)
    : center_(center),
      view_(toward_viewer.normalized()),
      scale_(pixels_per_unit),
      width_(width),
      height_(height) {
  // Up hint: the world axis least aligned with the view (y first, so a z-up grid seen from
  // above keeps x to the right and y up).
  Vec3 hint = Vec3::UnitY();
  if (std::abs(view_.y()) > 0.9) hint = Vec3::UnitZ();
  right_ = hint.cross(view_).normalized();
  up_ = view_.cross(right_);
}

Projected OrthoCamera::project(const Vec3& p) const {
  const Vec3 d = p - center_;
  return {width_ / 2.0 + scale_ * d.dot(right_), height_ / 2.0 - scale_ * d.dot(up_), d.dot(view_)};
}

namespace {

// Area-weighted normal sum of the faces around the vertices nearest to the path's points.
Vec3 normal_around(const Mesh& mesh, const std::vector<Vec3>& path) {
  // Each path point votes with the faces of its nearest vertex.
  Vec3 sum = Vec3::Zero();
  const double reach = 2.0 * mesh.mean_edge_length();
  for (const Vec3& p : path) {
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const double d = (mesh.position(v) - p).squaredNorm();
      if (d < best_d) best_d = d, best = v;
    }
    if (best < 0 || std::sqrt(best_d) > reach) continue;
    for (const int* f = mesh.vertex_faces_begin(best); f != mesh.vertex_faces_end(best); ++f)
      sum += mesh.face_area(*f) * mesh.face_normal(*f);
  }
  return sum;
}

}  // namespace

OrthoCamera frame_on_path(const Mesh& mesh, const std::vector<Vec3>& path, int width, int height) {
  Vec3 path_center = Vec3::Zero();
  for (const Vec3& p : path) path_center += p;
  path_center /= double(std::max<size_t>(path.size(), 1));
  const BoundingBox& box = mesh.bounding_box();
  const Vec3 mesh_center = (box.min + box.max) / 2.0;

  Vec3 view = normal_around(mesh, path);
  double total_area = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) total_area += mesh.face_area(f);
  // Normals that mostly cancel (a path around a closed surface): look from outside instead.
  if (view.norm() < 1e-9 * std::max(total_area, 1e-300)) view = path_center - mesh_center;
  if (view.norm() < 1e-12 * std::max(box.diagonal(), 1e-300)) view = Vec3::UnitZ();

  // Extent of the path across the view, about its centre.
  const OrthoCamera probe(path_center, view, 1.0, 0, 0);
  double lo_x = 0, hi_x = 0, lo_y = 0, hi_y = 0;
  for (const Vec3& p : path) {
    const Projected q = probe.project(p);
    lo_x = std::min(lo_x, q.x), hi_x = std::max(hi_x, q.x);
    lo_y = std::min(lo_y, -q.y), hi_y = std::max(hi_y, -q.y);
  }
  const Vec3 center = path_center + probe.right() * (lo_x + hi_x) / 2 + probe.up() * (lo_y + hi_y) / 2;
  const double min_half = 0.125 * box.diagonal();
  const double half_x = std::max(1.25 * (hi_x - lo_x) / 2, min_half);
  const double half_y = std::max(1.25 * (hi_y - lo_y) / 2, min_half);
  const double scale = std::min(width / (2 * half_x), height / (2 * half_y));
  return OrthoCamera(center, view, scale, width, height);
}

}  // namespace depath::picture
