#include "refine_common.hpp"

#include <cmath>

namespace depath::refine {

bool face_contains(const Mesh& mesh, int f, const SurfacePoint& p) {
  if (f < 0 || f >= mesh.num_faces()) return false;
  if (mesh.corner_of(f, p.v0) < 0) return false;
  return p.is_vertex() || mesh.corner_of(f, p.v1) >= 0;
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
