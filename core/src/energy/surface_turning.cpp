// SPDX-License-Identifier: MIT
#include "depath/energy/surface_turning.hpp"

#include "energy/unfolding.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace depath {

namespace {

double angle_between(const Vec3& x, const Vec3& y) { return std::atan2(x.cross(y).norm(), x.dot(y)); }

// 3D angle between the segment directions a and b (the fallback where the surface gives
// no unfolding: a point whose segment faces do not hold it as documented).
double turning_3d(const Vec3& a, const Vec3& b) { return angle_between(a, b); }

// The vertex of face f that is neither a nor b.
int third_vertex(const Mesh& mesh, int f, int a, int b) {
  for (int v : mesh.face(f))
    if (v != a && v != b) return v;
  return -1;
}

// Turning at an edge point with incoming direction a (in face fa) and outgoing b (in face
// fb), both faces holding the edge: face fb unfolded about the edge into fa's plane, where a
// straight path keeps its angle to the edge.
double edge_turning(const Mesh& mesh, const SurfacePoint& p, const Vec3& a, const Vec3& b, int fa, int fb) {
  const EdgeUnfolding unfold(mesh, p, fa, fb);
  if (!unfold.has_edge()) return turning_3d(a, b);
  return std::abs(signed_angle(unfold.incoming(a), unfold.outgoing(b)));
}

// Turning at a vertex v with the path arriving from direction u (points back to the
// previous point, in face fa) and leaving along w (in face fb): the surface angles on
// the two sides of the path at v, theta_1 + theta_2 = the vertex's total angle; the path
// turns by pi - min(theta_1, theta_2) (0 if both sides span at least pi, as for every
// locally shortest path, e.g. through a saddle vertex). At a boundary vertex only the
// side through the surface exists: |pi - theta|. NaN when the fan does not connect fa to
// fb (the caller falls back to 3D).
double vertex_turning(const Mesh& mesh, int v, const Vec3& u, const Vec3& w, int fa, int fb) {
  const Vec3& pv = mesh.position(v);
  double total = 0.0;
  bool interior = true;
  for (const int* f = mesh.vertex_faces_begin(v); f != mesh.vertex_faces_end(v); ++f) {
    const int c = mesh.corner_of(*f, v);
    total += mesh.corner_angle(*f, c);
    // The two edges at v are opposite the other two corners.
    interior =
        interior && mesh.face_neighbor(*f, (c + 1) % 3) >= 0 && mesh.face_neighbor(*f, (c + 2) % 3) >= 0;
  }
  const int max_steps = static_cast<int>(mesh.vertex_faces_end(v) - mesh.vertex_faces_begin(v)) + 1;
  // Angle from u to w going round v through the fan, leaving fa across edge (v, first_exit);
  // NaN if that way meets the boundary or never reaches fb.
  auto walk = [&](int first_exit) {
    double angle = angle_between(u, mesh.position(first_exit) - pv);
    int g = fa, exit = first_exit;
    for (int step = 0; step < max_steps; ++step) {
      const int opposite = third_vertex(mesh, g, v, exit);
      const int next = opposite < 0 ? -1 : mesh.face_neighbor(g, mesh.corner_of(g, opposite));
      if (next < 0 || next == fa) return std::nan("");
      const int entry = exit;
      g = next;
      if (g == fb) return angle + angle_between(mesh.position(entry) - pv, w);
      angle += mesh.corner_angle(g, mesh.corner_of(g, v));
      exit = third_vertex(mesh, g, v, entry);
      if (exit < 0) return std::nan("");
    }
    return std::nan("");
  };
  double theta = 0.0;
  if (fa == fb) {
    theta = angle_between(u, w);
  } else {
    int x1 = -1, x2 = -1;
    for (int c : mesh.face(fa))
      if (c != v) (x1 < 0 ? x1 : x2) = c;
    theta = walk(x1);
    if (!std::isfinite(theta) && !interior) theta = walk(x2);
    if (!std::isfinite(theta)) return theta;
  }
  if (!interior) return std::abs(std::numbers::pi - theta);
  return std::max(0.0, std::numbers::pi - std::min(theta, total - theta));
}

}  // namespace

double surface_turning(const Mesh& mesh, const SurfacePath& path, int i) {
  if (i <= 0 || i + 1 >= static_cast<int>(path.points.size())) return 0.0;
  const SurfacePoint& q = path.points[i];
  const Vec3 p = q.position(mesh);
  const Vec3 a = p - path.points[i - 1].position(mesh);
  const Vec3 b = path.points[i + 1].position(mesh) - p;
  if (a.norm() == 0.0 || b.norm() == 0.0) return 0.0;  // repeated point: no direction, no turn
  const int fa = face_before(path, i), fb = face_after(path, i);
  if (!face_holds(mesh, fa, q) || !face_holds(mesh, fb, q)) return turning_3d(a, b);
  if (!q.is_vertex()) return edge_turning(mesh, q, a, b, fa, fb);
  const double t = vertex_turning(mesh, q.v0, -a, b, fa, fb);
  return std::isfinite(t) ? t : turning_3d(a, b);
}

double total_surface_turning(const Mesh& mesh, const SurfacePath& path) {
  double sum = 0.0;
  for (int i = 1; i + 1 < static_cast<int>(path.points.size()); ++i) sum += surface_turning(mesh, path, i);
  return sum;
}

}  // namespace depath
