// SPDX-License-Identifier: MIT
// What the service implementations (gRPC and HTTP) share: the stores, the limits, and the
// checks that every call goes through (authentication and request rate, shutting down).
#pragma once

#include <grpcpp/server_context.h>
#include <grpcpp/support/status.h>

#include <algorithm>
#include <atomic>
#include <string>
#include <string_view>

#include "access_guard.hpp"
#include "depath/util/thread_pool.hpp"
#include "job_manager.hpp"
#include "log.hpp"
#include "mesh_store.hpp"
#include "metrics/service_metrics.hpp"
#include "options.hpp"
#include "upload_budget.hpp"

namespace depath::service {

struct ServiceContext {
  const ServerOptions& options;
  MeshStore& meshes;
  JobManager& jobs;
  Log& log;
  ThreadPool& blocking;  ///< its own workers for slow work (mesh parsing), off gRPC's threads
  ServiceMetrics& metrics;
  AccessGuard& access;
  UploadBudget& upload_memory;  ///< --max-upload-memory-bytes: uploads (both transports) and parses
  std::atomic<bool> shutting_down{false};
  /// Set once a durable server's jobs are handed back at shutdown: watch streams end, after
  /// the events they have not sent yet, with UNAVAILABLE (the client reconnects).
  std::atomic<bool> release_watchers{false};
  std::atomic<int> uploads{0};  ///< UploadMesh streams in flight (--max-concurrent-uploads)
  std::atomic<int> parked{0};   ///< calls waiting on `blocking` for a mesh reload (park())

  /// AccessGuard::check of the call (`method` names it in logs): OK, or UNAUTHENTICATED /
  /// RESOURCE_EXHAUSTED. `client`, if given, receives the caller's identity for quotas.
  grpc::Status authenticate(const grpc::CallbackServerContext* ctx, std::string_view method,
                            std::string* client = nullptr) const {
    const bool mutual_tls = !options.tls_client_ca.empty();
    return access.check(method, ctx->client_metadata(), ctx->peer(), client,
                        mutual_tls ? AccessGuard::certificate_name(*ctx) : std::string());
  }

  /// The same check for another transport (HTTP): `authorization` is the value of the
  /// Authorization header sent (null when none was), `peer` in gRPC's form ("ipv4:ADDR:PORT").
  grpc::Status authorize(std::string_view method, const std::string* authorization, const std::string& peer,
                         std::string* client = nullptr) const {
    AccessGuard::Metadata metadata;
    if (authorization) metadata.emplace("authorization", grpc::string_ref(*authorization));
    return access.check(method, metadata, peer, client);
  }

  /// Takes a place for a call that waits on `blocking` for its mesh to reload (unary_blocking):
  /// OK, or RESOURCE_EXHAUSTED when --max-queued-jobs + --max-running-jobs calls wait already
  /// (each would become a queued or running job). unpark() gives the place back.
  grpc::Status park() {
    const int limit = std::max(1, options.max_queued_jobs + options.max_running_jobs);
    if (parked.fetch_add(1) >= limit) {
      parked.fetch_sub(1);
      return {grpc::StatusCode::RESOURCE_EXHAUSTED,
              std::to_string(limit) +
                  " calls already wait for meshes to reload from the store "
                  "(--max-queued-jobs + --max-running-jobs); try again shortly"};
    }
    return grpc::Status::OK;
  }
  void unpark() { parked.fetch_sub(1); }

  /// authenticate(), then UNAVAILABLE while shutting down (for calls that start new work).
  grpc::Status admit(const grpc::CallbackServerContext* ctx, std::string_view method,
                     std::string* client = nullptr) const {
    grpc::Status s = authenticate(ctx, method, client);
    if (!s.ok()) return s;
    if (shutting_down.load()) return {grpc::StatusCode::UNAVAILABLE, "server is shutting down"};
    return grpc::Status::OK;
  }
};

}  // namespace depath::service
