// SPDX-License-Identifier: MIT
// The generic DE optimizer on analytic functions: operators, stop rules, reproducibility.
#include "depath/de/differential_evolution.hpp"
#include "depath/util/error.hpp"
#include "depath/util/thread_pool.hpp"

#include "../core/src/de/strategy.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

namespace depath {
namespace {

// Shifted sphere: minimum 0 at x = -0.5 (inside the log(U(0,1]) initial range).
double sphere(std::span<const double> x) {
  double sum = 0.0;
  for (double v : x) sum += (v + 0.5) * (v + 0.5);
  return sum;
}

// Shifted Rastrigin: many local minima, global minimum 0 at x = -0.5.
double rastrigin(std::span<const double> x) {
  double sum = 10.0 * static_cast<double>(x.size());
  for (double v : x) {
    const double y = v + 0.5;
    sum += y * y - 10.0 * std::cos(2.0 * std::numbers::pi * y);
  }
  return sum;
}

DeProblem make_problem(int dimension, double (*f)(std::span<const double>)) {
  DeProblem problem;
  problem.dimension = dimension;
  problem.evaluate = [f](int, int, std::span<const double> x) { return f(x); };
  return problem;
}

DeSettings settings(int population, int generations, const std::string& strategy = "rand1bin", uint64_t seed = 7) {
  DeSettings s;
  s.population = population;
  s.generations = generations;
  s.strategy = strategy;
  s.seed = seed;
  return s;
}

TEST(DeRandom, StreamsDependOnlyOnKeysAndStayInRange) {
  DeRandom a(1, 2, 3), b(1, 2, 3), c(1, 2, 4), d(2, 2, 3);
  int differ_c = 0, differ_d = 0;
  for (int k = 0; k < 1000; ++k) {
    const uint64_t x = a.next();
    EXPECT_EQ(x, b.next());
    differ_c += x != c.next();
    differ_d += x != d.next();
  }
  EXPECT_EQ(differ_c, 1000);
  EXPECT_EQ(differ_d, 1000);
  DeRandom r(5, 0, 0);
  double sum = 0.0;
  std::set<int> seen;
  for (int k = 0; k < 20000; ++k) {
    const double u = r.uniform_open_closed();
    ASSERT_GT(u, 0.0);
    ASSERT_LE(u, 1.0);
    const double v = r.uniform();
    ASSERT_GE(v, 0.0);
    ASSERT_LT(v, 1.0);
    sum += v;
    const int i = r.below(7);
    ASSERT_GE(i, 0);
    ASSERT_LT(i, 7);
    seen.insert(i);
  }
  EXPECT_EQ(seen.size(), 7u);
  EXPECT_NEAR(sum / 20000, 0.5, 0.01);
}

// N agents of n coordinates, agent i's coordinate j = value(i, j), every energy 1: a
// population for a strategy to draw trials from.
struct Population {
  template <class Value>
  Population(int agents, int dimension, Value value)
      : N(agents), n(dimension), rows(agents, std::vector<double>(dimension)), energies(agents, 1.0) {
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < n; ++j) rows[i][j] = value(i, j);
    for (auto& r : rows) ptrs.push_back(r.data());
  }
  de::PopulationView view() const { return {N, n, ptrs.data(), energies.data()}; }

  int N, n;
  std::vector<std::vector<double>> rows;
  std::vector<const double*> ptrs;
  std::vector<double> energies;
};

// The paper's operator: with CR = 0 the trial is the parent with exactly one coordinate
// replaced by x_r1 + F (x_r2 - x_r3) for distinct r1, r2, r3 != i.
TEST(DeStrategy, Rand1BinIsThePapersOperator) {
  const int N = 6, n = 5;
  // Square roots of distinct primes are linearly independent over the rationals, so no
  // mutant coordinate can equal the parent's and each (r1, r2, r3) gives its own value.
  const double primes[N] = {2, 3, 5, 7, 11, 13};
  const Population population(N, n, [&](int i, int j) { return std::sqrt(primes[i]) + 100.0 * j; });
  const auto& rows = population.rows;
  const de::PopulationView view = population.view();
  DeSettings s = settings(N, 1);
  s.F = 0.5;
  s.CR = 0.0;
  auto strategy = de::make_strategy(s, N, n);
  std::set<int> used_coordinates;
  for (int trial_no = 0; trial_no < 200; ++trial_no) {
    const int i = trial_no % N;
    DeRandom rng(3, 1, static_cast<uint64_t>(trial_no));
    std::vector<double> trial(n);
    strategy->make_trial(view, i, rng, trial);
    int changed = -1;
    for (int j = 0; j < n; ++j) {
      if (trial[j] != rows[i][j]) {
        ASSERT_EQ(changed, -1) << "more than one coordinate from the mutant with CR = 0";
        changed = j;
      }
    }
    ASSERT_GE(changed, 0);
    used_coordinates.insert(changed);
    // Find the (r1, r2, r3) that produced it: must exist, distinct, none equal to i.
    bool found = false;
    for (int r1 = 0; r1 < N && !found; ++r1)
      for (int r2 = 0; r2 < N && !found; ++r2)
        for (int r3 = 0; r3 < N && !found; ++r3) {
          if (r1 == i || r2 == i || r3 == i || r1 == r2 || r1 == r3 || r2 == r3) continue;
          found = trial[changed] == rows[r1][changed] + 0.5 * (rows[r2][changed] - rows[r3][changed]);
        }
    EXPECT_TRUE(found) << "trial coordinate is not x_r1 + F (x_r2 - x_r3)";
  }
  EXPECT_EQ(used_coordinates.size(), static_cast<size_t>(n));  // j_rand is uniform
}

TEST(DeStrategy, CrossoverRateControlsTheShareOfMutantCoordinates) {
  const int N = 8, n = 2000;
  const Population population(N, n, [](int i, int j) { return i * 1.0 + j * 1e-3; });
  const auto& rows = population.rows;
  const de::PopulationView view = population.view();
  DeSettings s = settings(N, 1);
  s.CR = 0.3;
  auto strategy = de::make_strategy(s, N, n);
  std::vector<double> trial(n);
  DeRandom rng(1, 1, 0);
  strategy->make_trial(view, 0, rng, trial);
  int from_mutant = 0;
  for (int j = 0; j < n; ++j) from_mutant += trial[j] != rows[0][j];
  EXPECT_NEAR(from_mutant / double(n), 0.3, 0.04);
}

TEST(DifferentialEvolution, Rand1BinConvergesOnSphere) {
  ThreadPool pool(1);
  DeSettings s = settings(30, 300);
  const DeResult r = run_differential_evolution(make_problem(8, sphere), s, pool);
  EXPECT_EQ(r.stop_reason, "max_generations");
  EXPECT_EQ(r.generations, 300);
  EXPECT_EQ(r.evaluations, 30 * 301);
  EXPECT_LT(r.best_energy, 1e-6);
  ASSERT_EQ(r.best.size(), 8u);
  EXPECT_DOUBLE_EQ(sphere(r.best), r.best_energy);
  for (double v : r.best) EXPECT_NEAR(v, -0.5, 1e-3);
}

TEST(DifferentialEvolution, ShadeSolvesRastriginBetterThanRand1Bin) {
  ThreadPool pool(1);
  const DeResult shade = run_differential_evolution(make_problem(6, rastrigin), settings(30, 400, "shade"), pool);
  const DeResult rand1 = run_differential_evolution(make_problem(6, rastrigin), settings(30, 400, "rand1bin"), pool);
  EXPECT_LT(shade.best_energy, 1e-6);
  EXPECT_LE(shade.best_energy, rand1.best_energy);
  EXPECT_LT(rand1.best_energy, 6.0);  // rand/1/bin makes real progress too (start: ~60)
}

// Same seed, any number of threads: identical result, bit for bit.
TEST(DifferentialEvolution, ReproducibleWhateverTheThreadCount) {
  for (const std::string strategy : {"rand1bin", "shade"}) {
    std::vector<DeResult> results;
    for (int workers : {0, 1, 3}) {
      ThreadPool pool(workers);
      results.push_back(run_differential_evolution(make_problem(10, rastrigin), settings(12, 60, strategy, 99), pool));
    }
    for (size_t k = 1; k < results.size(); ++k) {
      EXPECT_EQ(results[k].best, results[0].best) << strategy;
      EXPECT_EQ(results[k].best_energy, results[0].best_energy) << strategy;
      EXPECT_EQ(results[k].evaluations, results[0].evaluations) << strategy;
    }
    ThreadPool pool(1);
    const DeResult other = run_differential_evolution(make_problem(10, rastrigin), settings(12, 60, strategy, 100), pool);
    EXPECT_NE(other.best, results[0].best) << "the seed must matter";
  }
}

TEST(DifferentialEvolution, ReportsEveryGenerationWithMonotoneBest) {
  ThreadPool pool(1);
  std::vector<DeGenerationReport> reports;
  int new_best_calls = 0;
  DeHooks hooks;
  hooks.on_generation = [&](const DeGenerationReport& r) { reports.push_back(r); };
  hooks.on_new_best = [&](int index) {
    ++new_best_calls;
    EXPECT_GE(index, 0);
    EXPECT_LT(index, 10);
  };
  const DeResult r = run_differential_evolution(make_problem(4, sphere), settings(10, 25), pool, hooks);
  ASSERT_EQ(reports.size(), 25u);
  int total_improvements = 0;
  for (size_t g = 0; g < reports.size(); ++g) {
    EXPECT_EQ(reports[g].generation, static_cast<int>(g) + 1);
    EXPECT_EQ(reports[g].max_generations, 25);
    EXPECT_EQ(reports[g].evaluations, 10 * static_cast<int64_t>(g + 2));
    EXPECT_GE(reports[g].mean_energy, reports[g].best_energy);
    EXPECT_GE(reports[g].improvements, 0);
    EXPECT_LE(reports[g].improvements, 10);
    total_improvements += reports[g].improvements;
    if (g > 0) {
      EXPECT_LE(reports[g].best_energy, reports[g - 1].best_energy);
    }
  }
  EXPECT_GT(total_improvements, 25);
  EXPECT_EQ(reports.back().best_energy, r.best_energy);
  EXPECT_GE(new_best_calls, 2);
}

TEST(DifferentialEvolution, NewBestHookSeesTheIndexWhoseCandidateWon) {
  // The problem records the last candidate per index; on_new_best must point at one whose
  // energy is the new best.
  ThreadPool pool(2);
  std::vector<double> last_energy(8, 0.0);
  DeProblem problem = make_problem(3, sphere);
  problem.evaluate = [&](int, int index, std::span<const double> x) {
    const double e = sphere(x);
    last_energy[index] = e;
    return e;
  };
  double tracked = std::numeric_limits<double>::infinity();
  DeHooks hooks;
  hooks.on_new_best = [&](int index) {
    EXPECT_LT(last_energy[index], tracked);
    tracked = last_energy[index];
  };
  const DeResult r = run_differential_evolution(problem, settings(8, 40), pool, hooks);
  EXPECT_EQ(tracked, r.best_energy);
}

TEST(DifferentialEvolution, AgentReplacedHookFollowsThePopulation) {
  // Called for every initial agent and every accepted trial, with that index's last
  // candidate: following it, the caller knows the population, whose best is the best.
  ThreadPool pool(2);
  const int N = 8;
  std::vector<double> last_energy(N, 0.0), agent_energy(N, std::numeric_limits<double>::infinity());
  DeProblem problem = make_problem(3, sphere);
  problem.evaluate = [&](int, int index, std::span<const double> x) { return last_energy[index] = sphere(x); };
  int calls = 0, improvements = 0;
  DeHooks hooks;
  hooks.on_agent_replaced = [&](int index) {
    ++calls;
    agent_energy[index] = last_energy[index];
  };
  hooks.on_generation = [&](const DeGenerationReport& report) { improvements += report.improvements; };
  const DeResult r = run_differential_evolution(problem, settings(N, 30), pool, hooks);
  EXPECT_EQ(calls, N + improvements);
  EXPECT_GT(improvements, 30);
  EXPECT_EQ(*std::min_element(agent_energy.begin(), agent_energy.end()), r.best_energy);
}

TEST(DifferentialEvolution, StopsWhenStalled) {
  ThreadPool pool(1);
  DeProblem flat = make_problem(3, sphere);
  flat.evaluate = [](int, int, std::span<const double>) { return 1.0; };
  DeSettings s = settings(6, 100);
  s.stall = 5;
  const DeResult r = run_differential_evolution(flat, s, pool);
  EXPECT_EQ(r.stop_reason, "stalled");
  EXPECT_EQ(r.generations, 5);
  EXPECT_EQ(r.evaluations, 6 * 6);
  EXPECT_EQ(r.best_energy, 1.0);
}

TEST(DifferentialEvolution, StopsWhenThePopulationCollapsed) {
  ThreadPool pool(1);
  DeProblem problem = make_problem(3, sphere);
  problem.initialize = [](int, DeRandom&, std::span<double> x) { std::fill(x.begin(), x.end(), 0.25); };
  for (const std::string strategy : {"rand1bin", "shade"}) {
    const DeResult r = run_differential_evolution(problem, settings(5, 50, strategy), pool);
    EXPECT_EQ(r.stop_reason, "converged") << strategy;
    EXPECT_EQ(r.generations, 1) << strategy;
    EXPECT_DOUBLE_EQ(r.best_energy, 3 * 0.75 * 0.75) << strategy;
  }
}

TEST(DifferentialEvolution, CancellationStopsBetweenEvaluations) {
  ThreadPool pool(1);
  std::atomic<int> calls{0};
  DeProblem problem = make_problem(4, sphere);
  problem.evaluate = [&](int, int, std::span<const double> x) {
    ++calls;
    return sphere(x);
  };
  DeHooks hooks;
  hooks.is_cancelled = [&] { return calls.load() >= 25; };
  const DeResult r = run_differential_evolution(problem, settings(10, 100), pool, hooks);
  EXPECT_EQ(r.stop_reason, "cancelled");
  EXPECT_EQ(r.evaluations, calls.load());
  EXPECT_GE(r.evaluations, 25);
  EXPECT_LE(r.evaluations, 26);  // at most one evaluation per thread already under way
  EXPECT_EQ(r.generations, 1);
  EXPECT_TRUE(std::isfinite(r.best_energy));
  EXPECT_EQ(sphere(r.best), r.best_energy);
}

TEST(DifferentialEvolution, SeedPointIsAnAgentSoTheResultIsNeverWorse) {
  ThreadPool pool(0);  // serial: the evaluation counter below is not thread-safe
  const std::vector<double> seed_point(6, -0.5);  // the optimum
  DeSettings s = settings(10, 5);
  s.seed_point = seed_point;
  std::vector<double> initial_energies(10, -1.0);
  DeProblem problem = make_problem(6, sphere);
  int evaluations = 0;
  problem.evaluate = [&](int, int index, std::span<const double> x) {
    if (evaluations++ < 10) initial_energies[index] = sphere(x);
    return sphere(x);
  };
  const DeResult r = run_differential_evolution(problem, s, pool);
  EXPECT_EQ(r.best_energy, 0.0);
  EXPECT_EQ(r.best, seed_point);
  EXPECT_EQ(initial_energies[0], 0.0);
  // Agents 1..4 are perturbations of growing amplitude (<= 1 per coordinate) ...
  for (int i = 1; i < 5; ++i) {
    EXPECT_GT(initial_energies[i], 0.0);
    EXPECT_LE(initial_energies[i], 6.0);
  }
  EXPECT_LT(initial_energies[1], initial_energies[4]);
  // ... and agents 5..9 are the usual random ones.
  for (int i = 5; i < 10; ++i) EXPECT_GT(initial_energies[i], initial_energies[1]);
}

// The perturbations of the seed point come from DeProblem::perturb when it is given.
TEST(DifferentialEvolution, SeededAgentsUseTheProblemsPerturbation) {
  ThreadPool pool(0);  // serial: the evaluation counter below is not thread-safe
  DeSettings s = settings(8, 1);
  s.seed_point.assign(4, -0.5);
  DeProblem problem = make_problem(4, sphere);
  std::vector<double> amplitudes;
  problem.perturb = [&](DeRandom&, double amplitude, std::span<double> x) {
    amplitudes.push_back(amplitude);
    x[0] += amplitude;
  };
  std::vector<double> initial(8, -1.0);
  int calls = 0;
  problem.evaluate = [&](int, int index, std::span<const double> x) {
    if (calls++ < 8) initial[index] = sphere(x);
    return sphere(x);
  };
  run_differential_evolution(problem, s, pool);
  ASSERT_EQ(amplitudes.size(), 3u);  // agents 1..3 of ceil(0.5 * 8) seeded
  EXPECT_DOUBLE_EQ(amplitudes.front(), 0.02);
  EXPECT_DOUBLE_EQ(amplitudes.back(), 1.0);
  for (int i = 1; i < 4; ++i) EXPECT_NEAR(initial[i], amplitudes[i - 1] * amplitudes[i - 1], 1e-12);
}

// Restart on collapse: a population that agrees on its energy is replaced by a fresh one
// (one generation's evaluations), the best is kept aside and never lost, the run goes on.
TEST(DifferentialEvolution, RestartsACollapsedPopulationKeepingTheBest) {
  for (const std::string strategy : {"rand1bin", "shade"}) {
    std::vector<DeResult> results;
    for (int workers : {0, 2}) {
      ThreadPool pool(workers);
      DeSettings s = settings(8, 200, strategy, 5);
      s.restart = true;
      s.restart_tolerance = 1e-2;
      std::vector<DeGenerationReport> reports;
      DeHooks hooks;
      hooks.on_generation = [&](const DeGenerationReport& r) { reports.push_back(r); };
      const DeResult r = run_differential_evolution(make_problem(5, rastrigin), s, pool, hooks);
      EXPECT_EQ(r.stop_reason, "max_generations") << strategy;
      EXPECT_EQ(r.generations, 200) << strategy;
      EXPECT_EQ(r.evaluations, 8 * 201) << strategy;
      EXPECT_GE(r.restarts, 1) << strategy;
      int restarted = 0;
      for (size_t g = 0; g < reports.size(); ++g) {
        restarted += reports[g].restarted;
        if (g > 0) {
          EXPECT_LE(reports[g].best_energy, reports[g - 1].best_energy);
        }
      }
      EXPECT_EQ(restarted, r.restarts) << strategy;
      ASSERT_EQ(r.best.size(), 5u);
      EXPECT_EQ(rastrigin(r.best), r.best_energy) << strategy;  // also when kept aside
      results.push_back(r);
    }
    EXPECT_EQ(results[1].best, results[0].best) << strategy;
    EXPECT_EQ(results[1].restarts, results[0].restarts) << strategy;
  }
  // Without restart, an identical population stops ("converged"); with it, it goes on.
  ThreadPool pool(1);
  DeProblem problem = make_problem(3, sphere);
  problem.initialize = [](int, DeRandom&, std::span<double> x) { std::fill(x.begin(), x.end(), 0.25); };
  DeSettings s = settings(5, 6, "shade");
  s.restart = true;
  const DeResult r = run_differential_evolution(problem, s, pool);
  EXPECT_EQ(r.stop_reason, "max_generations");
  EXPECT_EQ(r.generations, 6);
  EXPECT_GE(r.restarts, 1);
  EXPECT_DOUBLE_EQ(r.best_energy, 3 * 0.75 * 0.75);
  EXPECT_EQ(r.best, std::vector<double>(3, 0.25));
}

// 10 + sphere: once the population sits near the minimum, its lowest energy improves by
// far less than 5% of 10 per 50 generations. With collapse detection off (tolerance 0),
// the restarts are the stagnation rule's alone: none without a window, and with one
// never sooner than `window` generations after the start or the previous restart.
double lifted_sphere(std::span<const double> x) { return 10.0 + sphere(x); }

TEST(DifferentialEvolution, RestartsAStagnantPopulation) {
  for (int window : {0, 40}) {
    ThreadPool pool(0);
    DeSettings s = settings(8, 200, "shade", 3);
    s.restart = true;
    s.restart_tolerance = 0.0;
    s.restart_window = window;
    std::vector<int> restarted_at;
    DeHooks hooks;
    hooks.on_generation = [&](const DeGenerationReport& r) {
      if (r.restarted) restarted_at.push_back(r.generation);
    };
    const DeResult r = run_differential_evolution(make_problem(10, lifted_sphere), s, pool, hooks);
    EXPECT_EQ(r.restarts, static_cast<int>(restarted_at.size()));
    if (window == 0) {
      EXPECT_EQ(r.restarts, 0);
      continue;
    }
    EXPECT_GE(r.restarts, 2);
    int previous = 0;
    for (int g : restarted_at) {
      EXPECT_GT(g - previous, window) << "restart at generation " << g;
      previous = g;
    }
    EXPECT_LT(r.best_energy, 10.01);  // the best is kept across restarts
  }
}

TEST(DifferentialEvolution, RejectsBadSettingsNamingTheProblem) {
  ThreadPool pool(0);
  const DeProblem problem = make_problem(3, sphere);
  auto message = [&](DeSettings s) -> std::string {
    try {
      run_differential_evolution(problem, s, pool);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
      return e.what();
    }
    return "no error";
  };
  DeSettings s = settings(3, 10);
  EXPECT_NE(message(s).find("population"), std::string::npos);
  s = settings(10, 0);
  EXPECT_NE(message(s).find("generations"), std::string::npos);
  s = settings(10, 10);
  s.F = 0.0;
  EXPECT_NE(message(s).find("F"), std::string::npos);
  s = settings(10, 10);
  s.CR = 1.5;
  EXPECT_NE(message(s).find("CR"), std::string::npos);
  s = settings(10, 10);
  s.stall = -1;
  EXPECT_NE(message(s).find("stall"), std::string::npos);
  s = settings(10, 10);
  s.restart_tolerance = -1.0;
  EXPECT_NE(message(s).find("restart tolerance"), std::string::npos);
  s = settings(10, 10);
  s.restart_window = -1;
  EXPECT_NE(message(s).find("restart window"), std::string::npos);
  s = settings(10, 10);
  s.restart_progress = 1.0;
  EXPECT_NE(message(s).find("restart progress"), std::string::npos);
  s = settings(10, 10, "best2exp");
  const std::string m = message(s);
  EXPECT_NE(m.find("best2exp"), std::string::npos);
  EXPECT_NE(m.find("rand1bin"), std::string::npos);
  EXPECT_NE(m.find("shade"), std::string::npos);
  s = settings(10, 10);
  s.seed_point = {1.0};
  EXPECT_NE(message(s).find("seed point"), std::string::npos);
}

}  // namespace
}  // namespace depath
