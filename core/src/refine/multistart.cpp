// SPDX-License-Identifier: MIT
// refine_best_of: multi-start refinement (see depath/refine/refine.hpp).
#include "depath/refine/refine.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace depath {
namespace {

// The hops run from the distinct local optima within this relative gap above the lowest
// one. Hops gain little per run (on the 108 exact-geodesic pairs of the shared meshes at
// most 1%, from the fmm path), so an optimum farther up rarely overtakes the lowest, and
// each run costs about a hundred descents on windows of the path (test_paper_experiments,
// vector fields: 20 s with hops from every optimum, 13 s with this gap, under load). On
// the 48 small-mesh pairs (de --refine, seeds 1-10) this keeps every run as good as hops
// from every optimum.
constexpr double kHopGap = 0.01;
// Local optima whose energies agree to this relative tolerance count as one (starts in
// one basin end there within the descent's tolerance); the hops run once per optimum.
constexpr double kSameOptimum = 1e-9;

}  // namespace

SurfacePath refine_best_of(const Energy& energy, std::span<const SurfacePath> starts, const RefineOptions& options,
                           const std::function<bool()>& cancelled, RefineReport* report) {
  RefineReport local_report;
  RefineReport& rep = report ? *report : local_report;
  rep = RefineReport{};
  if (starts.empty()) return {};

  struct Optimum {
    SurfacePath path;
    RefineReport report;
  };
  std::vector<Optimum> optima;
  int64_t evaluations = 0;  // of the refinements finished
  // Progress over all the refinements: sweeps counted on from one to the next, and the
  // lowest energy so far with its path.
  int sweeps = 0;
  double lowest_so_far = INFINITY;
  SurfacePath lowest_path;
  RefineOptions hopping = options;
  if (options.on_sweep) {
    hopping.on_sweep = [&](const RefineSweep& sweep) {
      if (sweep.energy < lowest_so_far) {
        lowest_so_far = sweep.energy;
        lowest_path = *sweep.path;
      }
      options.on_sweep(RefineSweep{++sweeps, lowest_so_far, evaluations + sweep.evaluations, &lowest_path});
    };
  }
  RefineOptions local = hopping;
  local.max_hops = 0;
  for (const SurfacePath& start : starts) {
    Optimum o;
    o.path = refine_path(energy, start, local, cancelled, &o.report);
    evaluations += o.report.evaluations;
    optima.push_back(std::move(o));
    if (cancelled && cancelled()) break;
  }
  std::vector<int> order(optima.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return optima[a].report.final_energy < optima[b].report.final_energy; });

  int best = order.front();
  double best_energy = optima[best].report.final_energy;
  RefineReport best_report = optima[best].report;
  SurfacePath best_path = optima[best].path;
  if (options.max_hops > 0) {
    double previous = NAN;
    const double lowest = optima[order.front()].report.final_energy;
    int hopped = 0;
    for (const int i : order) {
      if (cancelled && cancelled()) break;
      const double e = optima[i].report.final_energy;
      if (e > lowest + kHopGap * std::abs(lowest)) break;
      if (std::abs(e - previous) <= kSameOptimum * std::abs(e)) continue;
      if (options.hop_starts > 0 && hopped++ == options.hop_starts) break;
      previous = e;
      RefineReport r;
      SurfacePath path = refine_path(energy, optima[i].path, hopping, cancelled, &r);
      evaluations += r.evaluations;
      if (r.final_energy < best_energy) {
        best_energy = r.final_energy;
        best_path = std::move(path);
        // The whole chain from the start: its local refinement, then the hops.
        best_report = optima[i].report;
        best_report.sweeps += r.sweeps;
        best_report.reroutes += r.reroutes;
        best_report.hops = r.hops;
        best_report.stop_reason = r.stop_reason;
        best_report.final_energy = r.final_energy;
      }
    }
  }
  rep = best_report;
  rep.initial_energy = energy.evaluate(starts.front());
  rep.evaluations = evaluations;
  return best_path;
}

}  // namespace depath
