// SPDX-License-Identifier: MIT
// The jobs of a depathd replica, kept in the job store (store/job_store.hpp): validates and
// stores submitted jobs; its driver threads (--max-running-jobs) claim queued jobs — or
// running ones whose runner died (lease expired) — from the store, and run them with
// evaluation work on the server's shared ThreadPool. A running DE job checkpoints every
// --checkpoint-seconds and resumes from its checkpoint after a restart or takeover, ending
// bit-identical to an uninterrupted run. Events are published to live watchers at once and
// stored (state changes and results always, progress at most a few times a second);
// watchers of jobs running elsewhere follow the store. Finished jobs are removed after
// --job-ttl-seconds.
//
// Shutdown: on a durable store running jobs checkpoint and are handed back (they resume
// on the next start or on another replica), queued ones stay queued; on `memory` every job
// is cancelled (nothing would survive).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "depath/util/thread_pool.hpp"
#include "depath/v1/job.pb.h"
#include "event_log.hpp"
#include "log.hpp"
#include "mesh_store.hpp"
#include "metrics/service_metrics.hpp"
#include "options.hpp"
#include "store/job_store.hpp"

namespace depath::service {

class JobManager {
 public:
  /// `metrics` (optional) gets evaluations, generations and decode-time samples of the runs.
  JobManager(const ServerOptions& options, JobStore& store, MeshStore& meshes, EventHub& hub,
             ThreadPool& pool, Log& log, ServiceMetrics* metrics = nullptr);
  ~JobManager();  ///< stops (as begin_shutdown) and joins the threads
  JobManager(const JobManager&) = delete;
  JobManager& operator=(const JobManager&) = delete;

  /// Validates and queues a job. Throws ServiceError / depath::Error (see job.proto).
  /// `client` (AccessGuard's identity of the caller) is stored with the job: with
  /// --max-jobs-per-client, RESOURCE_EXHAUSTED when it has that many jobs queued or running
  /// in the store, on whichever replicas share it.
  v1::SubmitJobResponse submit(const v1::SubmitJobRequest& request, const std::string& client = "");
  v1::JobInfo get(const std::string& job_id);
  /// The job as stored, with its whole spec (JobInfo's leaves out the per-vertex arrays; the
  /// store keeps them until the job finishes). NOT_FOUND as get().
  JobRecord record(const std::string& job_id) { return find(job_id); }
  v1::JobResult result(const std::string& job_id);
  /// Best and mean energy per generation so far (the store's history and, for a job running
  /// here, the generations not stored yet), thinned as store/job_store.hpp says.
  std::vector<ProgressPoint> progress_history(const std::string& job_id);
  v1::ListJobsResponse list(const v1::ListJobsRequest& request);
  v1::JobInfo cancel(const std::string& job_id);
  /// The job's event log (NOT_FOUND for an unknown job).
  std::shared_ptr<EventLog> events(const std::string& job_id);

  /// Refuses new jobs (UNAVAILABLE); suspends (durable store) or cancels (memory) the
  /// running ones, and on memory cancels the queued ones.
  void begin_shutdown();
  /// Waits until no job runs here; false if `deadline` passed first.
  bool wait_idle(std::chrono::steady_clock::time_point deadline);

  /// Wakes every watch stream (their reactors re-check the server's state).
  void poke_watchers();

  int running_jobs();
  int queued_jobs();
  /// Jobs in the store per state; throws StoreError when the store is unreachable.
  std::map<v1::JobState, int64_t> jobs_by_state() { return store_.count_by_state(); }
  /// True when the store answers a query (readiness).
  bool store_reachable();
  const std::string& replica_id() const { return replica_; }

 private:
  struct Running;
  void driver_loop();
  void heartbeat_loop();
  void run_job(JobRecord job);
  void execute(Running& run, const JobRecord& job);
  bool emit(Running& run, v1::JobEvent event, bool persist);
  void finish(Running& run, v1::JobState state, int code, const std::string& message,
              const std::shared_ptr<v1::JobResult>& result);
  v1::JobInfo info_of(const JobRecord& job, int queue_position);
  JobRecord find(const std::string& job_id);
  std::shared_ptr<EventLog> log_for(const std::string& job_id);
  void sync_log(const std::string& job_id, const std::shared_ptr<EventLog>& log);
  /// Brings the job's log up to date with the store if some watcher here has it open (a
  /// cancel the store itself numbered).
  void sync_open_log(const std::string& job_id);
  void sync_mirrors();

  const ServerOptions options_;
  JobStore& store_;
  MeshStore& meshes_;
  EventHub& hub_;
  ThreadPool& pool_;
  Log& log_;
  ServiceMetrics* metrics_;
  const std::string replica_;  // this process's identity as a lease owner

  std::mutex mutex_;
  std::condition_variable work_, idle_, beat_wake_;
  std::map<std::string, std::shared_ptr<Running>> running_;
  std::map<std::string, std::weak_ptr<EventLog>> logs_;     // logs someone holds (watchers, runners)
  std::map<std::string, std::shared_ptr<MeshLease>> pins_;  // meshes of jobs submitted here, until they run
  int busy_ = 0;                                            // drivers between claim and the end of the run
  bool stopping_ = false;                                   // shutting down: refuse new jobs, claim nothing
  bool exiting_ = false;                                    // threads must exit
  std::vector<std::thread> drivers_;
  std::thread heartbeat_;
};

}  // namespace depath::service
