// SPDX-License-Identifier: MIT
// The orthographic camera of `depath render`: where a 3D point lands in the picture.
//
// Inputs: the mesh, the path's points and the picture size. Outputs: a camera looking at the
// path along the mean surface normal around it, framed so the path fills most of the picture
// with some of the surrounding surface. Guarantees: project() is the only mapping from 3D to
// pixels (the painter and the tests use it), pixel y grows downwards.
#pragma once

#include <vector>

#include "depath/mesh/mesh.hpp"

namespace depath::picture {

/// A point in the picture: pixel coordinates and depth (larger is nearer the viewer).
struct Projected {
  double x = 0, y = 0, depth = 0;
};

class OrthoCamera {
 public:
  /// `toward_viewer` need not be unit length but must be non-zero.
  OrthoCamera(const Vec3& center, const Vec3& toward_viewer, double pixels_per_unit, int width, int height);

  Projected project(const Vec3& p) const;
  /// Unit vector from the scene toward the viewer.
  const Vec3& view() const { return view_; }
  const Vec3& right() const { return right_; }
  const Vec3& up() const { return up_; }
  int width() const { return width_; }
  int height() const { return height_; }
  double pixels_per_unit() const { return scale_; }

 private:
  Vec3 center_, view_, right_, up_;
  double scale_;
  int width_, height_;
};

/// Camera framed on `path` (at least two points): looks along the area-weighted mean normal of
/// the faces around the path's vertices (or from the mesh's centre through the path's centre
/// when the normals cancel out); the frame holds the path with a 25% margin and at least a
/// quarter of the mesh's diagonal.
OrthoCamera frame_on_path(const Mesh& mesh, const std::vector<Vec3>& path, int width, int height);

}  // namespace depath::picture
