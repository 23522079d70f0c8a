// SPDX-License-Identifier: MIT
#include "solve/methods/guide.hpp"

#include "depath/mesh/tangent_fields.hpp"

#include <algorithm>
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

struct Trace {
  std::vector<Vec3> points;
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

// Traces from vertex `source` along `initial` (then always the preferred line closest to
// the previous direction), edge crossing by edge crossing, until the boundary, a face
// without preference, the target (within a quarter edge) or the length / step limits.
Trace trace_curve(const Mesh& mesh, const Energy& energy, int source, const Vec3& initial, const Vec3& target) {
  Trace trace;
  const Vec3 start = mesh.position(source);
  trace.points.push_back(start);
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
  const double max_length = 4.0 * mesh.bounding_box().diagonal();
  const int max_steps = 20 * static_cast<int>(std::sqrt(static_cast<double>(mesh.num_faces()))) + 1000;
  Vec3 x = start, direction = initial;
  int entry = -1;  // corner opposite the edge we entered through (-1 at the start)
  double length = 0.0;
  for (int step = 0; step < max_steps && length < max_length; ++step) {
    const Vec3 d = follow(energy, face, x, direction);
    if (d.squaredNorm() == 0.0) break;
    const FaceFrame frame = face_frame(mesh, face);
    if (!frame.valid) break;
    const auto& t = mesh.face(face);
    const double dx = d.dot(frame.e1), dy = d.dot(frame.e2);
    // Exit: the first edge the ray x + s d crosses (s > 0), other than the entry edge.
    int exit = -1;
    double exit_s = std::numeric_limits<double>::infinity(), exit_u = 0.0;
    for (int k = 0; k < 3; ++k) {
      if (k == entry) continue;
      const Vec3 p = mesh.position(t[(k + 1) % 3]) - x, q = mesh.position(t[(k + 2) % 3]) - x;
      const double px = p.dot(frame.e1), py = p.dot(frame.e2), ex = q.dot(frame.e1) - px, ey = q.dot(frame.e2) - py;
      const double denom = dx * ey - dy * ex;
      if (denom == 0.0) continue;
      const double s = (px * ey - py * ex) / denom, u = (px * dy - py * dx) / denom;
      if (s > 1e-12 * edge && u >= -1e-9 && u <= 1.0 + 1e-9 && s < exit_s) {
        exit = k;
        exit_s = s;
        exit_u = u;
      }
    }
    if (exit < 0) break;
    // Keep off the vertices (a ray through a vertex has no next face).
    exit_u = std::clamp(exit_u, 1e-6, 1.0 - 1e-6);
    const int va = t[(exit + 1) % 3], vb = t[(exit + 2) % 3];
    const Vec3 y = (1.0 - exit_u) * mesh.position(va) + exit_u * mesh.position(vb);
    length += (y - x).norm();
    trace.points.push_back(y);
    const double to_target = (y - target).norm();
    if (to_target < trace.closest_distance) {
      trace.closest_distance = to_target;
      trace.closest = static_cast<int>(trace.points.size()) - 1;
    }
    if (to_target < 0.25 * edge) break;
    const int next = mesh.face_neighbor(face, exit);
    if (next < 0) break;
    direction = d;
    x = y;
    face = next;
    entry = -1;
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.face(next)[(k + 1) % 3], b = mesh.face(next)[(k + 2) % 3];
      if ((a == va && b == vb) || (a == vb && b == va)) entry = k;
    }
  }
  return trace;
}

}  // namespace

std::vector<std::vector<double>> guide_densities(const Mesh& mesh, const Energy& energy, int source, int target) {
  // Initial directions: every preferred line of every face at the source, both senses.
  std::vector<Vec3> initial;
  const Vec3 s = mesh.position(source);
  for (const int* f = mesh.vertex_faces_begin(source); f != mesh.vertex_faces_end(source); ++f) {
    Vec3 lines[2];
    const int n = energy.preferred_lines(*f, s, lines);
    for (int k = 0; k < n; ++k) {
      for (const double sign : {1.0, -1.0}) {
        const Vec3 d = sign * lines[k];
        bool seen = false;
        for (const Vec3& e : initial) seen = seen || e.dot(d) > 0.999;
        if (!seen) initial.push_back(d);
      }
    }
  }
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
    Trace trace = trace_curve(mesh, energy, source, d, t);
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
  for (const Cut& cut : cuts) {
    if (cut.point < 1) continue;
    const std::vector<Vec3>& points = traces[cut.trace].points;
    std::vector<double> density(mesh.num_vertices(), 1.0);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const Vec3& p = mesh.position(v);
      for (int i = 1; i <= cut.point; ++i) {
        // Distance to the curve's segment (i - 1, i).
        const Vec3& a = points[i - 1];
        const Vec3 ab = points[i] - a;
        const double l2 = ab.squaredNorm();
        const double u = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
        if ((a + u * ab - p).squaredNorm() <= width * width) {
          density[v] = kChannelDensity;
          break;
        }
      }
    }
    density[target] = kChannelDensity;
    channels.push_back(std::move(density));
  }
  return channels;
}

}  // namespace depath
