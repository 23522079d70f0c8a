// SPDX-License-Identifier: MIT
// The one entry point that runs a job: used by `depath solve`, the server and the tests.
//
// Inputs: a mesh, a JobSpec and optional hooks (progress, cancellation, a shared pool).
// Outputs: a SolveResult (path, energy, length, figures, metrics). Guarantees: validates
// the job first; reproducible (same inputs and seed, same path, whatever the thread count);
// a cancelled job returns the best path so far.
// Reference: DE-Path (Ye, Liu, Zheng, Hormann, He) — differential evolution over per-vertex
// density fields, each decoded into a path by fast marching and back-tracing.
#pragma once

#include "depath/solve/job.hpp"
#include "depath/solve/progress.hpp"
#include "depath/mesh/mesh.hpp"
#include "depath/mesh/surface_path.hpp"
#include "depath/energy/energy.hpp"

#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace depath {

class ThreadPool;
class FastMarchingStencils;

/// Final result of a job.
struct SolveResult {
  SurfacePath path;
  double energy = 0.0;
  double length = 0.0;
  Method method = Method::de;
  bool refined = false;
  int generations = 0;
  int64_t evaluations = 0;
  double seconds = 0.0;
  double fmm_energy = 0.0;    ///< energy of the `fmm` baseline path on the same problem
  std::vector<Metric> metrics;  ///< energy-specific figures (normalized energy, slope error)
  std::string stop_reason;    ///< "converged", "max_generations", "stalled", "cancelled", "suspended"
};

/// Hooks the caller may set; all optional.
struct SolveHooks {
  /// Called on the solving thread after each generation (keep it cheap).
  std::function<void(const Progress&)> on_progress;
  /// Polled between evaluations; once true, the method stops and the best so far is returned
  /// with stop_reason "cancelled".
  std::function<bool()> is_cancelled;
  /// Pool to evaluate on (the server's shared pool). Null: solve() makes one with
  /// job.threads threads.
  ThreadPool* pool = nullptr;
  /// Fast-marching stencils of this very mesh object (decode/fast_marching.hpp), built once
  /// and kept by the caller (the server's mesh cache), which keeps them alive for the call.
  /// Null: solve() builds them, which costs up to several full marches. Results are the same
  /// either way, bit for bit.
  const FastMarchingStencils* stencils = nullptr;
  /// Checkpoints of a `de` job (other methods take none), for exact resume elsewhere or
  /// later: checkpoint_due is polled between generations; when true, on_checkpoint gets the
  /// run's whole state as bytes (de/checkpoint.hpp). Both on the solving thread.
  std::function<bool()> checkpoint_due;
  std::function<void(std::string checkpoint)> on_checkpoint;  ///< owns the bytes (may keep them)
  /// Polled between generations: true checkpoints and stops; the result then has
  /// stop_reason "suspended" and is not refined.
  std::function<bool()> suspend;
  /// Bytes an earlier on_checkpoint gave for the same mesh and job: the run continues from
  /// there and ends bit-identical to an uninterrupted one. Empty: start afresh.
  std::string resume_from;
  /// A journal of a `de` job since its last checkpoint: after each generation, on the
  /// solving thread, its trials' energies (one per agent, before selection; generation 0:
  /// the initial agents').
  std::function<void(int generation, std::span<const double> energies)> on_trial_energies;
  /// What on_trial_energies reported in an interrupted run of the same job, for generations
  /// after resume_from's checkpoint (from generation 0 without one): generation -> energies.
  /// The run takes them instead of decoding those candidates again (except one that would
  /// become the best, or with refine) and still ends bit-identical. An entry of another
  /// population size is ignored.
  std::map<int, std::vector<double>> recorded_trial_energies;
};

/// Validates and runs a job. Throws Error (invalid_argument, failed_precondition) for bad
/// jobs, and invalid_argument for hooks.stencils built from another mesh object. Results
/// are reproducible: same mesh, job and seed give the same path and energy whatever the
/// number of threads.
SolveResult solve(const Mesh& mesh, const JobSpec& job, const SolveHooks& hooks = {});

}  // namespace depath
