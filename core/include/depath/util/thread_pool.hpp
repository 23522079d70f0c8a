// SPDX-License-Identifier: MIT
// A fixed pool of worker threads that runs index-parallel loops for many callers at once,
// and detached tasks (the server's queue for blocking work is such a pool).
//
// Inputs: a loop size and a function of (slot, index), or a task. Outputs: none; a loop's
// exceptions are rethrown to its caller. Guarantees: fair between concurrent callers and
// tasks, no deadlock with 0 workers, per-slot scratch space needs no locking, tasks posted
// before destruction run before the workers exit (see ThreadPool).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace depath {

/// Runs `parallel_for` batches on `num_threads()` workers plus the calling thread.
///
/// Several threads (e.g. several server jobs) may call parallel_for concurrently; the
/// workers take indices from the active batches in round-robin, so concurrent jobs share
/// the pool fairly. The caller always works on its own batch, so a pool of 0 workers is
/// a plain serial loop and a caller never deadlocks waiting for busy workers.
class ThreadPool {
 public:
  /// `workers` >= 0 threads in addition to the callers.
  explicit ThreadPool(int workers);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int num_threads() const { return static_cast<int>(threads_.size()); }
  /// Number of distinct slot values fn may see: num_threads() + 1.
  int num_slots() const { return num_threads() + 1; }

  /// Calls fn(slot, i) for every i in [0, n) and returns when all calls finished.
  /// `slot` is in [0, num_slots()): worker k uses slot k, the calling thread uses
  /// num_threads(); two calls running at the same time within one batch never share a
  /// slot, so per-slot scratch space needs no locking. The first exception thrown by fn
  /// is rethrown here after the batch drained.
  void parallel_for(int n, const std::function<void(int slot, int index)>& fn);

  /// Runs `task` once on a worker and returns at once; with 0 workers it runs here, now.
  /// Tasks take their turn with the loops' indices (one rotation for both). Every task
  /// posted before the destructor starts runs before it returns. A task must not throw:
  /// as with an exception leaving a std::thread, that ends the program.
  void post(std::function<void()> task);

 private:
  struct Batch;
  struct Task;
  void worker_loop(int slot);
  bool run_one(Batch& batch, int slot);

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Batch*> active_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace depath
