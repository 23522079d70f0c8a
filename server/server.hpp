// SPDX-License-Identifier: MIT
// depathd's server as a library: tests start it in-process on 127.0.0.1:0.
#pragma once

#include "options.hpp"

#include <chrono>
#include <memory>

namespace depath::service {

class Server {
 public:
  /// Builds the stores, the pool and the gRPC server, and starts listening. Throws
  /// depath::Error(invalid_argument) for bad options or an address it cannot bind.
  explicit Server(const ServerOptions& options);
  ~Server();  ///< shutdown() if not done yet
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// The port it listens on (the chosen one when the options said port 0).
  int port() const;
  /// The HTTP port (--http-listen), or 0 when there is no HTTP listener.
  int http_port() const;
  /// The port of --health-listen (0 without it).
  int health_port() const;

  /// Graceful shutdown, bounded by options.shutdown_timeout_seconds: health goes
  /// NOT_SERVING, new work is refused with UNAVAILABLE; on a durable store running jobs
  /// checkpoint and are handed back (they resume after a restart or on another replica),
  /// on `memory` queued and running jobs are cancelled (watchers get the final CANCELLED
  /// event); then the gRPC server stops.
  /// Returns false if running jobs did not stop in time. Idempotent.
  bool shutdown();

  /// Blocks until shutdown() completed.
  void wait();

  struct Impl;

 private:
  static void add_state_collector(Impl& s);
  void start_health_server();
  std::unique_ptr<Impl> impl_;
};

}  // namespace depath::service
