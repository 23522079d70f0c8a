// SPDX-License-Identifier: MIT
// A differential evolution run's whole state between two generations, as plain data, and its
// byte encoding: what a caller saves to resume a run later (in another process, after a crash)
// with a result bit-identical to an uninterrupted run.
//
// Inputs/outputs: DeState is filled by run_differential_evolution (DeHooks::on_checkpoint) and
// handed back to it to resume. encode_de_state / decode_de_state turn it into bytes and back
// exactly (doubles are copied bit for bit). decode_de_state throws Error(invalid_argument)
// naming the problem for bytes that are not a checkpoint of this format.
// Size: 8 x (N x n + archive x n + N + a few) bytes; nothing is compressed (random
// log-densities do not compress).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace depath {

struct DeState {
  int population = 0;  ///< N
  int dimension = 0;   ///< n
  uint64_t seed = 0;
  std::string strategy;
  int generation = 0;              ///< generations completed; the run resumes with generation + 1
  std::vector<double> agents;      ///< N x n, row-major
  std::vector<double> energies;    ///< N
  double best_energy = 0.0;        ///< lowest energy ever evaluated
  int best_index = -1;             ///< agent holding it, -1 while kept aside (saved_best)
  std::vector<double> saved_best;  ///< the best kept outside the population since a restart
  int64_t evaluations = 0;
  int restarts = 0;
  int since_improvement = 0;
  bool restart_pending = false;
  std::vector<double> lowest_since_restart;
  std::vector<double> strategy_memory;  ///< the strategy's own state (shade: F/CR memory, archive)

  /// The best vector (agents row or saved_best); empty if none.
  std::vector<double> best_vector() const;
};

std::string encode_de_state(const DeState& state);
DeState decode_de_state(std::string_view bytes);

}  // namespace depath
