// SPDX-License-Identifier: MIT
#include "refine/common.hpp"

#include <algorithm>
#include <cmath>

namespace depath::refine {

bool face_contains(const Mesh& mesh, int f, const SurfacePoint& p) {
  if (f < 0 || f >= mesh.num_faces()) return false;
  if (mesh.corner_of(f, p.v0) < 0) return false;
  return p.is_vertex() || mesh.corner_of(f, p.v1) >= 0;
}

int third_vertex(const Mesh& mesh, int f, int a, int b) {
  for (int v : mesh.face(f)) {
    if (v != a && v != b) return v;
  }
  return -1;
}

bool same_location(const SurfacePoint& a, const SurfacePoint& b) {
  if (a.is_vertex() != b.is_vertex()) return false;
  if (a.is_vertex()) return a.v0 == b.v0;
  if (a.v0 == b.v0 && a.v1 == b.v1) return a.t == b.t;
  if (a.v0 == b.v1 && a.v1 == b.v0) return a.t == 1.0 - b.t;
  return false;
}

double Evaluator::window(const SurfacePath& path, int first, int last) {
  double sum = 0.0;
  for (int s = first; s < last; ++s) sum += segment(path, s);
  if (smooth()) {
    for (int i = first; i <= last; ++i) sum += turn(path, i);
  }
  return sum;
}

int Evaluator::best_common_face(const SurfacePoint& a, const SurfacePoint& b, int preferred) {
  int best = -1;
  double best_energy = 0.0;
  auto consider = [&](int f) {
    if (f == best || !face_contains(mesh_, f, a) || !face_contains(mesh_, f, b)) return;
    const double e = segment(a, b, f);
    // NaN energies never win; a finite one always beats "none yet".
    if (best < 0 ? !std::isnan(e) : e < best_energy) {
      best = f;
      best_energy = e;
    }
  };
  consider(preferred);
  const int anchor = anchor_vertex(a);
  for (const int* f = mesh_.vertex_faces_begin(anchor); f != mesh_.vertex_faces_end(anchor); ++f) consider(*f);
  if (best < 0) {
    // Only NaN energies (or no common face): fall back to any common face.
    for (const int* f = mesh_.vertex_faces_begin(anchor); f != mesh_.vertex_faces_end(anchor); ++f) {
      if (face_contains(mesh_, *f, a) && face_contains(mesh_, *f, b)) return *f;
    }
  }
  return best;
}

double replacement_delta(Evaluator& eval, const SurfacePath& path, int first, int last,
                         const std::vector<SurfacePoint>& points, const std::vector<int>& faces) {
  const int n = static_cast<int>(path.points.size());
  const double before = eval.window(path, first - 1, last + 1);
  // A local path: one extra point on each side, so that the smoothness terms at the
  // window's ends see their true neighbours.
  const int lo = std::max(0, first - 2), hi = std::min(n - 1, last + 2);
  SurfacePath& local = eval.scratch();
  local.points.assign(path.points.begin() + lo, path.points.begin() + first);
  local.points.insert(local.points.end(), points.begin(), points.end());
  local.points.insert(local.points.end(), path.points.begin() + last + 1, path.points.begin() + hi + 1);
  local.segment_faces.assign(path.segment_faces.begin() + lo, path.segment_faces.begin() + (first - 1));
  local.segment_faces.insert(local.segment_faces.end(), faces.begin(), faces.end());
  local.segment_faces.insert(local.segment_faces.end(), path.segment_faces.begin() + last + 1,
                             path.segment_faces.begin() + hi);
  const int a = first - 1 - lo;
  const double after = eval.window(local, a, a + static_cast<int>(points.size()) + 1);
  return after - before;
}

void apply_replacement(SurfacePath& path, int first, int last, const std::vector<SurfacePoint>& points,
                       const std::vector<int>& faces) {
  path.points.erase(path.points.begin() + first, path.points.begin() + last + 1);
  path.points.insert(path.points.begin() + first, points.begin(), points.end());
  path.segment_faces.erase(path.segment_faces.begin() + (first - 1), path.segment_faces.begin() + last + 1);
  path.segment_faces.insert(path.segment_faces.begin() + (first - 1), faces.begin(), faces.end());
}

bool snap_and_merge(SurfacePath& path) {
  bool changed = false;
  for (auto& p : path.points) {
    if (p.is_vertex()) continue;
    if (p.t <= 0.0) {
      p = SurfacePoint::at_vertex(p.v0);
      changed = true;
    } else if (p.t >= 1.0) {
      p = SurfacePoint::at_vertex(p.v1);
      changed = true;
    }
  }
  // Merge runs of equal points; keep the first's incoming face and the last's outgoing
  // face, so every kept segment keeps the face it had.
  std::size_t out = 0;
  for (std::size_t i = 0; i < path.points.size(); ++i) {
    if (out > 0 && same_location(path.points[out - 1], path.points[i])) {
      // Segment (out-1 -> i) has zero length: drop point i, and the outgoing face of
      // point out-1 becomes the one of point i.
      if (i < path.segment_faces.size()) path.segment_faces[out - 1] = path.segment_faces[i];
      changed = true;
      continue;
    }
    path.points[out] = path.points[i];
    if (i < path.segment_faces.size()) path.segment_faces[out] = path.segment_faces[i];
    ++out;
  }
  path.points.resize(out);
  path.segment_faces.resize(out > 0 ? out - 1 : 0);
  return changed;
}

bool repair_faces(Evaluator& eval, SurfacePath& path) {
  const Mesh& mesh = eval.mesh();
  path.segment_faces.resize(path.points.size() > 0 ? path.points.size() - 1 : 0, -1);
  for (std::size_t s = 0; s + 1 < path.points.size(); ++s) {
    const int f = path.segment_faces[s];
    if (face_contains(mesh, f, path.points[s]) && face_contains(mesh, f, path.points[s + 1])) continue;
    const int g = eval.best_common_face(path.points[s], path.points[s + 1], -1);
    if (g < 0) return false;
    path.segment_faces[s] = g;
  }
  return true;
}

}  // namespace depath::refine
