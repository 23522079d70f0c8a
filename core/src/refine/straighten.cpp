// SPDX-License-Identifier: MIT
#include "refine/straighten.hpp"

#include "refine/common.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace depath::refine {
namespace {

using Vec2 = Eigen::Vector2d;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// One face of the strip laid out in the plane: its vertices and their positions.
struct FlatFace {
  std::array<int, 3> vertex{};
  std::array<Vec2, 3> at{};

  const Vec2* find(int v) const {
    for (int k = 0; k < 3; ++k) {
      if (vertex[k] == v) return &at[k];
    }
    return nullptr;
  }
};

// An edge the strip crosses, as seen walking through the strip: its left and right ends.
struct Portal {
  Vec2 left, right;
  bool left_is_v0 = true;  // the edge point's t runs from left to right
};

// Lays out vertex c of a face whose other vertices p, q are laid out already, on the left
// of p -> q or on its right; the face keeps its edge lengths.
Vec2 lay_out(const Mesh& mesh, int p, const Vec2& p2, int q, const Vec2& q2, int c, bool left) {
  const Vec2 pq = q2 - p2;
  const double d = pq.norm();
  const Vec2 ex = pq / d, ey(-ex.y(), ex.x());
  const double a2 = (mesh.position(c) - mesh.position(p)).squaredNorm();
  const double b2 = (mesh.position(c) - mesh.position(q)).squaredNorm();
  const double x = (a2 - b2 + d * d) / (2.0 * d);
  const double y = std::sqrt(std::max(0.0, a2 - x * x));
  return p2 + x * ex + (left ? y : -y) * ey;
}

// Where point p (a vertex or edge point of face `flat`) lies in the layout; false if it is
// not on that face.
bool locate(const FlatFace& flat, const SurfacePoint& p, Vec2& out) {
  const Vec2* a = flat.find(p.v0);
  if (a == nullptr) return false;
  if (p.is_vertex()) {
    out = *a;
    return true;
  }
  const Vec2* b = flat.find(p.v1);
  if (b == nullptr) return false;
  out = (1.0 - p.t) * *a + p.t * *b;
  return true;
}

// Unfolds the strip of the run first..last (interior points on edges) into portals:
// portals[0] and portals[m + 1] are the run's fixed ends, portals[j] the edge of point
// first + j. False if the faces do not form a strip.
bool unfold(const Mesh& mesh, const SurfacePath& path, int first, int last, std::vector<Portal>& portals) {
  const int m = last - first - 1;
  portals.resize(m + 2);
  for (int j = 1; j <= m; ++j) {
    const SurfacePoint& p = path.points[first + j];
    const int in = path.segment_faces[first + j - 1], out = path.segment_faces[first + j];
    if (in == out || mesh.corner_of(in, p.v0) < 0 || mesh.corner_of(in, p.v1) < 0 ||
        mesh.corner_of(out, p.v0) < 0 || mesh.corner_of(out, p.v1) < 0) {
      return false;
    }
  }
  // The first face: its edge to the next face along the x axis, the rest behind it (y < 0).
  const SurfacePoint& e1 = path.points[first + 1];
  const double d = (mesh.position(e1.v1) - mesh.position(e1.v0)).norm();
  if (!(d > 0.0)) return false;
  const int behind_first = third_vertex(mesh, path.segment_faces[first], e1.v0, e1.v1);
  if (behind_first < 0) return false;
  FlatFace flat;
  flat.vertex = {e1.v0, e1.v1, behind_first};
  flat.at[0] = Vec2(0.0, 0.0);
  flat.at[1] = Vec2(d, 0.0);
  flat.at[2] = lay_out(mesh, e1.v0, flat.at[0], e1.v1, flat.at[1], flat.vertex[2], false);
  Vec2 start;
  if (!locate(flat, path.points[first], start)) return false;
  portals[0] = {start, start, true};
  for (int j = 1; j <= m; ++j) {
    const SurfacePoint& p = path.points[first + j];
    const Vec2* a = flat.find(p.v0);
    const Vec2* b = flat.find(p.v1);
    if (a == nullptr || b == nullptr || *a == *b) return false;
    const int behind = third_vertex(mesh, path.segment_faces[first + j - 1], p.v0, p.v1);
    const int ahead = third_vertex(mesh, path.segment_faces[first + j], p.v0, p.v1);
    const Vec2* behind2 = flat.find(behind);
    if (behind2 == nullptr || ahead < 0) return false;
    // The next face lies across the edge from the face behind it.
    const bool ahead_left = cross(*b - *a, *behind2 - *a) < 0.0;
    FlatFace next;
    next.vertex = {p.v0, p.v1, ahead};
    next.at = {*a, *b, lay_out(mesh, p.v0, *a, p.v1, *b, ahead, ahead_left)};
    // Walking into the face ahead, whose far vertex is left of v0 -> v1, v0 is on the left.
    portals[j] = ahead_left ? Portal{*a, *b, true} : Portal{*b, *a, false};
    flat = next;
  }
  Vec2 end;
  if (!locate(flat, path.points[last], end)) return false;
  portals[m + 1] = {end, end, true};
  return true;
}

// A corner of the shortest path: where it bends, and the portal it bends at.
struct Corner {
  Vec2 at;
  int portal;
};

// The funnel algorithm: the corners of the shortest polyline from portals[0] to the last
// portal that crosses every portal in between, in order.
void funnel(const std::vector<Portal>& portals, std::vector<Corner>& corners) {
  const int n = static_cast<int>(portals.size());
  corners.assign(1, Corner{portals[0].left, 0});
  Vec2 apex = portals[0].left;
  // The funnel's two sides: the portal end each was last narrowed to. Side 0 is the right
  // one, side 1 the left; `turn` makes "narrows" one sign for both.
  struct Side {
    Vec2 end;
    int portal;
  };
  std::array<Side, 2> sides{Side{apex, 0}, Side{apex, 0}};
  constexpr std::array<double, 2> turn{1.0, -1.0};
  for (int i = 1; i < n; ++i) {
    for (int k = 0; k < 2; ++k) {
      const Vec2& end = k == 0 ? portals[i].right : portals[i].left;
      Side& side = sides[k];
      const Side other = sides[1 - k];
      if (turn[k] * cross(side.end - apex, end - apex) < 0.0) continue;  // it would widen
      // A side narrows unless it crosses the other one: then the path bends around the
      // other side's end. A side still at the apex (a fan around it) bounds nothing.
      if (side.end == apex || other.end == apex || turn[k] * cross(other.end - apex, end - apex) < 0.0) {
        side = {end, i};
      } else {
        apex = other.end;
        corners.push_back({apex, other.portal});
        sides = {other, other};
        i = other.portal;  // from the portal after the new corner
        break;
      }
    }
  }
  corners.push_back({portals[n - 1].left, n - 1});
}

}  // namespace

int straighten_runs(const Mesh& mesh, SurfacePath& path) {
  const int n = static_cast<int>(path.points.size());
  int left_alone = 0;
  std::vector<Portal> portals;
  std::vector<Corner> corners;
  std::vector<double> t;
  int first = 0;
  while (first + 1 < n) {
    int last = first + 1;
    while (last + 1 < n && !path.points[last].is_vertex()) ++last;
    const int m = last - first - 1;
    if (m == 0) {
      first = last;
      continue;
    }
    if (!unfold(mesh, path, first, last, portals)) {
      ++left_alone;
      first = last;
      continue;
    }
    funnel(portals, corners);
    // Each portal is crossed by the straight piece between the corners around it; at a
    // corner's own portal the path passes through that end of the edge exactly.
    t.assign(m + 2, 0.0);
    bool crossed = true;
    for (std::size_t c = 0; c + 1 < corners.size() && crossed; ++c) {
      const Vec2 a = corners[c].at, b = corners[c + 1].at, ab = b - a;
      for (int j = std::max(1, corners[c].portal); j <= std::min(m, corners[c + 1].portal); ++j) {
        const Portal& p = portals[j];
        double u;
        if (p.left == a || p.left == b) {
          u = 0.0;
        } else if (p.right == a || p.right == b) {
          u = 1.0;
        } else {
          const double denom = cross(p.right - p.left, ab);
          if (denom == 0.0) {
            crossed = false;
            break;
          }
          u = std::clamp(cross(a - p.left, ab) / denom, 0.0, 1.0);
        }
        t[j] = p.left_is_v0 ? u : 1.0 - u;
      }
    }
    if (crossed) {
      for (int j = 1; j <= m; ++j) path.points[first + j].t = t[j];
    } else {
      ++left_alone;
    }
    first = last;
  }
  return left_alone;
}

}  // namespace depath::refine
