// SPDX-License-Identifier: MIT
#include "client_job_quota.hpp"

#include <vector>

#include "service_error.hpp"

namespace depath::service {

void ClientJobQuota::forget_finished(const std::string& client) {
  std::vector<std::string> ids;
  {
    std::lock_guard lock(mutex_);
    auto it = clients_.find(client);
    if (it == clients_.end()) return;
    ids.assign(it->second.active.begin(), it->second.active.end());
  }
  std::vector<std::string> finished;
  for (const auto& id : ids) {
    try {
      const auto state = jobs_.get(id).state();
      if (state != v1::JOB_STATE_QUEUED && state != v1::JOB_STATE_RUNNING) finished.push_back(id);
    } catch (...) {  // expired or deleted: no longer counts
      finished.push_back(id);
    }
  }
  std::lock_guard lock(mutex_);
  auto it = clients_.find(client);
  if (it == clients_.end()) return;
  for (const auto& id : finished) it->second.active.erase(id);
}

v1::SubmitJobResponse ClientJobQuota::submit(const std::string& client,
                                             const std::function<v1::SubmitJobResponse()>& submit) {
  if (max_ <= 0) return submit();
  forget_finished(client);
  {
    std::lock_guard lock(mutex_);
    Jobs& mine = clients_[client];
    const size_t held = mine.active.size() + static_cast<size_t>(mine.submitting);
    if (held >= static_cast<size_t>(max_)) {
      throw ServiceError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                         "client " + client + " already has " + std::to_string(held) +
                             " jobs queued or running, the limit per client (--max-jobs-per-client " +
                             std::to_string(max_) + "); wait for one to finish");
    }
    ++mine.submitting;
  }
  auto release = [&](const std::string* job_id) {
    std::lock_guard lock(mutex_);
    Jobs& mine = clients_[client];
    --mine.submitting;
    if (job_id) mine.active.insert(*job_id);
    if (mine.active.empty() && mine.submitting == 0) clients_.erase(client);
  };
  v1::SubmitJobResponse reply;
  try {
    reply = submit();
  } catch (...) {
    release(nullptr);
    throw;
  }
  release(&reply.job_id());
  return reply;
}

}  // namespace depath::service
