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
// density by an ulp), the `fmm` path itself is returned.
#include "methods/methods.hpp"

#include "depath/differential_evolution.hpp"
#include "depath/error.hpp"
#include "depath/path_decoder.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace depath {

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
  if (job.de.seed_with_problem) {
    settings.seed_point = ctx.energy.baseline_density();
    for (double& rho : settings.seed_point) rho = std::log(rho);
  }

  // Decoders are made on first use by their slot (a slot is never used by two threads at
  // once); a server pool may have more slots than this job ever touches.
  std::vector<std::unique_ptr<PathDecoder>> decoders(ctx.pool.num_slots());
  std::vector<SurfacePath> paths(N);

  DeProblem problem;
  problem.dimension = n;
  problem.evaluate = [&](int slot, int index, std::span<const double> log_density) {
    auto& decoder = decoders[slot];
    if (!decoder) decoder = std::make_unique<PathDecoder>(ctx.stencils);
    SurfacePath& path = paths[index];
    if (!decoder->decode_log(log_density, job.source, job.target, path)) {
      return std::numeric_limits<double>::infinity();
    }
    return ctx.energy.evaluate(path);
  };

  SurfacePath best_path;
  DeHooks hooks;
  hooks.on_new_best = [&](int index) { best_path = paths[index]; };
  if (ctx.hooks.is_cancelled) hooks.is_cancelled = ctx.hooks.is_cancelled;
  if (ctx.hooks.on_progress) {
    hooks.on_generation = [&](const DeGenerationReport& report) {
      Progress progress;
      progress.generation = report.generation;
      progress.max_generations = report.max_generations;
      progress.best_energy = report.best_energy;
      progress.mean_energy = report.mean_energy;
      progress.evaluations = report.evaluations;
      progress.improvements = report.improvements;
      progress.elapsed_seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - ctx.start).count();
      if (job.path_every > 0 && report.generation % job.path_every == 0 && !best_path.empty()) {
        progress.best_path = &best_path;
      }
      ctx.hooks.on_progress(progress);
    };
  }

  DeResult result = run_differential_evolution(problem, settings, ctx.pool, hooks);

  MethodOutcome outcome;
  outcome.generations = result.generations;
  outcome.evaluations = result.evaluations;
  outcome.stop_reason = result.stop_reason;
  const bool found = std::isfinite(result.best_energy) && !best_path.empty();
  // Fall back to the baseline when seeding promised "never worse", or when no agent
  // decoded at all (cancelled before the first evaluation, or no finite energy).
  if (!found || (job.de.seed_with_problem && result.best_energy > ctx.fmm_energy)) {
    outcome.path = ctx.fmm_path;
    outcome.energy = ctx.fmm_energy;
  } else {
    outcome.path = std::move(best_path);
    outcome.energy = result.best_energy;
  }
  return outcome;
}

}  // namespace depath
