// SPDX-License-Identifier: MIT
// Differential evolution driver: population, parallel evaluation, greedy selection, stop
// rules. Trial generation and parameter adaptation live in the strategies (src/de/).
#include "depath/de/differential_evolution.hpp"

#include "de/strategy.hpp"
#include "depath/util/error.hpp"
#include "depath/util/thread_pool.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace depath {

// ---------------------------------------------------------------------------------------
// DeRandom

namespace {

uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

}  // namespace

DeRandom::DeRandom(uint64_t seed, uint64_t a, uint64_t b) {
  // Hash the three keys into one state, then expand it; different (seed, a, b) give
  // unrelated streams.
  uint64_t key = seed;
  uint64_t h = splitmix64(key);
  key = h ^ (a * 0xD1B54A32D192ED03ull);
  h = splitmix64(key);
  key = h ^ (b * 0xAEF17502108EF2D9ull);
  for (auto& s : s_) s = splitmix64(key);
}

uint64_t DeRandom::next() {
  const uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

double DeRandom::uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

double DeRandom::uniform_open_closed() { return static_cast<double>((next() >> 11) + 1) * 0x1.0p-53; }

int DeRandom::below(int n) {
  // Lemire's multiply-shift on the top 32 bits: bias below n / 2^32, negligible here.
  return static_cast<int>(((next() >> 32) * static_cast<uint64_t>(n)) >> 32);
}

double DeRandom::normal(double mean, double sigma) {
  const double u1 = uniform_open_closed();
  const double u2 = uniform();
  return mean + sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

double DeRandom::cauchy(double location, double scale) {
  return location + scale * std::tan(std::numbers::pi * (uniform_open_closed() - 0.5));
}

// ---------------------------------------------------------------------------------------
// Settings

void validate_de_parameters(int population, int generations, int stall, double F, double CR,
                            const std::string& strategy) {
  auto fail = [](const std::string& message) { throw Error(ErrorCode::invalid_argument, message); };
  if (population < 4)
    fail("population must be at least 4 (DE needs 3 other agents), got " + std::to_string(population));
  if (generations < 1) fail("generations must be at least 1, got " + std::to_string(generations));
  if (stall < 0) fail("stall must be >= 0 (0 = never stop early), got " + std::to_string(stall));
  if (!std::isfinite(F) || F <= 0.0 || F > 2.0) fail("F must be in (0, 2], got " + std::to_string(F));
  if (!std::isfinite(CR) || CR < 0.0 || CR > 1.0) fail("CR must be in [0, 1], got " + std::to_string(CR));
  de::check_strategy_name(strategy);
}

void validate_de_settings(const DeSettings& s, int dimension) {
  auto fail = [](const std::string& message) { throw Error(ErrorCode::invalid_argument, message); };
  auto str = [](double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  if (dimension < 1) fail("DE problem dimension must be >= 1 (got " + std::to_string(dimension) + ")");
  validate_de_parameters(s.population, s.generations, s.stall, s.F, s.CR, s.strategy);
  if (!s.seed_point.empty() && static_cast<int>(s.seed_point.size()) != dimension) {
    fail("DE seed point has " + std::to_string(s.seed_point.size()) + " values, expected " +
         std::to_string(dimension));
  }
  if (!(s.seed_fraction >= 0.0 && s.seed_fraction <= 1.0)) fail("DE seed fraction must be in [0, 1]");
  if (!(s.restart_tolerance >= 0.0 && s.restart_tolerance < 1.0)) {
    fail("DE restart tolerance must be in [0, 1) (got " + str(s.restart_tolerance) + ")");
  }
  if (s.restart_window < 0) fail("DE restart window must be >= 0 (got " + std::to_string(s.restart_window) + ")");
  if (!(s.restart_progress >= 0.0 && s.restart_progress < 1.0)) {
    fail("DE restart progress must be in [0, 1) (got " + str(s.restart_progress) + ")");
  }
}

// ---------------------------------------------------------------------------------------
// The optimizer

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Stream ids for the serial steps of a generation (agent streams use 0..N-1).
constexpr uint64_t kBeginStream = ~uint64_t{0} - 1;
constexpr uint64_t kEndStream = ~uint64_t{0};

// Seeded agents: agent 0 is the seed point; agents 1..m-1 add uniform noise whose
// amplitude grows geometrically from kMinAmplitude to kMaxAmplitude, so DE starts with
// both near copies (fine moves) and bolder variants (room to explore) of the seed.
constexpr double kMinAmplitude = 0.02;
constexpr double kMaxAmplitude = 1.0;

void perturb(const DeProblem& problem, DeRandom& rng, double amplitude, std::span<double> x) {
  if (problem.perturb) {
    problem.perturb(rng, amplitude, x);
    return;
  }
  for (double& v : x) v += amplitude * (2.0 * rng.uniform() - 1.0);
}

void initialize_agent(const DeProblem& problem, const DeSettings& s, int seeded, int i, DeRandom& rng,
                      std::span<double> x) {
  if (i < seeded) {
    std::copy(s.seed_point.begin(), s.seed_point.end(), x.begin());
    if (i == 0) return;
    const double ratio = seeded > 2 ? static_cast<double>(i - 1) / (seeded - 2) : 0.0;
    const double amplitude = kMinAmplitude * std::pow(kMaxAmplitude / kMinAmplitude, ratio);
    perturb(problem, rng, amplitude, x);
    return;
  }
  if (problem.initialize) {
    problem.initialize(i, rng, x);
    return;
  }
  for (double& v : x) v = std::log(rng.uniform_open_closed());  // log of a (0, 1] density
}

bool population_collapsed(const std::vector<double*>& agents, int n) {
  for (size_t i = 1; i < agents.size(); ++i) {
    if (!std::equal(agents[i], agents[i] + n, agents[0])) return false;
  }
  return true;
}

}  // namespace

DeResult run_differential_evolution(const DeProblem& problem, const DeSettings& s, ThreadPool& pool,
                                    const DeHooks& hooks, const DeState* resume) {
  validate_de_settings(s, problem.dimension);
  if (!problem.evaluate) throw Error(ErrorCode::invalid_argument, "DE problem has no evaluate function");
  const int N = s.population;
  const int n = problem.dimension;
  const auto strategy = de::make_strategy(s, N, n);
  const int seeded =
      s.seed_point.empty() ? 0 : std::clamp(static_cast<int>(std::ceil(s.seed_fraction * N)), 1, N);

  // Two populations' worth of storage; agents and trials are row pointers into it, so
  // selection swaps pointers instead of copying rows.
  std::vector<double> storage(static_cast<size_t>(2) * N * n);
  std::vector<double*> agents(N), trials(N);
  for (int i = 0; i < N; ++i) {
    agents[i] = storage.data() + static_cast<size_t>(i) * n;
    trials[i] = storage.data() + static_cast<size_t>(N + i) * n;
  }
  std::vector<double> energies(N, kInf), trial_energies(N, kInf), parent_energies(N, kInf);
  std::vector<unsigned char> evaluated(N, 0), trial_done(N, 0), replaced(N, 0);

  std::atomic<bool> cancelled{false};
  auto check_cancel = [&] {
    if (cancelled.load(std::memory_order_relaxed)) return true;
    if (hooks.is_cancelled && hooks.is_cancelled()) {
      cancelled.store(true, std::memory_order_relaxed);
      return true;
    }
    return false;
  };
  auto evaluate = [&](int slot, int i, const double* x) {
    const double e = problem.evaluate(slot, i, std::span<const double>(x, static_cast<size_t>(n)));
    return std::isnan(e) ? kInf : e;
  };

  DeResult result;
  result.best_energy = kInf;
  int best = -1;

  const de::PopulationView view{N, n, agents.data(), energies.data()};
  result.stop_reason = "max_generations";
  int since_improvement = 0;
  bool restart_pending = false;
  std::vector<double> saved_best;  // the best, while a restart keeps it out of the population
  std::vector<double> lowest_since_restart;  // the population's lowest energy, per generation
  int first_generation = 1;
  // The state between generations g - 1 and g (de/checkpoint.hpp).
  auto capture = [&](int completed) {
    DeState st;
    st.population = N;
    st.dimension = n;
    st.seed = s.seed;
    st.strategy = s.strategy;
    st.generation = completed;
    st.agents.resize(static_cast<size_t>(N) * n);
    for (int i = 0; i < N; ++i) std::copy(agents[i], agents[i] + n, st.agents.begin() + static_cast<std::ptrdiff_t>(i) * n);
    st.energies = energies;
    st.best_energy = result.best_energy;
    st.best_index = best;
    st.saved_best = saved_best;
    st.evaluations = result.evaluations;
    st.restarts = result.restarts;
    st.since_improvement = since_improvement;
    st.restart_pending = restart_pending;
    st.lowest_since_restart = lowest_since_restart;
    strategy->save(st.strategy_memory);
    return st;
  };
  if (resume) {
    const DeState& st = *resume;
    if (st.population != N || st.dimension != n || st.seed != s.seed || st.strategy != s.strategy ||
        st.generation > s.generations) {
      throw Error(ErrorCode::invalid_argument, "DE checkpoint does not belong to this run (population, dimension, "
                                               "seed, strategy or generations differ)");
    }
    for (int i = 0; i < N; ++i) {
      std::copy_n(st.agents.begin() + static_cast<std::ptrdiff_t>(i) * n, n, agents[i]);
    }
    energies = st.energies;
    result.best_energy = st.best_energy;
    best = st.best_index;
    saved_best = st.saved_best;
    result.evaluations = st.evaluations;
    result.restarts = st.restarts;
    result.generations = st.generation;
    since_improvement = st.since_improvement;
    restart_pending = st.restart_pending;
    lowest_since_restart = st.lowest_since_restart;
    strategy->load(st.strategy_memory);
    first_generation = st.generation + 1;
  } else {
    // Initial population. Recorded energies (generation 0) stand in for all but the first
    // lowest, which becomes the best (on_new_best).
    const bool replay = hooks.recorded_energy && !hooks.on_agent_replaced;
    std::vector<double> recorded(N, kInf);
    std::vector<unsigned char> known(N, 0);
    int first_lowest = -1;
    if (replay) {
      for (int i = 0; i < N; ++i) {
        known[i] = hooks.recorded_energy(0, i, recorded[i]);
        if (!known[i]) continue;
        if (std::isnan(recorded[i])) recorded[i] = kInf;
        if (first_lowest < 0 || recorded[i] < recorded[first_lowest]) first_lowest = i;
      }
    }
    pool.parallel_for(N, [&](int slot, int i) {
      if (check_cancel()) return;
      DeRandom rng(s.seed, 0, static_cast<uint64_t>(i));
      initialize_agent(problem, s, seeded, i, rng, std::span<double>(agents[i], static_cast<size_t>(n)));
      energies[i] = known[i] && i != first_lowest ? recorded[i] : evaluate(slot, i, agents[i]);
      evaluated[i] = 1;
    });
    if (hooks.on_trials &&
        std::all_of(evaluated.begin(), evaluated.end(), [](unsigned char d) { return d != 0; })) {
      hooks.on_trials(0, energies);
    }
    for (int i = 0; i < N; ++i) {
      if (!evaluated[i]) continue;
      ++result.evaluations;
      if (hooks.on_agent_replaced) hooks.on_agent_replaced(i);
      if (energies[i] < result.best_energy) {
        result.best_energy = energies[i];
        best = i;
      }
    }
    if (best >= 0 && hooks.on_new_best) hooks.on_new_best(best);
  }

  for (int g = first_generation; g <= s.generations; ++g) {
    const bool suspend = hooks.suspend && hooks.suspend();
    if (hooks.on_checkpoint && (suspend || (hooks.checkpoint_due && hooks.checkpoint_due()))) {
      hooks.on_checkpoint(capture(g - 1));
    }
    if (suspend) {
      result.stop_reason = "suspended";
      break;
    }
    if (check_cancel()) {
      result.stop_reason = "cancelled";
      break;
    }
    DeRandom begin_rng(s.seed, static_cast<uint64_t>(g), kBeginStream);
    const bool restarting = restart_pending;
    restart_pending = false;
    if (restarting) {
      strategy->restart();
      ++result.restarts;
      // The best leaves the population: kept in it, it would pull every new agent back
      // into its basin within a few generations (measured: restarts around the best
      // escape far less often than fresh ones).
      if (best >= 0) {
        saved_best.assign(agents[best], agents[best] + n);
        best = -1;
      }
    }
    strategy->begin_generation(view, begin_rng);

    std::fill(trial_done.begin(), trial_done.end(), 0);
    // Recorded energies stand in for evaluations that cannot change what the caller keeps.
    const bool replay = hooks.recorded_energy && !hooks.on_agent_replaced;
    const double best_before = result.best_energy;
    pool.parallel_for(N, [&](int slot, int i) {
      if (check_cancel()) return;
      DeRandom rng(s.seed, static_cast<uint64_t>(g), static_cast<uint64_t>(i));
      const std::span<double> trial(trials[i], static_cast<size_t>(n));
      if (restarting) {
        initialize_agent(problem, s, seeded, i, rng, trial);  // as in generation 0, new streams
      } else {
        strategy->make_trial(view, i, rng, trial);
      }
      double recorded = 0.0;
      if (replay && hooks.recorded_energy(g, i, recorded) && !(recorded < best_before)) {
        trial_energies[i] = std::isnan(recorded) ? kInf : recorded;
      } else {
        trial_energies[i] = evaluate(slot, i, trials[i]);
      }
      trial_done[i] = 1;
    });
    if (hooks.on_trials &&
        std::all_of(trial_done.begin(), trial_done.end(), [](unsigned char d) { return d != 0; })) {
      hooks.on_trials(g, trial_energies);
    }

    // Greedy selection, in index order so that ties resolve the same way every run.
    int improvements = 0;
    bool complete = true;
    bool improved = false;
    for (int i = 0; i < N; ++i) {
      parent_energies[i] = energies[i];
      // A restart's new agents replace the old ones whatever their energy; they are no
      // success of the strategy, so it sees them as not replaced.
      const bool forced = restarting && trial_done[i];
      replaced[i] = trial_done[i] && trial_energies[i] < energies[i] && !forced;
      complete = complete && trial_done[i];
      result.evaluations += trial_done[i];
      if (!replaced[i] && !forced) continue;
      std::swap(agents[i], trials[i]);  // trials[i] now holds the parent (for the archive)
      energies[i] = trial_energies[i];
      if (hooks.on_agent_replaced) hooks.on_agent_replaced(i);
      if (!forced || energies[i] < parent_energies[i]) ++improvements;
      if (energies[i] < result.best_energy) {
        result.best_energy = energies[i];
        best = i;
        improved = true;
      }
    }
    if (improved && hooks.on_new_best) hooks.on_new_best(best);
    if (!complete) {  // cancelled inside the generation: keep what was found, stop
      result.stop_reason = "cancelled";
      break;
    }
    DeRandom end_rng(s.seed, static_cast<uint64_t>(g), kEndStream);
    const de::SelectionView selection{replaced.data(), trials.data(), parent_energies.data(), trial_energies.data()};
    strategy->end_generation(view, selection, end_rng);
    result.generations = g;

    double sum = 0.0;
    int finite = 0;
    double lowest = kInf, highest = -kInf;
    for (double e : energies) {
      lowest = std::min(lowest, e);
      highest = std::max(highest, e);
      if (std::isfinite(e)) {
        sum += e;
        ++finite;
      }
    }
    if (hooks.on_generation) {
      DeGenerationReport report;
      report.generation = g;
      report.max_generations = s.generations;
      report.best_energy = result.best_energy;
      report.mean_energy = finite > 0 ? sum / finite : kInf;
      report.evaluations = result.evaluations;
      report.improvements = improvements;
      report.best_index = best;
      report.restarted = restarting;
      hooks.on_generation(report);
    }

    since_improvement = improved ? 0 : since_improvement + 1;
    if (s.stall > 0 && since_improvement >= s.stall) {
      result.stop_reason = "stalled";
      break;
    }
    if (s.restart) {
      // Energies agree to a relative tolerance: the agents sit in one basin (for DE-Path
      // usually on one decoded path) and will not leave it. Or the population's best has
      // crept by less than restart_progress over restart_window generations: it is sliding
      // down a basin too slowly to matter (measured on the rotation-field experiment: such
      // runs end 2-10x above the arc). Restart next generation unless this was the last.
      if (restarting) lowest_since_restart.clear();
      lowest_since_restart.push_back(lowest);
      const bool collapsed = std::isfinite(highest) && highest - lowest <= s.restart_tolerance * std::abs(lowest);
      const size_t window = static_cast<size_t>(s.restart_window);
      const bool stagnant = window > 0 && lowest_since_restart.size() > window && std::isfinite(lowest) &&
                            lowest_since_restart[lowest_since_restart.size() - 1 - window] - lowest <=
                                s.restart_progress * std::abs(lowest);
      restart_pending = g < s.generations && (collapsed || stagnant);
      continue;
    }
    // Every agent identical and nothing else to draw on: no difference vector is left,
    // no trial can differ from its parent any more.
    if (lowest == highest && !strategy->has_external_diversity() && population_collapsed(agents, n)) {
      result.stop_reason = "converged";
      break;
    }
  }

  if (best >= 0) {
    result.best.assign(agents[best], agents[best] + n);
  } else if (!saved_best.empty()) {
    result.best = std::move(saved_best);
  }
  return result;
}

}  // namespace depath
