// SPDX-License-Identifier: MIT
// Structural checks of a surface path, shared by the tests.
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/mesh/surface_path.hpp"

#include <gtest/gtest.h>

namespace depath::test {

inline bool point_in_face(const Mesh& mesh, const SurfacePoint& p, int f) {
  if (f < 0 || f >= mesh.num_faces() || mesh.corner_of(f, p.v0) < 0) return false;
  return p.is_vertex() || mesh.corner_of(f, p.v1) >= 0;
}

/// A valid path goes from s to t, its interior points lie at vertices or on edges with
/// t in [0, 1], and each segment lies in its recorded face.
inline ::testing::AssertionResult is_valid_path(const Mesh& mesh, const SurfacePath& path, int s, int t) {
  if (path.points.size() < 2) return ::testing::AssertionFailure() << "fewer than 2 points";
  if (path.segment_faces.size() + 1 != path.points.size())
    return ::testing::AssertionFailure() << "segment_faces size mismatch";
  if (!path.points.front().is_vertex() || path.points.front().v0 != s)
    return ::testing::AssertionFailure() << "does not start at source " << s;
  if (!path.points.back().is_vertex() || path.points.back().v0 != t)
    return ::testing::AssertionFailure() << "does not end at target " << t;
  for (size_t i = 0; i < path.points.size(); ++i) {
    const auto& p = path.points[i];
    if (!p.is_vertex() && (!(p.t >= 0.0 && p.t <= 1.0) || mesh.face_with_edge(p.v0, p.v1) < 0))
      return ::testing::AssertionFailure() << "point " << i << " is not on a mesh edge";
  }
  for (size_t i = 0; i + 1 < path.points.size(); ++i) {
    const int f = path.segment_faces[i];
    if (!point_in_face(mesh, path.points[i], f) || !point_in_face(mesh, path.points[i + 1], f))
      return ::testing::AssertionFailure() << "segment " << i << " does not lie in face " << f;
  }
  return ::testing::AssertionSuccess();
}

}  // namespace depath::test
