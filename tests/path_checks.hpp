// SPDX-License-Identifier: MIT
// Structural checks of a surface path, shared by the tests.
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/mesh/surface_path.hpp"
#include "depath/solve/solve.hpp"

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

/// Two results bit for bit: every point (vertex ids, edge parameter) and face of the path,
/// the energies, generations, evaluations and stop reason (not the times).
inline ::testing::AssertionResult identical_results(const SolveResult& a, const SolveResult& b) {
  if (a.path.points.size() != b.path.points.size())
    return ::testing::AssertionFailure() << a.path.points.size() << " points against " << b.path.points.size();
  for (size_t i = 0; i < a.path.points.size(); ++i) {
    const SurfacePoint &p = a.path.points[i], &q = b.path.points[i];
    if (p.v0 != q.v0 || p.v1 != q.v1 || p.t != q.t) return ::testing::AssertionFailure() << "point " << i << " differs";
  }
  if (a.path.segment_faces != b.path.segment_faces) return ::testing::AssertionFailure() << "the faces differ";
  if (a.energy != b.energy || a.fmm_energy != b.fmm_energy)
    return ::testing::AssertionFailure() << "energy " << a.energy << " / " << b.energy << ", fmm energy "
                                         << a.fmm_energy << " / " << b.fmm_energy;
  if (a.generations != b.generations || a.evaluations != b.evaluations || a.stop_reason != b.stop_reason)
    return ::testing::AssertionFailure() << "generations " << a.generations << " / " << b.generations
                                         << ", evaluations " << a.evaluations << " / " << b.evaluations
                                         << ", stop reason " << a.stop_reason << " / " << b.stop_reason;
  return ::testing::AssertionSuccess();
}

}  // namespace depath::test
