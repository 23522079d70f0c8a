// SPDX-License-Identifier: MIT
// What the gRPC service implementations share: the stores, the limits, and the checks that
// every call goes through (authentication, shutting down).
#pragma once

#include "job_manager.hpp"
#include "log.hpp"
#include "mesh_store.hpp"
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
  std::atomic<bool> shutting_down{false};
  /// Set once a durable server's jobs are handed back at shutdown: watch streams end, after
  /// the events they have not sent yet, with UNAVAILABLE (the client reconnects).
  std::atomic<bool> release_watchers{false};

  /// OK, or UNAUTHENTICATED when --auth-token is set and the call lacks
  /// `authorization: Bearer TOKEN`.
  grpc::Status authenticate(const grpc::CallbackServerContext* ctx) const {
    if (options.auth_token.empty()) return grpc::Status::OK;
    const auto& md = ctx->client_metadata();
    auto it = md.find("authorization");
    if (it == md.end()) {
      return {grpc::StatusCode::UNAUTHENTICATED, "missing 'authorization: Bearer TOKEN' metadata (server requires a token)"};
    }
    const std::string expected = "Bearer " + options.auth_token;
    const grpc::string_ref got = it->second;
    if (got.size() != expected.size() || std::string(got.data(), got.size()) != expected) {
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
