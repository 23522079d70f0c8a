// SPDX-License-Identifier: MIT
// ThreadPool: every index once, distinct slots per batch, many callers, exceptions, posted
// tasks (run off the caller, drained at destruction, taking turns with loops).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <stdexcept>
#include <thread>
#include <vector>

#include "depath/util/thread_pool.hpp"

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

TEST(ThreadPool, PostedTasksRunOnWorkersAndDrainAtDestruction) {
  std::atomic<int> ran{0};
  std::atomic<bool> on_caller{false};
  const auto caller = std::this_thread::get_id();
  {
    ThreadPool pool(2);
    for (int i = 0; i < 500; ++i) {
      pool.post([&] {
        if (std::this_thread::get_id() == caller) on_caller = true;
        ++ran;
      });
    }
  }  // the destructor waits for all 500
  EXPECT_EQ(ran.load(), 500);
  EXPECT_FALSE(on_caller.load());
}

TEST(ThreadPool, APostedTaskRunsAtOnceWithoutWorkers) {
  ThreadPool pool(0);
  int ran = 0;
  pool.post([&] { ++ran; });
  EXPECT_EQ(ran, 1);
}

// A task blocked on a worker leaves the other worker to the loops, and a loop's caller
// never waits for tasks: its own batch always makes progress.
TEST(ThreadPool, LoopsGoOnWhileATaskBlocksAWorker) {
  // Declared before the pool, so they outlive the workers that use them.
  std::promise<void> started;
  std::promise<void> release;
  std::promise<void> second;
  std::shared_future<void> released = release.get_future().share();
  ThreadPool pool(2);
  pool.post([&] {
    started.set_value();
    released.wait();
  });
  started.get_future().wait();
  std::atomic<int> sum{0};
  for (int round = 0; round < 20; ++round) pool.parallel_for(50, [&](int, int i) { sum += i; });
  EXPECT_EQ(sum.load(), 20 * (49 * 50 / 2));
  // A task posted now runs on the free worker, not behind the blocked one.
  pool.post([&] { second.set_value(); });
  EXPECT_EQ(second.get_future().wait_for(std::chrono::minutes(5)), std::future_status::ready);
  release.set_value();
}

}  // namespace
}  // namespace depath
