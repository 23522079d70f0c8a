// SPDX-License-Identifier: MIT
#include "depath/solve/solve.hpp"

#include "depath/util/error.hpp"
#include "depath/decode/fast_marching.hpp"
#include "depath/decode/path_decoder.hpp"
#include "depath/refine/refine.hpp"
#include "depath/util/thread_pool.hpp"
#include "solve/methods/methods.hpp"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

namespace depath {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

SolveResult solve(const Mesh& mesh, const JobSpec& job, const SolveHooks& hooks) {
  const auto start = std::chrono::steady_clock::now();
  validate_job_options(mesh, job);
  const std::unique_ptr<Energy> energy = make_energy(mesh, job.energy);
  std::optional<FastMarchingStencils> own_stencils;
  if (hooks.stencils != nullptr && &hooks.stencils->mesh() != &mesh)
    throw Error(ErrorCode::invalid_argument, "the stencils given to solve() belong to another mesh");
  const FastMarchingStencils& stencils = hooks.stencils ? *hooks.stencils : own_stencils.emplace(mesh);

  std::optional<ThreadPool> own_pool;
  ThreadPool* pool = hooks.pool;
  if (pool == nullptr) {
    const int threads = job.threads > 0 ? job.threads : std::max(1u, std::thread::hardware_concurrency());
    pool = &own_pool.emplace(threads - 1);
  }

  // The classic FMM baseline: every method reports it, `fmm` returns it, `descent` starts there.
  SurfacePath fmm_path;
  {
    PathDecoder decoder(stencils);
    if (!decoder.decode(energy->baseline_density(), job.source, job.target, fmm_path))
      throw Error(ErrorCode::failed_precondition, "no path: target vertex " + std::to_string(job.target) +
                                                      " cannot be reached from source vertex " +
                                                      std::to_string(job.source));
  }
  const double fmm_energy = energy->evaluate(fmm_path);

  const MethodContext ctx{mesh, stencils, *energy, job, hooks, *pool, start, fmm_path, fmm_energy};
  MethodOutcome outcome;
  switch (job.method) {
    case Method::fmm:
      outcome = run_fmm_method(ctx);
      break;
    case Method::de:
      outcome = run_de_method(ctx);
      break;
    case Method::descent:
      outcome = run_descent_method(ctx);
      break;
  }

  SolveResult result;
  result.method = job.method;
  result.generations = outcome.generations;
  result.evaluations = outcome.evaluations;
  result.stop_reason = outcome.stop_reason;
  result.fmm_energy = fmm_energy;
  const bool cancelled = outcome.stop_reason == "cancelled" || outcome.stop_reason == "suspended";
  // `descent` without a smoothness penalty has refined its path under this very energy
  // already: refining it again would repeat the same moves from their own optimum (the
  // same path on all 84 exact-geodesic pairs, at a quarter more time).
  const bool refined_by_method = job.method == Method::descent && energy->smoothness() == 0.0;
  if (job.refine && !cancelled && refined_by_method) {
    result.path = std::move(outcome.path);
    result.refined = true;
  } else if (job.refine && !cancelled) {
    // The method's path first: with equal energies it wins.
    std::vector<SurfacePath> starts{std::move(outcome.path)};
    for (SurfacePath& start : outcome.refine_starts) starts.push_back(std::move(start));
    if (energy->smoothness() > 0.0) {
      // Continuation in the penalty weight: every start is refined under the penalty-free
      // energy first, exactly as a job without the penalty would be (where the angle term
      // alone shapes it, e.g. onto a contour line); that optimum, the method's own path and
      // the method's last start (de: the guide curve's path, smooth where the penalty-free
      // optimum may zig-zag, e.g. between the two constant-slope lines, which that energy
      // does not tell apart) are then refined under the whole energy. So the result's whole
      // energy is never above that of the penalty-free job's result (de ranks by segment
      // energies under refinement, so both jobs search alike). The other starts are not
      // refined again: with the penalty a refinement costs several times more (a turning
      // term per point).
      EnergySpec plain = job.energy;
      plain.smoothness = 0.0;
      const std::unique_ptr<Energy> unpenalized = make_energy(mesh, plain);
      SurfacePath settled = refine_best_of(*unpenalized, starts, {}, hooks.is_cancelled);
      if (starts.size() > 2) starts.erase(starts.begin() + 1, starts.end() - 1);
      starts.push_back(std::move(settled));
    }
    result.path = refine_best_of(*energy, starts, {}, hooks.is_cancelled);
    result.refined = true;
  } else {
    result.path = std::move(outcome.path);
  }
  result.energy = energy->evaluate(result.path);
  result.length = path_length(mesh, result.path);
  result.metrics = energy->metrics(result.path);
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace depath
