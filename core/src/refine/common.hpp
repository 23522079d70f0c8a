// SPDX-License-Identifier: MIT
// Internal helpers of the path refinement (refine.cpp, points.cpp,
// reroute.cpp): point/face predicates, path clean-up, and an energy evaluator
// that counts work and evaluates windows of a path.
#pragma once

#include "depath/energy/energy.hpp"
#include "depath/mesh/mesh.hpp"
#include "depath/mesh/surface_path.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace depath::refine {

/// True if face f contains the point (its vertex, or both ends of its edge).
bool face_contains(const Mesh& mesh, int f, const SurfacePoint& p);

/// The vertex of face f that is neither a nor b (-1 if there is none).
int third_vertex(const Mesh& mesh, int f, int a, int b);

/// True if a and b denote the same location combinatorially (same vertex, or the same
/// edge at the same parameter in either orientation).
bool same_location(const SurfacePoint& a, const SurfacePoint& b);

/// A vertex of the mesh that is incident to every face containing p (p's vertex, or
/// the first end of its edge): the place to start looking for faces that contain p.
inline int anchor_vertex(const SurfacePoint& p) { return p.v0; }

/// Evaluates segment energies and turning angles of paths, counting the segment
/// evaluations (the unit of work reported to callers).
class Evaluator {
 public:
  explicit Evaluator(const Energy& energy) : energy_(energy), mesh_(energy.mesh()) {}

  const Energy& energy() const { return energy_; }
  const Mesh& mesh() const { return mesh_; }
  bool smooth() const { return energy_.smoothness() > 0.0; }
  int64_t evaluations() const { return evaluations_; }

  double segment(const SurfacePoint& a, const SurfacePoint& b, int face) {
    ++evaluations_;
    return energy_.segment_energy(a, b, face);
  }
  double segment(const SurfacePath& path, int s) {
    return segment(path.points[s], path.points[s + 1], path.segment_faces[s]);
  }
  /// Smoothness term at point i (lambda * turning angle; 0 without smoothness).
  double turn(const SurfacePath& path, int i) const {
    return smooth() ? energy_.smoothness() * energy_.turning_angle(path, i) : 0.0;
  }
  /// Energy terms that involve only points first..last: the segments between them and
  /// the smoothness terms at them. Changing points strictly inside (first, last) changes
  /// exactly these terms, so comparing windows compares whole-path energies.
  double window(const SurfacePath& path, int first, int last);
  /// Whole-path energy (same sum as Energy::evaluate, counted).
  double total(const SurfacePath& path) { return window(path, 0, static_cast<int>(path.points.size()) - 1); }

  /// Among the faces containing both a and b, the one giving the lowest segment
  /// energy (ties: the first found; `preferred` first). -1 if they share no face.
  int best_common_face(const SurfacePoint& a, const SurfacePoint& b, int preferred);

  /// A path to build candidate windows in, kept so that trying one allocates nothing.
  SurfacePath& scratch() { return scratch_; }

 private:
  const Energy& energy_;
  const Mesh& mesh_;
  int64_t evaluations_ = 0;
  SurfacePath scratch_;
};

/// Energy change (new - old) of replacing the interior points first..last of `path` by
/// `points`, with `faces` (points.size() + 1 of them) for the segments from point
/// first - 1 through `points` to point last + 1. first > last inserts. Only the terms
/// that change are evaluated.
double replacement_delta(Evaluator& eval, const SurfacePath& path, int first, int last,
                         const std::vector<SurfacePoint>& points, const std::vector<int>& faces);

/// Applies that replacement.
void apply_replacement(SurfacePath& path, int first, int last, const std::vector<SurfacePoint>& points,
                       const std::vector<int>& faces);

/// Clean-up that never changes the geometry of the path: edge points at t <= 0 or
/// t >= 1 become vertices, and consecutive points at the same location are merged
/// (dropping the zero-length segment between them). Returns true if anything changed.
bool snap_and_merge(SurfacePath& path);

/// Makes every segment face valid: keeps segment_faces[i] if it contains both ends,
/// otherwise picks the best common face. Returns false if some segment's ends share no
/// face (the path is not a surface path).
bool repair_faces(Evaluator& eval, SurfacePath& path);

/// Polled cancellation callback (empty means never cancelled).
inline bool is_cancelled(const std::function<bool()>& cancelled) { return cancelled && cancelled(); }

}  // namespace depath::refine
