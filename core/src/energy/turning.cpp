// SPDX-License-Identifier: MIT
// Energy::turning_angle: the turning the smoothness penalty charges. For energies with
// preferred lines (vector_field, constant_slope) it is the turning relative to the line the
// path follows; otherwise, and wherever that is undefined, the plain turning within the
// surface (surface_turning.hpp).
#include "depath/energy/energy.hpp"
#include "depath/energy/surface_turning.hpp"

#include "energy/unfolding.hpp"

#include <cmath>

namespace depath {

namespace {

// sin^2 of the acute angle between the direction d and the unit line u: increasing with that
// angle on [0, pi/2], so it ranks lines by nearness without an atan2.
double off_line(const Vec2d& d, const Vec2d& u) {
  const double cross = d.x * u.y - d.y * u.x;
  return cross * cross / (d.x * d.x + d.y * d.y);
}

// The rotation taking direction u to direction v, as a complex number: its argument is
// signed_angle(u, v). Composing rotations by complex products keeps the whole turning to
// one atan2 (the refinement evaluates it at every move).
Vec2d rotation(const Vec2d& u, const Vec2d& v) { return {u.x * v.x + u.y * v.y, u.x * v.y - u.y * v.x}; }

// The rotation from the line along u to the line along v: lines have no sense, so it is
// taken modulo pi, with its argument in (-pi/2, pi/2].
Vec2d line_rotation(const Vec2d& u, const Vec2d& v) {
  const Vec2d r = rotation(u, v);
  return r.x < 0.0 || (r.x == 0.0 && r.y < 0.0) ? Vec2d{-r.x, -r.y} : r;
}

}  // namespace

double Energy::turning_angle(const SurfacePath& path, int i) const {
  if (i <= 0 || i + 1 >= static_cast<int>(path.points.size())) return 0.0;
  const SurfacePoint& q = path.points[i];
  // A vertex point keeps the plain vertex turning: the path may pass between many faces
  // there, and there is no single unfolding in which to compare it with the lines.
  if (q.is_vertex()) return surface_turning(mesh_, path, i);
  const int fa = face_before(path, i), fb = face_after(path, i);
  if (!face_holds(mesh_, fa, q) || !face_holds(mesh_, fb, q)) return surface_turning(mesh_, path, i);
  // Each segment's preferred lines are taken at its midpoint: the field varies inside a face,
  // and a chord of a field line runs along the field near its middle, whereas at the edge
  // point both faces see the same (continuous) field, which would hide its rotation.
  const Vec3 prev = path.points[i - 1].position(mesh_), p = q.position(mesh_),
             next = path.points[i + 1].position(mesh_);
  Vec3 lines_a[2], lines_b[2];
  const int na = preferred_lines(fa, 0.5 * (prev + p), lines_a);
  if (na == 0) return surface_turning(mesh_, path, i);  // no preferred direction (geodesic, zero field)
  const int nb = preferred_lines(fb, 0.5 * (p + next), lines_b);
  if (nb == 0) return surface_turning(mesh_, path, i);
  const Vec3 a = p - prev, b = next - p;
  const EdgeUnfolding unfold(mesh_, q, fa, fb);
  if (!unfold.valid() || a.squaredNorm() == 0.0 || b.squaredNorm() == 0.0) return surface_turning(mesh_, path, i);

  const Vec2d da = unfold.incoming(a), db = unfold.outgoing(b);
  Vec2d la[2], lb[2];
  for (int k = 0; k < na; ++k) la[k] = unfold.in_a(lines_a[k]);
  for (int k = 0; k < nb; ++k) lb[k] = unfold.in_b(lines_b[k]);
  // Which line on b's side continues which on a's: with two on each side (constant slope's
  // two branches), the matching that rotates them least, so that a zig-zag from one branch
  // to the other is charged; then, of the matched pairs (or all pairs, where a side has one
  // line), the pair nearest the path.
  // (Both ranked by sin^2 of the angles, the angles' own order for one angle and a close
  // stand-in for sums, without atan2: the refinement evaluates this at every move.)
  const bool two_by_two = na == 2 && nb == 2;
  const bool crossed =
      two_by_two && off_line(la[0], lb[1]) + off_line(la[1], lb[0]) < off_line(la[0], lb[0]) + off_line(la[1], lb[1]);
  int best_a = 0, best_b = 0;
  double best = INFINITY;
  for (int ka = 0; ka < na; ++ka) {
    for (int kb = 0; kb < nb; ++kb) {
      if (two_by_two && (kb == ka) == crossed) continue;
      const double off = off_line(da, la[ka]) + off_line(db, lb[kb]);
      if (off < best) best = off, best_a = ka, best_b = kb;
    }
  }
  // |path's turn - lines' turn|, modulo 2 pi: the argument of one rotation times the other's
  // inverse.
  const Vec2d path_turn = rotation(da, db), line_turn = line_rotation(la[best_a], lb[best_b]);
  return std::abs(std::atan2(path_turn.y * line_turn.x - path_turn.x * line_turn.y,
                             path_turn.x * line_turn.x + path_turn.y * line_turn.y));
}

}  // namespace depath
