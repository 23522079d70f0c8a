// SPDX-License-Identifier: MIT
// Internal: the methods that solve() dispatches to. Each lives in its own file here.
#pragma once

#include "depath/energy/energy.hpp"
#include "depath/decode/fast_marching.hpp"
#include "depath/solve/job.hpp"
#include "depath/mesh/mesh.hpp"
#include "depath/solve/solve.hpp"
#include "depath/mesh/surface_path.hpp"
#include "depath/util/thread_pool.hpp"

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace depath {

/// What every method gets: the validated problem and the caller's hooks.
struct MethodContext {
  const Mesh& mesh;
  const FastMarchingStencils& stencils;
  const Energy& energy;
  const JobSpec& job;
  const SolveHooks& hooks;
  ThreadPool& pool;
  std::chrono::steady_clock::time_point start;  ///< when solve() started (for elapsed times)
  const SurfacePath& fmm_path;  ///< the `fmm` baseline path (decode of energy.baseline_density())
  double fmm_energy;            ///< its energy
};

/// What a method found (before the optional refinement).
struct MethodOutcome {
  SurfacePath path;
  double energy = 0.0;
  int generations = 0;
  int64_t evaluations = 0;
  std::string stop_reason;  ///< "converged", "max_generations", "stalled", "cancelled"
  /// More paths for the optional refinement to start from besides `path` (de: the fmm
  /// path and the final population's); the refined result is the best of all.
  std::vector<SurfacePath> refine_starts;
};

/// The one place a Progress is built: `figures` carries the method's generation figures;
/// elapsed_seconds is set from ctx.start and best_path to `path` every job.path_every
/// generations (generation 0 included). No-op without an on_progress hook.
void report_progress(const MethodContext& ctx, Progress figures, const SurfacePath* path);

/// The `fmm` baseline itself (core/src/solve/methods/fmm.cpp).
MethodOutcome run_fmm_method(const MethodContext& ctx);
/// DE-Path (core/src/solve/methods/de.cpp).
MethodOutcome run_de_method(const MethodContext& ctx);
/// Local descent from the fmm path (core/src/solve/methods/descent.cpp).
MethodOutcome run_descent_method(const MethodContext& ctx);

}  // namespace depath
