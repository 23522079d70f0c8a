// SPDX-License-Identifier: MIT
// Internal: the pieces a DE strategy is made of (trial generation and its adaptation).
//
// A strategy turns the current population into one trial per agent. The optimizer
// (differential_evolution.cpp) owns the population, evaluation, selection and stopping;
// a strategy only decides how trials are built and may adapt its parameters from which
// trials succeeded. Each strategy lives in its own file; make_de_strategy picks by name.
#pragma once

#include "depath/de/differential_evolution.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

namespace depath::de {

/// Read-only view of the population of the current generation.
struct PopulationView {
  int size = 0;                      ///< N
  int dimension = 0;                 ///< n
  const double* const* agents = nullptr;  ///< agents[i]: n values
  const double* energies = nullptr;       ///< energies[i] (+inf for failed decodes)
  std::span<const double> agent(int i) const { return {agents[i], static_cast<size_t>(dimension)}; }
};

/// Outcome of a generation's selection, for adaptive strategies.
struct SelectionView {
  const unsigned char* replaced = nullptr;  ///< replaced[i]: trial i replaced agent i
  const double* const* parents = nullptr;   ///< parents[i]: the agent i before selection (valid if replaced)
  const double* parent_energies = nullptr;  ///< energy of agent i before selection
  const double* trial_energies = nullptr;   ///< energy of trial i
};

class Strategy {
 public:
  virtual ~Strategy() = default;

  /// Serial, once per generation before its trials (e.g. rank the agents). `rng` is the
  /// generation's own stream.
  virtual void begin_generation(const PopulationView& pop, DeRandom& rng) {}

  /// Writes agent i's trial. Called concurrently for different i: may write only state
  /// that belongs to agent i. `rng` is the (generation, i) stream.
  virtual void make_trial(const PopulationView& pop, int i, DeRandom& rng, std::span<double> trial) = 0;

  /// Serial, after selection (the population view already shows the new agents).
  virtual void end_generation(const PopulationView& pop, const SelectionView& sel, DeRandom& rng) {}

  /// True if trials can draw on vectors outside the population (e.g. an archive), so a
  /// population whose agents are all identical may still move.
  virtual bool has_external_diversity() const { return false; }

  /// Serial, when the optimizer restarts a collapsed population (DeSettings::restart):
  /// forget what the adaptation learnt about the old basin.
  virtual void restart() {}

  /// The state that carries from one generation to the next (checkpoints), appended to
  /// `out`; load() restores it (throws Error(invalid_argument) if it does not fit).
  virtual void save(std::vector<double>& out) const {}
  virtual void load(std::span<const double> in);
};

/// Builds the strategy named settings.strategy. Throws Error(invalid_argument) naming the
/// valid strategies for an unknown name.
/// Throws Error(invalid_argument) naming `name` and the valid strategies unless it is one.
void check_strategy_name(const std::string& name);

std::unique_ptr<Strategy> make_strategy(const DeSettings& settings, int population, int dimension);

/// Draws k distinct indices in [0, n) that differ from every index in `exclude`
/// (rejection sampling; n must exceed k + exclude.size() - overlaps).
void pick_distinct(DeRandom& rng, int n, std::span<const int> exclude, std::span<int> out);

/// Binomial crossover: trial[j] = mutant(j) with probability CR, else parent[j]; coordinate
/// j_rand (uniform) always comes from the mutant, so the trial differs from the parent.
/// Each 64-bit draw decides two coordinates (32-bit uniforms against CR * 2^32), which
/// halves the random-number cost of the one loop that runs over every vertex.
template <class Mutant>
void binomial_crossover(std::span<const double> parent, double CR, DeRandom& rng, std::span<double> trial,
                        Mutant&& mutant) {
  const int n = static_cast<int>(parent.size());
  const int j_rand = rng.below(n);
  const uint64_t threshold = static_cast<uint64_t>(CR * 4294967296.0);  // CR = 1: 2^32, always taken
  uint64_t bits = 0;
  for (int j = 0; j < n; ++j) {
    if ((j & 1) == 0) bits = rng.next();
    const uint64_t u = (j & 1) ? (bits >> 32) : (bits & 0xFFFFFFFFu);
    trial[j] = (j == j_rand || u < threshold) ? mutant(j) : parent[j];
  }
}

}  // namespace depath::de
