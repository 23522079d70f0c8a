// SPDX-License-Identifier: MIT
#include "event_log.hpp"

#include "depath/wire/wire.hpp"

#include <algorithm>
#include <chrono>

namespace depath::service {

bool is_terminal_event(const v1::JobEvent& event) {
  return event.has_state() && wire::is_terminal(event.state().state());
}

uint64_t EventLog::publish(v1::JobEvent event) {
  uint64_t seq;
  {
    std::lock_guard lock(mutex_);
    if (closed_) return 0;  // nothing follows the terminal event
    // A sequence names one event, in the store and here alike: a numbered event at or below
    // the last one is that event again (a runner's own event read back from the store by a
    // sync before the runner published it), never a new one to renumber.
    if (event.sequence() != 0 && event.sequence() < next_sequence_) return 0;
    seq = std::max<uint64_t>(next_sequence_, event.sequence());
    next_sequence_ = seq + 1;
    event.set_job_id(job_id_);
    event.set_sequence(seq);
    if (event.time_unix() == 0) {
      event.set_time_unix(std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count());
    }
    auto ptr = std::make_shared<const v1::JobEvent>(std::move(event));
    if (ptr->has_progress()) {
      latest_progress_ = std::move(ptr);
    } else {
      closed_ = is_terminal_event(*ptr);
      kept_.push_back(std::move(ptr));
    }
  }
  hub_.post(shared_from_this());
  return seq;
}

void EventLog::skip_to(uint64_t sequence) {
  std::lock_guard lock(mutex_);
  next_sequence_ = std::max(next_sequence_, sequence + 1);
}

EventPtr EventLog::next_after(uint64_t after) const {
  std::lock_guard lock(mutex_);
  auto it = std::upper_bound(kept_.begin(), kept_.end(), after,
                             [](uint64_t a, const EventPtr& e) { return a < e->sequence(); });
  EventPtr kept = it == kept_.end() ? nullptr : *it;
  if (latest_progress_ && latest_progress_->sequence() > after &&
      (!kept || latest_progress_->sequence() < kept->sequence())) {
    return latest_progress_;
  }
  return kept;
}

bool EventLog::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

uint64_t EventLog::last_sequence() const {
  std::lock_guard lock(mutex_);
  return next_sequence_ - 1;
}

void EventLog::subscribe(const std::shared_ptr<EventSubscriber>& s) {
  std::lock_guard lock(mutex_);
  subscribers_.insert(s);
}

void EventLog::unsubscribe(const std::shared_ptr<EventSubscriber>& s) {
  std::lock_guard lock(mutex_);
  subscribers_.erase(s);
}

std::vector<std::shared_ptr<EventSubscriber>> EventLog::subscribers() const {
  std::lock_guard lock(mutex_);
  return {subscribers_.begin(), subscribers_.end()};
}

size_t EventLog::num_subscribers() const {
  std::lock_guard lock(mutex_);
  return subscribers_.size();
}

EventHub::EventHub() : thread_([this] { run(); }) {}

EventHub::~EventHub() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void EventHub::post(std::shared_ptr<EventLog> log) {
  {
    std::lock_guard lock(mutex_);
    if (!pending_set_.insert(log.get()).second) return;
    pending_.push_back(std::move(log));
  }
  wake_.notify_one();
}

void EventHub::flush() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [&] { return pending_.empty() && !dispatching_; });
}

void EventHub::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stopping_ || !pending_.empty(); });
    if (pending_.empty() && stopping_) break;
    auto batch = std::move(pending_);
    pending_.clear();
    pending_set_.clear();
    dispatching_ = true;
    lock.unlock();
    for (const auto& log : batch) {
      for (const auto& s : log->subscribers()) s->notify();
    }
    batch.clear();
    lock.lock();
    dispatching_ = false;
    if (pending_.empty()) idle_.notify_all();
  }
  dispatching_ = false;
  idle_.notify_all();
}

}  // namespace depath::service
