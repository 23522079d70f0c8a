// SPDX-License-Identifier: MIT
// The fast march's untidy bucket queue: order up to its bucket width, stale entries,
// keys over many orders of magnitude.
#include "depath/decode/bucket_queue.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace depath {
namespace {

// A bucket spans keys with the same top 12 mantissa bits: at most 2^-12 relative apart.
constexpr double kWidth = 1.0 / 4096;

// Pops everything, pushing as a fast march would: each pop adds a few keys above it.
struct Simulation {
  std::vector<double> popped;
  std::vector<double> pushed;
};

Simulation simulate(uint64_t seed, double low, double high) {
  std::mt19937_64 rng(seed);
  // Log-uniform increments: DE's densities span many orders of magnitude.
  std::uniform_real_distribution<double> exponent(std::log(low), std::log(high));
  std::vector<double> value(20000, INFINITY);
  std::vector<char> done(value.size(), 0);
  BucketQueue queue(value.size() * 8);
  Simulation sim;
  int next_vertex = 1;
  value[0] = 0.0;
  queue.push(0, 0.0);
  auto live = [&](int32_t v) { return !done[v]; };
  for (int32_t e = queue.front(live); e >= 0; e = queue.front(live)) {
    const int32_t v = queue.pop(e);
    EXPECT_FALSE(done[v]) << "vertex " << v << " popped twice";
    done[v] = 1;
    sim.popped.push_back(value[v]);
    for (int k = 0; k < 3 && next_vertex < static_cast<int>(value.size()); ++k) {
      const int w = next_vertex++;
      value[w] = value[v] + std::exp(exponent(rng));
      queue.push(w, value[w]);
      sim.pushed.push_back(value[w]);
      // Now and then lower a value still waiting (a decrease-key done as a second push).
      const int old = w - 1 - static_cast<int>(rng() % 8);
      if (old > 0 && !done[old] && rng() % 2 == 0) {
        value[old] = std::max(value[v], value[old] - 0.5 * (value[old] - value[v]));
        queue.push(old, value[old]);
      }
    }
  }
  return sim;
}

TEST(BucketQueue, PopsInKeyOrderUpToTheBucketWidth) {
  // Seeded random instances over narrow and very wide ranges of increments.
  const std::vector<std::pair<double, double>> ranges = {{1.0, 2.0}, {1e-3, 1.0}, {1e-9, 1e3}, {1e-12, 1e12}};
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    for (const auto& [low, high] : ranges) {
      const Simulation sim = simulate(seed, low, high);
      ASSERT_EQ(sim.popped.size(), 20000u) << "every vertex popped once (seed " << seed << ")";
      double highest = 0.0, worst = 0.0;
      int inversions = 0;
      for (const double key : sim.popped) {
        // Never below an earlier pop by more than the bucket width.
        EXPECT_GE(key, highest * (1.0 - kWidth)) << "seed " << seed << ", range " << low << ".." << high;
        inversions += key < highest;
        if (highest > 0.0) worst = std::max(worst, (highest - key) / highest);
        highest = std::max(highest, key);
      }
      if (seed == 1)
        std::printf("  increments %g..%g: %d of 20000 pops below an earlier one, by at most %.2e relative\n",
                    low, high, inversions, worst);
    }
  }
}

TEST(BucketQueue, DropsStaleEntriesAndIsEmptyAfterwards) {
  BucketQueue queue(16);
  std::vector<double> value = {3.0, 2.0, 5.0};
  std::vector<char> done(3, 0);
  auto live = [&](int32_t v) { return !done[v]; };
  queue.push(0, 3.0);
  queue.push(1, 2.0);
  queue.push(2, 5.0);
  value[2] = 2.5;  // lowered: its first entry is stale now
  queue.push(2, 2.5);
  std::vector<int32_t> order;
  for (int32_t e = queue.front(live); e >= 0; e = queue.front(live)) {
    const int32_t v = queue.pop(e);
    done[v] = 1;
    order.push_back(v);
  }
  EXPECT_EQ(order, (std::vector<int32_t>{1, 2, 0}));
  // Reusable after clear().
  queue.clear();
  std::fill(done.begin(), done.end(), 0);
  queue.push(1, 7.0);
  value[1] = 7.0;
  const int32_t e = queue.front(live);
  ASSERT_GE(e, 0);
  EXPECT_EQ(queue.pop(e), 1);
  done[1] = 1;
  EXPECT_LT(queue.front(live), 0);
}

TEST(BucketQueue, KeysFarAboveTheFrontWaitTheirTurn) {
  // Keys 2^40 apart cannot share the ring of buckets: they wait in the overflow.
  BucketQueue queue(8);
  std::vector<double> value = {1.0, std::ldexp(1.0, 40), 1.5, std::ldexp(1.0, 20)};
  std::vector<char> done(4, 0);
  auto live = [&](int32_t v) { return !done[v]; };
  for (int v = 0; v < 4; ++v) queue.push(v, value[v]);
  std::vector<double> popped;
  for (int32_t e = queue.front(live); e >= 0; e = queue.front(live)) {
    const int32_t v = queue.pop(e);
    done[v] = 1;
    popped.push_back(value[v]);
  }
  EXPECT_EQ(popped, (std::vector<double>{1.0, 1.5, std::ldexp(1.0, 20), std::ldexp(1.0, 40)}));
}

}  // namespace
}  // namespace depath
