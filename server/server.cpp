// SPDX-License-Identifier: MIT
#include "server.hpp"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/security/server_credentials.h>
#include <grpcpp/server.h>
#include <grpcpp/server_builder.h>

#include <condition_variable>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>

#include "depath/util/error.hpp"
#include "depath/util/thread_pool.hpp"
#include "depath/wire/wire.hpp"
#include "event_log.hpp"
#include "http/http_server.hpp"
#include "job_manager.hpp"
#include "job_service.hpp"
#include "log.hpp"
#include "mesh_service.hpp"
#include "mesh_store.hpp"
#include "metrics/rpc_interceptor.hpp"
#include "metrics/service_metrics.hpp"
#include "reflection_guard.hpp"
#include "service_context.hpp"
#include "store/job_store.hpp"
#include "tls_credentials.hpp"

namespace depath::service {

namespace {
void check_options(const ServerOptions& o) {
  auto bad = [](const std::string& what) { throw Error(ErrorCode::invalid_argument, what); };
  if (o.threads < 0) bad("--threads must be >= 0 (0 = all cores)");
  if (o.max_running_jobs < 1) bad("--max-running-jobs must be >= 1");
  if (o.max_queued_jobs < 0) bad("--max-queued-jobs must be >= 0");
  if (o.max_upload_bytes == 0) bad("--max-upload-bytes must be > 0");
  if (o.max_message_bytes < 1024) bad("--max-message-bytes must be >= 1024");
  if (o.job_ttl_seconds < 0) bad("--job-ttl-seconds must be >= 0");
  if (o.shutdown_timeout_seconds < 0) bad("--shutdown-timeout-seconds must be >= 0");
  if (o.upload_parsers < 1) bad("upload parser threads must be >= 1");
  if (!(o.checkpoint_seconds >= 0)) bad("--checkpoint-seconds must be >= 0 (0 = never)");
  if (!(o.lease_seconds > 0)) bad("--lease-seconds must be > 0");
  for (const auto& t : o.auth_tokens) {
    if (t.empty()) bad("an auth token is empty (--auth-token, --auth-token-file, DEPATHD_AUTH_TOKENS)");
    for (const unsigned char c : t) {
      if (c <= ' ' || c >= 0x7f)
        bad("an auth token contains a space or a non-printable character (tokens are sent as HTTP/2 header "
            "values)");
    }
  }
  if (!(o.auth_failure_burst >= 1)) bad("--auth-failure-burst must be >= 1");
  if (!(o.auth_failure_rate > 0)) bad("--auth-failure-rate must be > 0");
  if (o.max_jobs_per_client < 0) bad("--max-jobs-per-client must be >= 0 (0 = no cap)");
  if (!(o.max_requests_per_second_per_client >= 0))
    bad("--max-requests-per-second-per-client must be >= 0 (0 = no cap)");
  if (o.max_concurrent_uploads < 1) bad("--max-concurrent-uploads must be >= 1");
  if (o.max_upload_memory_bytes < 1) bad("--max-upload-memory-bytes must be >= 1");
}

std::string store_uri(const ServerOptions& o) {
  if (!o.store.empty()) return o.store;
  if (!o.data_dir.empty()) return "sqlite:" + (std::filesystem::path(o.data_dir) / "depath.db").string();
  return "memory";
}

std::unique_ptr<JobStore> open_store(const ServerOptions& o) {
  try {
    return JobStore::open(store_uri(o));
  } catch (const StoreError& e) {
    throw Error(ErrorCode::invalid_argument, e.what());
  }
}

int pool_workers(const ServerOptions& o) {
  if (o.threads > 0) return o.threads;
  const int hw = static_cast<int>(std::thread::hardware_concurrency());
  return std::max(1, hw);
}
}  // namespace

struct Server::Impl {
  explicit Impl(const ServerOptions& o)
      : options(o),
        log(o.log_format, o.log_level),
        // The pool's callers (one driver per running job) work too, so give it one fewer
        // worker than the threads asked for.
        pool(std::max(0, pool_workers(o) - 1)),
        store(open_store(o)),
        upload_memory(o.max_upload_memory_bytes),
        meshes(o.mesh_cache_bytes, *store, log,
               ParseLimits{o.max_concurrent_parses, o.parse_timeout_seconds, &upload_memory}),
        jobs(options, *store, meshes, hub, pool, log, &metrics),
        blocking(o.upload_parsers),
        access(options, log),
        context{options, meshes, jobs, log, blocking, metrics, access, upload_memory},
        mesh_service(context),
        job_service(context) {}

  ServerOptions options;
  Log log;
  ServiceMetrics metrics;
  ThreadPool pool;
  EventHub hub;
  std::unique_ptr<JobStore> store;
  UploadBudget upload_memory;  // before meshes, which reserve in it
  MeshStore meshes;
  JobManager jobs;
  ThreadPool blocking;  // tasks still queued at shutdown run before it is destroyed
  AccessGuard access;
  ServiceContext context;
  MeshServiceImpl mesh_service;
  JobServiceImpl job_service;
  std::unique_ptr<grpc::Server> server;
  std::unique_ptr<grpc::Server> health_server;  // --health-listen: plaintext, health only
  int port = 0;
  std::unique_ptr<HttpServer> http;  // --http-listen
  int health_port = 0;

  std::mutex mutex;
  std::condition_variable done_cv;
  bool shutdown_started = false;
  bool shutdown_done = false;
  bool clean = true;
};

Server::Server(const ServerOptions& options) {
  check_options(options);
  impl_ = std::make_unique<Impl>(options);
  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(options.listen, make_server_credentials(options), &impl_->port);
  // gRPC sets SO_REUSEPORT by default: a second server on a taken port would start and
  // silently take half the connections. Refuse the port instead.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.SetMaxReceiveMessageSize(options.max_message_bytes);
  builder.SetMaxSendMessageSize(options.max_message_bytes);
  builder.RegisterService(&impl_->mesh_service);
  builder.RegisterService(&impl_->job_service);
  auto interceptors = rpc_metrics_interceptors(impl_->metrics);
  interceptors.push_back(reflection_guard(impl_->access));
  builder.experimental().SetInterceptorCreators(std::move(interceptors));
  impl_->server = builder.BuildAndStart();
  if (!impl_->server || impl_->port == 0) {
    impl_.reset();
    throw Error(ErrorCode::invalid_argument,
                "cannot listen on '" + options.listen + "' (address in use or invalid?)");
  }
  add_state_collector(*impl_);
  if (!options.http_listen.empty()) {
    try {
      impl_->http = std::make_unique<HttpServer>(impl_->context);
    } catch (...) {
      impl_->server->Shutdown();
      impl_.reset();
      throw;
    }
  }
  if (!options.health_listen.empty()) start_health_server();
  impl_->server->GetHealthCheckService()->SetServingStatus(true);
  if (impl_->health_server) impl_->health_server->GetHealthCheckService()->SetServingStatus(true);
  impl_->log.info("server.started", {{"listen", options.listen},
                                     {"port", impl_->port},
                                     {"threads", impl_->pool.num_threads() + 1},
                                     {"max_running_jobs", options.max_running_jobs},
                                     {"max_queued_jobs", options.max_queued_jobs},
                                     {"mesh_cache_bytes", options.mesh_cache_bytes},
                                     {"store", impl_->store->description()},
                                     {"durable", impl_->store->durable()},
                                     {"replica", impl_->jobs.replica_id()},
                                     {"checkpoint_seconds", options.checkpoint_seconds},
                                     {"lease_seconds", options.lease_seconds},
                                     {"auth_tokens", options.auth_tokens.size()},
                                     {"tls", options.tls_cert.empty()        ? "off"
                                             : options.tls_client_ca.empty() ? "tls"
                                                                             : "mutual"},
                                     {"health_port", impl_->health_port}});
}

void Server::start_health_server() {
  // No service of ours is registered: only the standard health service (and reflection, which
  // then lists just that), so this unauthenticated plaintext port tells nothing but
  // SERVING / NOT_SERVING.
  const std::string address = impl_->options.health_listen;
  grpc::ServerBuilder builder;
  builder.AddListeningPort(impl_->options.health_listen, grpc::InsecureServerCredentials(),
                           &impl_->health_port);
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  impl_->health_server = builder.BuildAndStart();
  if (!impl_->health_server || impl_->health_port == 0) {
    impl_->server->Shutdown();
    impl_.reset();
    throw Error(ErrorCode::invalid_argument,
                "cannot listen on --health-listen '" + address + "' (address in use or invalid?)");
  }
}

int Server::health_port() const { return impl_->health_port; }

Server::~Server() {
  if (impl_) shutdown();
}

int Server::port() const { return impl_->port; }

int Server::http_port() const { return impl_->http ? impl_->http->port() : 0; }

void Server::add_state_collector(Impl& s) {
  // Gauges of live state, read at each scrape of /metrics.
  s.metrics.registry().add_collector([&s](MetricsRegistry& r) {
    std::map<v1::JobState, int64_t> by_state;
    try {
      by_state = s.jobs.jobs_by_state();
    } catch (const std::exception&) {
      // the store is unreachable: /readyz says so; keep the last values
      return;
    }
    for (const v1::JobState state : {v1::JOB_STATE_QUEUED, v1::JOB_STATE_RUNNING, v1::JOB_STATE_SUCCEEDED,
                                     v1::JOB_STATE_FAILED, v1::JOB_STATE_CANCELLED}) {
      r.set("depath_jobs", {{"state", wire::state_name(state)}}, static_cast<double>(by_state[state]));
    }
    r.set("depath_queue_depth", {}, static_cast<double>(by_state[v1::JOB_STATE_QUEUED]));  // the same count
    r.set("depath_running_jobs", {}, s.jobs.running_jobs());
    const MeshCacheStats c = s.meshes.cache_stats();
    r.set("depath_mesh_cache_bytes", {}, static_cast<double>(c.bytes));
    r.set("depath_mesh_cache_budget_bytes", {}, static_cast<double>(s.options.mesh_cache_bytes));
    r.set("depath_mesh_cache_meshes", {}, static_cast<double>(c.meshes));
    r.set("depath_mesh_cache_hits_total", {}, static_cast<double>(c.hits));
    r.set("depath_mesh_cache_misses_total", {}, static_cast<double>(c.misses));
    r.set("depath_mesh_cache_evictions_total", {}, static_cast<double>(c.evictions));
    r.set("depath_stencil_builds_total", {}, static_cast<double>(c.stencil_builds));
  });
}

bool Server::shutdown() {
  auto& s = *impl_;
  {
    std::unique_lock lock(s.mutex);
    if (s.shutdown_started) {
      s.done_cv.wait(lock, [&] { return s.shutdown_done; });
      return s.clean;
    }
    s.shutdown_started = true;
  }
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                    std::chrono::duration<double>(s.options.shutdown_timeout_seconds));
  s.log.info("server.shutting_down",
             {{"running_jobs", s.jobs.running_jobs()}, {"queued_jobs", s.jobs.queued_jobs()}});
  s.server->GetHealthCheckService()->SetServingStatus(false);
  if (s.health_server) s.health_server->GetHealthCheckService()->SetServingStatus(false);
  s.context.shutting_down.store(true);
  s.jobs.begin_shutdown();
  const bool clean = s.jobs.wait_idle(deadline);
  if (s.store->durable()) {  // the jobs live on: end the watch streams now, not at the deadline
    s.context.release_watchers.store(true);
    s.jobs.poke_watchers();
  }
  s.hub.flush();               // watchers now have their final events queued
  if (s.http) s.http->stop();  // event streams end after the events they have
  // Give open streams the rest of the budget (at least a moment) to deliver them.
  const auto grpc_deadline =
      std::max(deadline, std::chrono::steady_clock::now() + std::chrono::milliseconds(500));
  s.server->Shutdown(std::chrono::system_clock::now() +
                     std::chrono::duration_cast<std::chrono::system_clock::duration>(
                         grpc_deadline - std::chrono::steady_clock::now()));
  if (s.health_server) s.health_server->Shutdown(std::chrono::system_clock::now());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (clean)
    s.log.info("server.stopped", {{"seconds", seconds}});
  else
    s.log.warn("server.stopped", {{"seconds", seconds}, {"reason", "running jobs did not stop in time"}});
  {
    std::lock_guard lock(s.mutex);
    s.shutdown_done = true;
    s.clean = clean;
  }
  s.done_cv.notify_all();
  return clean;
}

void Server::wait() {
  auto& s = *impl_;
  std::unique_lock lock(s.mutex);
  s.done_cv.wait(lock, [&] { return s.shutdown_done; });
}

}  // namespace depath::service
