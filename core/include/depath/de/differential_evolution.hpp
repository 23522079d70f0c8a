// SPDX-License-Identifier: MIT
// Differential evolution (DE) over real vectors, run on a ThreadPool, reproducible per seed.
//
// Generic: knows nothing about meshes. DE-Path (core/src/solve/methods/de.cpp) plugs in
// "decode the log-density into a path and take its energy" as the objective.
//
// Algorithm (synchronous generations, SPEC §1):
//   - N agents x_0..x_{N-1} in R^n, initialised by DeProblem::initialize (default: every
//     coordinate log(U(0,1]) — the paper's uniform (0,1] densities, as log-densities),
//     optionally with a seed point and perturbations of it (DeSettings::seed_point).
//   - Each generation every agent i gets a trial u_i from the strategy (`rand1bin`: the
//     paper's v = x_r1 + F (x_r2 - x_r3) with binomial crossover; `shade`: adaptive
//     current-to-pbest/1 with an archive), all trials are evaluated in parallel, then
//     u_i replaces x_i if its energy is strictly lower (greedy selection).
//   - Stops after `generations`, after `stall` generations without a strictly better best,
//     when the population has collapsed to a single point ("converged"), or on
//     cancellation. With DeSettings::restart a collapsed population is restarted instead.
//
// Guarantees:
//   - Reproducible: every random number is drawn from a counter-based stream keyed by
//     (seed, generation, agent) and all serial steps run in index order, so the result is
//     bit-for-bit identical for a seed whatever the pool size, provided `evaluate` is a
//     pure function of its vector.
//   - Memory: the population and the trials (2 x N x n doubles); `shade` adds an archive
//     of at most N/2 vectors, restarts one vector (the best, kept aside). Nothing of size
//     n is allocated per thread or per evaluation.
//   - The best energy never rises; best_energy is the lowest energy ever evaluated.
//
// References: R. Storn, K. Price, "Differential evolution — a simple and efficient
// heuristic for global optimization over continuous spaces", J. Global Optimization 11
// (1997) (`rand1bin`); R. Tanabe, A. Fukunaga, "Success-history based parameter adaptation
// for differential evolution", IEEE CEC 2013 (`shade`). DE-Path (Ye, Liu, Zheng, Hormann,
// He) runs it over per-vertex log-densities.
#pragma once

#include "depath/de/checkpoint.hpp"

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace depath {

class ThreadPool;

/// Counter-based random stream: its numbers depend only on (seed, a, b), never on the
/// thread that draws them. SplitMix64-keyed xoshiro256**.
class DeRandom {
 public:
  DeRandom(uint64_t seed, uint64_t a, uint64_t b);
  uint64_t next();
  double uniform();                   ///< [0, 1)
  double uniform_open_closed();       ///< (0, 1]
  int below(int n);                   ///< integer in [0, n), n >= 1
  double normal(double mean, double sigma);
  double cauchy(double location, double scale);

 private:
  uint64_t s_[4];
};

/// What is minimised.
struct DeProblem {
  int dimension = 0;
  /// Energy of candidate `x` (lower is better; NaN counts as +infinity). Called
  /// concurrently from pool threads: `slot` is the pool slot of the calling thread (index
  /// per-thread scratch space with it), `index` the agent whose candidate this is (the
  /// initial agent or its trial; no two concurrent calls share an index).
  std::function<double(int slot, int index, std::span<const double> x)> evaluate;
  /// Fills initial agent `index`. Optional; default: log(U(0,1]) per coordinate.
  std::function<void(int index, DeRandom& rng, std::span<double> x)> initialize;
  /// Adds a random perturbation of scale `amplitude` to `x` (the seeded agents).
  /// Optional; default: uniform noise in [-amplitude, amplitude] per coordinate. A problem
  /// whose energy responds only to coherent changes (DE-Path: a path moves only where the
  /// density changes over a region) should supply spatially smooth perturbations here.
  std::function<void(DeRandom& rng, double amplitude, std::span<double> x)> perturb;
};

/// DE parameters.
struct DeSettings {
  int population = 20;     ///< N >= 4
  int generations = 100;   ///< >= 1
  int stall = 0;           ///< stop after this many generations without improvement (0 = never)
  double F = 0.5;          ///< mutation scale in (0, 2] (shade: initial mean)
  double CR = 0.9;         ///< crossover rate in [0, 1] (shade: initial mean)
  std::string strategy = "rand1bin";
  uint64_t seed = 1;
  /// If not empty (size n): agent 0 is this point and the next
  /// ceil(seed_fraction * N) - 1 agents are perturbations of it (DeProblem::perturb, by
  /// default uniform noise, of amplitudes from 0.02 to 1 growing geometrically); the
  /// others are initialised as usual.
  std::vector<double> seed_point;
  double seed_fraction = 0.5;
  /// Restart on collapse (opt-in; without it `rand1bin` is exactly the paper's DE): when
  /// the agents' energies agree to a relative `restart_tolerance` (highest - lowest <=
  /// tol * |lowest|), the next generation's trials are a fresh population, initialised as
  /// in generation 0 (seed point and its perturbations, random agents) from that
  /// generation's streams, and replace the agents unconditionally; the strategy resets its
  /// adaptation (shade keeps its archive). The best so far is kept aside, outside the
  /// population, until an agent beats it, so it is never lost and no restart is pulled
  /// back into its basin. Each restart costs one generation's evaluations, no more. A
  /// collapsed population then never stops the run ("converged").
  /// A stagnant population restarts the same way: when the lowest energy among the agents
  /// improved by at most `restart_progress` (relative) over the last `restart_window`
  /// generations since the last restart (window 0: never).
  bool restart = false;
  double restart_tolerance = 1e-3;
  int restart_window = 50;
  double restart_progress = 0.05;
};

/// Summary of one finished generation.
struct DeGenerationReport {
  int generation = 0;  ///< 1-based
  int max_generations = 0;
  double best_energy = 0.0;
  double mean_energy = 0.0;  ///< over agents with finite energy (+inf if none)
  int64_t evaluations = 0;   ///< so far, initial population included
  int improvements = 0;      ///< agents replaced by their trial in this generation
  int best_index = -1;       ///< agent holding the best (-1: kept aside since a restart)
  bool restarted = false;    ///< this generation's trials were a restart (DeSettings::restart)
};

/// Optional callbacks.
struct DeHooks {
  /// Called on the calling thread after each generation.
  std::function<void(const DeGenerationReport&)> on_generation;
  /// Called on the calling thread, right after the batch that evaluated it, when candidate
  /// `index` of that batch (initial agent or trial) became the new best — before `index`
  /// is evaluated again, so per-index results (e.g. the decoded path) can be kept.
  std::function<void(int index)> on_new_best;
  /// Called on the calling thread, right after the batch that evaluated it, for every
  /// agent `index` whose vector is now the candidate just evaluated for that index (each
  /// initial agent, each accepted trial, each restart's new agent), before `index` is
  /// evaluated again — so per-index results can follow the population.
  std::function<void(int index)> on_agent_replaced;
  /// Polled before every evaluation, concurrently from pool threads (must be thread-safe).
  std::function<bool()> is_cancelled;
  /// Checkpoints (de/checkpoint.hpp): polled on the calling thread before each generation;
  /// true hands the state as it is then (everything a resume needs) to on_checkpoint.
  std::function<bool()> checkpoint_due;
  std::function<void(const DeState&)> on_checkpoint;
  /// Polled before each generation: true stops the run there, after a checkpoint, with
  /// stop_reason "suspended" (a server going down that will resume the run later).
  std::function<bool()> suspend;
  /// Called on the calling thread once a generation's trials are all evaluated, before
  /// selection: trial `i`'s energy at [i]; generation 0 is the initial population (for a
  /// journal of the run since its last checkpoint).
  std::function<void(int generation, std::span<const double> trial_energies)> on_trials;
  /// What on_trials reported in an earlier run of the same problem and settings (from the
  /// checkpoint it resumes, or from the start): true and `energy` set when candidate `index`
  /// of `generation` is known. Called concurrently from pool threads. The candidate is still
  /// made (its vector may join the population) but not evaluated again, unless it would
  /// become the new best (it is then evaluated, so on_new_best finds its per-index results)
  /// or on_agent_replaced is set (every accepted candidate needs them). The run is
  /// deterministic, so it ends bit-identical to one that evaluated every candidate.
  std::function<bool(int generation, int index, double& energy)> recorded_energy;
};

struct DeResult {
  std::vector<double> best;  ///< best vector found
  double best_energy = 0.0;
  int generations = 0;       ///< generations completed
  int64_t evaluations = 0;
  std::string stop_reason;   ///< "max_generations", "stalled", "converged", "cancelled", "suspended"
  int restarts = 0;          ///< restarts on collapse (DeSettings::restart)
};

/// Names accepted as DeSettings::strategy: {"rand1bin", "shade"}.
const std::vector<std::string>& de_strategy_names();

/// The one check of DE's user-facing parameters (SPEC §2), shared by validate_de_settings
/// and depath::validate_job: throws Error(invalid_argument) naming the parameter and its
/// value (population < 4, generations < 1, stall < 0, F outside (0, 2], CR outside [0, 1],
/// unknown strategy with the list of valid names).
void validate_de_parameters(int population, int generations, int stall, double F, double CR,
                            const std::string& strategy);

/// validate_de_parameters, plus the settings only the optimizer has (dimension, seed
/// point size, seed fraction, restart parameters).
void validate_de_settings(const DeSettings& settings, int dimension);

/// Runs DE. Throws what validate_de_settings throws, and rethrows exceptions of
/// `evaluate`. With cancellation before anything was evaluated, best is empty and
/// best_energy +infinity.
/// `resume`: a checkpoint of an earlier run of the same problem and settings; the run goes
/// on from it (no initial population, no hooks for the restored agents) and ends exactly as
/// the uninterrupted run would. Throws Error(invalid_argument) if it does not fit.
DeResult run_differential_evolution(const DeProblem& problem, const DeSettings& settings, ThreadPool& pool,
                                    const DeHooks& hooks = {}, const DeState* resume = nullptr);

}  // namespace depath
