// SPDX-License-Identifier: MIT
#include "depath/decode/trace.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

namespace depath {
namespace {

using Vec2 = Eigen::Vector2d;
inline double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Points closer than this (as an edge parameter) to an edge end snap to the vertex.
constexpr double kSnap = 1e-9;

// Face f laid out in its plane: vertex i at p[i], with the gradient of the linear
// interpolant of the field values.
struct FlatFace {
  int v[3];
  Vec2 p[3];
  Vec2 grad;
  bool usable = false;  // non-degenerate with finite values at all corners
};

FlatFace flatten(const Mesh& mesh, std::span<const double> u, int f) {
  FlatFace face;
  const auto& t = mesh.face(f);
  for (int i = 0; i < 3; ++i) face.v[i] = t[i];
  if (mesh.face_area(f) <= 0.0 || mesh.face_normal(f).squaredNorm() == 0.0) return face;
  const auto& layout = mesh.face_layout(f);
  face.p[0] = Vec2(0, 0);
  face.p[1] = Vec2(layout[0], 0);
  face.p[2] = Vec2(layout[1], layout[2]);
  const double u0 = u[t[0]], u1 = u[t[1]], u2 = u[t[2]];
  if (!std::isfinite(u0) || !std::isfinite(u1) || !std::isfinite(u2)) return face;
  // grad . (p1 - p0) = u1 - u0, grad . (p2 - p0) = u2 - u0.
  const Vec2 e1 = face.p[1], e2 = face.p[2];
  const double det = cross2(e1, e2);
  if (!(std::abs(det) > 0.0)) return face;
  const double d1 = u1 - u0, d2 = u2 - u0;
  face.grad = Vec2((d1 * e2.y() - d2 * e1.y()) / det, (e1.x() * d2 - e2.x() * d1) / det);
  face.usable = face.grad.allFinite();
  return face;
}

int local_index(const FlatFace& face, int v) { return face.v[0] == v ? 0 : face.v[1] == v ? 1 : face.v[2] == v ? 2 : -1; }

// Where the ray from `origin` along `dir` leaves face `face` through edge (i, j), i != skip
// edge ends. Returns false if it leaves through none (numerically parallel).
struct Exit {
  int i = -1, j = -1;  // local vertex indices of the exit edge
  double w = 0.0;      // parameter along i -> j
  double s = 0.0;      // ray parameter
};
// Where the ray origin + s * dir (s > 0) crosses edge (i, j) of the face, if it does.
bool ray_hits_edge(const FlatFace& face, const Vec2& origin, const Vec2& dir, int i, int j, Exit& out) {
  const Vec2 e = face.p[j] - face.p[i];
  const double denom = cross2(dir, e);
  if (std::abs(denom) < 1e-300) return false;
  const Vec2 r = face.p[i] - origin;
  const double s = cross2(r, e) / denom;
  const double w = cross2(r, dir) / denom;
  if (!(s > 0.0 && w >= -1e-12 && w <= 1.0 + 1e-12)) return false;
  out = {i, j, std::clamp(w, 0.0, 1.0), s};
  return true;
}

// Where the ray leaves the face through an edge other than (skip_i, skip_j).
bool ray_exit(const FlatFace& face, const Vec2& origin, const Vec2& dir, int skip_i, int skip_j, Exit& out) {
  bool found = false;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if ((i == skip_i && j == skip_j) || (i == skip_j && j == skip_i)) continue;
    Exit hit;
    if (ray_hits_edge(face, origin, dir, i, j, hit) && (!found || hit.s < out.s)) {
      out = hit;
      found = true;
    }
  }
  return found;
}

class Tracer {
 public:
  Tracer(const FastMarching& fm, int source, SurfacePath& out)
      : fm_(fm), mesh_(fm.stencils().mesh()), u_(fm.values()), source_(source), out_(out) {}

  void run(int target) {
    out_.clear();
    out_.points.push_back(SurfacePoint::at_vertex(target));
    SurfacePoint cur = SurfacePoint::at_vertex(target);
    came_from_ = -1;
    const long max_steps = 4L * mesh_.num_faces() + 1000;
    long steps = 0;
    while (!(cur.is_vertex() && cur.v0 == source_)) {
      if (++steps > max_steps) {
        // Give up on face steps (numerical trouble): descend by acceptance order, which
        // strictly decreases at each step and so reaches the source.
        if (!cur.is_vertex()) cur = append_vertex(lower_end(cur), came_from_);
        const int earlier = earlier_neighbor(cur.v0);
        if (earlier < 0) {
          walk_edges_to_source(cur.v0);
          break;
        }
        cur = append_vertex(earlier, -1);
        continue;
      }
      const int came_from = came_from_;
      came_from_ = -1;
      cur = cur.is_vertex() ? step_from_vertex(cur.v0) : step_from_edge(cur, came_from);
    }
    out_.reverse();
  }

 private:
  double value(const SurfacePoint& p) const { return p.interpolate(u_.data()); }

  SurfacePoint append(const SurfacePoint& p, int face) {
    out_.points.push_back(p);
    out_.segment_faces.push_back(face);
    return p;
  }
  SurfacePoint append_vertex(int v, int face) {
    const int prev = out_.points.back().v0;
    const bool from_vertex = out_.points.back().is_vertex();
    if (face < 0 && from_vertex) face = mesh_.face_with_edge(prev, v);
    if (face < 0) face = *mesh_.vertex_faces_begin(v);
    return append(SurfacePoint::at_vertex(v), face);
  }

  // Edge end with the lower value (ties: the one accepted first).
  int lower_end(const SurfacePoint& p) const {
    const double ua = u_[p.v0], ub = u_[p.v1];
    if (ua != ub) return ua < ub ? p.v0 : p.v1;
    return fm_.order(p.v0) < fm_.order(p.v1) ? p.v0 : p.v1;
  }

  // The neighbour accepted before v with the lowest value: exists for every reached
  // vertex but the source (fast marching's guarantee); -1 if not.
  int earlier_neighbor(int v) const {
    int best = -1;
    for (const int* n = mesh_.vertex_neighbors_begin(v); n != mesh_.vertex_neighbors_end(v); ++n) {
      if (fm_.order(*n) >= fm_.order(v)) continue;
      if (best < 0 || u_[*n] < u_[best] || (u_[*n] == u_[best] && fm_.order(*n) < fm_.order(best))) best = *n;
    }
    return best;
  }

  // Last resort should the guarantee ever fail: the fewest-edges walk to the source
  // (breadth-first over mesh edges; s and t share a component, so it exists).
  void walk_edges_to_source(int from) {
    std::vector<int> parent(mesh_.num_vertices(), -1);
    std::vector<int> queue{source_};
    parent[source_] = source_;
    for (size_t head = 0; head < queue.size() && parent[from] < 0; ++head) {
      const int v = queue[head];
      for (const int* n = mesh_.vertex_neighbors_begin(v); n != mesh_.vertex_neighbors_end(v); ++n) {
        if (parent[*n] < 0) {
          parent[*n] = v;
          queue.push_back(*n);
        }
      }
    }
    for (int v = from; v != source_ && parent[v] >= 0;) {
      v = parent[v];
      append_vertex(v, -1);
    }
  }

  // A point on edge (face.v[i], face.v[j]) at parameter w, snapped to the ends.
  static SurfacePoint edge_point(const FlatFace& face, int i, int j, double w) {
    if (w <= kSnap) return SurfacePoint::at_vertex(face.v[i]);
    if (w >= 1.0 - kSnap) return SurfacePoint::at_vertex(face.v[j]);
    return SurfacePoint::on_edge(face.v[i], face.v[j], w);
  }

  bool face_has_source(int f) const { return mesh_.corner_of(f, source_) >= 0; }

  SurfacePoint step_from_vertex(int v) {
    const double uv = u_[v];
    // The face step or edge step with the steepest descent.
    double best_rate = 0.0;
    int best_face = -1;
    int best_vertex = -1;
    for (const int* fp = mesh_.vertex_faces_begin(v); fp != mesh_.vertex_faces_end(v); ++fp) {
      const int f = *fp;
      if (face_has_source(f)) return append(SurfacePoint::at_vertex(source_), f);
      const FlatFace face = flatten(mesh_, u_, f);
      if (!face.usable) continue;
      const int i = local_index(face, v);
      const Vec2 e1 = face.p[(i + 1) % 3] - face.p[i], e2 = face.p[(i + 2) % 3] - face.p[i];
      const Vec2 d = -face.grad;
      const double g = face.grad.norm();
      // Inside the corner's wedge (the layout is counter-clockwise).
      if (g > 0.0 && cross2(e1, d) >= 0.0 && cross2(d, e2) >= 0.0 && -g < best_rate) {
        best_rate = -g;
        best_face = f;
        best_vertex = -1;
      }
    }
    for (const int* n = mesh_.vertex_neighbors_begin(v); n != mesh_.vertex_neighbors_end(v); ++n) {
      if (!std::isfinite(u_[*n])) continue;
      const double len = (mesh_.position(*n) - mesh_.position(v)).norm();
      if (len <= 0.0) continue;
      const double rate = (u_[*n] - uv) / len;
      if (rate < best_rate) {
        best_rate = rate;
        best_vertex = *n;
        best_face = -1;
      }
    }
    if (best_vertex >= 0) return append_vertex(best_vertex, -1);
    if (best_face >= 0) {
      const FlatFace face = flatten(mesh_, u_, best_face);
      const int i = local_index(face, v);
      Exit exit;
      if (ray_hits_edge(face, face.p[i], -face.grad, (i + 1) % 3, (i + 2) % 3, exit)) {
        const SurfacePoint next = edge_point(face, exit.i, exit.j, exit.w);
        if (value(next) < uv) {
          if (!next.is_vertex()) came_from_ = best_face;
          return append(next, best_face);
        }
      }
    }
    const int earlier = earlier_neighbor(v);
    if (earlier >= 0) return append_vertex(earlier, -1);
    walk_edges_to_source(v);
    return SurfacePoint::at_vertex(source_);
  }

  SurfacePoint step_from_edge(const SurfacePoint& p, int came_from) {
    const double up = value(p);
    // The face across the edge from where we came (at the target no face yet: try both).
    int candidates[2] = {-1, -1};
    int count = 0;
    for (const int* fp = mesh_.vertex_faces_begin(p.v0); fp != mesh_.vertex_faces_end(p.v0); ++fp) {
      if (*fp != came_from && mesh_.corner_of(*fp, p.v1) >= 0 && count < 2) candidates[count++] = *fp;
    }
    for (int c = 0; c < count; ++c) {
      const int f = candidates[c];
      if (face_has_source(f)) return append(SurfacePoint::at_vertex(source_), f);
      const FlatFace face = flatten(mesh_, u_, f);
      if (!face.usable) continue;
      const int i = local_index(face, p.v0), j = local_index(face, p.v1);
      const Vec2 origin = (1.0 - p.t) * face.p[i] + p.t * face.p[j];
      const Vec2 d = -face.grad;
      const int k = 3 - i - j;
      // Descent must point into the face, i.e. to the side of the edge where vertex k is.
      const Vec2 e = face.p[j] - face.p[i];
      if (cross2(e, d) * cross2(e, face.p[k] - face.p[i]) <= 0.0) continue;
      Exit exit;
      if (!ray_exit(face, origin, d, i, j, exit)) continue;
      const SurfacePoint next = edge_point(face, exit.i, exit.j, exit.w);
      if (value(next) < up) {
        if (!next.is_vertex()) came_from_ = f;
        return append(next, f);
      }
    }
    // Valley along the edge, boundary, or no descent across: slide to the lower end.
    const int face = came_from >= 0 ? came_from : mesh_.face_with_edge(p.v0, p.v1);
    return append(SurfacePoint::at_vertex(lower_end(p)), face);
  }

  const FastMarching& fm_;
  const Mesh& mesh_;
  std::span<const double> u_;
  int source_;
  SurfacePath& out_;
  int came_from_ = -1;  // face the current edge point was reached through (-1: none)
};

}  // namespace

bool trace_steepest_descent(const FastMarching& fm, int source, int target, SurfacePath& out) {
  out.clear();
  if (!std::isfinite(fm.value(target)) || !fm.is_final(source)) return false;
  Tracer tracer(fm, source, out);
  tracer.run(target);
  return true;
}

}  // namespace depath
