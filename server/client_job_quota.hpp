// SPDX-License-Identifier: MIT
// --max-jobs-per-client: how many queued + running jobs one client (token, mutual-TLS
// certificate or peer; see AccessGuard::check) may have on this replica.
#pragma once

#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <string>

#include "job_manager.hpp"

namespace depath::service {

class ClientJobQuota {
 public:
  /// max_jobs <= 0: no cap (submit() just submits).
  ClientJobQuota(int max_jobs, JobManager& jobs) : max_(max_jobs), jobs_(jobs) {}

  /// Calls `submit` unless `client` already has max_jobs jobs queued or running (or being
  /// submitted): then throws ServiceError(RESOURCE_EXHAUSTED) naming --max-jobs-per-client.
  /// The new job counts for the client until it reaches a terminal state.
  v1::SubmitJobResponse submit(const std::string& client,
                               const std::function<v1::SubmitJobResponse()>& submit);

 private:
  /// Forgets the client's jobs that have finished (or expired); asks the job manager, unlocked.
  void forget_finished(const std::string& client);

  struct Jobs {
    std::set<std::string> active;
    int submitting = 0;
  };
  const int max_;
  JobManager& jobs_;
  std::mutex mutex_;
  std::map<std::string, Jobs> clients_;
};

}  // namespace depath::service
