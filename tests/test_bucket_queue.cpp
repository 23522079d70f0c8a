// SPDX-License-Identifier: MIT
// The fast march's untidy bucket queue: order up to its bucket width, lowered keys (moved,
// never popped twice), keys over many orders of magnitude, the overflow beyond the ring.
#include "depath/decode/bucket_queue.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace depath {
namespace {

constexpr double kWidth = BucketQueue::kRelativeWidth;

// Pops until empty (or 100 pops: a broken list could cycle); returns the vertices in the
// order popped.
std::vector<int32_t> pop_all(BucketQueue& queue) {
  std::vector<int32_t> order;
  for (int32_t v = queue.front(); v >= 0 && order.size() < 100; v = queue.front()) {
    queue.pop(v);
    order.push_back(v);
  }
  return order;
}

// Pops everything, pushing as a fast march would: each pop adds a few keys above it and
// now and then lowers the key of a vertex still waiting.
struct Simulation {
  std::vector<double> popped;
  int lowered = 0;
};

Simulation simulate(uint64_t seed, double low, double high) {
  std::mt19937_64 rng(seed);
  // Log-uniform increments: DE's densities span many orders of magnitude.
  std::uniform_real_distribution<double> exponent(std::log(low), std::log(high));
  std::vector<double> value(20000, INFINITY);
  std::vector<char> done(value.size(), 0);
  BucketQueue queue(value.size());
  Simulation sim;
  int next_vertex = 1;
  value[0] = 0.0;
  queue.push(0, 0.0);
  for (int32_t v = queue.front(); v >= 0; v = queue.front()) {
    queue.pop(v);
    EXPECT_FALSE(done[v]) << "vertex " << v << " popped twice";
    done[v] = 1;
    sim.popped.push_back(value[v]);
    for (int k = 0; k < 3 && next_vertex < static_cast<int>(value.size()); ++k) {
      const int w = next_vertex++;
      value[w] = value[v] + std::exp(exponent(rng));
      queue.push(w, value[w]);
      const int old = w - 1 - static_cast<int>(rng() % 8);
      if (old > 0 && !done[old] && rng() % 2 == 0) {
        value[old] = std::max(value[v], value[old] - 0.5 * (value[old] - value[v]));
        queue.push(old, value[old]);
        ++sim.lowered;
      }
    }
  }
  return sim;
}

TEST(BucketQueue, PopsInKeyOrderUpToTheBucketWidth) {
  // Seeded random instances over narrow and very wide ranges of increments (the widest
  // put keys more than four binades above the front, into the overflow).
  const std::vector<std::pair<double, double>> ranges = {{1.0, 2.0}, {1e-3, 1.0}, {1e-9, 1e3}, {1e-12, 1e12}};
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    for (const auto& [low, high] : ranges) {
      const Simulation sim = simulate(seed, low, high);
      ASSERT_EQ(sim.popped.size(), 20000u) << "every vertex popped once (seed " << seed << ")";
      EXPECT_GT(sim.lowered, 1000) << "the simulation lowers keys";
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

TEST(BucketQueue, MovesAVertexWhoseKeyFallsAndIsReusableAfterClear) {
  BucketQueue queue(3);
  queue.push(0, 3.0);
  queue.push(1, 2.0);
  queue.push(2, 5.0);
  queue.push(2, 2.5);  // lowered: moved, not queued twice
  EXPECT_EQ(pop_all(queue), (std::vector<int32_t>{1, 2, 0}));
  // Cleared with vertices still queued, then used again.
  queue.push(0, 1.0);
  queue.push(2, 4.0);
  queue.clear();
  queue.push(1, 7.0);
  queue.push(2, 6.0);
  EXPECT_EQ(pop_all(queue), (std::vector<int32_t>{2, 1}));
  EXPECT_LT(queue.front(), 0);
}

TEST(BucketQueue, WithinABucketTheLastPushedComesFirst) {
  // Keys 1e-6 relative apart share a bucket: their order is the reverse push order, a
  // moved vertex counting as pushed when moved.
  BucketQueue queue(4);
  for (int v = 0; v < 4; ++v) queue.push(v, 1.0 + 1e-6 * v);
  queue.push(1, 1.0 + 0.5e-6);
  EXPECT_EQ(pop_all(queue), (std::vector<int32_t>{1, 3, 2, 0}));
}

TEST(BucketQueue, KeysFarAboveTheFrontWaitTheirTurn) {
  // Keys 2^40 apart cannot share the ring of buckets: they wait in the overflow.
  BucketQueue queue(4);
  const std::vector<double> value = {1.0, std::ldexp(1.0, 40), 1.5, std::ldexp(1.0, 20)};
  for (int v = 0; v < 4; ++v) queue.push(v, value[v]);
  EXPECT_EQ(pop_all(queue), (std::vector<int32_t>{0, 2, 3, 1}));
}

TEST(BucketQueue, AVertexLoweredOutOfOrWithinTheOverflowComesOutOnceInOrder) {
  // From a front at 1.0 the ring holds keys below 16.0, from 2.0 below 32.0.
  BucketQueue queue(6);
  queue.push(0, 1.0);
  ASSERT_EQ(queue.front(), 0);  // moves the ring to 1.0 (an empty queue's ring starts at 0)
  queue.push(1, 20.0);          // overflow
  queue.push(1, 3.0);           // lowered into the ring: its overflow entry is stale
  queue.push(2, 16.0);          // overflow, taken in with 1 still in the ring
  queue.push(4, 2.0);
  queue.push(3, std::ldexp(1.0, 50));  // overflow
  queue.push(5, std::ldexp(1.0, 40));  // overflow
  queue.push(5, std::ldexp(1.0, 35));  // lowered within the overflow
  EXPECT_EQ(pop_all(queue), (std::vector<int32_t>{0, 4, 1, 2, 5, 3}));
  // Entries left in the overflow by a clear() do not come back.
  queue.push(0, 1.0);
  queue.push(1, 1e9);
  queue.clear();
  queue.push(3, 2.0);
  EXPECT_EQ(pop_all(queue), (std::vector<int32_t>{3}));
}

TEST(BucketQueue, AKeyThatWaitedTakesItsPlaceInItsBucketAsIfPushedIntoTheRing) {
  // Waiting lists are linked in push order when their binade reaches the ring, so within a
  // bucket the last pushed still comes first, whether it waited or not.
  BucketQueue queue(5);
  queue.push(0, 1.0);
  ASSERT_EQ(queue.front(), 0);  // the ring holds binades [1, 16)
  queue.push(1, 100.0);                // waits (binade [64, 128))
  queue.push(2, 100.0 * (1 + 1e-9));  // waits, same bucket as 1
  queue.push(3, 40.0);                 // waits (binade [32, 64))
  queue.pop(0);
  // The ring is empty: it moves to 40's binade and takes in the binades up to 512.
  ASSERT_EQ(queue.front(), 3);
  queue.pop(3);
  queue.push(4, 100.0 * (1 + 2e-9));  // straight into the ring, the same bucket again
  EXPECT_EQ(pop_all(queue), (std::vector<int32_t>{4, 2, 1}));
}

TEST(BucketQueue, ClearVisitsEveryVertexStillQueued) {
  BucketQueue queue(6);
  queue.push(0, 1.0);
  ASSERT_EQ(queue.front(), 0);
  queue.pop(0);
  queue.push(1, 1.5);
  queue.push(2, 1.5);  // same bucket as 1
  queue.push(3, 3.0);
  queue.push(4, std::ldexp(1.0, 30));  // overflow
  std::vector<int32_t> visited;
  queue.clear([&](int32_t v) { visited.push_back(v); });
  std::sort(visited.begin(), visited.end());
  EXPECT_EQ(visited, (std::vector<int32_t>{1, 2, 3, 4}));
  queue.push(5, 2.0);
  EXPECT_EQ(pop_all(queue), (std::vector<int32_t>{5}));
}

}  // namespace
}  // namespace depath
