// SPDX-License-Identifier: MIT
#include "metrics/service_metrics.hpp"

namespace depath::service {

using Type = MetricsRegistry::Type;

namespace {

struct Family {
  const char* name;
  Type type;
  const char* help;
};

// Every family but the histogram, which also needs buckets.
constexpr Family kFamilies[] = {
    {"depath_jobs", Type::gauge,
     "Jobs in the store by state (queued, running, succeeded, failed, cancelled)"},
    {"depath_queue_depth", Type::gauge, "Jobs waiting to run"},
    {"depath_running_jobs", Type::gauge, "Jobs solving on this replica"},
    {"depath_jobs_finished_total", Type::counter, "Jobs this replica ran to a terminal state, by state"},
    {"depath_evaluations_total", Type::counter,
     "Energy evaluations (decode + energy) of jobs run here; rate() gives evaluations per second"},
    {"depath_generations_total", Type::counter,
     "DE generations (progress reports) of jobs run here; rate() gives generations per second"},
    {"depath_mesh_cache_bytes", Type::gauge, "Memory of the parsed meshes in the cache"},
    {"depath_mesh_cache_budget_bytes", Type::gauge, "The cache's budget (--mesh-cache-bytes)"},
    {"depath_mesh_cache_meshes", Type::gauge, "Meshes in the cache"},
    {"depath_mesh_cache_hits_total", Type::counter, "Mesh lookups answered from the cache"},
    {"depath_mesh_cache_misses_total", Type::counter, "Mesh lookups that had to reload from the store"},
    {"depath_mesh_cache_evictions_total", Type::counter, "Meshes evicted to stay within the budget"},
    {"depath_stencil_builds_total", Type::counter,
     "Fast-marching stencil tables built for jobs (once per cached mesh; more means the cache drops them)"},
    {"depath_uploads_total", Type::counter, "Mesh uploads received in full, by transport"},
    {"depath_upload_bytes_total", Type::counter, "Bytes of the mesh uploads received in full, by transport"},
    {"depath_rpcs_total", Type::counter, "gRPC calls finished, by method and status code"},
    {"depath_http_requests_total", Type::counter, "HTTP requests answered, by route and status"},
    {"depath_watchers", Type::gauge, "Open event streams (gRPC WatchJob/Solve, HTTP SSE), by transport"},
    {"depath_auth_failures_total", Type::counter, "Calls refused for a missing or wrong token, by transport"},
    {"depath_up", Type::gauge, "1 while the server is serving"},
};

}  // namespace

ServiceMetrics::ServiceMetrics() {
  auto& r = registry_;
  for (const Family& f : kFamilies) r.declare(f.name, f.type, f.help);
  r.declare(
      "depath_decode_seconds", Type::histogram,
      "Time of one evaluation (fast-marching decode + energy), sampled once per generation as the "
      "generation's wall time x the job's share of the evaluation threads / its evaluations",
      {1e-5, 5e-5, 1e-4, 2.5e-4, 5e-4, 1e-3, 2.5e-3, 5e-3, 1e-2, 2.5e-2, 5e-2, 0.1, 0.25, 0.5, 1, 2.5, 5});
  r.set("depath_up", {}, 1);
  // Series that exist from the start, so that rate() and increase() see their first step.
  for (const char* name : {"depath_evaluations_total", "depath_generations_total"}) r.inc(name, {}, 0);
  for (const char* transport : {"grpc", "http"}) {
    r.inc("depath_auth_failures_total", {{"transport", transport}}, 0);
    r.inc("depath_uploads_total", {{"transport", transport}}, 0);
    r.inc("depath_upload_bytes_total", {{"transport", transport}}, 0);
    r.inc("depath_watchers", {{"transport", transport}}, 0);
  }
}

void ServiceMetrics::job_progress(int64_t evaluations, int generations, double decode_seconds) {
  if (evaluations > 0) registry_.inc("depath_evaluations_total", {}, static_cast<double>(evaluations));
  if (generations > 0) registry_.inc("depath_generations_total", {}, generations);
  if (decode_seconds >= 0) registry_.observe("depath_decode_seconds", {}, decode_seconds);
}

void ServiceMetrics::job_finished(const std::string& state) {
  registry_.inc("depath_jobs_finished_total", {{"state", state}});
}

void ServiceMetrics::rpc(const std::string& method, const std::string& code) {
  registry_.inc("depath_rpcs_total", {{"method", method}, {"code", code}});
}

void ServiceMetrics::http_request(const std::string& route, int status) {
  registry_.inc("depath_http_requests_total", {{"route", route}, {"status", std::to_string(status)}});
}

void ServiceMetrics::upload(uint64_t bytes, const std::string& transport) {
  registry_.inc("depath_uploads_total", {{"transport", transport}});
  registry_.inc("depath_upload_bytes_total", {{"transport", transport}}, static_cast<double>(bytes));
}

void ServiceMetrics::auth_failure(const std::string& transport) {
  registry_.inc("depath_auth_failures_total", {{"transport", transport}});
}

void ServiceMetrics::watcher_started(const std::string& transport) {
  registry_.inc("depath_watchers", {{"transport", transport}}, 1);
}

void ServiceMetrics::watcher_ended(const std::string& transport) {
  registry_.inc("depath_watchers", {{"transport", transport}}, -1);
}

}  // namespace depath::service
