// SPDX-License-Identifier: MIT
// Internal to the energies: the unfolding of two faces about a shared edge, in which the
// turning of a path at an edge point is measured (surface_turning.cpp, turning.cpp).
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/mesh/surface_path.hpp"

#include <cmath>

namespace depath {

/// True if f is a face of the mesh with positive area that holds the point (its vertex, or
/// both ends of its edge): where a turning at the point can be measured in f.
inline bool face_holds(const Mesh& mesh, int f, const SurfacePoint& q) {
  return f >= 0 && f < mesh.num_faces() && mesh.face_area(f) > 0.0 && mesh.corner_of(f, q.v0) >= 0 &&
         (q.is_vertex() || mesh.corner_of(f, q.v1) >= 0);
}

/// The faces of the segments before and after point i of the path (-1 where missing).
inline int face_before(const SurfacePath& path, int i) {
  return i >= 1 && static_cast<size_t>(i) <= path.segment_faces.size() ? path.segment_faces[i - 1] : -1;
}
inline int face_after(const SurfacePath& path, int i) {
  return i >= 0 && static_cast<size_t>(i) < path.segment_faces.size() ? path.segment_faces[i] : -1;
}

/// A 2D vector of the unfolded plane.
struct Vec2d {
  double x = 0.0, y = 0.0;
};

/// Signed angle (radians, in [-pi, pi]) from u to v, counter-clockwise positive.
inline double signed_angle(const Vec2d& u, const Vec2d& v) {
  return std::atan2(u.x * v.y - u.y * v.x, u.x * v.x + u.y * v.y);
}

/// Inputs: an edge point p (edge v0 -> v1), the face fa of the path's segment arriving at p
/// and the face fb of the one leaving it, both holding the edge (fa == fb when the path
/// goes back into the face it came from).
/// Outputs: 2D coordinates of the plane in which fb is unfolded about the edge into fa's
/// plane: x along the edge (v0 -> v1), y across it, positive from fa's side towards fb's
/// (when fa == fb, the plane of fa, y positive towards the edge from fa's inside).
/// Guarantees: an isometry of each face's plane onto the 2D plane that keeps the edge fixed,
/// so a path straight in the unfolding keeps its direction; it does not depend on how the
/// faces are oriented (no normals). On a zero-length edge nothing is defined (has_edge()
/// false); on a degenerate face (no plane) only the path's directions are (valid() false).
class EdgeUnfolding {
 public:
  EdgeUnfolding(const Mesh& mesh, const SurfacePoint& p, int fa, int fb) {
    const Vec3& o = mesh.position(p.v0);
    e_ = mesh.position(p.v1) - o;
    const double len = e_.norm();
    if (!(len > 0.0)) return;
    e_ /= len;
    has_edge_ = true;
    // Unit vector in the face's plane, across the edge, pointing away from the face's third
    // vertex (out of the face); zero when the face is degenerate.
    auto outward = [&](int f) -> Vec3 {
      for (int v : mesh.face(f)) {
        if (v == p.v0 || v == p.v1) continue;
        const Vec3 w = mesh.position(v) - o;
        const Vec3 across = w - w.dot(e_) * e_;
        const double n = across.norm();
        return n > 0.0 ? Vec3(-across / n) : Vec3(Vec3::Zero());
      }
      return Vec3::Zero();
    };
    out_a_ = outward(fa);
    // Out of fb is into fa's side: y = -(v . out_b). Back into fa: fa's own coordinates.
    in_b_ = fa == fb ? out_a_ : Vec3(-outward(fb));
    same_face_ = fa == fb;
    valid_ = out_a_.squaredNorm() > 0.0 && in_b_.squaredNorm() > 0.0;
  }

  /// The edge has a direction: incoming() and outgoing() are defined.
  bool has_edge() const { return has_edge_; }
  /// Both faces have a plane too: in_a() and in_b() are defined.
  bool valid() const { return valid_; }

  /// A vector of fa's plane (e.g. a preferred line there).
  Vec2d in_a(const Vec3& v) const { return {v.dot(e_), v.dot(out_a_)}; }
  /// A vector of fb's plane, unfolded.
  Vec2d in_b(const Vec3& v) const { return {v.dot(e_), v.dot(in_b_)}; }

  /// The path's incoming direction a (through fa, towards the edge) and outgoing direction b
  /// (into fb, or back into fa), measured as the plain turning always was: the component
  /// across the edge by its length, so a direction a few ulps off its face's plane still
  /// maps exactly.
  Vec2d incoming(const Vec3& a) const {
    const double x = a.dot(e_);
    return {x, (a - x * e_).norm()};
  }
  Vec2d outgoing(const Vec3& b) const {
    const double x = b.dot(e_);
    return {x, (same_face_ ? -1.0 : 1.0) * (b - x * e_).norm()};
  }

 private:
  Vec3 e_ = Vec3::Zero(), out_a_ = Vec3::Zero(), in_b_ = Vec3::Zero();
  bool has_edge_ = false, valid_ = false, same_face_ = false;
};

}  // namespace depath
