// SPDX-License-Identifier: MIT
#include "depath/util/thread_pool.hpp"

#include <algorithm>
#include <atomic>
#include <exception>

namespace depath {

// One parallel_for call, or one posted task. Indices are claimed under the pool mutex; a
// loop's batch lives on the caller's stack until every claimed index has finished.
struct ThreadPool::Batch {
  int n = 0;
  int next = 0;      // next unclaimed index
  int finished = 0;  // indices done
  int busy_workers = 0;
  const std::function<void(int, int)>* fn = nullptr;
  std::exception_ptr error;
  std::condition_variable done;
  bool is_task = false;  // a Task: nobody waits on `done`
};

// A posted task: a batch of one index that owns its body, owned by the pool and deleted by
// the worker that ran it.
struct ThreadPool::Task final : Batch {
  explicit Task(std::function<void()> task) : body([task = std::move(task)](int, int) { task(); }) {
    n = 1;
    fn = &body;
    is_task = true;
  }
  std::function<void(int, int)> body;
};

ThreadPool::ThreadPool(int workers) {
  threads_.reserve(std::max(0, workers));
  for (int i = 0; i < workers; ++i) threads_.emplace_back([this, i] { worker_loop(i); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  for (auto& t : threads_) t.join();
}

// Runs one index of `batch` (mutex held on entry and exit). Returns false if none is left.
bool ThreadPool::run_one(Batch& batch, int slot) {
  if (batch.next >= batch.n) return false;
  const int index = batch.next++;
  if (batch.next >= batch.n) {
    // Fully claimed: take it out of the rotation.
    auto it = std::find(active_.begin(), active_.end(), &batch);
    if (it != active_.end()) active_.erase(it);
  }
  mutex_.unlock();
  std::exception_ptr error;
  try {
    (*batch.fn)(slot, index);
  } catch (...) {
    error = std::current_exception();
  }
  mutex_.lock();
  if (error && !batch.error) batch.error = error;
  ++batch.finished;
  return true;
}

void ThreadPool::worker_loop(int slot) {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stopping_ || !active_.empty(); });
    if (stopping_ && active_.empty()) return;
    // Round-robin: take one index from the front batch, then move it to the back.
    Batch* batch = active_.front();
    active_.pop_front();
    if (batch->next < batch->n - 1) active_.push_back(batch);
    ++batch->busy_workers;
    // run_one would erase the batch from active_ when it claims the last index; it is
    // already out of the rotation or at the back, which find() handles.
    run_one(*batch, slot);
    --batch->busy_workers;
    if (batch->finished < batch->n || batch->busy_workers > 0) continue;
    if (!batch->is_task) {
      batch->done.notify_all();
      continue;
    }
    // A posted task has no caller to rethrow to; the task's captures die outside the lock.
    lock.unlock();
    if (batch->error) std::rethrow_exception(batch->error);  // ends the program, see post()
    delete static_cast<Task*>(batch);
    lock.lock();
  }
}

void ThreadPool::post(std::function<void()> task) {
  if (threads_.empty()) {
    task();
    return;
  }
  auto* batch = new Task(std::move(task));
  {
    std::lock_guard lock(mutex_);
    active_.push_back(batch);
  }
  wake_.notify_one();
}

void ThreadPool::parallel_for(int n, const std::function<void(int slot, int index)>& fn) {
  if (n <= 0) return;
  const int caller_slot = num_threads();
  if (threads_.empty()) {
    for (int i = 0; i < n; ++i) fn(caller_slot, i);
    return;
  }
  Batch batch;
  batch.n = n;
  batch.fn = &fn;
  std::unique_lock lock(mutex_);
  active_.push_back(&batch);
  wake_.notify_all();
  while (run_one(batch, caller_slot)) {
  }
  batch.done.wait(lock, [&] { return batch.finished == batch.n && batch.busy_workers == 0; });
  lock.unlock();
  if (batch.error) std::rethrow_exception(batch.error);
}

}  // namespace depath
