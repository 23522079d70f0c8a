// SPDX-License-Identifier: MIT
#include "refine/hops.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace depath::refine {
namespace {

// A candidate hop is judged on a window of the path: from the nearest vertex points of
// the path around the pinned run, but at most kWindowReach points either side of it, and
// after kScreenSweeps sweeps of the descent there with at most kScreenNewtonIterations
// Newton iterations each; the chosen hop then gets the full descent on the whole path. A
// hop changes the path near the vertex first and shows most of its gain within a few
// sweeps. Measured on the 108 exact-geodesic pairs of the shared meshes (descent from the
// fmm path; 15 pairs above 0.1% without hops): windows up to the nearest vertices with
// full descents leave 5 above 0.1%, these limits also 5 at a fifth of the cost (reach 8
// and 2 sweeps: 7).
constexpr int kWindowReach = 12;
constexpr int kScreenSweeps = 3;
constexpr int kScreenNewtonIterations = 10;

bool face_has(const Mesh& mesh, int f, int w) { return mesh.corner_of(f, w) >= 0; }

// A candidate hop: the path pinned to vertex w, the window [first, last] of the pinned
// path that the descent may change, and the result.
struct Hop {
  double delta = 0.0;                // whole-path energy change
  int first = 0, last = 0;           // window ends in the current path (kept)
  std::vector<SurfacePoint> points;  // new points strictly inside the window
  std::vector<int> faces;            // points.size() + 1 segment faces
};

// Pins `path` to vertex w across its segments k..l (their faces all contain w, the points
// between them lie on edges around w) and descends on the window around; fills `hop`
// with the result.
void try_hop(Evaluator& eval, const SurfacePath& path, int w, int k, int l, const RefineOptions& options,
             const std::function<bool()>& cancelled, Hop& hop) {
  // Window ends: the nearest vertex points of the path at or before point k and at or
  // after point l + 1, within kWindowReach points. Only the points between them change.
  int first = k, last = l + 1;
  while (first > 0 && !path.points[first].is_vertex() && k - first < kWindowReach) --first;
  while (last + 1 < static_cast<int>(path.points.size()) && !path.points[last].is_vertex() &&
         last - (l + 1) < kWindowReach) {
    ++last;
  }
  SurfacePath window;
  window.points.assign(path.points.begin() + first, path.points.begin() + k + 1);
  window.segment_faces.assign(path.segment_faces.begin() + first, path.segment_faces.begin() + k + 1);
  window.points.push_back(SurfacePoint::at_vertex(w));
  window.segment_faces.push_back(path.segment_faces[l]);
  window.points.insert(window.points.end(), path.points.begin() + l + 1, path.points.begin() + last + 1);
  window.segment_faces.insert(window.segment_faces.end(), path.segment_faces.begin() + l + 1,
                              path.segment_faces.begin() + last);
  DescentStats local;
  RefineOptions screening = options;
  screening.max_newton_iterations = std::min(options.max_newton_iterations, kScreenNewtonIterations);
  descend(eval, window, eval.total(window), screening, kScreenSweeps, {}, cancelled, local);
  hop.first = first;
  hop.last = last;
  hop.points.assign(window.points.begin() + 1, window.points.end() - 1);
  hop.faces = window.segment_faces;
  hop.delta = replacement_delta(eval, path, first + 1, last - 1, hop.points, hop.faces);
}

}  // namespace

int hop_over_vertices(Evaluator& eval, SurfacePath& path, double& energy, const RefineOptions& options,
                      int sweep_budget, const std::function<bool()>& cancelled, DescentStats& stats) {
  const Mesh& mesh = eval.mesh();
  int hops = 0;
  Hop hop, best;
  SurfacePath previous;
  std::vector<int> on_path;
  while (hops < options.max_hops && stats.sweeps < sweep_budget) {
    on_path.clear();
    for (const SurfacePoint& p : path.points) {
      if (p.is_vertex()) on_path.push_back(p.v0);
    }
    std::sort(on_path.begin(), on_path.end());
    // A hop must gain more than the descent's own tolerance (no cycling on round-off).
    const double needed = -options.tolerance * std::abs(energy);
    best.delta = needed;
    bool found = false;
    const int segments = path.num_segments();
    for (int s = 0; s < segments; ++s) {
      for (const int w : mesh.face(path.segment_faces[s])) {
        if (is_cancelled(cancelled)) {
          stats.cancelled = true;
          return hops;
        }
        // Each maximal run of segments whose faces contain w, from its first segment; a
        // vertex already on the path is not pinned again (the path would visit it twice).
        if (s > 0 && face_has(mesh, path.segment_faces[s - 1], w) && !path.points[s].is_vertex()) continue;
        if (std::binary_search(on_path.begin(), on_path.end(), w)) continue;
        int l = s;
        while (l + 1 < segments && face_has(mesh, path.segment_faces[l + 1], w) && !path.points[l + 1].is_vertex()) {
          ++l;
        }
        try_hop(eval, path, w, s, l, options, cancelled, hop);
        if (hop.delta < best.delta) {
          std::swap(best, hop);
          found = true;
        }
      }
    }
    if (!found) break;
    previous = path;
    apply_replacement(path, best.first + 1, best.last - 1, best.points, best.faces);
    snap_and_merge(path);
    const double hopped = eval.total(path);
    if (!(hopped < energy)) {  // the window sums promised a gain that the true total lacks
      path = previous;
      break;
    }
    energy = hopped;
    ++hops;
    energy = descend(eval, path, energy, options, sweep_budget - stats.sweeps, options.on_sweep, cancelled, stats);
    if (stats.cancelled) break;
  }
  return hops;
}

}  // namespace depath::refine
