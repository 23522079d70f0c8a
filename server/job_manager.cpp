// SPDX-License-Identifier: MIT
#include "job_manager.hpp"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <future>
#include <random>
#include <span>
#include <tuple>

#include "depath/de/checkpoint.hpp"
#include "depath/solve/solve.hpp"
#include "depath/util/error.hpp"
#include "depath/wire/wire.hpp"
#include "job_limits.hpp"
#include "service_error.hpp"

namespace depath::service {

namespace {
double now_unix() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
constexpr int kCancelled = static_cast<int>(grpc::StatusCode::CANCELLED);
constexpr int kUnavailable = static_cast<int>(grpc::StatusCode::UNAVAILABLE);
// Sequences a runner reserves in the store at a time (one write per this many events).
constexpr uint64_t kSequenceBlock = 1000;
// Progress rows stored per job at most this often: often enough for watchers on other
// replicas (shared store), rarely enough to cost nothing; the live log has every one.
constexpr double kSharedProgressSeconds = 0.2;
constexpr double kLocalProgressSeconds = 1.0;
// The journal of trial energies is stored at most this often: a crash then costs a resume
// the decodes of this long at most, instead of everything since the last checkpoint.
constexpr double kJournalSeconds = 0.1;
// Unstored journal kept while the store lags behind, at most: past it the oldest generations
// are dropped (a crash then decodes them again).
constexpr size_t kJournalMaxBytes = size_t{16} << 20;

// Trial energies as the journal stores them: IEEE doubles, little-endian, generation after
// generation.
void append_energies(std::string& bytes, std::span<const double> energies) {
  for (const double e : energies) {
    const uint64_t bits = std::bit_cast<uint64_t>(e);
    for (int b = 0; b < 8; ++b) bytes.push_back(static_cast<char>((bits >> (8 * b)) & 0xff));
  }
}

// The generations of `entry` after `after`, into `journal`; an entry whose bytes do not
// split into its generations is skipped.
void decode_journal(const JournalEntry& entry, int after, std::map<int, std::vector<double>>& journal) {
  const int generations = entry.last_generation - entry.first_generation + 1;
  if (generations <= 0 || entry.energies.size() % (8 * static_cast<size_t>(generations)) != 0) return;
  const size_t per_generation = entry.energies.size() / 8 / static_cast<size_t>(generations);
  for (int k = 0; k < generations; ++k) {
    if (entry.first_generation + k <= after) continue;
    std::vector<double>& energies = journal[entry.first_generation + k];
    energies.resize(per_generation);
    for (size_t i = 0; i < per_generation; ++i) {
      const size_t at = (static_cast<size_t>(k) * per_generation + i) * 8;
      uint64_t bits = 0;
      for (int b = 0; b < 8; ++b)
        bits |= uint64_t{static_cast<unsigned char>(entry.energies[at + b])} << (8 * b);
      energies[i] = std::bit_cast<double>(bits);
    }
  }
}

std::string random_hex(int bytes) {
  std::random_device rd;
  std::string out;
  char buf[3];
  for (int i = 0; i < bytes; ++i) {
    std::snprintf(buf, sizeof buf, "%02x", static_cast<unsigned>(rd() & 0xff));
    out += buf;
  }
  return out;
}

v1::JobEvent state_event(v1::JobState state, int code, const std::string& message) {
  v1::JobEvent ev;
  ev.mutable_state()->set_state(state);
  ev.mutable_state()->set_error_code(code);
  ev.mutable_state()->set_message(message);
  return ev;
}

/// The generations a runner reported that the store's history does not have yet, under a
/// lock of their own: the runner adds one per generation, each store write (progress,
/// checkpoint, finish) sends a copy and drops what the store took, a history request reads one.
class UnstoredHistory {
 public:
  void add(const ProgressPoint& p) {
    std::lock_guard lock(mutex_);
    points_.push_back(p);
    // Bounded while the store is busy: thinned as the stored history is.
    if (points_.size() > 2 * kProgressHistoryPoints) thin_progress_history(points_, p.generation);
  }
  std::vector<ProgressPoint> copy() const {
    std::lock_guard lock(mutex_);
    return points_;
  }
  /// The store took `points` (a copy): they leave, the generations reported since stay.
  void stored(const std::vector<ProgressPoint>& points) {
    if (points.empty()) return;
    const int upto = points.back().generation;
    std::lock_guard lock(mutex_);
    std::erase_if(points_, [upto](const ProgressPoint& p) { return p.generation <= upto; });
  }

 private:
  mutable std::mutex mutex_;
  std::vector<ProgressPoint> points_;
};

std::chrono::steady_clock::duration seconds(double s) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(s));
}
}  // namespace

/// A job this replica runs (between claim and finish or hand-back).
struct JobManager::Running {
  std::string id;
  std::shared_ptr<EventLog> log;
  std::atomic<bool> cancel{false};   // stop computing (client cancel, shutdown on memory, lease lost)
  std::atomic<bool> suspend{false};  // checkpoint and hand back (shutdown on a durable store)
  std::atomic<bool> lost{false};     // the lease went to another replica: write nothing more
  uint64_t reserved = 0;             // sequences reserved in the store (runner thread only)
  std::optional<v1::JobEvent> unstored_progress;  // the latest progress, if not stored (runner thread only)
  UnstoredHistory unstored_history;  // generations the store's history lacks (its own lock)
  // Guarded by JobManager::mutex_:
  int cancel_code = kCancelled;
  std::string cancel_message;
  std::optional<v1::Progress> last_progress;
  double started = 0;
};

JobManager::JobManager(const ServerOptions& options, JobStore& store, MeshStore& meshes, EventHub& hub,
                       ThreadPool& pool, Log& log, ServiceMetrics* metrics)
    : options_(options),
      store_(store),
      meshes_(meshes),
      hub_(hub),
      pool_(pool),
      log_(log),
      metrics_(metrics),
      replica_(options.replica_id.empty() ? random_hex(8) : options.replica_id) {
  // A named replica that restarts (kill -9, OOM) holds leases of its former life: its jobs
  // go back to the queue now instead of after --lease-seconds, and resume from checkpoints.
  if (!options.replica_id.empty()) {
    const int released = store_.release_all(replica_);
    if (released > 0) log_.info("jobs.released", {{"replica", replica_}, {"count", released}});
  }
  const int drivers = std::max(1, options_.max_running_jobs);
  for (int i = 0; i < drivers; ++i) drivers_.emplace_back([this] { driver_loop(); });
  heartbeat_ = std::thread([this] { heartbeat_loop(); });
}

JobManager::~JobManager() {
  begin_shutdown();
  {
    std::lock_guard lock(mutex_);
    exiting_ = true;
  }
  work_.notify_all();
  beat_wake_.notify_all();
  for (auto& t : drivers_) t.join();
  heartbeat_.join();
}

// ---- queries ------------------------------------------------------------------------------

JobRecord JobManager::find(const std::string& job_id) {
  if (auto job = store_.get_job(job_id)) return *job;
  if (store_.expired(job_id)) {
    throw ServiceError(grpc::StatusCode::NOT_FOUND,
                       "job '" + job_id + "' has expired: finished jobs and their results are kept for " +
                           std::to_string(static_cast<long long>(options_.job_ttl_seconds)) +
                           " s (--job-ttl-seconds), at most " + std::to_string(options_.max_finished_jobs) +
                           " of them (--max-finished-jobs)");
  }
  throw ServiceError(grpc::StatusCode::NOT_FOUND,
                     "job '" + job_id + "' not found: no job with this id was submitted to this store");
}

v1::JobInfo JobManager::info_of(const JobRecord& job, int queue_position) {
  v1::JobInfo info;
  info.set_job_id(job.id);
  info.set_state(job.state);
  info.set_mesh_id(job.mesh_id);
  info.set_client_request_id(job.request_id);
  *info.mutable_spec() = job.spec;
  // Per-vertex arrays can be large; JobInfo only summarises the spec.
  info.mutable_spec()->mutable_energy()->clear_density();
  info.mutable_spec()->mutable_energy()->clear_field();
  info.set_created_unix(job.created);
  info.set_started_unix(job.started);
  info.set_finished_unix(job.finished);
  if (job.progress) *info.mutable_last_progress() = *job.progress;
  info.set_error_code(job.error_code);
  info.set_error_message(job.error_message);
  uint64_t last = job.last_sequence;
  {
    std::lock_guard lock(mutex_);
    auto run = running_.find(job.id);
    if (run != running_.end() && run->second->last_progress) {
      *info.mutable_last_progress() = *run->second->last_progress;
    }
    auto it = logs_.find(job.id);
    if (it != logs_.end()) {
      if (auto log = it->second.lock()) last = std::max(last, log->last_sequence());
    }
  }
  info.set_last_sequence(last);
  if (job.state == v1::JOB_STATE_QUEUED) info.set_queue_position(queue_position);
  info.set_has_result(job.has_result);
  return info;
}

v1::SubmitJobResponse JobManager::submit(const v1::SubmitJobRequest& request, const std::string& client) {
  auto existing_reply = [&](const JobRecord& job) {
    if (job.spec.SerializeAsString() != request.spec().SerializeAsString()) {
      throw ServiceError(grpc::StatusCode::ALREADY_EXISTS,
                         "client request id '" + request.client_request_id() + "' was already used for job " +
                             job.id + " with a different spec");
    }
    v1::SubmitJobResponse reply;
    reply.set_job_id(job.id);
    *reply.mutable_job() =
        info_of(job, job.state == v1::JOB_STATE_QUEUED ? store_.queue_position(job.number) : 0);
    reply.set_existing(true);
    return reply;
  };
  {
    std::lock_guard lock(mutex_);
    if (stopping_)
      throw ServiceError(grpc::StatusCode::UNAVAILABLE, "server is shutting down; not accepting new jobs");
  }
  if (!request.client_request_id().empty()) {
    if (auto job = store_.find_request(request.client_request_id())) return existing_reply(*job);
  }
  if (request.spec().mesh_id().empty())
    throw Error(ErrorCode::invalid_argument, "the job spec has no mesh_id");
  JobSpec spec = wire::job_from_proto(request.spec());
  // A store that keeps meshes reloads them when the job runs, so a queued job holds none
  // in memory; the memory store cannot, so its queued jobs hold theirs, within the budget.
  auto lease = store_.keeps_meshes() ? meshes_.acquire(request.spec().mesh_id())
                                     : meshes_.hold_for_queue(request.spec().mesh_id());
  validate_job(lease->mesh(), spec);
  check_job_limits(options_, spec, lease->mesh().num_vertices());

  int free_drivers;
  {
    std::lock_guard lock(mutex_);
    if (stopping_)
      throw ServiceError(grpc::StatusCode::UNAVAILABLE, "server is shutting down; not accepting new jobs");
    free_drivers = std::max(0, std::max(1, options_.max_running_jobs) - busy_);
  }
  const auto waiting = store_.count_queued();
  if (waiting - free_drivers >= options_.max_queued_jobs) {
    throw ServiceError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                       "job queue is full (" + std::to_string(waiting) + " jobs waiting, --max-queued-jobs " +
                           std::to_string(options_.max_queued_jobs) + "); try again later");
  }
  JobRecord job;
  job.id = "job-" + random_hex(8);  // unique across restarts and replicas, hard to guess
  job.request_id = request.client_request_id();
  job.mesh_id = request.spec().mesh_id();
  job.spec = request.spec();
  job.created = now_unix();
  job.client = client;
  JobRecord stored;
  bool inserted = false;
  try {
    std::tie(stored, inserted) =
        store_.insert_job(job, state_event(v1::JOB_STATE_QUEUED, 0, "queued"), options_.max_jobs_per_client);
  } catch (const ClientQuotaExceeded& e) {
    throw ServiceError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                       "client " + client + " already has " + std::to_string(e.held) +
                           " jobs queued or running, the limit per client (--max-jobs-per-client " +
                           std::to_string(options_.max_jobs_per_client) + "); wait for one to finish");
  }
  if (!inserted) return existing_reply(stored);
  if (!store_.keeps_meshes()) {
    std::lock_guard lock(mutex_);
    pins_[stored.id] = std::move(lease);  // kept in the cache until it runs
  }
  log_.info("job.queued", {{"job", stored.id},
                           {"mesh", stored.mesh_id},
                           {"method", method_name(spec.method)},
                           {"energy", energy_kind_name(spec.energy.kind)},
                           {"source", spec.source},
                           {"target", spec.target},
                           {"request_id", stored.request_id},
                           {"queue_length", waiting + 1}});
  work_.notify_one();
  v1::SubmitJobResponse reply;
  reply.set_job_id(stored.id);
  *reply.mutable_job() = info_of(stored, store_.queue_position(stored.number));
  return reply;
}

v1::JobInfo JobManager::get(const std::string& job_id) {
  const JobRecord job = find(job_id);
  return info_of(job, job.state == v1::JOB_STATE_QUEUED ? store_.queue_position(job.number) : 0);
}

std::vector<ProgressPoint> JobManager::progress_history(const std::string& job_id) {
  // The runner's points not stored yet first: read after them, the store has every point
  // they lose to a concurrent flush.
  std::shared_ptr<Running> run;
  {
    std::lock_guard lock(mutex_);
    auto it = running_.find(job_id);
    if (it != running_.end()) run = it->second;
  }
  const std::vector<ProgressPoint> unstored = run ? run->unstored_history.copy() : std::vector<ProgressPoint>{};
  std::vector<ProgressPoint> history = store_.progress_history(job_id);
  // Points name a job that exists; without any, read the job (with its spec) only to answer
  // NOT_FOUND for an unknown one.
  if (history.empty() && unstored.empty()) find(job_id);
  const int stored_upto = history.empty() ? -1 : history.back().generation;
  for (const auto& p : unstored) {
    if (p.generation > stored_upto) history.push_back(p);
  }
  return history;
}

v1::JobResult JobManager::result(const std::string& job_id) {
  const JobRecord job = find(job_id);
  if (job.has_result) {
    if (auto result = store_.get_result(job_id)) return *result;
  }
  if (job.state == v1::JOB_STATE_FAILED) {
    throw ServiceError(static_cast<grpc::StatusCode>(job.error_code),
                       "job " + job_id + " failed: " + job.error_message);
  }
  if (job.state == v1::JOB_STATE_CANCELLED) {
    throw ServiceError(grpc::StatusCode::FAILED_PRECONDITION,
                       "job " + job_id + " was cancelled before it found a path (" + job.error_message + ")");
  }
  throw ServiceError(grpc::StatusCode::FAILED_PRECONDITION,
                     "job " + job_id + " has no result yet: it is " + wire::state_name(job.state));
}

v1::ListJobsResponse JobManager::list(const v1::ListJobsRequest& request) {
  const auto all = store_.list_jobs("");
  v1::ListJobsResponse out;
  int position = 0;
  for (const auto& job : all) {
    if (job.state == v1::JOB_STATE_QUEUED) ++position;
    if (!request.mesh_id().empty() && job.mesh_id != request.mesh_id()) continue;
    if (request.states_size() > 0 &&
        std::find(request.states().begin(), request.states().end(), job.state) == request.states().end()) {
      continue;
    }
    *out.add_jobs() = info_of(job, position);
  }
  return out;
}

v1::JobInfo JobManager::cancel(const std::string& job_id) {
  find(job_id);
  {
    std::lock_guard lock(mutex_);
    auto it = running_.find(job_id);
    if (it != running_.end() && !it->second->cancel.load()) {
      it->second->cancel_code = kCancelled;
      it->second->cancel_message = "cancelled by client";
      it->second->cancel.store(true);
    }
  }
  v1::JobEvent ev = state_event(v1::JOB_STATE_CANCELLED, kCancelled, "cancelled by client before it ran");
  ev.set_time_unix(now_unix());
  const CancelOutcome outcome = store_.cancel(job_id, ev);
  if (outcome == CancelOutcome::cancelled_queued) {
    {
      std::lock_guard lock(mutex_);
      pins_.erase(job_id);
    }
    sync_open_log(job_id);
    log_.info("job.cancelled", {{"job", job_id}, {"was", "queued"}});
  } else if (outcome == CancelOutcome::requested) {
    log_.info("job.cancel_requested", {{"job", job_id}});
    beat_wake_.notify_all();  // a shared store: tell the runner soon
  }
  return get(job_id);
}

// ---- event logs ---------------------------------------------------------------------------

std::shared_ptr<EventLog> JobManager::events(const std::string& job_id) {
  find(job_id);
  return log_for(job_id);
}

std::shared_ptr<EventLog> JobManager::log_for(const std::string& job_id) {
  std::shared_ptr<EventLog> log;
  {
    std::lock_guard lock(mutex_);
    auto it = logs_.find(job_id);
    if (it != logs_.end()) log = it->second.lock();
    if (log) return log;
    log = std::make_shared<EventLog>(job_id, hub_);
    logs_[job_id] = log;
  }
  sync_log(job_id, log);
  return log;
}

void JobManager::sync_log(const std::string& job_id, const std::shared_ptr<EventLog>& log) {
  try {
    for (auto& ev : store_.events_after(job_id, log->last_sequence())) log->publish(std::move(ev));
  } catch (const StoreError& e) {
    log_.warn("store.error", {{"job", job_id}, {"reason", e.what()}});
  }
}

void JobManager::sync_open_log(const std::string& job_id) {
  std::shared_ptr<EventLog> log;
  {
    std::lock_guard lock(mutex_);
    auto it = logs_.find(job_id);
    if (it != logs_.end()) log = it->second.lock();
  }
  if (log) sync_log(job_id, log);
}

void JobManager::sync_mirrors() {
  std::vector<std::pair<std::string, std::shared_ptr<EventLog>>> mirrors;
  {
    std::lock_guard lock(mutex_);
    for (auto it = logs_.begin(); it != logs_.end();) {
      auto log = it->second.lock();
      if (!log) {
        it = logs_.erase(it);
        continue;
      }
      if (!running_.count(it->first) && !log->closed()) mirrors.emplace_back(it->first, std::move(log));
      ++it;
    }
  }
  for (const auto& [id, log] : mirrors) sync_log(id, log);
}

// ---- running ------------------------------------------------------------------------------

void JobManager::driver_loop() {
  const auto idle_poll = seconds(store_.shared() ? 0.25 : 1.0);
  std::unique_lock lock(mutex_);
  for (;;) {
    if (exiting_) return;
    if (stopping_) {
      work_.wait(lock);
      continue;
    }
    ++busy_;
    lock.unlock();
    std::optional<JobRecord> job;
    try {
      job = store_.claim(replica_, now_unix(), options_.lease_seconds);
    } catch (const StoreError& e) {
      log_.warn("store.error", {{"during", "claim"}, {"reason", e.what()}});
    }
    if (job) run_job(std::move(*job));
    lock.lock();
    --busy_;
    idle_.notify_all();
    if (!job) work_.wait_for(lock, idle_poll);
  }
}

bool JobManager::emit(Running& run, v1::JobEvent event, bool persist) {
  if (run.lost.load()) return false;
  const uint64_t seq = run.log->last_sequence() + 1;  // this thread is the log's only publisher
  try {
    if (seq > run.reserved) {
      if (!store_.reserve_sequences(run.id, replica_, seq + kSequenceBlock)) {
        run.lost.store(true);
        run.cancel.store(true);
        return false;
      }
      run.reserved = seq + kSequenceBlock;
    }
    event.set_job_id(run.id);
    event.set_sequence(seq);
    event.set_time_unix(now_unix());
    // Progress never waits for the store (it may be busy storing a large checkpoint): if
    // it is busy, this one stays unstored and a later one (or the finish) is stored instead.
    auto stored = JobStore::Append::busy;
    std::vector<ProgressPoint> history;
    if (persist && event.has_progress()) history = run.unstored_history.copy();
    if (persist) stored = store_.append_event(run.id, replica_, event, !event.has_progress(), history);
    if (stored == JobStore::Append::stored) run.unstored_history.stored(history);
    if (stored == JobStore::Append::lost) {
      run.lost.store(true);
      run.cancel.store(true);
      return false;
    }
    if (event.has_progress()) {
      if (stored == JobStore::Append::stored) {
        run.unstored_progress.reset();
      } else {
        run.unstored_progress = event;
      }
    }
  } catch (const StoreError& e) {
    log_.warn("store.error", {{"job", run.id}, {"reason", e.what()}});
  }
  run.log->publish(std::move(event));
  return true;
}

void JobManager::run_job(JobRecord job) {
  auto run = std::make_shared<Running>();
  run->id = job.id;
  run->started = now_unix();
  {
    std::lock_guard lock(mutex_);
    if (stopping_) {  // claimed just as the server began to stop: give it back untouched
      store_.release(job.id, replica_);
      return;
    }
    running_[job.id] = run;
  }
  run->log = log_for(job.id);  // one log per job per process: watchers here keep theirs
  sync_log(job.id, run->log);  // events of a previous runner
  run->log->skip_to(job.seq_reserved);
  run->reserved = job.seq_reserved;
  try {
    execute(*run, job);
  } catch (const std::exception& e) {  // the store failed mid-run: the lease runs out, another run resumes
    log_.error("job.aborted", {{"job", job.id}, {"reason", e.what()}});
  }
  std::lock_guard lock(mutex_);
  running_.erase(job.id);
  pins_.erase(job.id);
}

void JobManager::execute(Running& run, const JobRecord& job) {
  if (job.cancel_requested) {
    finish(run, v1::JOB_STATE_CANCELLED, kCancelled, "cancelled by client", nullptr);
    return;
  }
  std::shared_ptr<MeshLease> mesh_lease;
  JobSpec spec;
  try {
    mesh_lease = meshes_.acquire(job.mesh_id);
    spec = wire::job_from_proto(job.spec);
  } catch (...) {
    const grpc::Status s = current_exception_status();
    finish(run, v1::JOB_STATE_FAILED, s.error_code(), s.error_message(), nullptr);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    pins_.erase(job.id);  // held by mesh_lease now
  }
  const Mesh& mesh = mesh_lease->mesh();
  std::string checkpoint = store_.get_checkpoint(job.id);
  int resumed_generation = -1;
  if (!checkpoint.empty()) {
    try {
      resumed_generation = decode_de_state(checkpoint).generation;
    } catch (const Error& e) {
      log_.warn("job.checkpoint_unusable", {{"job", job.id}, {"reason", e.what()}});
      checkpoint.clear();
    }
  }
  std::map<int, std::vector<double>> journal;  // generations after the checkpoint (all without one)
  if (job.state == v1::JOB_STATE_RUNNING) {
    for (const JournalEntry& e : store_.journal_after(job.id, resumed_generation)) {
      decode_journal(e, resumed_generation, journal);
    }
  }
  std::string message = "running";
  if (job.state == v1::JOB_STATE_RUNNING) {
    message = resumed_generation >= 0
                  ? "resumed from its checkpoint after generation " + std::to_string(resumed_generation)
                  : "restarted from the beginning (no checkpoint yet)";
    if (!journal.empty()) {
      message += "; the energies of " + std::to_string(journal.size()) +
                 " journaled generations spare it their decodes";
    }
  }
  if (!emit(run, state_event(v1::JOB_STATE_RUNNING, 0, message), true)) return;
  log_.info(job.state == v1::JOB_STATE_RUNNING ? "job.resumed" : "job.started",
            {{"job", job.id},
             {"mesh", job.mesh_id},
             {"checkpoint_generation", resumed_generation},
             {"journal_generations", journal.size()}});

  SolveHooks hooks;
  hooks.pool = &pool_;
  hooks.resume_from = std::move(checkpoint);
  const int replayed_through = journal.empty() ? -1 : journal.rbegin()->first;
  hooks.recorded_trial_energies = std::move(journal);
  hooks.is_cancelled = [r = &run] { return r->cancel.load(std::memory_order_relaxed); };
  hooks.suspend = [r = &run] { return r->suspend.load(std::memory_order_relaxed); };
  // Checkpoints are written on a thread of their own while the DE goes on: the run pays only
  // for copying its state out (a 167 MB checkpoint takes seconds to store, ~0.1 s to copy).
  auto last_checkpoint = std::chrono::steady_clock::now();
  const bool checkpoints = options_.checkpoint_seconds > 0 && store_.durable();
  std::future<void> writing;
  auto write_done = [&] {
    return !writing.valid() || writing.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
  };
  hooks.checkpoint_due = [&] {
    return checkpoints && write_done() &&
           std::chrono::steady_clock::now() - last_checkpoint >= seconds(options_.checkpoint_seconds);
  };
  hooks.on_checkpoint = [&](std::string bytes) {
    last_checkpoint = std::chrono::steady_clock::now();
    if (!store_.durable() || run.lost.load()) return;
    int generation = 0;  // the checkpoint is taken before the generation after the last reported one
    {
      std::lock_guard lock(mutex_);
      if (run.last_progress) generation = run.last_progress->generation();
    }
    // Stored with it: a resume from it leaves no gap in the history.
    std::vector<ProgressPoint> history = run.unstored_history.copy();
    if (generation == 0) generation = std::max(0, resumed_generation);
    if (writing.valid()) writing.get();  // a suspend's checkpoint follows the one being written
    writing = std::async(std::launch::async, [this, &run, id = job.id, generation, bytes = std::move(bytes),
                                              history = std::move(history)] {
      const auto t0 = std::chrono::steady_clock::now();
      try {
        if (!store_.put_checkpoint(id, replica_, generation, bytes, history)) {
          run.lost.store(true);
          run.cancel.store(true);
        } else {
          run.unstored_history.stored(history);
        }
        log_.debug(
            "job.checkpointed",
            {{"job", id},
             {"generation", generation},
             {"bytes", bytes.size()},
             {"seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()}});
      } catch (const std::exception& e) {
        log_.warn("job.checkpoint_failed", {{"job", id}, {"reason", e.what()}});
      }
    });
  };
  // The journal since the checkpoint: a few generations at a time, on a thread of its own
  // like the checkpoints (a write waits for the disk).
  JournalEntry journal_unstored;  // generations not handed to a write yet
  auto last_journal = std::chrono::steady_clock::now();
  std::future<void> journal_writing;
  if (checkpoints && !spec.refine) {  // a refined run decodes every accepted trial: no use for one
    hooks.on_trial_energies = [&](int generation, std::span<const double> energies) {
      if (journal_unstored.energies.size() > kJournalMaxBytes) journal_unstored = {};
      if (journal_unstored.energies.empty()) journal_unstored.first_generation = generation;
      journal_unstored.last_generation = generation;
      append_energies(journal_unstored.energies, energies);
      const auto now = std::chrono::steady_clock::now();
      if (now - last_journal < seconds(kJournalSeconds) || run.lost.load()) return;
      if (journal_writing.valid() &&
          journal_writing.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
        return;  // one write at a time: the next takes all generations since
      last_journal = now;
      if (journal_writing.valid()) journal_writing.get();
      journal_writing =
          std::async(std::launch::async, [this, id = job.id, entry = std::move(journal_unstored)] {
            try {
              if (store_.append_journal(id, replica_, entry)) {  // a lost lease shows at the next checkpoint
                log_.debug("job.journaled", {{"job", id},
                                             {"first_generation", entry.first_generation},
                                             {"last_generation", entry.last_generation}});
              }
            } catch (const std::exception& e) {
              log_.warn("job.journal_failed", {{"job", id}, {"reason", e.what()}});
            }
          });
      journal_unstored = {};
    };
  }
  const double persist_every = store_.shared() ? kSharedProgressSeconds : kLocalProgressSeconds;
  auto last_persist = std::chrono::steady_clock::time_point{};
  // Metrics: evaluations and generations since the last report, and one sample of the time
  // an evaluation takes (the generation's wall time x this job's share of the threads).
  int64_t counted_evaluations = 0;
  int counted_generation = std::max(0, resumed_generation);
  auto last_report = std::chrono::steady_clock::now();
  auto count_progress = [&](const Progress& p) {
    if (!metrics_) return;
    const auto now = std::chrono::steady_clock::now();
    if (p.generation <= replayed_through) {  // its evaluations came from the journal: none ran here
      counted_evaluations = p.evaluations;
      counted_generation = p.generation;
      last_report = now;
      return;
    }
    if (counted_evaluations == 0 && resumed_generation >= 0) counted_evaluations = p.evaluations;  // counted before
    const int64_t evaluations = p.evaluations - counted_evaluations;
    const int generations = std::max(0, p.generation - counted_generation);
    double sample = -1;
    if (evaluations > 0 && counted_evaluations > 0) {
      const int sharing = std::max(1, running_jobs());
      const double threads = static_cast<double>(pool_.num_slots()) / sharing;
      sample = std::chrono::duration<double>(now - last_report).count() * std::max(1.0, threads) /
               static_cast<double>(evaluations);
    }
    metrics_->job_progress(std::max<int64_t>(0, evaluations), generations, sample);
    counted_evaluations = std::max(counted_evaluations, p.evaluations);
    counted_generation = std::max(counted_generation, p.generation);
    last_report = now;
  };
  hooks.on_progress = [&](const Progress& p) {
    count_progress(p);
    v1::JobEvent ev;
    wire::progress_to_proto(mesh, p, ev.mutable_progress());
    run.unstored_history.add({p.generation, p.best_energy, p.mean_energy});
    {
      // The summary JobInfo shows, without the path (set aside rather than copied and cleared).
      std::unique_ptr<v1::Path> path(ev.mutable_progress()->release_best_path());
      std::lock_guard lock(mutex_);
      run.last_progress = ev.progress();
      ev.mutable_progress()->set_allocated_best_path(path.release());
    }
    const auto now = std::chrono::steady_clock::now();
    const bool persist = now - last_persist >= seconds(persist_every);
    if (persist) last_persist = now;
    emit(run, std::move(ev), persist);
  };

  std::shared_ptr<v1::JobResult> result;
  v1::JobState state = v1::JOB_STATE_SUCCEEDED;
  int code = 0;
  std::string error;
  std::string stop_reason;
  try {
    hooks.stencils = &mesh_lease->stencils();  // kept with the cached mesh: built by its first job only
    SolveResult r = solve(mesh, spec, hooks);
    if (metrics_ && r.evaluations > counted_evaluations)  // evaluations after the last report (refinement)
      metrics_->job_progress(r.evaluations - counted_evaluations, 0, -1);
    stop_reason = r.stop_reason;
    result = std::make_shared<v1::JobResult>();
    wire::result_to_proto(mesh, r, result.get());
    if (r.path.empty()) result.reset();
    if (run.cancel.load() || r.stop_reason == "cancelled") state = v1::JOB_STATE_CANCELLED;
  } catch (const Error& e) {
    if (e.code() == ErrorCode::cancelled) {
      state = v1::JOB_STATE_CANCELLED;
    } else {
      state = v1::JOB_STATE_FAILED;
      code = static_cast<int>(wire::status_code(e.code()));
      error = e.what();
    }
  } catch (const std::exception& e) {
    state = v1::JOB_STATE_FAILED;
    code = static_cast<int>(grpc::StatusCode::INTERNAL);
    error = std::string("internal error: ") + e.what();
  }
  if (writing.valid()) writing.get();  // stored before the job is handed back or finished
  if (journal_writing.valid()) journal_writing.get();
  if (run.lost.load()) {
    log_.warn("job.lease_lost",
              {{"job", job.id}, {"reason", "another replica took the job over; this run stops"}});
    return;
  }
  bool cancelled_by_client;
  {
    std::lock_guard lock(mutex_);
    cancelled_by_client = run.cancel.load() && run.cancel_message == "cancelled by client";
  }
  if (run.suspend.load() &&
      (stop_reason == "suspended" || (state != v1::JOB_STATE_SUCCEEDED && !cancelled_by_client))) {
    // Shutting down on a durable store: the checkpoint is saved, the job resumes later.
    store_.release(job.id, replica_);
    log_.info("job.suspended", {{"job", job.id}, {"stop_reason", stop_reason}});
    return;
  }
  if (state == v1::JOB_STATE_CANCELLED) {
    std::lock_guard lock(mutex_);
    code = run.cancel_code;
    error = run.cancel_message.empty() ? "cancelled" : run.cancel_message;
  }
  finish(run, state, code, error, result);
}

void JobManager::finish(Running& run, v1::JobState state, int code, const std::string& message,
                        const std::shared_ptr<v1::JobResult>& result) {
  if (state == v1::JOB_STATE_SUCCEEDED) code = 0;
  std::vector<v1::JobEvent> events;
  uint64_t seq = run.log->last_sequence();
  const double now = now_unix();
  if (result) {
    v1::JobEvent ev;
    *ev.mutable_result() = *result;
    events.push_back(std::move(ev));
  }
  events.push_back(state_event(state, code, state == v1::JOB_STATE_SUCCEEDED ? "succeeded" : message));
  for (auto& ev : events) {
    ev.set_job_id(run.id);
    ev.set_sequence(++seq);
    ev.set_time_unix(now);
  }
  if (seq > run.reserved && !store_.reserve_sequences(run.id, replica_, seq)) run.lost.store(true);
  // The store keeps the latest progress too (watchers after the end see what live ones saw).
  std::vector<v1::JobEvent> stored = events;
  if (run.unstored_progress) stored.insert(stored.begin(), *run.unstored_progress);
  if (run.lost.load() ||
      !store_.finish(run.id, replica_, result.get(), stored, run.unstored_history.copy())) {
    log_.warn("job.lease_lost",
              {{"job", run.id}, {"reason", "finished elsewhere or taken over; result dropped"}});
    return;
  }
  for (auto& ev : events) run.log->publish(std::move(ev));
  if (metrics_) metrics_->job_finished(wire::state_name(state));
  nlohmann::json fields = {
      {"job", run.id}, {"state", wire::state_name(state)}, {"seconds", now - run.started}};
  if (result) {
    fields["energy"] = result->energy();
    fields["generations"] = result->generations();
    fields["evaluations"] = result->evaluations();
    fields["stop_reason"] = result->stop_reason();
  }
  if (!message.empty() && state != v1::JOB_STATE_SUCCEEDED) fields["reason"] = message;
  if (state == v1::JOB_STATE_FAILED)
    log_.warn("job.finished", fields);
  else
    log_.info("job.finished", fields);
}

// ---- lifecycle ----------------------------------------------------------------------------

void JobManager::begin_shutdown() {
  std::vector<std::string> queued;
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
    for (auto& [id, run] : running_) {
      if (store_.durable()) {
        run->suspend.store(true);
      } else if (!run->cancel.load()) {
        run->cancel_code = kUnavailable;
        run->cancel_message = "server shutting down";
        run->cancel.store(true);
      }
    }
  }
  work_.notify_all();
  int dropped = 0;
  if (!store_.durable()) {  // nothing survives a memory store: end the queued jobs now
    for (const auto& job : store_.list_jobs("")) {
      if (job.state != v1::JOB_STATE_QUEUED) continue;
      v1::JobEvent ev = state_event(v1::JOB_STATE_CANCELLED, kUnavailable, "server shutting down");
      ev.set_time_unix(now_unix());
      if (store_.cancel(job.id, ev) != CancelOutcome::cancelled_queued) continue;
      ++dropped;
      {
        std::lock_guard lock(mutex_);
        pins_.erase(job.id);
      }
      sync_open_log(job.id);
    }
  }
  std::lock_guard lock(mutex_);
  log_.info("jobs.shutdown", {{"queued_cancelled", dropped},
                              {"running", running_.size()},
                              {"running_jobs_resume_later", store_.durable()}});
}

bool JobManager::wait_idle(std::chrono::steady_clock::time_point deadline) {
  std::unique_lock lock(mutex_);
  return idle_.wait_until(lock, deadline, [&] { return running_.empty() && busy_ == 0; });
}

void JobManager::poke_watchers() {
  std::vector<std::shared_ptr<EventLog>> logs;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [id, weak] : logs_) {
      if (auto log = weak.lock()) logs.push_back(std::move(log));
    }
  }
  for (auto& log : logs) hub_.post(std::move(log));
}

int JobManager::running_jobs() {
  std::lock_guard lock(mutex_);
  return static_cast<int>(running_.size());
}

int JobManager::queued_jobs() {
  try {
    return static_cast<int>(store_.count_queued());
  } catch (const StoreError&) {
    return 0;
  }
}

bool JobManager::store_reachable() {
  try {
    store_.count_queued();
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

void JobManager::heartbeat_loop() {
  // Leases are renewed well before they run out; on a shared store this is also how a
  // cancel made on another replica reaches the runner, and how watchers here follow jobs
  // running elsewhere.
  const double period = store_.shared() ? std::clamp(options_.lease_seconds / 5, 0.05, 0.2)
                                        : std::min(1.0, options_.lease_seconds / 3);
  const double reap_every = std::clamp(options_.job_ttl_seconds / 2 + 0.01, 0.01, 1.0);
  auto last_reap = std::chrono::steady_clock::now();
  std::unique_lock lock(mutex_);
  while (!exiting_) {
    beat_wake_.wait_for(lock, seconds(std::min(period, reap_every)));
    if (exiting_) break;
    std::vector<std::string> ids;
    for (const auto& [id, run] : running_) ids.push_back(id);
    lock.unlock();
    try {
      const auto beat = store_.heartbeat(replica_, ids, now_unix(), options_.lease_seconds);
      {
        std::lock_guard guard(mutex_);
        for (const auto& id : beat.cancel) {
          auto it = running_.find(id);
          if (it == running_.end() || it->second->cancel.load()) continue;
          it->second->cancel_code = kCancelled;
          it->second->cancel_message = "cancelled by client";
          it->second->cancel.store(true);
        }
        for (const auto& id : beat.lost) {
          auto it = running_.find(id);
          if (it == running_.end()) continue;
          it->second->lost.store(true);
          it->second->cancel.store(true);
        }
      }
      if (store_.shared()) sync_mirrors();
      if (std::chrono::steady_clock::now() - last_reap >= seconds(reap_every)) {
        last_reap = std::chrono::steady_clock::now();
        const int expired = store_.expire(now_unix() - options_.job_ttl_seconds, options_.max_finished_jobs);
        if (expired > 0) log_.debug("jobs.expired", {{"count", expired}});
      }
    } catch (const StoreError& e) {
      log_.warn("store.error", {{"during", "heartbeat"}, {"reason", e.what()}});
    }
    if (store_.shared()) work_.notify_all();
    lock.lock();
  }
}

}  // namespace depath::service
