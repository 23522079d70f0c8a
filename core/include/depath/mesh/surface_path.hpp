// SPDX-License-Identifier: MIT
// A path on a mesh surface: a polyline whose points lie on vertices or on edges.
//
// What decode produces, energy evaluates, refine improves and io writes, from the source
// vertex to the target vertex. Guarantee kept by every producer: the two ends of segment i
// lie in face segment_faces[i], so per-face quantities are well defined.
#pragma once

#include "depath/mesh/mesh.hpp"

#include <algorithm>
#include <vector>

namespace depath {

/// A point on the mesh: a vertex (v1 < 0), or the point (1 - t) * v0 + t * v1 on edge (v0, v1).
struct SurfacePoint {
  int v0 = -1;
  int v1 = -1;
  double t = 0.0;

  static SurfacePoint at_vertex(int v) { return {v, -1, 0.0}; }
  static SurfacePoint on_edge(int a, int b, double t) { return {a, b, t}; }
  bool is_vertex() const { return v1 < 0; }
  Vec3 position(const Mesh& mesh) const {
    return is_vertex() ? mesh.position(v0) : ((1.0 - t) * mesh.position(v0) + t * mesh.position(v1)).eval();
  }
  /// Linear interpolation of a per-vertex scalar at this point.
  double interpolate(const double* per_vertex) const {
    return is_vertex() ? per_vertex[v0] : (1.0 - t) * per_vertex[v0] + t * per_vertex[v1];
  }
};

/// Polyline from source to target. Segment i (points[i] -> points[i+1]) lies inside face
/// segment_faces[i] (or on one of its edges), so per-face quantities are well defined.
struct SurfacePath {
  std::vector<SurfacePoint> points;
  std::vector<int> segment_faces;

  bool empty() const { return points.empty(); }
  int num_segments() const { return points.empty() ? 0 : static_cast<int>(points.size()) - 1; }
  void clear() {
    points.clear();
    segment_faces.clear();
  }
  /// The same polyline walked the other way (target to source).
  void reverse() {
    std::reverse(points.begin(), points.end());
    std::reverse(segment_faces.begin(), segment_faces.end());
  }
};

/// Euclidean length of the polyline.
double path_length(const Mesh& mesh, const SurfacePath& path);

/// 3D positions of the path's points.
std::vector<Vec3> path_positions(const Mesh& mesh, const SurfacePath& path);

}  // namespace depath
