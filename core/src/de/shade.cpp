// SPDX-License-Identifier: MIT
// SHADE (Tanabe & Fukunaga 2013; JADE's current-to-pbest/1 with an archive, plus
// success-history adaptation of F and CR):
//   v = x_i + F_i (x_pbest - x_i) + F_i (x_r1 - x~_r2)
// where x_pbest is one of the best max(2, p_i N) agents (p_i ~ U[2/N, 0.2]), r1 != i is
// an agent and x~_r2 (!= i, r1) is an agent or an archived parent; binomial crossover
// with CR_i. F_i ~ Cauchy(M_F[r], 0.1) (redrawn while <= 0, cut at 1) and
// CR_i ~ N(M_CR[r], 0.1) clipped to [0, 1], with r a random slot of an H-slot memory.
// After selection, the slot k of the memory takes the improvement-weighted Lehmer mean
// of the successful F_i and the weighted mean of the successful CR_i, and k advances.
// Replaced parents enter the archive (capacity N/2 to keep memory near two populations;
// a random entry is overwritten once full).
#include "de/strategy.hpp"

#include "depath/util/error.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace depath::de {
namespace {

constexpr int kMemorySize = 6;     // H, as in L-SHADE
constexpr double kParamSpread = 0.1;
constexpr double kMaxP = 0.2;

class Shade final : public Strategy {
 public:
  Shade(double F, double CR, int population, int dimension)
      : n_(dimension),
        initial_F_(std::min(F, 1.0)),
        initial_CR_(CR),
        memory_F_(kMemorySize, initial_F_),
        memory_CR_(kMemorySize, initial_CR_),
        F_(population),
        CR_(population),
        order_(population),
        archive_capacity_(std::max(1, population / 2)) {
    archive_.reserve(static_cast<size_t>(archive_capacity_) * dimension);
  }

  void begin_generation(const PopulationView& pop, DeRandom&) override {
    std::iota(order_.begin(), order_.end(), 0);
    std::sort(order_.begin(), order_.end(), [&](int a, int b) {
      return pop.energies[a] < pop.energies[b] || (pop.energies[a] == pop.energies[b] && a < b);
    });
  }

  void make_trial(const PopulationView& pop, int i, DeRandom& rng, std::span<double> trial) override {
    const int slot = rng.below(kMemorySize);
    const double CR = std::clamp(rng.normal(memory_CR_[slot], kParamSpread), 0.0, 1.0);
    double F = 0.0;
    for (int tries = 0; F <= 0.0 && tries < 64; ++tries) F = rng.cauchy(memory_F_[slot], kParamSpread);
    if (!(F > 0.0)) F = memory_F_[slot];  // 64 non-positive draws: practically never
    F = std::min(F, 1.0);
    F_[i] = F;
    CR_[i] = CR;

    const int N = pop.size;
    const double p_min = 2.0 / N;
    const double p = p_min + rng.uniform() * std::max(0.0, kMaxP - p_min);
    const int top = std::clamp(static_cast<int>(std::lround(p * N)), 2, N);
    const double* best = pop.agents[order_[rng.below(top)]];

    int r1 = 0;
    const int exclude_i[1] = {i};
    pick_distinct(rng, N, exclude_i, std::span<int>(&r1, 1));
    const int archived = archive_size();
    const int exclude_r2[2] = {i, r1};
    int r2 = 0;
    pick_distinct(rng, N + archived, exclude_r2, std::span<int>(&r2, 1));
    const double* a = pop.agents[r1];
    const double* b = r2 < N ? pop.agents[r2] : archive_.data() + static_cast<size_t>(r2 - N) * n_;
    const double* x = pop.agents[i];
    binomial_crossover(pop.agent(i), CR, rng, trial,
                       [=](int j) { return x[j] + F * (best[j] - x[j]) + F * (a[j] - b[j]); });
  }

  void end_generation(const PopulationView& pop, const SelectionView& sel, DeRandom& rng) override {
    // Success weights: the improvement; an improvement from +inf outweighs any finite one.
    double sum_w = 0.0, sum_wF = 0.0, sum_wF2 = 0.0, sum_wCR = 0.0;
    bool any_infinite = false;
    for (int i = 0; i < pop.size; ++i) {
      if (sel.replaced[i] && !std::isfinite(sel.parent_energies[i] - sel.trial_energies[i])) any_infinite = true;
    }
    for (int i = 0; i < pop.size; ++i) {
      if (!sel.replaced[i]) continue;
      const double delta = sel.parent_energies[i] - sel.trial_energies[i];
      const double w = any_infinite ? (std::isfinite(delta) ? 0.0 : 1.0) : delta;
      sum_w += w;
      sum_wF += w * F_[i];
      sum_wF2 += w * F_[i] * F_[i];
      sum_wCR += w * CR_[i];
      archive(sel.parents[i], rng);
    }
    if (sum_w > 0.0 && sum_wF > 0.0) {
      memory_F_[next_slot_] = sum_wF2 / sum_wF;  // Lehmer mean favours larger steps
      memory_CR_[next_slot_] = sum_wCR / sum_w;
      next_slot_ = (next_slot_ + 1) % kMemorySize;
    }
  }

  bool has_external_diversity() const override { return archive_size() > 0; }

  // Layout: H values of M_F, H of M_CR, the next slot, then the archive's rows.
  void save(std::vector<double>& out) const override {
    out.insert(out.end(), memory_F_.begin(), memory_F_.end());
    out.insert(out.end(), memory_CR_.begin(), memory_CR_.end());
    out.push_back(next_slot_);
    out.insert(out.end(), archive_.begin(), archive_.end());
  }

  void load(std::span<const double> in) override {
    const size_t head = 2 * kMemorySize + 1;
    const size_t rows = in.size() < head ? 0 : (in.size() - head) / n_;
    if (in.size() < head || (in.size() - head) % n_ != 0 || rows > static_cast<size_t>(archive_capacity_) ||
        !(in[2 * kMemorySize] >= 0 && in[2 * kMemorySize] < kMemorySize)) {
      throw Error(ErrorCode::invalid_argument, "checkpoint's shade memory does not fit this run");
    }
    std::copy(in.begin(), in.begin() + kMemorySize, memory_F_.begin());
    std::copy(in.begin() + kMemorySize, in.begin() + 2 * kMemorySize, memory_CR_.begin());
    next_slot_ = static_cast<int>(in[2 * kMemorySize]);
    archive_.assign(in.begin() + head, in.end());
  }

  void restart() override {
    std::fill(memory_F_.begin(), memory_F_.end(), initial_F_);
    std::fill(memory_CR_.begin(), memory_CR_.end(), initial_CR_);
    next_slot_ = 0;
  }

 private:
  int archive_size() const { return static_cast<int>(archive_.size() / n_); }

  void archive(const double* parent, DeRandom& rng) {
    if (archive_size() < archive_capacity_) {
      archive_.insert(archive_.end(), parent, parent + n_);
    } else {
      std::copy(parent, parent + n_, archive_.data() + static_cast<size_t>(rng.below(archive_capacity_)) * n_);
    }
  }

  int n_;
  double initial_F_;
  double initial_CR_;
  std::vector<double> memory_F_;
  std::vector<double> memory_CR_;
  int next_slot_ = 0;
  std::vector<double> F_;   // per agent, this generation
  std::vector<double> CR_;  // per agent, this generation
  std::vector<int> order_;  // agents by energy, best first
  int archive_capacity_;
  std::vector<double> archive_;  // archive_size() x n, row-major
};

}  // namespace

std::unique_ptr<Strategy> make_shade(const DeSettings& settings, int population, int dimension) {
  return std::make_unique<Shade>(settings.F, settings.CR, population, dimension);
}

}  // namespace depath::de
