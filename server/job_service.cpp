// SPDX-License-Identifier: MIT
#include "job_service.hpp"

#include "depath/wire/wire.hpp"
#include "grpc_handoff.hpp"
#include "service_error.hpp"
#include "unary_call.hpp"

#include <mutex>

namespace depath::service {

namespace {

/// Streams a job's events to one client. State is guarded by the subscriber's mutex;
/// notify() comes from the hub's dispatcher, OnWriteDone from gRPC: whichever finds the
/// stream idle starts the next write. OnDone detaches and deletes the reactor.
/// grpc_handoff / grpc_reaction (grpc_handoff.hpp) show TSan gRPC's own ordering.
class WatchReactor final : public grpc::ServerWriteReactor<v1::JobEvent> {
 public:
  WatchReactor(ServiceContext& ctx, std::shared_ptr<EventLog> log, uint64_t after_sequence)
      : ctx_(ctx), cursor_(after_sequence) {
    start(std::move(log));
    grpc_handoff(this);  // a write started here waits for the handler to return
  }

  /// A stream that fails before it starts.
  WatchReactor(ServiceContext& ctx, const grpc::Status& status) : ctx_(ctx) {
    Finish(status);
    grpc_handoff(this);
  }

  /// A stream that starts later, from another thread, with start() or fail() (exactly one,
  /// once): a Solve whose submit waits on the blocking queue for its mesh to reload. gRPC
  /// calls OnDone only after Finish, so the reactor lives until then.
  explicit WatchReactor(ServiceContext& ctx) : ctx_(ctx) { grpc_handoff(this); }

  /// Subscribes to `log` and sends what it has after the cursor (the first constructor's, in
  /// its constructor; a deferred stream's, once its job is submitted).
  void start(std::shared_ptr<EventLog> log) {
    auto sub = std::make_shared<Subscriber>(this);
    bool cancelled;
    {
      std::lock_guard lock(start_mutex_);
      log_ = std::move(log);
      sub_ = sub;
      cancelled = cancelled_before_start_;
    }
    log_->subscribe(sub);
    ctx_.metrics.watcher_started("grpc");
    std::lock_guard lock(sub->mutex);
    if (cancelled) finish_locked(grpc::Status(grpc::StatusCode::CANCELLED, "watch cancelled by the client"));
    else pump_locked();
  }

  void fail(const grpc::Status& status) { finish_from_our_thread(*this, status); }

  void OnWriteDone(bool ok) override {
    grpc_reaction(this);
    std::lock_guard lock(sub_->mutex);
    writing_ = false;
    in_flight_.reset();
    if (!ok) {  // the client went away
      finish_locked(grpc::Status(grpc::StatusCode::CANCELLED, "watcher disconnected"));
      return;
    }
    if (sent_terminal_) {
      finish_locked(grpc::Status::OK);
      return;
    }
    pump_locked();
  }

  void OnCancel() override {
    grpc_reaction(this);
    std::shared_ptr<Subscriber> sub;
    {
      std::lock_guard lock(start_mutex_);
      sub = sub_;
      if (!sub) cancelled_before_start_ = true;  // a deferred stream: start() finishes it
    }
    if (!sub) return;  // (or a stream that failed at once: finished already)
    std::lock_guard lock(sub->mutex);
    if (!writing_) finish_locked(grpc::Status(grpc::StatusCode::CANCELLED, "watch cancelled by the client"));
    // else OnWriteDone(false) follows and finishes
  }

  void OnDone() override {
    grpc_reaction(this);
    if (sub_) {
      {
        std::lock_guard lock(sub_->mutex);
        sub_->reactor = nullptr;
      }
      log_->unsubscribe(sub_);
      ctx_.metrics.watcher_ended("grpc");
    }
    delete this;
  }

 private:
  struct Subscriber final : EventSubscriber {
    explicit Subscriber(WatchReactor* r) : reactor(r) {}
    void notify() override {
      std::lock_guard lock(mutex);
      if (reactor) reactor->pump_locked();
    }
    std::mutex mutex;
    WatchReactor* reactor;
  };

  void pump_locked() {
    if (writing_ || finished_) return;
    EventPtr next = log_->next_after(cursor_);
    if (!next) {
      // Nothing new; the log may already be closed (resumed after the terminal event).
      if (log_->closed() && log_->next_after(cursor_) == nullptr) {
        finish_locked(grpc::Status::OK);
      } else if (ctx_.release_watchers.load()) {
        finish_locked(grpc::Status(grpc::StatusCode::UNAVAILABLE,
                                   "server shutting down; the job goes on after a restart or on another replica: "
                                   "watch again with after_sequence"));
      }
      return;
    }
    in_flight_ = std::move(next);
    cursor_ = in_flight_->sequence();
    sent_terminal_ = is_terminal_event(*in_flight_);
    writing_ = true;
    grpc_handoff(this);
    StartWrite(in_flight_.get());
  }

  // Runs in gRPC's reactions and on the hub's dispatcher (notify) alike.
  void finish_locked(const grpc::Status& status) {
    if (finished_) return;
    finished_ = true;
    finish_from_our_thread(*this, status);
  }

  ServiceContext& ctx_;
  std::shared_ptr<EventLog> log_;
  uint64_t cursor_ = 0;
  std::mutex start_mutex_;  // sub_ of a deferred stream is set by start() while OnCancel may read it
  std::shared_ptr<Subscriber> sub_;
  bool cancelled_before_start_ = false;  // guarded by start_mutex_
  // Guarded by sub_->mutex:
  EventPtr in_flight_;
  bool writing_ = false;
  bool finished_ = false;
  bool sent_terminal_ = false;
};

}  // namespace

grpc::ServerUnaryReactor* JobServiceImpl::SubmitJob(grpc::CallbackServerContext* context,
                                                    const v1::SubmitJobRequest* request, v1::SubmitJobResponse* reply) {
  auto body = [this, context, request, reply](const std::string& client) {
    try {
      *reply = ctx_.jobs.submit(*request, client);
    } catch (...) {
      const grpc::Status s = current_exception_status();
      ctx_.log.info("job.refused", {{"peer", context->peer()}, {"mesh", request->spec().mesh_id()},
                                    {"code", wire::status_code_name(s.error_code())}, {"reason", s.error_message()}});
      throw;
    }
  };
  // A mesh to reload from the store (evicted, or stored before a restart) is parsed off gRPC's threads.
  if (ctx_.meshes.must_reload(request->spec().mesh_id())) {
    return unary_blocking(ctx_, context, "SubmitJob", true, std::move(body));
  }
  return unary(ctx_, context, "SubmitJob", true, body);
}

grpc::ServerWriteReactor<v1::JobEvent>* JobServiceImpl::WatchJob(grpc::CallbackServerContext* context,
                                                                 const v1::WatchJobRequest* request) {
  grpc::Status status = ctx_.authenticate(context, "WatchJob");
  if (!status.ok()) return new WatchReactor(ctx_, status);
  try {
    return new WatchReactor(ctx_, ctx_.jobs.events(request->job_id()), request->after_sequence());
  } catch (...) {
    return new WatchReactor(ctx_, current_exception_status());
  }
}

grpc::ServerWriteReactor<v1::JobEvent>* JobServiceImpl::Solve(grpc::CallbackServerContext* context,
                                                              const v1::SubmitJobRequest* request) {
  std::string client;
  grpc::Status status = ctx_.admit(context, "Solve", &client);
  if (!status.ok()) return new WatchReactor(ctx_, status);
  if (ctx_.meshes.must_reload(request->spec().mesh_id())) {  // as SubmitJob: parse off gRPC's threads
    status = ctx_.park();
    if (!status.ok()) return new WatchReactor(ctx_, status);
    auto* reactor = new WatchReactor(ctx_);
    ctx_.blocking.post([this, reactor, request, client] {
      std::shared_ptr<EventLog> log;
      grpc::Status failed;
      try {
        const auto reply = ctx_.jobs.submit(*request, client);
        log = ctx_.jobs.events(reply.job_id());
      } catch (...) {
        failed = current_exception_status();
      }
      ctx_.unpark();
      if (log) reactor->start(std::move(log));
      else reactor->fail(failed);
    });
    return reactor;
  }
  try {
    const auto reply = ctx_.jobs.submit(*request, client);
    return new WatchReactor(ctx_, ctx_.jobs.events(reply.job_id()), 0);
  } catch (...) {
    return new WatchReactor(ctx_, current_exception_status());
  }
}

grpc::ServerUnaryReactor* JobServiceImpl::GetJob(grpc::CallbackServerContext* context, const v1::GetJobRequest* request,
                                                 v1::JobInfo* reply) {
  return unary(ctx_, context, "GetJob", false, [&] { *reply = ctx_.jobs.get(request->job_id()); });
}

grpc::ServerUnaryReactor* JobServiceImpl::GetResult(grpc::CallbackServerContext* context,
                                                    const v1::GetResultRequest* request, v1::JobResult* reply) {
  return unary(ctx_, context, "GetResult", false, [&] { *reply = ctx_.jobs.result(request->job_id()); });
}

grpc::ServerUnaryReactor* JobServiceImpl::ListJobs(grpc::CallbackServerContext* context,
                                                   const v1::ListJobsRequest* request, v1::ListJobsResponse* reply) {
  return unary(ctx_, context, "ListJobs", false, [&] { *reply = ctx_.jobs.list(*request); });
}

grpc::ServerUnaryReactor* JobServiceImpl::CancelJob(grpc::CallbackServerContext* context,
                                                    const v1::CancelJobRequest* request, v1::JobInfo* reply) {
  return unary(ctx_, context, "CancelJob", false, [&] { *reply = ctx_.jobs.cancel(request->job_id()); });
}

}  // namespace depath::service
