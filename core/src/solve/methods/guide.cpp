// SPDX-License-Identifier: MIT
#include "solve/methods/guide.hpp"

#include "depath/mesh/tangent_fields.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace depath {
namespace {

// Inside the channel the density is this fraction of the outside's: following the curve
// for a length L then costs 0.05 L, so the decoded path keeps to it unless a shortcut is
// 20 times shorter.
constexpr double kChannelDensity = 0.05;
constexpr double kChannelWidth = 1.5;  // mean edge lengths either side of the curve
constexpr double kNear = 3.0;          // close approach: within this many mean edge lengths
constexpr size_t kCutsPerTrace = 3;
// Inside a face the curve is integrated (RK4) in steps of this fraction of the mean edge
// length: the field is linear there, so the curve bends inside the face, and a trace
// that kept the direction of its entry point for the whole face (one Euler step per
// face) drifts off the field line by O(h) per unit length: on the random contour cases
// (tests/random_cases.hpp) it missed t by up to half an edge, the sub-stepped trace by
// 0.06 edges at most.
constexpr double kSubStep = 0.125;
// A trace stops after this many passes through the far end's star (a closed field line
// comes round again; later passes only add length), or at the length / step limits.
constexpr int kMaxPasses = 3;

struct Trace {
  std::vector<Vec3> points;           // positions, the start first
  std::vector<SurfacePoint> surface;  // the same points on the mesh (edge crossings)
  std::vector<int> faces;             // faces[i] holds the chord points[i] -> points[i + 1]
  int closest = 0;
  double closest_distance = std::numeric_limits<double>::infinity();
};

// The preferred line at (face, x) closest to `previous`, oriented along it (zero vector
// if none).
Vec3 follow(const Energy& energy, int face, const Vec3& x, const Vec3& previous) {
  Vec3 lines[2];
  const int n = energy.preferred_lines(face, x, lines);
  Vec3 best = Vec3::Zero();
  double best_dot = -2.0;
  for (int k = 0; k < n; ++k) {
    const double d = lines[k].dot(previous);
    const Vec3 oriented = d >= 0 ? lines[k] : Vec3(-lines[k]);
    if (std::abs(d) > best_dot) {
      best_dot = std::abs(d);
      best = oriented;
    }
  }
  return best;
}

bool face_has(const Mesh& mesh, int f, int v) { return f >= 0 && mesh.corner_of(f, v) >= 0; }

// Traces from vertex `source` along `initial` (then always the preferred line closest to
// the previous direction), integrating the curve inside each face and recording where it
// crosses the edges, until the boundary, a face without preference, kMaxPasses passes
// through the star of vertex `far` (-1: none), or the length / step limits. Records the
// closest approach to `target`.
Trace trace_curve(const Mesh& mesh, const Energy& energy, int source, const Vec3& initial, const Vec3& target,
                  int far) {
  Trace trace;
  const Vec3 start = mesh.position(source);
  trace.points.push_back(start);
  trace.surface.push_back(SurfacePoint::at_vertex(source));
  trace.closest_distance = (start - target).norm();
  // The face around the source whose corner wedge holds the direction.
  int face = -1;
  for (const int* f = mesh.vertex_faces_begin(source); f != mesh.vertex_faces_end(source) && face < 0; ++f) {
    const FaceFrame frame = face_frame(mesh, *f);
    if (!frame.valid) continue;
    const auto& t = mesh.face(*f);
    const int c = mesh.corner_of(*f, source);
    const Vec3 a = mesh.position(t[(c + 1) % 3]) - start, b = mesh.position(t[(c + 2) % 3]) - start;
    const double dx = initial.dot(frame.e1), dy = initial.dot(frame.e2);
    const double ax = a.dot(frame.e1), ay = a.dot(frame.e2), bx = b.dot(frame.e1), by = b.dot(frame.e2);
    // Inside the wedge from a to b (counter-clockwise in the face frame).
    if (ax * dy - ay * dx >= 0.0 && dx * by - dy * bx >= 0.0) face = *f;
  }
  if (face < 0) return trace;
  const double edge = mesh.mean_edge_length();
  const double h = kSubStep * edge;
  const double max_length = 16.0 * mesh.bounding_box().diagonal();
  const int max_steps = 20 * static_cast<int>(std::sqrt(static_cast<double>(mesh.num_faces()))) + 1000 +
                        static_cast<int>(max_length / edge) * 4;
  Vec3 x = start, direction = initial;
  double length = 0.0;
  int passes = 0;
  bool in_star = false;
  for (int step = 0; step < max_steps && length < max_length; ++step) {
    const FaceFrame frame = face_frame(mesh, face);
    if (!frame.valid) break;
    const auto& t = mesh.face(face);
    // Corners and the current point in the face's 2D frame (origin: corner 0).
    const Vec3& p0 = mesh.position(t[0]);
    std::array<double, 6> corner{};
    for (int k = 0; k < 3; ++k) {
      const Vec3 q = mesh.position(t[k]) - p0;
      corner[2 * k] = q.dot(frame.e1);
      corner[2 * k + 1] = q.dot(frame.e2);
    }
    auto to_3d = [&](double px, double py) { return Vec3(p0 + px * frame.e1 + py * frame.e2); };
    // Unit direction in the frame at (px, py), oriented along (ox, oy); false if none.
    auto dir = [&](double px, double py, double ox, double oy, double& dx, double& dy) {
      const Vec3 d = follow(energy, face, to_3d(px, py), ox * frame.e1 + oy * frame.e2);
      dx = d.dot(frame.e1);
      dy = d.dot(frame.e2);
      const double n = std::hypot(dx, dy);
      if (!(n > 0.0)) return false;
      dx /= n;
      dy /= n;
      return true;
    };
    double px = (x - p0).dot(frame.e1), py = (x - p0).dot(frame.e2);
    double ox = direction.dot(frame.e1), oy = direction.dot(frame.e2);
    int exit = -1;
    double exit_u = 0.0;
    bool stuck = false;
    // Sub-steps until one leaves the face; then the crossing of its straight step with
    // the first edge it meets.
    for (int sub = 0; sub < 4096 && exit < 0; ++sub) {
      double k1x, k1y, k2x, k2y, k3x, k3y, k4x, k4y;
      if (!dir(px, py, ox, oy, k1x, k1y) || !dir(px + 0.5 * h * k1x, py + 0.5 * h * k1y, k1x, k1y, k2x, k2y) ||
          !dir(px + 0.5 * h * k2x, py + 0.5 * h * k2y, k1x, k1y, k3x, k3y) ||
          !dir(px + h * k3x, py + h * k3y, k1x, k1y, k4x, k4y)) {
        stuck = true;
        break;
      }
      const double sx = h * (k1x + 2 * k2x + 2 * k3x + k4x) / 6, sy = h * (k1y + 2 * k2y + 2 * k3y + k4y) / 6;
      double exit_s = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 3; ++k) {
        // Edge k: from corner k + 1 to corner k + 2.
        const double ax = corner[2 * ((k + 1) % 3)] - px, ay = corner[2 * ((k + 1) % 3) + 1] - py;
        const double ex = corner[2 * ((k + 2) % 3)] - px - ax, ey = corner[2 * ((k + 2) % 3) + 1] - py - ay;
        const double denom = sx * ey - sy * ex;
        if (denom == 0.0) continue;
        const double s = (ax * ey - ay * ex) / denom, u = (ax * sy - ay * sx) / denom;
        if (s > 1e-9 && s <= 1.0 && u >= -1e-9 && u <= 1.0 + 1e-9 && s < exit_s) {
          exit = k;
          exit_s = s;
          exit_u = u;
        }
      }
      if (exit >= 0) break;
      px += sx;
      py += sy;
      ox = k1x;
      oy = k1y;
      length += h;
    }
    if (stuck || exit < 0) break;
    // Keep off the vertices (a crossing at a vertex has no next face).
    exit_u = std::clamp(exit_u, 1e-6, 1.0 - 1e-6);
    const int va = t[(exit + 1) % 3], vb = t[(exit + 2) % 3];
    const Vec3 y = (1.0 - exit_u) * mesh.position(va) + exit_u * mesh.position(vb);
    const Vec3 chord = y - x;
    trace.points.push_back(y);
    trace.surface.push_back(SurfacePoint::on_edge(va, vb, exit_u));
    trace.faces.push_back(face);
    const double to_target = (y - target).norm();
    if (to_target < trace.closest_distance) {
      trace.closest_distance = to_target;
      trace.closest = static_cast<int>(trace.points.size()) - 1;
    }
    const int next = mesh.face_neighbor(face, exit);
    if (next < 0) break;
    const bool star = face_has(mesh, next, far) || face_has(mesh, face, far);
    if (in_star && !star && ++passes >= kMaxPasses) break;
    in_star = star;
    direction = chord.squaredNorm() > 0.0 ? Vec3(chord.normalized()) : Vec3(ox * frame.e1 + oy * frame.e2);
    x = y;
    face = next;
  }
  return trace;
}

// Every preferred line of every face at vertex v, both senses (distinct directions).
std::vector<Vec3> initial_directions(const Mesh& mesh, const Energy& energy, int v) {
  std::vector<Vec3> initial;
  const Vec3 p = mesh.position(v);
  for (const int* f = mesh.vertex_faces_begin(v); f != mesh.vertex_faces_end(v); ++f) {
    Vec3 lines[2];
    const int n = energy.preferred_lines(*f, p, lines);
    for (int k = 0; k < n; ++k) {
      for (const double sign : {1.0, -1.0}) {
        const Vec3 d = sign * lines[k];
        bool seen = false;
        for (const Vec3& e : initial) seen = seen || e.dot(d) > 0.999;
        if (!seen) initial.push_back(d);
      }
    }
  }
  return initial;
}

}  // namespace

std::vector<int> first_close_chord(const Mesh& mesh, const VertexCubes& cubes, std::span<const Vec3> points,
                                   int last, double width) {
  std::vector<int> first(mesh.num_vertices(), std::numeric_limits<int>::max());
  for (int i = 1; i <= last; ++i) {
    const Vec3& a = points[i - 1];
    const Vec3 ab = points[i] - a;
    const double l2 = ab.squaredNorm();
    const auto test = [&](int v) {
      if (first[v] < i) return;  // an earlier chord came close
      const Vec3& p = mesh.position(v);
      const double u = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
      if ((a + u * ab - p).squaredNorm() <= width * width) first[v] = i;
    };
    const Vec3 margin = Vec3::Constant(width);
    if (!cubes.for_each_in_box(a.cwiseMin(points[i]) - margin, a.cwiseMax(points[i]) + margin, test)) {
      for (int v = 0; v < mesh.num_vertices(); ++v) test(v);
    }
  }
  return first;
}

std::vector<std::vector<double>> guide_densities(const Mesh& mesh, const Energy& energy, int source, int target) {
  const std::vector<Vec3> initial = initial_directions(mesh, energy, source);
  const Vec3 t = mesh.position(target);
  const double edge = mesh.mean_edge_length();
  // Candidates: each trace cut at its close approaches to the target (local minima of the
  // distance within kNear edges; a curve may pass near the target on another branch first,
  // e.g. a contour near a saddle), at most kCutsPerTrace per trace, nearest first.
  struct Cut {
    int trace, point;
    double distance;
  };
  std::vector<Trace> traces;
  std::vector<Cut> cuts;
  for (const Vec3& d : initial) {
    Trace trace = trace_curve(mesh, energy, source, d, t, target);
    if (trace.points.size() < 2) continue;
    std::vector<Cut> mine;
    for (int i = 1; i < static_cast<int>(trace.points.size()); ++i) {
      const double di = (trace.points[i] - t).norm();
      if (di > kNear * edge) continue;
      const bool left = (trace.points[i - 1] - t).norm() >= di;
      const bool right = i + 1 == static_cast<int>(trace.points.size()) || (trace.points[i + 1] - t).norm() >= di;
      if (left && right) mine.push_back({static_cast<int>(traces.size()), i, di});
    }
    if (mine.empty()) mine.push_back({static_cast<int>(traces.size()), trace.closest, trace.closest_distance});
    std::sort(mine.begin(), mine.end(), [](const Cut& a, const Cut& b) { return a.distance < b.distance; });
    if (mine.size() > kCutsPerTrace) mine.resize(kCutsPerTrace);
    cuts.insert(cuts.end(), mine.begin(), mine.end());
    traces.push_back(std::move(trace));
  }
  // The closest approach of all first (the caller's seed).
  std::stable_sort(cuts.begin(), cuts.end(), [](const Cut& a, const Cut& b) { return a.distance < b.distance; });
  std::vector<std::vector<double>> channels;
  const double width = kChannelWidth * edge;
  const VertexCubes cubes(mesh, width);
  // Per trace, the first chord near each vertex, up to the trace's farthest cut.
  std::vector<int> reach(traces.size(), 0);
  for (const Cut& cut : cuts) reach[cut.trace] = std::max(reach[cut.trace], cut.point);
  std::vector<std::vector<int>> first_chord(traces.size());
  for (const Cut& cut : cuts) {
    if (cut.point < 1) continue;
    std::vector<int>& first = first_chord[cut.trace];
    if (first.empty()) first = first_close_chord(mesh, cubes, traces[cut.trace].points, reach[cut.trace], width);
    std::vector<double> density(mesh.num_vertices(), 1.0);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (first[v] <= cut.point) density[v] = kChannelDensity;
    }
    density[target] = kChannelDensity;
    channels.push_back(std::move(density));
  }
  return channels;
}

std::vector<SurfacePath> guide_paths(const Mesh& mesh, const Energy& energy, int source, int target) {
  std::vector<SurfacePath> paths;
  // From each end: the traced curves, each cut where it passes through the other end's
  // star (a face holding it), then straight to that end inside the face; per end the cut
  // of least segment energy.
  for (const bool from_source : {true, false}) {
    const int a = from_source ? source : target, b = from_source ? target : source;
    const Vec3 pb = mesh.position(b);
    SurfacePath best;
    double best_energy = std::numeric_limits<double>::infinity();
    for (const Vec3& d : initial_directions(mesh, energy, a)) {
      const Trace trace = trace_curve(mesh, energy, a, d, pb, b);
      const SurfacePoint end = SurfacePoint::at_vertex(b);
      double prefix = 0.0;  // segment energy of the trace up to point i
      for (int i = 1; i < static_cast<int>(trace.surface.size()); ++i) {
        prefix += energy.segment_energy(trace.surface[i - 1], trace.surface[i], trace.faces[i - 1]);
        if (!(prefix < best_energy)) break;
        for (const int f : {trace.faces[i - 1], i < static_cast<int>(trace.faces.size()) ? trace.faces[i] : -1}) {
          if (!face_has(mesh, f, b)) continue;
          const double e = prefix + energy.segment_energy(trace.surface[i], end, f);
          if (!(e < best_energy)) continue;
          best_energy = e;
          best.points.assign(trace.surface.begin(), trace.surface.begin() + i + 1);
          best.points.push_back(end);
          best.segment_faces.assign(trace.faces.begin(), trace.faces.begin() + i);
          best.segment_faces.push_back(f);
        }
      }
    }
    if (best.empty()) continue;
    if (!from_source) best.reverse();
    paths.push_back(std::move(best));
  }
  return paths;
}

}  // namespace depath
