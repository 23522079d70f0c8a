// SPDX-License-Identifier: MIT
// DE/rand/1/bin, the paper's strategy: v = x_r1 + F (x_r2 - x_r3), r1, r2, r3 distinct and
// != i, then binomial crossover with rate CR against x_i. Fixed F and CR, no state.
#include "de/strategy.hpp"

namespace depath::de {
namespace {

class Rand1Bin final : public Strategy {
 public:
  Rand1Bin(double F, double CR) : F_(F), CR_(CR) {}

  void make_trial(const PopulationView& pop, int i, DeRandom& rng, std::span<double> trial) override {
    int r[3];
    const int exclude[1] = {i};
    pick_distinct(rng, pop.size, exclude, r);
    const double* a = pop.agents[r[0]];
    const double* b = pop.agents[r[1]];
    const double* c = pop.agents[r[2]];
    const double F = F_;
    binomial_crossover(pop.agent(i), CR_, rng, trial, [=](int j) { return a[j] + F * (b[j] - c[j]); });
  }

 private:
  double F_;
  double CR_;
};

}  // namespace

std::unique_ptr<Strategy> make_rand1bin(const DeSettings& settings) {
  return std::make_unique<Rand1Bin>(settings.F, settings.CR);
}

}  // namespace depath::de
