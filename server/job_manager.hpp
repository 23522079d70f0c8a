// SPDX-License-Identifier: MIT
// The job queue: validates and queues jobs, runs up to --max-running-jobs of them at once
// (one driver thread each, evaluation work on the server's shared ThreadPool), publishes
// their events, cancels them, forgets finished ones after --job-ttl-seconds.
#pragma once

#include "depath/util/thread_pool.hpp"
#include "depath/v1/job.pb.h"
#include "event_log.hpp"
#include "log.hpp"
#include "mesh_store.hpp"
#include "options.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace depath::service {

class JobManager {
 public:
  JobManager(const ServerOptions& options, MeshStore& meshes, EventHub& hub, ThreadPool& pool, Log& log);
  ~JobManager();  ///< cancels everything and joins the driver threads
  JobManager(const JobManager&) = delete;
  JobManager& operator=(const JobManager&) = delete;

  /// Validates and queues a job. Throws ServiceError / depath::Error (see job.proto).
  v1::SubmitJobResponse submit(const v1::SubmitJobRequest& request);
  v1::JobInfo get(const std::string& job_id);
  v1::JobResult result(const std::string& job_id);
  v1::ListJobsResponse list(const v1::ListJobsRequest& request);
  v1::JobInfo cancel(const std::string& job_id);
  /// The job's event log (NOT_FOUND for an unknown job).
  std::shared_ptr<EventLog> events(const std::string& job_id);

  /// Refuses new jobs (UNAVAILABLE) and cancels every queued and running one.
  void begin_shutdown();
  /// Waits until no job runs; false if `deadline` passed first.
  bool wait_idle(std::chrono::steady_clock::time_point deadline);

  int running_jobs();
  int queued_jobs();

 private:
  struct Job;
  void driver_loop();
  void reaper_loop();
  void run_job(const std::shared_ptr<Job>& job);
  void finish_locked(Job& job, v1::JobState state, int code, const std::string& message);
  v1::JobInfo info_locked(const Job& job) const;
  std::shared_ptr<Job> find_locked(const std::string& job_id) const;
  std::string new_job_id();

  const ServerOptions options_;
  MeshStore& meshes_;
  EventHub& hub_;
  ThreadPool& pool_;
  Log& log_;

  std::mutex mutex_;
  std::condition_variable work_, idle_, reaper_wake_;
  std::map<std::string, std::shared_ptr<Job>> jobs_;
  std::map<std::string, std::string> by_request_id_;
  std::deque<std::shared_ptr<Job>> queue_;
  int running_ = 0;
  bool stopping_ = false;  // shutting down: refuse new jobs
  bool exiting_ = false;   // threads must exit
  uint64_t counter_ = 0;
  uint64_t id_salt_ = 0;
  std::vector<std::thread> drivers_;
  std::thread reaper_;
};

}  // namespace depath::service
