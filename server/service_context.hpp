// SPDX-License-Identifier: MIT
// What the gRPC service implementations share: the stores, the limits, and the checks that
// every call goes through (authentication, shutting down).
#pragma once

#include "job_manager.hpp"
#include "log.hpp"
#include "mesh_store.hpp"
#include "metrics/service_metrics.hpp"
#include "options.hpp"
#include "task_queue.hpp"

#include <grpcpp/server_context.h>
#include <grpcpp/support/status.h>

#include <atomic>

namespace depath::service {

struct ServiceContext {
  const ServerOptions& options;
  MeshStore& meshes;
  JobManager& jobs;
  Log& log;
  TaskQueue& blocking;  ///< for slow work (mesh parsing)
  ServiceMetrics& metrics;
  std::atomic<bool> shutting_down{false};
  /// Set once a durable server's jobs are handed back at shutdown: watch streams end, after
  /// the events they have not sent yet, with UNAVAILABLE (the client reconnects).
  std::atomic<bool> release_watchers{false};

  /// OK, or UNAUTHENTICATED when --auth-token is set and the call lacks
  /// `authorization: Bearer TOKEN`.
  grpc::Status authenticate(const grpc::CallbackServerContext* ctx) const {
    const auto& md = ctx->client_metadata();
    auto it = md.find("authorization");
    if (it == md.end()) return authorize(nullptr);
    const std::string got(it->second.data(), it->second.size());
    return authorize(&got);
  }

  /// The token check itself, for any transport (gRPC metadata, the HTTP Authorization
  /// header): `authorization` is the value sent, or null when none was.
  grpc::Status authorize(const std::string* authorization) const {
    if (options.auth_token.empty()) return grpc::Status::OK;
    if (!authorization) {
      return {grpc::StatusCode::UNAUTHENTICATED, "missing 'authorization: Bearer TOKEN' metadata (server requires a token)"};
    }
    const std::string expected = "Bearer " + options.auth_token;
    if (authorization->size() != expected.size() || *authorization != expected) {
      return {grpc::StatusCode::UNAUTHENTICATED, "invalid token in 'authorization' metadata"};
    }
    return grpc::Status::OK;
  }

  /// authenticate(), then UNAVAILABLE while shutting down (for calls that start new work).
  grpc::Status admit(const grpc::CallbackServerContext* ctx) const {
    grpc::Status s = authenticate(ctx);
    if (!s.ok()) return s;
    if (shutting_down.load()) return {grpc::StatusCode::UNAVAILABLE, "server is shutting down"};
    return grpc::Status::OK;
  }
};

}  // namespace depath::service
