// SPDX-License-Identifier: MIT
#include "refine/reroute.hpp"

#include "refine/points.hpp"

#include <cmath>
#include <numbers>
#include <vector>

namespace depath::refine {
namespace {

// A vertex where the path's surface angle is within this of pi on its smaller side is
// passed straight (the re-route would gain ~ length * angle^2, nothing), which keeps
// paths that run exactly through flat vertices from cycling between collapse and
// re-route.
constexpr double kStraightAngle = 1e-6;

// Angle between two 3D vectors, in [0, pi].
double angle_between(const Vec3& x, const Vec3& y) { return std::atan2(x.cross(y).norm(), x.dot(y)); }

// Face across edge (v, w) of face f (which contains v and w), or -1.
int face_across(const Mesh& mesh, int f, int v, int w) {
  const int opposite = third_vertex(mesh, f, v, w);
  if (opposite < 0) return -1;
  return mesh.face_neighbor(f, mesh.corner_of(f, opposite));
}

// True if p lies on the closed edge (v, w).
bool on_edge(const SurfacePoint& p, int v, int w) {
  if (p.is_vertex()) return p.v0 == w || p.v0 == v;
  return (p.v0 == v && p.v1 == w) || (p.v0 == w && p.v1 == v);
}

// A route from a to b around vertex v through one side of its fan.
struct FanRoute {
  std::vector<SurfacePoint> points;  // crossings of the edges (v, w_j)
  std::vector<int> faces;            // points.size() + 1 faces: a -> p_1, ..., p_k -> b
};

// Builds the straight route a -> b through the fan of v that starts in face f_a leaving
// it across edge (v, first_exit). False if that side is not usable: it meets a
// boundary, wraps all the way around, needs no crossing, or spans an angle >= pi (then
// the route through v is the shorter one).
bool fan_route(const Mesh& mesh, int v, const SurfacePoint& a, const SurfacePoint& b, int f_a, int first_exit,
               FanRoute& route) {
  route.points.clear();
  route.faces.clear();
  const Vec3 pv = mesh.position(v);
  const int max_steps = static_cast<int>(mesh.vertex_faces_end(v) - mesh.vertex_faces_begin(v)) + 2;
  // Skip ahead while a lies on the edge to cross: the route starts in the last face
  // that contains a.
  int g = f_a, exit = first_exit, steps = 0;
  while (on_edge(a, v, exit)) {
    const int next = face_across(mesh, g, v, exit);
    if (next < 0 || ++steps > max_steps) return false;
    const int entry = exit;
    g = next;
    exit = third_vertex(mesh, g, v, entry);
    if (exit < 0) return false;
  }
  if (face_contains(mesh, g, b)) return false;  // a and b share a face: a direct segment, not a re-route
  const int start = g;
  // Unfold the fan into the plane around v: edge (v, w_j) along angle theta_j.
  std::vector<int> exits;
  std::vector<double> theta;
  const Vec3 va = a.position(mesh) - pv;
  const double phi_a = angle_between(va, mesh.position(exit) - pv);
  double angle = 0.0;
  route.faces.push_back(g);
  for (;;) {
    exits.push_back(exit);
    theta.push_back(angle);
    const int next = face_across(mesh, g, v, exit);
    if (next < 0 || next == start || ++steps > max_steps) return false;
    const int entry = exit;
    g = next;
    route.faces.push_back(g);
    if (face_contains(mesh, g, b)) break;
    angle += mesh.corner_angle(g, mesh.corner_of(g, v));
    exit = third_vertex(mesh, g, v, entry);
    if (exit < 0) return false;
  }
  const Vec3 vb = b.position(mesh) - pv;
  const double phi_b = angle_between(mesh.position(exits.back()) - pv, vb);
  const double span = phi_a + angle + phi_b;
  if (!(span < std::numbers::pi - kStraightAngle) || phi_a <= 0.0 || phi_b <= 0.0) return false;
  // a at angle -phi_a, b at angle + phi_b past the last edge; the segment between them
  // crosses every edge ray once since the span is below pi.
  const double ra = va.norm(), rb = vb.norm();
  const double ax = ra * std::cos(-phi_a), ay = ra * std::sin(-phi_a);
  const double bx = rb * std::cos(angle + phi_b), by = rb * std::sin(angle + phi_b);
  for (std::size_t j = 0; j < exits.size(); ++j) {
    const double dx = std::cos(theta[j]), dy = std::sin(theta[j]);
    const double denom = (bx - ax) * dy - (by - ay) * dx;
    if (denom == 0.0) return false;
    const double s = -(ax * dy - ay * dx) / denom;
    const double r = (ax + s * (bx - ax)) * dx + (ay + s * (by - ay)) * dy;
    const double len = (mesh.position(exits[j]) - pv).norm();
    if (!(r > 0.0) || !(len > 0.0)) return false;
    // Beyond the edge's far end the straight line leaves the fan: pass through w_j.
    route.points.push_back(SurfacePoint::on_edge(v, exits[j], std::min(1.0, r / len)));
  }
  return true;
}

}  // namespace

int remove_redundant_points(Evaluator& eval, SurfacePath& path, double& energy) {
  const Mesh& mesh = eval.mesh();
  int removed = 0;
  int i = 1;
  while (i + 1 < static_cast<int>(path.points.size())) {
    const SurfacePoint a = path.points[i - 1], b = path.points[i + 1];
    const int f = eval.best_common_face(a, b, path.segment_faces[i - 1]);
    if (f < 0 || !face_contains(mesh, f, a)) {
      ++i;
      continue;
    }
    const SurfacePoint dropped = path.points[i];
    const int f_in = path.segment_faces[i - 1], f_out = path.segment_faces[i];
    const double before = eval.window(path, i - 1, i + 1);
    path.points.erase(path.points.begin() + i);
    path.segment_faces.erase(path.segment_faces.begin() + i);
    path.segment_faces[i - 1] = f;
    const double after = eval.window(path, i - 1, i);
    if (after <= before) {
      energy += after - before;
      ++removed;
      // The previous point has a new neighbour: it may have become redundant too.
      i = std::max(1, i - 1);
    } else {
      path.points.insert(path.points.begin() + i, dropped);
      path.segment_faces.insert(path.segment_faces.begin() + i, f_out);
      path.segment_faces[i - 1] = f_in;
      ++i;
    }
  }
  return removed;
}

int collapse_vertex_runs(Evaluator& eval, SurfacePath& path, double& energy) {
  int collapsed = 0;
  std::vector<SurfacePoint> replacement;
  std::vector<int> faces;
  // The run i..last through vertex v in `replacement` and `faces`: a -> v -> b on the faces of
  // the run's outer segments (they contain v); where a or b is v itself the run is simply
  // dropped.
  const auto run_through = [&](int i, int last, int v) {
    const SurfacePoint& a = path.points[i - 1];
    const SurfacePoint& b = path.points[last + 1];
    replacement.clear();
    if (a.is_vertex() && a.v0 == v) {
      faces = {path.segment_faces[last]};
    } else if (b.is_vertex() && b.v0 == v) {
      faces = {path.segment_faces[i - 1]};
    } else {
      replacement.push_back(SurfacePoint::at_vertex(v));
      faces = {path.segment_faces[i - 1], path.segment_faces[last]};
    }
  };
  for (int i = 1; i + 1 < static_cast<int>(path.points.size()); ++i) {
    if (path.points[i].is_vertex()) continue;
    int best_v = -1, best_last = -1;
    double best_delta = 0.0;
    for (const int v : {path.points[i].v0, path.points[i].v1}) {
      // Every run i..last of points on edges around v (a path may pass v with only
      // part of the run belonging at v).
      for (int last = i; last + 1 < static_cast<int>(path.points.size()); ++last) {
        const SurfacePoint& p = path.points[last];
        if (p.is_vertex() || (p.v0 != v && p.v1 != v)) break;
        run_through(i, last, v);
        const double delta = replacement_delta(eval, path, i, last, replacement, faces);
        if (delta <= best_delta && (best_v < 0 || delta < best_delta)) {
          best_delta = delta;
          best_v = v;
          best_last = last;
        }
      }
    }
    if (best_v < 0) continue;
    run_through(i, best_last, best_v);
    apply_replacement(path, i, best_last, replacement, faces);
    energy += best_delta;
    ++collapsed;
  }
  return collapsed;
}

int reroute_vertices(Evaluator& eval, SurfacePath& path, double& energy, const std::function<bool()>& cancelled) {
  const Mesh& mesh = eval.mesh();
  int rerouted = 0;
  FanRoute route;
  SurfacePath candidate, best;
  for (int i = 1; i + 1 < static_cast<int>(path.points.size()); ++i) {
    if (!path.points[i].is_vertex()) continue;
    if (is_cancelled(cancelled)) break;
    const int v = path.points[i].v0;
    const SurfacePoint a = path.points[i - 1], b = path.points[i + 1];
    const int f_a = path.segment_faces[i - 1];
    const double before = eval.window(path, i - 1, i + 1);
    double best_after = before;
    int best_count = 0;
    for (int w : mesh.face(f_a)) {
      if (w == v || !fan_route(mesh, v, a, b, f_a, w, route)) continue;
      const int k = static_cast<int>(route.points.size());
      candidate.points.assign(path.points.begin() + (i - 1), path.points.begin() + (i + 2));
      candidate.points.erase(candidate.points.begin() + 1);
      candidate.points.insert(candidate.points.begin() + 1, route.points.begin(), route.points.end());
      candidate.segment_faces = route.faces;
      // The window a .. b is evaluated on its own, so smoothness terms at a and b
      // need their outer neighbours: include them.
      const bool left = i >= 2, right = i + 2 < static_cast<int>(path.points.size());
      if (left) {
        candidate.points.insert(candidate.points.begin(), path.points[i - 2]);
        candidate.segment_faces.insert(candidate.segment_faces.begin(), path.segment_faces[i - 2]);
      }
      if (right) {
        candidate.points.push_back(path.points[i + 2]);
        candidate.segment_faces.push_back(path.segment_faces[i + 1]);
      }
      const int first = left ? 1 : 0;
      const int last = first + k + 1;
      double after = eval.window(candidate, first, last);
      if (!(after < best_after)) {
        // Not better on the straight line (non-uniform energies): let the new points
        // find their place before judging the route.
        std::vector<int> fresh;
        for (int j = first + 1; j < last; ++j) fresh.push_back(j);
        for (int pass = 0; pass < 3; ++pass) {
          if (!(golden_pass(eval, candidate, fresh) > 0.0)) break;
        }
        after = eval.window(candidate, first, last);
      }
      if (after < best_after) {
        best_after = after;
        best_count = k;
        best.points.assign(candidate.points.begin() + first, candidate.points.begin() + last + 1);
        best.segment_faces.assign(candidate.segment_faces.begin() + first, candidate.segment_faces.begin() + last);
      }
    }
    if (best_count == 0) continue;
    // Splice best (a, p_1..p_k, b) over (a, v, b).
    path.points.erase(path.points.begin() + i);
    path.points.insert(path.points.begin() + i, best.points.begin() + 1, best.points.end() - 1);
    path.segment_faces.erase(path.segment_faces.begin() + (i - 1), path.segment_faces.begin() + (i + 1));
    path.segment_faces.insert(path.segment_faces.begin() + (i - 1), best.segment_faces.begin(),
                              best.segment_faces.end());
    energy += best_after - before;
    ++rerouted;
    i += best_count - 1;
  }
  return rerouted;
}

}  // namespace depath::refine
