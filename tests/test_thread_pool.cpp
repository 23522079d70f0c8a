// SPDX-License-Identifier: MIT
// ThreadPool: every index once, distinct slots per batch, many callers, exceptions.
#include "depath/util/thread_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

namespace depath {
namespace {

TEST(ThreadPool, RunsEveryIndexOnceWithSlotsInRange) {
  for (int workers : {0, 1, 3}) {
    ThreadPool pool(workers);
    std::vector<std::atomic<int>> hits(1000);
    std::vector<std::atomic<int>> busy(pool.num_slots());
    std::atomic<bool> slot_shared{false};
    pool.parallel_for(1000, [&](int slot, int i) {
      ASSERT_GE(slot, 0);
      ASSERT_LT(slot, pool.num_slots());
      if (busy[slot].fetch_add(1) != 0) slot_shared = true;
      hits[i].fetch_add(1);
      busy[slot].fetch_sub(1);
    });
    for (const auto& h : hits) EXPECT_EQ(h.load(), 1);
    EXPECT_FALSE(slot_shared) << workers << " workers";
  }
}

TEST(ThreadPool, ConcurrentCallersShareThePool) {
  ThreadPool pool(2);
  std::atomic<long> total{0};
  std::vector<std::thread> callers;
  for (int c = 0; c < 4; ++c) {
    callers.emplace_back([&] {
      for (int round = 0; round < 50; ++round) pool.parallel_for(20, [&](int, int i) { total += i; });
    });
  }
  for (auto& t : callers) t.join();
  EXPECT_EQ(total.load(), 4L * 50 * (19 * 20 / 2));
}

TEST(ThreadPool, RethrowsTheFirstExceptionAfterDraining) {
  ThreadPool pool(2);
  std::atomic<int> ran{0};
  EXPECT_THROW(pool.parallel_for(100,
                                 [&](int, int i) {
                                   ++ran;
                                   if (i == 10) throw std::runtime_error("boom");
                                 }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 100);
  // The pool still works afterwards.
  std::atomic<int> after{0};
  pool.parallel_for(10, [&](int, int) { ++after; });
  EXPECT_EQ(after.load(), 10);
}

}  // namespace
}  // namespace depath
