// SPDX-License-Identifier: MIT
#include "job_manager.hpp"

#include "depath/util/error.hpp"
#include "depath/solve/solve.hpp"
#include "depath/wire/wire.hpp"
#include "job_limits.hpp"
#include "service_error.hpp"

#include <algorithm>
#include <cstdio>
#include <random>

namespace depath::service {

namespace {
double now_unix() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
constexpr int kCancelled = static_cast<int>(grpc::StatusCode::CANCELLED);
constexpr int kUnavailable = static_cast<int>(grpc::StatusCode::UNAVAILABLE);
}  // namespace

struct JobManager::Job {
  uint64_t number = 0;
  std::string id;
  std::string client_request_id;
  std::string fingerprint;  // serialized spec, for idempotent resubmission
  v1::JobSpec spec_proto;
  JobSpec spec;
  std::shared_ptr<MeshLease> mesh;  // held while queued or running
  std::shared_ptr<EventLog> log;
  std::atomic<bool> cancel{false};
  // Guarded by JobManager::mutex_:
  int cancel_code = kCancelled;
  std::string cancel_message;
  v1::JobState state = v1::JOB_STATE_QUEUED;
  double created = 0, started = 0, finished = 0;
  int error_code = 0;
  std::string error_message;
  bool has_progress = false;
  v1::Progress last_progress;
  std::shared_ptr<const v1::JobResult> result;
  std::chrono::steady_clock::time_point finished_at{};
};

JobManager::JobManager(const ServerOptions& options, MeshStore& meshes, EventHub& hub, ThreadPool& pool, Log& log)
    : options_(options), meshes_(meshes), hub_(hub), pool_(pool), log_(log) {
  std::random_device rd;
  id_salt_ = (static_cast<uint64_t>(rd()) << 32) ^ rd();
  const int drivers = std::max(1, options_.max_running_jobs);
  for (int i = 0; i < drivers; ++i) drivers_.emplace_back([this] { driver_loop(); });
  reaper_ = std::thread([this] { reaper_loop(); });
}

JobManager::~JobManager() {
  begin_shutdown();
  {
    std::lock_guard lock(mutex_);
    exiting_ = true;
  }
  work_.notify_all();
  reaper_wake_.notify_all();
  for (auto& t : drivers_) t.join();
  reaper_.join();
}

std::string JobManager::new_job_id() {
  // Unique within this server's life, hard to guess across restarts.
  std::mt19937_64 rng(id_salt_ ^ (counter_ * 0x9e3779b97f4a7c15ull));
  char buf[48];
  std::snprintf(buf, sizeof buf, "job-%llu-%08llx", static_cast<unsigned long long>(counter_),
                static_cast<unsigned long long>(rng() & 0xffffffffull));
  return buf;
}

std::shared_ptr<JobManager::Job> JobManager::find_locked(const std::string& job_id) const {
  auto it = jobs_.find(job_id);
  if (it == jobs_.end()) {
    throw ServiceError(grpc::StatusCode::NOT_FOUND,
                       "job '" + job_id + "' not found (unknown, or finished more than " +
                           std::to_string(static_cast<long long>(options_.job_ttl_seconds)) + " s ago)");
  }
  return it->second;
}

v1::JobInfo JobManager::info_locked(const Job& job) const {
  v1::JobInfo info;
  info.set_job_id(job.id);
  info.set_state(job.state);
  info.set_mesh_id(job.spec_proto.mesh_id());
  info.set_client_request_id(job.client_request_id);
  *info.mutable_spec() = job.spec_proto;
  // Per-vertex arrays can be large; JobInfo only summarises the spec.
  info.mutable_spec()->mutable_energy()->clear_density();
  info.mutable_spec()->mutable_energy()->clear_field();
  info.set_created_unix(job.created);
  info.set_started_unix(job.started);
  info.set_finished_unix(job.finished);
  if (job.has_progress) *info.mutable_last_progress() = job.last_progress;
  info.set_error_code(job.error_code);
  info.set_error_message(job.error_message);
  info.set_last_sequence(job.log->last_sequence());
  if (job.state == v1::JOB_STATE_QUEUED) {
    auto it = std::find_if(queue_.begin(), queue_.end(), [&](const auto& j) { return j.get() == &job; });
    if (it != queue_.end()) info.set_queue_position(static_cast<int>(it - queue_.begin()) + 1);
  }
  info.set_has_result(job.result != nullptr);
  return info;
}

v1::SubmitJobResponse JobManager::submit(const v1::SubmitJobRequest& request) {
  const std::string fingerprint = request.spec().SerializeAsString();
  auto existing_reply = [&](const Job& job) {
    if (job.fingerprint != fingerprint) {
      throw ServiceError(grpc::StatusCode::ALREADY_EXISTS,
                         "client request id '" + request.client_request_id() + "' was already used for job " +
                             job.id + " with a different spec");
    }
    v1::SubmitJobResponse reply;
    reply.set_job_id(job.id);
    *reply.mutable_job() = info_locked(job);
    reply.set_existing(true);
    return reply;
  };
  {
    std::lock_guard lock(mutex_);
    if (stopping_) throw ServiceError(grpc::StatusCode::UNAVAILABLE, "server is shutting down; not accepting new jobs");
    if (!request.client_request_id().empty()) {
      auto it = by_request_id_.find(request.client_request_id());
      if (it != by_request_id_.end()) return existing_reply(*jobs_.at(it->second));
    }
  }
  if (request.spec().mesh_id().empty()) throw Error(ErrorCode::invalid_argument, "the job spec has no mesh_id");
  JobSpec spec = wire::job_from_proto(request.spec());
  auto lease = meshes_.acquire(request.spec().mesh_id());
  validate_job(lease->mesh(), spec);
  check_job_limits(options_, spec, lease->mesh().num_vertices());

  std::lock_guard lock(mutex_);
  if (stopping_) throw ServiceError(grpc::StatusCode::UNAVAILABLE, "server is shutting down; not accepting new jobs");
  if (!request.client_request_id().empty()) {  // a concurrent twin may have won the race
    auto it = by_request_id_.find(request.client_request_id());
    if (it != by_request_id_.end()) return existing_reply(*jobs_.at(it->second));
  }
  const int waiting = static_cast<int>(queue_.size());
  const int free_drivers = std::max(0, std::max(1, options_.max_running_jobs) - running_);
  if (waiting - free_drivers >= options_.max_queued_jobs) {
    throw ServiceError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                       "job queue is full (" + std::to_string(waiting) + " jobs waiting, --max-queued-jobs " +
                           std::to_string(options_.max_queued_jobs) + "); try again later");
  }
  auto job = std::make_shared<Job>();
  job->number = ++counter_;
  job->id = new_job_id();
  job->client_request_id = request.client_request_id();
  job->fingerprint = fingerprint;
  job->spec_proto = request.spec();
  job->spec = std::move(spec);
  job->mesh = std::move(lease);
  job->log = std::make_shared<EventLog>(job->id, hub_);
  job->created = now_unix();
  jobs_.emplace(job->id, job);
  if (!job->client_request_id.empty()) by_request_id_.emplace(job->client_request_id, job->id);
  queue_.push_back(job);
  v1::JobEvent queued;
  queued.mutable_state()->set_state(v1::JOB_STATE_QUEUED);
  queued.mutable_state()->set_message("queued");
  job->log->publish(std::move(queued));
  log_.info("job.queued", {{"job", job->id},
                           {"mesh", job->spec_proto.mesh_id()},
                           {"method", method_name(job->spec.method)},
                           {"energy", energy_kind_name(job->spec.energy.kind)},
                           {"source", job->spec.source},
                           {"target", job->spec.target},
                           {"request_id", job->client_request_id},
                           {"queue_length", queue_.size()}});
  work_.notify_one();
  v1::SubmitJobResponse reply;
  reply.set_job_id(job->id);
  *reply.mutable_job() = info_locked(*job);
  return reply;
}

void JobManager::finish_locked(Job& job, v1::JobState state, int code, const std::string& message) {
  job.state = state;
  job.finished = now_unix();
  job.finished_at = std::chrono::steady_clock::now();
  job.error_code = state == v1::JOB_STATE_SUCCEEDED ? 0 : code;
  job.error_message = state == v1::JOB_STATE_SUCCEEDED ? "" : message;
  job.mesh.reset();  // the mesh may be evicted from now on
  if (job.result) {
    v1::JobEvent ev;
    *ev.mutable_result() = *job.result;
    job.log->publish(std::move(ev));
  }
  v1::JobEvent ev;
  ev.mutable_state()->set_state(state);
  ev.mutable_state()->set_error_code(job.error_code);
  ev.mutable_state()->set_message(state == v1::JOB_STATE_SUCCEEDED ? "succeeded" : message);
  job.log->publish(std::move(ev));
}

void JobManager::driver_loop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    work_.wait(lock, [&] { return exiting_ || !queue_.empty(); });
    if (exiting_) return;
    auto job = queue_.front();
    queue_.pop_front();
    job->state = v1::JOB_STATE_RUNNING;
    job->started = now_unix();
    ++running_;
    v1::JobEvent ev;
    ev.mutable_state()->set_state(v1::JOB_STATE_RUNNING);
    ev.mutable_state()->set_message("running");
    job->log->publish(std::move(ev));
    lock.unlock();
    run_job(job);
    lock.lock();
    --running_;
    idle_.notify_all();
  }
}

void JobManager::run_job(const std::shared_ptr<Job>& job) {
  const Mesh& mesh = job->mesh->mesh();
  log_.info("job.started", {{"job", job->id}, {"mesh", job->spec_proto.mesh_id()}});
  SolveHooks hooks;
  hooks.pool = &pool_;
  hooks.is_cancelled = [j = job.get()] { return j->cancel.load(std::memory_order_relaxed); };
  hooks.on_progress = [this, j = job.get(), &mesh](const Progress& p) {
    v1::JobEvent ev;
    wire::progress_to_proto(mesh, p, ev.mutable_progress());
    {
      std::lock_guard lock(mutex_);
      j->last_progress = ev.progress();
      j->last_progress.clear_best_path();
      j->has_progress = true;
    }
    j->log->publish(std::move(ev));
  };
  std::shared_ptr<v1::JobResult> result;
  v1::JobState state = v1::JOB_STATE_SUCCEEDED;
  int code = 0;
  std::string message;
  try {
    SolveResult r = solve(mesh, job->spec, hooks);
    result = std::make_shared<v1::JobResult>();
    wire::result_to_proto(mesh, r, result.get());
    if (r.path.empty()) result.reset();
    if (job->cancel.load() || r.stop_reason == "cancelled") state = v1::JOB_STATE_CANCELLED;
  } catch (const Error& e) {
    if (e.code() == ErrorCode::cancelled) {
      state = v1::JOB_STATE_CANCELLED;
    } else {
      state = v1::JOB_STATE_FAILED;
      code = static_cast<int>(wire::status_code(e.code()));
      message = e.what();
    }
  } catch (const std::exception& e) {
    state = v1::JOB_STATE_FAILED;
    code = static_cast<int>(grpc::StatusCode::INTERNAL);
    message = std::string("internal error: ") + e.what();
  }
  std::lock_guard lock(mutex_);
  if (state == v1::JOB_STATE_CANCELLED) {
    code = job->cancel_code;
    message = job->cancel_message.empty() ? "cancelled" : job->cancel_message;
  }
  job->result = result;
  finish_locked(*job, state, code, message);
  nlohmann::json fields = {{"job", job->id}, {"state", wire::state_name(state)},
                           {"seconds", job->finished - job->started}};
  if (result) {
    fields["energy"] = result->energy();
    fields["generations"] = result->generations();
    fields["evaluations"] = result->evaluations();
    fields["stop_reason"] = result->stop_reason();
  }
  if (!message.empty() && state != v1::JOB_STATE_SUCCEEDED) fields["reason"] = message;
  if (state == v1::JOB_STATE_FAILED) log_.warn("job.finished", fields);
  else log_.info("job.finished", fields);
}

v1::JobInfo JobManager::get(const std::string& job_id) {
  std::lock_guard lock(mutex_);
  return info_locked(*find_locked(job_id));
}

v1::JobResult JobManager::result(const std::string& job_id) {
  std::lock_guard lock(mutex_);
  auto job = find_locked(job_id);
  if (job->result) return *job->result;
  if (job->state == v1::JOB_STATE_FAILED) {
    throw ServiceError(static_cast<grpc::StatusCode>(job->error_code),
                       "job " + job_id + " failed: " + job->error_message);
  }
  if (job->state == v1::JOB_STATE_CANCELLED) {
    throw ServiceError(grpc::StatusCode::FAILED_PRECONDITION,
                       "job " + job_id + " was cancelled before it found a path (" + job->error_message + ")");
  }
  throw ServiceError(grpc::StatusCode::FAILED_PRECONDITION,
                     "job " + job_id + " has no result yet: it is " + wire::state_name(job->state));
}

v1::ListJobsResponse JobManager::list(const v1::ListJobsRequest& request) {
  std::lock_guard lock(mutex_);
  std::vector<const Job*> selected;
  for (const auto& [id, job] : jobs_) {
    if (!request.mesh_id().empty() && job->spec_proto.mesh_id() != request.mesh_id()) continue;
    if (request.states_size() > 0 &&
        std::find(request.states().begin(), request.states().end(), job->state) == request.states().end()) {
      continue;
    }
    selected.push_back(job.get());
  }
  std::sort(selected.begin(), selected.end(), [](const Job* a, const Job* b) { return a->number < b->number; });
  v1::ListJobsResponse out;
  for (const Job* job : selected) *out.add_jobs() = info_locked(*job);
  return out;
}

v1::JobInfo JobManager::cancel(const std::string& job_id) {
  std::lock_guard lock(mutex_);
  auto job = find_locked(job_id);
  if (job->state == v1::JOB_STATE_QUEUED) {
    queue_.erase(std::remove(queue_.begin(), queue_.end(), job), queue_.end());
    finish_locked(*job, v1::JOB_STATE_CANCELLED, kCancelled, "cancelled by client before it ran");
    log_.info("job.cancelled", {{"job", job_id}, {"was", "queued"}});
  } else if (job->state == v1::JOB_STATE_RUNNING && !job->cancel.load()) {
    job->cancel_code = kCancelled;
    job->cancel_message = "cancelled by client";
    job->cancel.store(true);
    log_.info("job.cancel_requested", {{"job", job_id}});
  }
  return info_locked(*job);
}

std::shared_ptr<EventLog> JobManager::events(const std::string& job_id) {
  std::lock_guard lock(mutex_);
  return find_locked(job_id)->log;
}

void JobManager::begin_shutdown() {
  std::lock_guard lock(mutex_);
  if (stopping_) return;
  stopping_ = true;
  for (auto& job : queue_) {
    finish_locked(*job, v1::JOB_STATE_CANCELLED, kUnavailable, "server shutting down");
  }
  const size_t dropped = queue_.size();
  queue_.clear();
  int cancelled = 0;
  for (auto& [id, job] : jobs_) {
    if (job->state == v1::JOB_STATE_RUNNING && !job->cancel.load()) {
      job->cancel_code = kUnavailable;
      job->cancel_message = "server shutting down";
      job->cancel.store(true);
      ++cancelled;
    }
  }
  log_.info("jobs.shutdown", {{"queued_cancelled", dropped}, {"running_cancelled", cancelled}});
}

bool JobManager::wait_idle(std::chrono::steady_clock::time_point deadline) {
  std::unique_lock lock(mutex_);
  return idle_.wait_until(lock, deadline, [&] { return running_ == 0; });
}

int JobManager::running_jobs() {
  std::lock_guard lock(mutex_);
  return running_;
}

int JobManager::queued_jobs() {
  std::lock_guard lock(mutex_);
  return static_cast<int>(queue_.size());
}

void JobManager::reaper_loop() {
  std::unique_lock lock(mutex_);
  const auto ttl = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(std::max(0.0, options_.job_ttl_seconds)));
  const auto period = std::min<std::chrono::steady_clock::duration>(std::chrono::seconds(1), ttl / 2 + std::chrono::milliseconds(10));
  while (!exiting_) {
    reaper_wake_.wait_for(lock, period, [&] { return exiting_; });
    if (exiting_) break;
    const auto now = std::chrono::steady_clock::now();
    for (auto it = jobs_.begin(); it != jobs_.end();) {
      Job& job = *it->second;
      if (wire::is_terminal(job.state) && now - job.finished_at >= ttl) {
        log_.debug("job.expired", {{"job", job.id}});
        if (!job.client_request_id.empty()) by_request_id_.erase(job.client_request_id);
        it = jobs_.erase(it);
      } else {
        ++it;
      }
    }
  }
}

}  // namespace depath::service
