// SPDX-License-Identifier: MIT
// A job's numbered events, and the hub that tells watchers about new ones.
//
// The log keeps every state change and the result, and only the latest progress event
// (older progress is coalesced away): a watcher resuming after any sequence misses no state
// change and no result, and a slow watcher simply gets the latest progress when it is
// ready. Publishing is O(1) for the job's thread: fan-out to watchers happens on the hub's
// dispatcher thread and on gRPC's threads, never on the job's.
#pragma once

#include "depath/v1/job.pb.h"

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <unordered_set>
#include <vector>

namespace depath::service {

using EventPtr = std::shared_ptr<const v1::JobEvent>;

/// Something waiting for a log's events (a WatchJob stream). notify() is called from the
/// dispatcher thread, must not block and must tolerate spurious calls.
class EventSubscriber {
 public:
  virtual ~EventSubscriber() = default;
  virtual void notify() = 0;
};

class EventHub;

class EventLog : public std::enable_shared_from_this<EventLog> {
 public:
  EventLog(std::string job_id, EventHub& hub) : job_id_(std::move(job_id)), hub_(hub) {}

  /// Numbers, timestamps and stores the event, then wakes the watchers (asynchronously);
  /// returns its sequence, or 0 if nothing was added. A state event whose state is terminal
  /// closes the log: nothing may follow it. An event that already carries a sequence keeps
  /// it (and its time, if set) if it is above the last; at or below the last it is that
  /// event again and is dropped (a sequence names one event, here and in the store).
  /// A log mirroring the store gets the events numbered elsewhere this way too.
  uint64_t publish(v1::JobEvent event);
  /// The next published event gets a sequence above `sequence` (a job taken over: above
  /// every number its previous runner may have used).
  void skip_to(uint64_t sequence);

  /// The next event to send to a watcher that has seen everything up to `after`: the first
  /// kept event with a larger sequence (nullptr if none yet).
  EventPtr next_after(uint64_t after) const;
  /// True once the terminal state event is in the log.
  bool closed() const;
  uint64_t last_sequence() const;

  void subscribe(const std::shared_ptr<EventSubscriber>& s);
  void unsubscribe(const std::shared_ptr<EventSubscriber>& s);
  std::vector<std::shared_ptr<EventSubscriber>> subscribers() const;
  size_t num_subscribers() const;

 private:
  const std::string job_id_;
  EventHub& hub_;
  mutable std::mutex mutex_;
  std::vector<EventPtr> kept_;  // state changes and results, by sequence
  EventPtr latest_progress_;
  uint64_t next_sequence_ = 1;
  bool closed_ = false;
  std::unordered_set<std::shared_ptr<EventSubscriber>> subscribers_;
};

/// One dispatcher thread that fans new events out to the watchers of each log. Posting a
/// log that is already pending is a no-op, which coalesces bursts.
class EventHub {
 public:
  EventHub();
  ~EventHub();
  EventHub(const EventHub&) = delete;
  EventHub& operator=(const EventHub&) = delete;

  void post(std::shared_ptr<EventLog> log);
  /// Waits until every log posted so far has been dispatched.
  void flush();

 private:
  void run();
  std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::vector<std::shared_ptr<EventLog>> pending_;
  std::unordered_set<EventLog*> pending_set_;
  bool dispatching_ = false;
  bool stopping_ = false;
  std::thread thread_;
};

/// True for a state event with a terminal state.
bool is_terminal_event(const v1::JobEvent& event);

}  // namespace depath::service
