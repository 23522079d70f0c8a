// SPDX-License-Identifier: MIT
// Method `de`: DE-Path. Differential evolution over per-vertex log-densities; an agent's
// energy is the energy of the path its density decodes to (fast marching from the
// source + back-trace from the target), +infinity when the target is not reached.
//
// Per pool slot one PathDecoder (its own fast-marching workspace), per agent index one
// SurfacePath buffer that every evaluation of that index reuses, so nothing is
// allocated per evaluation once the buffers have grown; the best path is copied out
// when the optimizer reports a new best, so no agent is ever decoded twice.
//
// With DeOptions::seed_with_problem the population starts from the problem's own
// density (the `fmm` baseline, as log) plus perturbations of it, and the result is never
// worse than the `fmm` path: if DE ends above it (e.g. the exp(log(rho)) round trip moved a
// density by an ulp), the `fmm` path itself is returned. The seed's perturbations are
// spatially smooth (below). `shade` restarts a collapsed population (DeSettings::restart).
//
// With refinement, the final population's decoded paths (the best few distinct ones) and
// the fmm path are handed on as further refinement starts: DE ranks agents by the energy
// of their decoded paths, whose decoding error (fmm geodesics on the shared meshes: a
// median 0.55% long) can exceed the gap between the local optima that refinement reaches
// from them, so the best decoded path need not refine best (on beethoven.ply
// 1051 -> 2350 the best agent refines to +0.31% above the exact geodesic, other agents
// to the exact one).
#include "solve/methods/methods.hpp"
#include "solve/methods/detours.hpp"
#include "solve/methods/guide.hpp"

#include "depath/de/differential_evolution.hpp"
#include "depath/util/error.hpp"
#include "depath/decode/path_decoder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <vector>

namespace depath {
namespace {

// Perturbations of the seed point (the problem's own density) for the seeded agents: a few
// Gaussian bumps of the log-density, with radii from a few edges to a third of the mesh
// and signed heights of up to 2 `amplitude` (a bump scales the density there by up to
// e^(2 amplitude)). A decoded path only moves where the density changes coherently over
// a region; i.i.d. per-vertex noise mostly adds jitter that the fast marching averages out
// (with it, 6 of 10 seeds of the rotation-field experiment reached the arc's basin; with
// bumps, 8 of 10, before restarts). Most bumps sit near the best path so far (the fmm
// path at first, the best one found at a restart), where they bend it; the others
// anywhere, to explore.
constexpr int kMaxBumps = 6;
constexpr double kBumpHeightScale = 2.0;
constexpr double kNearPathShare = 0.75;

// Refinement starts taken from the final population, best first; refining one costs
// about as much as 1-10 decodes. Measured on the 48 exact-geodesic pairs of the small
// shared meshes (seeded shade, 16 agents x 30 generations, seeds 1-10): 4 starts leave
// one run at +0.20% above exact, 8 none above 0.1%, as do 16.
constexpr int kMaxRefineStarts = 8;

void smooth_perturbation(const Mesh& mesh, std::span<const Vec3> path, DeRandom& rng, double amplitude,
                         std::span<double> x) {
  const int n = mesh.num_vertices();
  const double diagonal = mesh.bounding_box().diagonal();
  const double r_min = std::max(3.0 * mesh.mean_edge_length(), 1e-3 * diagonal);
  const double r_max = std::max(r_min, diagonal / 3.0);
  const double scale = kBumpHeightScale * amplitude;
  const int bumps = 1 + rng.below(kMaxBumps);
  for (int b = 0; b < bumps; ++b) {
    const double radius = r_min * std::pow(r_max / r_min, rng.uniform());
    Vec3 centre;
    if (path.size() >= 2 && rng.uniform() < kNearPathShare) {
      const int k = rng.below(static_cast<int>(path.size()) - 1);
      const double t = rng.uniform();
      centre = (1.0 - t) * path[k] + t * path[k + 1];
      for (int d = 0; d < 3; ++d) centre[d] += rng.normal(0.0, radius);
    } else {
      centre = mesh.position(rng.below(n));
    }
    const double height = scale * (2.0 * rng.uniform() - 1.0);
    const double inv = 1.0 / (2.0 * radius * radius);
    const double cutoff = 9.0 * radius * radius;  // 3 radii: exp(-4.5) ~ 1 %
    for (int v = 0; v < n; ++v) {
      const double d2 = (mesh.position(v) - centre).squaredNorm();
      if (d2 < cutoff) x[v] += height * std::exp(-d2 * inv);
    }
  }
}

// The fmm path and the best kMaxRefineStarts agents' paths (moved out of `paths`), one
// per distinct finite energy and none equal in energy to the outcome's own path (equal
// energies: the same decoded path, as a rule).
std::vector<SurfacePath> refine_starts(const MethodContext& ctx, double fmm_energy, std::vector<SurfacePath>& paths,
                                       const std::vector<double>& energies, double outcome_energy) {
  std::vector<SurfacePath> starts;
  if (fmm_energy != outcome_energy) starts.push_back(ctx.fmm_path);
  std::vector<int> order(paths.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return energies[a] < energies[b]; });
  double previous = outcome_energy;
  int taken = 0;
  for (const int i : order) {
    if (taken == kMaxRefineStarts) break;
    if (!std::isfinite(energies[i]) || energies[i] == previous || paths[i].empty()) continue;
    previous = energies[i];
    starts.push_back(std::move(paths[i]));
    ++taken;
  }
  return starts;
}

// A resumed run skips the initial population, so the hooks never saw the restored agents:
// rebuild what they keep (the best path, and for refinement every agent's path) by decoding
// the restored vectors again; decoding is deterministic, so these are the paths the
// uninterrupted run holds at that point.
void restore_hook_state(const MethodContext& ctx, const DeState& state, SurfacePath& best_path,
                        std::vector<Vec3>& best_points, std::vector<SurfacePath>& agent_paths,
                        std::vector<double>& agent_energies) {
  PathDecoder decoder(ctx.stencils);
  const std::vector<double> best = state.best_vector();
  if (!best.empty() && decoder.decode_log(best, ctx.job.source, ctx.job.target, best_path)) {
    best_points = path_positions(ctx.mesh, best_path);
  }
  if (agent_paths.empty()) return;
  for (int i = 0; i < state.population; ++i) {
    const std::span<const double> x(state.agents.data() + static_cast<size_t>(i) * state.dimension,
                                    static_cast<size_t>(state.dimension));
    if (decoder.decode_log(x, ctx.job.source, ctx.job.target, agent_paths[i])) {
      agent_energies[i] = state.energies[i];
    } else {
      agent_paths[i].clear();
    }
  }
}

}  // namespace

MethodOutcome run_de_method(const MethodContext& ctx) {
  const JobSpec& job = ctx.job;
  const int n = ctx.mesh.num_vertices();
  const int N = job.de.population;

  DeSettings settings;
  settings.population = N;
  settings.generations = job.de.generations;
  settings.stall = job.de.stall;
  settings.F = job.de.F;
  settings.CR = job.de.CR;
  settings.strategy = job.de.strategy;
  settings.seed = job.seed;
  // The adaptive strategy restarts a collapsed population (premature convergence is its
  // weak point on DE-Path: a population of 20 often settles on a wrong decoded path
  // within 100 generations); rand1bin stays the paper's DE.
  settings.restart = settings.strategy != "rand1bin";

  // Decoders are made on first use by their slot (a slot is never used by two threads at
  // once); a server pool may have more slots than this job ever touches.
  std::vector<std::unique_ptr<PathDecoder>> decoders(ctx.pool.num_slots());
  std::vector<SurfacePath> paths(N);
  std::vector<double> energies(N);

  DeProblem problem;
  problem.dimension = n;
  // Where the best path so far runs; read by perturb (called inside evaluation batches
  // only), written by on_new_best (called between them only).
  std::vector<Vec3> best_points = path_positions(ctx.mesh, ctx.fmm_path);
  problem.perturb = [&](DeRandom& rng, double amplitude, std::span<double> x) {
    smooth_perturbation(ctx.mesh, best_points, rng, amplitude, x);
  };
  // With refinement and a smoothness penalty, the search ranks decoded paths by their
  // segment energies alone: a back-traced path bends at every edge it crosses (the fast
  // marching gradient is constant per face), so its turning measures the decoding more
  // than the path's shape, and charging it steers the search to paths along mesh lines.
  // The refinement then minimises the whole energy, penalty included, from the starts the
  // search hands on (solve.cpp). Without refinement the decoded path is the result, so the
  // search ranks by the whole energy.
  const bool rank_without_penalty = job.refine && ctx.energy.smoothness() > 0.0;
  auto search_energy = [&](const SurfacePath& path) {
    return rank_without_penalty ? ctx.energy.segment_sum(path) : ctx.energy.evaluate(path);
  };
  const double fmm_search_energy = rank_without_penalty ? search_energy(ctx.fmm_path) : ctx.fmm_energy;
  // Direction energies: the guide channel along the traced field / constant-slope curve
  // (guide.hpp). Its decoded path always joins the refinement starts; with seeding it is
  // the seed point when it beats the problem's own density.
  // The closest approach's channel seeds; the candidate whose decoded path costs least
  // joins the refinement starts too, as do the traced curves themselves (guide_paths).
  SurfacePath guide_path, cheapest_guide_path;
  double guide_search_energy = std::numeric_limits<double>::infinity();
  std::vector<double> guide;
  {
    PathDecoder decoder(ctx.stencils);
    SurfacePath candidate;
    double cheapest = std::numeric_limits<double>::infinity();
    bool first = true;
    for (std::vector<double>& channel : guide_densities(ctx.mesh, ctx.energy, job.source, job.target)) {
      if (!decoder.decode(channel, job.source, job.target, candidate)) continue;
      const double e = search_energy(candidate);
      if (first) {
        first = false;
        guide_search_energy = e;
        guide_path = candidate;
        guide = std::move(channel);
      } else if (e < cheapest && e < guide_search_energy) {
        cheapest = e;
        cheapest_guide_path = candidate;
      }
    }
  }
  const bool seed_with_guide = job.de.seed_with_problem && guide_search_energy < fmm_search_energy;
  if (job.de.seed_with_problem) {
    settings.seed_point = seed_with_guide ? guide : ctx.energy.baseline_density();
    for (double& rho : settings.seed_point) rho = std::log(rho);
  }
  if (seed_with_guide) best_points = path_positions(ctx.mesh, guide_path);
  problem.evaluate = [&](int slot, int index, std::span<const double> log_density) {
    auto& decoder = decoders[slot];
    if (!decoder) decoder = std::make_unique<PathDecoder>(ctx.stencils);
    SurfacePath& path = paths[index];
    if (!decoder->decode_log(log_density, job.source, job.target, path)) {
      return energies[index] = std::numeric_limits<double>::infinity();
    }
    return energies[index] = search_energy(path);
  };

  SurfacePath best_path;
  DeHooks hooks;
  hooks.on_new_best = [&](int index) {
    best_path = paths[index];
    best_points = path_positions(ctx.mesh, best_path);
  };
  // The population's decoded paths and energies, for the refinement starts.
  std::vector<SurfacePath> agent_paths;
  std::vector<double> agent_energies;
  if (job.refine) {
    agent_paths.resize(N);
    agent_energies.assign(N, std::numeric_limits<double>::infinity());
    hooks.on_agent_replaced = [&](int index) {
      agent_paths[index] = paths[index];
      agent_energies[index] = energies[index];
    };
  }
  if (ctx.hooks.is_cancelled) hooks.is_cancelled = ctx.hooks.is_cancelled;
  hooks.checkpoint_due = ctx.hooks.checkpoint_due;
  hooks.suspend = ctx.hooks.suspend;
  if (ctx.hooks.on_checkpoint) {
    hooks.on_checkpoint = [&](const DeState& state) { ctx.hooks.on_checkpoint(encode_de_state(state)); };
  }
  std::optional<DeState> resume;
  if (!ctx.hooks.resume_from.empty()) {
    resume = decode_de_state(ctx.hooks.resume_from);
    restore_hook_state(ctx, *resume, best_path, best_points, agent_paths, agent_energies);
  }
  hooks.on_trials = ctx.hooks.on_trial_energies;
  if (!ctx.hooks.recorded_trial_energies.empty()) {
    hooks.recorded_energy = [&recorded = ctx.hooks.recorded_trial_energies, N](int generation, int index,
                                                                               double& energy) {
      const auto it = recorded.find(generation);
      if (it == recorded.end() || static_cast<int>(it->second.size()) != N) return false;
      energy = it->second[static_cast<size_t>(index)];
      return true;
    };
  }
  if (ctx.hooks.on_progress) {
    hooks.on_generation = [&](const DeGenerationReport& report) {
      Progress figures;
      figures.generation = report.generation;
      figures.max_generations = report.max_generations;
      figures.best_energy = report.best_energy;
      figures.mean_energy = report.mean_energy;
      figures.evaluations = report.evaluations;
      figures.improvements = report.improvements;
      report_progress(ctx, figures, best_path.empty() ? nullptr : &best_path);
    };
  }

  DeResult result = run_differential_evolution(problem, settings, ctx.pool, hooks, resume ? &*resume : nullptr);

  MethodOutcome outcome;
  outcome.generations = result.generations;
  outcome.evaluations = result.evaluations;
  outcome.stop_reason = result.stop_reason;
  const bool found = std::isfinite(result.best_energy) && !best_path.empty();
  // Fall back to the baseline when seeding promised "never worse", or when no agent
  // decoded at all (cancelled before the first evaluation, or no finite energy).
  double outcome_search_energy = result.best_energy;
  if (!found || (job.de.seed_with_problem && result.best_energy > fmm_search_energy)) {
    outcome.path = ctx.fmm_path;
    outcome_search_energy = fmm_search_energy;
  } else {
    outcome.path = std::move(best_path);
  }
  outcome.energy = rank_without_penalty ? ctx.energy.evaluate(outcome.path) : outcome_search_energy;
  if (job.refine) {
    outcome.refine_starts = refine_starts(ctx, fmm_search_energy, agent_paths, agent_energies, outcome_search_energy);
    for (SurfacePath& path : guide_paths(ctx.mesh, ctx.energy, job.source, job.target)) {
      outcome.refine_starts.push_back(std::move(path));
    }
    if (!cheapest_guide_path.empty()) outcome.refine_starts.push_back(std::move(cheapest_guide_path));
    if (!guide_path.empty()) outcome.refine_starts.push_back(std::move(guide_path));
    // The local minima DE's paths lead to are those of the fmm path's neighbourhood as a
    // rule; for a length the descent's other starts reach the rest cheaply.
    if (ctx.energy.length_factor() > 0.0) {
      for (SurfacePath& path : descent_starts(ctx)) outcome.refine_starts.push_back(std::move(path));
    }
  }
  return outcome;
}

}  // namespace depath
