// SPDX-License-Identifier: MIT
// Limits and settings of a depathd server (each is a command-line flag of depathd).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace depath::service {

struct ServerOptions {
  std::string listen = "0.0.0.0:50051";  ///< host:port; port 0 picks a free port
  int threads = 0;                        ///< evaluation workers of the shared pool (0 = all cores)
  int max_running_jobs = 2;               ///< jobs solving at the same time
  int max_queued_jobs = 64;               ///< jobs waiting to run; more: RESOURCE_EXHAUSTED
  uint64_t mesh_cache_bytes = 1ull << 30; ///< budget of parsed meshes in memory (LRU)
  uint64_t max_upload_bytes = 256ull << 20;
  int max_message_bytes = 64 << 20;       ///< largest gRPC message received or sent
  double job_ttl_seconds = 3600;          ///< finished jobs are forgotten after this
  int64_t max_finished_jobs = 10000;      ///< and past this many, the oldest finished first
  double shutdown_timeout_seconds = 10;   ///< bound on a graceful shutdown
  std::string data_dir;                   ///< the SQLite store's directory when `store` is empty
  /// "memory", "sqlite:PATH", "postgresql://..."; empty: sqlite in data_dir, or memory
  /// when data_dir is empty too (depathd itself defaults data_dir, see main.cpp).
  std::string store;
  double checkpoint_seconds = 30;         ///< a running DE job saves its state this often
  double lease_seconds = 15;              ///< a replica's claim on a job lasts this long unrenewed
  /// This replica's name as a lease owner; empty: a random one. A stable name (a StatefulSet
  /// pod's) lets a restarted replica take its own running jobs back at once, lease or not.
  std::string replica_id;
  /// Accepted bearer tokens (any of them): calls need `authorization: Bearer TOKEN`; empty:
  /// no authentication. main.cpp gathers them from --auth-token (repeatable),
  /// --auth-token-file and DEPATHD_AUTH_TOKENS.
  std::vector<std::string> auth_tokens;
  double auth_failure_burst = 20;         ///< failed token checks a peer may make at once...
  double auth_failure_rate = 1;           ///< ...and per second after that; then RESOURCE_EXHAUSTED
  int max_jobs_per_client = 0;            ///< queued + running jobs of one token (or certificate, or peer) in the store, all replicas; 0 = no cap
  double max_requests_per_second_per_client = 0;  ///< calls per second of one token (or peer); 0 = no cap
  int max_concurrent_uploads = 4;         ///< UploadMesh streams in flight; more: RESOURCE_EXHAUSTED
  /// Memory of uploads being received plus mesh parses in flight, by the estimate of
  /// upload_budget.hpp (file bytes x 7, x 12 for PLY): one text upload of --max-upload-bytes fits.
  uint64_t max_upload_memory_bytes = 2ull << 30;
  std::string tls_cert;                   ///< PEM certificate chain: serve TLS (with tls_key)
  std::string tls_key;                    ///< PEM private key of tls_cert
  std::string tls_client_ca;              ///< PEM CA bundle: require client certificates it signed (mutual TLS)
  double tls_reload_seconds = 60;         ///< how often the TLS files are re-read (certificate rotation)
  std::string health_listen;              ///< host:port of a plaintext health-only port (empty: none)
  std::string log_format = "text";        ///< "text" or "json"
  std::string log_level = "info";         ///< spdlog level name ("off" in quiet tests)
  int upload_parsers = 2;                 ///< threads parsing uploaded meshes
  int max_concurrent_parses = 2;          ///< mesh parses (uploads and reloads) at the same time
  double parse_timeout_seconds = 60;      ///< budget of one parse, and of the wait for a parse slot
  uint64_t max_generations = 1000000;     ///< per DE job; more: RESOURCE_EXHAUSTED at submit
  uint64_t max_evaluations = 100000000;   ///< population x (generations + 1) per DE job
  uint64_t max_job_memory_bytes = 1ull << 30;  ///< estimate population x vertices x 16 bytes per job
  // The HTTP face (server/http/): /metrics, /healthz, /readyz, /v1 JSON + SSE, the web page.
  std::string http_listen;                ///< host:port; empty = off; port 0 picks a free port
  std::string web_root;                   ///< the web page's files; empty: `web` beside the executable
  int http_threads = 16;                  ///< HTTP worker threads (each open event stream holds one)
};

}  // namespace depath::service
