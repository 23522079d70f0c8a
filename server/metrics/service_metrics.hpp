// SPDX-License-Identifier: MIT
// depathd's metrics (all named depath_*), fed by the job loop, the gRPC interceptor and the
// HTTP face, and exposed at /metrics (http/metrics_route.cpp).
//
// Counters only count up; rates (evaluations or generations per second) are computed by
// Prometheus from them, e.g. rate(depath_evaluations_total[1m]). Gauges that mirror live
// state (jobs by state, queue depth, mesh cache) are read at scrape time by collectors the
// server registers (server.cpp). Every update is a mutex and a map lookup: cheap enough for
// once per generation, per RPC and per HTTP request; nothing is measured per evaluation.
#pragma once

#include "metrics/registry.hpp"

#include <cstdint>
#include <string>

namespace depath::service {

class ServiceMetrics {
 public:
  ServiceMetrics();  ///< declares the depath_* families

  MetricsRegistry& registry() { return registry_; }
  std::string exposition() { return registry_.exposition(); }

  /// One generation (or one progress report) of a running job: `evaluations` new energy
  /// evaluations, `generations` new generations; `decode_seconds` >= 0 is one sample of
  /// the time one evaluation (decode + energy) took, or < 0 for none.
  void job_progress(int64_t evaluations, int generations, double decode_seconds);
  /// A job reached a terminal state ("succeeded", "failed", "cancelled").
  void job_finished(const std::string& state);
  void rpc(const std::string& method, const std::string& code);
  void http_request(const std::string& route, int status);
  /// A mesh upload that reached the parser (`transport` "grpc" or "http").
  void upload(uint64_t bytes, const std::string& transport);
  void auth_failure(const std::string& transport);
  void watcher_started(const std::string& transport);
  void watcher_ended(const std::string& transport);

 private:
  MetricsRegistry registry_;
};

}  // namespace depath::service
