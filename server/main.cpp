// SPDX-License-Identifier: MIT
// depathd: the depath gRPC server (SPEC §3).
#include "depath/util/error.hpp"
#include "server.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <future>
#include <pthread.h>
#include <stdexcept>
#include <string>
#include <vector>
#include <unistd.h>

namespace {
// Durable by default: a user's state directory (XDG base directory spec).
std::string default_data_dir() {
  if (const char* state = std::getenv("XDG_STATE_HOME"); state && *state) return std::string(state) + "/depath";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.local/state/depath";
  return {};
}
// --auth-token (each), --auth-token-file (one a line) and DEPATHD_AUTH_TOKENS (separated by
// commas or white space): every one is accepted.
std::vector<std::string> gather_tokens(std::vector<std::string> tokens, const std::string& file) {
  auto add_words = [&](const std::string& text, const std::string& separators) {
    size_t start = 0;
    while ((start = text.find_first_not_of(separators, start)) != std::string::npos) {
      const size_t end = text.find_first_of(separators, start);
      tokens.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
      start = end;
    }
  };
  if (const char* env = std::getenv("DEPATHD_AUTH_TOKENS"); env && *env) add_words(env, ", \t\r\n");
  if (!file.empty()) {
    std::ifstream in(file);
    if (!in) throw std::runtime_error("--auth-token-file '" + file + "': cannot open the file");
    std::string line;
    int count = 0;
    while (std::getline(in, line)) {
      const size_t first = line.find_first_not_of(" \t\r");
      if (first == std::string::npos || line[first] == '#') continue;
      const size_t last = line.find_last_not_of(" \t\r");
      tokens.push_back(line.substr(first, last - first + 1));
      ++count;
    }
    if (count == 0) throw std::runtime_error("--auth-token-file '" + file + "' holds no token");
  }
  return tokens;
}
}  // namespace

int main(int argc, char** argv) {
  depath::service::ServerOptions o;
  std::string port_file;
  CLI::App app{"depathd: the depath gRPC server (mesh and job services, health, reflection)"};
  app.set_version_flag("--version", "depathd 0.1.0");
  app.add_option("--listen", o.listen, "Address to listen on, host:port (port 0 picks a free one)")
      ->capture_default_str();
  app.add_option("--threads", o.threads, "Evaluation threads shared by all running jobs (0 = all cores)")
      ->capture_default_str();
  app.add_option("--max-running-jobs", o.max_running_jobs, "Jobs solving at the same time")->capture_default_str();
  app.add_option("--max-queued-jobs", o.max_queued_jobs, "Jobs waiting to run; more are refused (RESOURCE_EXHAUSTED)")
      ->capture_default_str();
  app.add_option("--mesh-cache-bytes", o.mesh_cache_bytes, "Memory budget of parsed meshes (LRU; in-use meshes stay)")
      ->capture_default_str();
  app.add_option("--max-upload-bytes", o.max_upload_bytes, "Largest mesh file accepted by UploadMesh")
      ->capture_default_str();
  app.add_option("--max-message-bytes", o.max_message_bytes, "Largest gRPC message received or sent")
      ->capture_default_str();
  app.add_option("--job-ttl-seconds", o.job_ttl_seconds, "How long finished jobs (and results) are kept")
      ->capture_default_str();
  app.add_option("--max-finished-jobs", o.max_finished_jobs,
                 "Finished jobs kept (with their results); past it the oldest are forgotten first, TTL or not")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--shutdown-timeout-seconds", o.shutdown_timeout_seconds,
                 "Bound on a graceful shutdown (SIGTERM/SIGINT)")
      ->capture_default_str();
  app.add_option("--max-concurrent-parses", o.max_concurrent_parses,
                 "Mesh parses (uploads and reloads from --data-dir) running at the same time")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--parse-timeout-seconds", o.parse_timeout_seconds,
                 "Budget of one mesh parse (and of the wait for a parse slot); past it RESOURCE_EXHAUSTED")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--max-generations", o.max_generations, "Largest number of generations of a DE job")
      ->capture_default_str();
  app.add_option("--max-evaluations", o.max_evaluations,
                 "Largest population x (generations + 1) of a DE job")
      ->capture_default_str();
  app.add_option("--max-job-memory-bytes", o.max_job_memory_bytes,
                 "Memory a DE job may take by the estimate population x vertices x 16 bytes")
      ->capture_default_str();
  app.add_option("--data-dir", o.data_dir,
                 "Directory of the default store (SQLite file depath.db: meshes, jobs, events, results, "
                 "checkpoints). Default: $XDG_STATE_HOME/depath, else ~/.local/state/depath")
      ->envname("DEPATHD_DATA_DIR");
  app.add_option("--store", o.store,
                 "Where jobs and meshes live: sqlite:PATH, postgresql://USER@HOST:PORT/DB (shared by replicas) or "
                 "memory (nothing survives a restart). Default: sqlite:<data-dir>/depath.db")
      ->envname("DEPATHD_STORE");
  app.add_option("--checkpoint-seconds", o.checkpoint_seconds,
                 "A running DE job saves its whole state this often (and at SIGTERM); it resumes from there "
                 "after a restart, bit-identical to an uninterrupted run (0 = only at SIGTERM)")
      ->capture_default_str();
  app.add_option("--lease-seconds", o.lease_seconds,
                 "A replica's claim on a running job lasts this long without renewal; then another replica "
                 "takes the job over from its checkpoint")
      ->capture_default_str();
  app.add_option("--replica-id", o.replica_id,
                 "This replica's name on a shared store (e.g. a StatefulSet pod name; unique among live "
                 "replicas). A restarted replica takes its running jobs back at once instead of after "
                 "--lease-seconds. Default: a random name per start")
      ->envname("DEPATHD_REPLICA_ID");
  std::vector<std::string> tokens;
  std::string token_file;
  app.add_option("--auth-token", tokens,
                 "Require metadata 'authorization: Bearer TOKEN' on every call (health exempt); repeat for several "
                 "tokens. Visible in `ps`: prefer --auth-token-file or DEPATHD_AUTH_TOKENS")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app.add_option("--auth-token-file", token_file,
                 "File of accepted tokens, one per line (blank lines and lines starting with # ignored)")
      ->check(CLI::ExistingFile);
  app.add_option("--auth-failure-burst", o.auth_failure_burst,
                 "Failed token checks one peer (IP address) may make at once...")
      ->capture_default_str();
  app.add_option("--auth-failure-rate", o.auth_failure_rate,
                 "...and per second after that; past it the peer's calls get RESOURCE_EXHAUSTED")
      ->capture_default_str();
  app.add_option("--max-jobs-per-client", o.max_jobs_per_client,
                 "Queued + running jobs of one client (its token; else its mutual-TLS certificate name; else its IP "
                 "address), counted in the job store: across all replicas sharing it; 0 = no cap")
      ->capture_default_str();
  app.add_option("--max-requests-per-second-per-client", o.max_requests_per_second_per_client,
                 "Calls per second of one client (identified as for --max-jobs-per-client); 0 = no cap")
      ->capture_default_str();
  app.add_option("--max-concurrent-uploads", o.max_concurrent_uploads,
                 "Mesh uploads in flight at once; more are refused (RESOURCE_EXHAUSTED)")
      ->capture_default_str();
  app.add_option("--max-upload-memory-bytes", o.max_upload_memory_bytes,
                 "Memory that mesh uploads being received and mesh parses in flight (uploads and reloads) may hold "
                 "together, estimated as the file's bytes x 7 (x 12 for PLY); an upload that does not fit is refused "
                 "(RESOURCE_EXHAUSTED, HTTP 429), a reload waits up to --parse-timeout-seconds")
      ->capture_default_str();
  app.add_option("--tls-cert", o.tls_cert, "PEM certificate (chain) of the server: serve TLS (needs --tls-key)")
      ->envname("DEPATHD_TLS_CERT");
  app.add_option("--tls-key", o.tls_key, "PEM private key of --tls-cert (unencrypted)")->envname("DEPATHD_TLS_KEY");
  app.add_option("--tls-client-ca", o.tls_client_ca,
                 "PEM CA bundle: mutual TLS, clients must present a certificate signed by it")
      ->envname("DEPATHD_TLS_CLIENT_CA");
  app.add_option("--tls-reload-seconds", o.tls_reload_seconds,
                 "How often the TLS files are re-read: a renewed certificate is served to new connections "
                 "without a restart (replace key and certificate together, e.g. by renaming a directory)")
      ->capture_default_str();
  app.add_option("--health-listen", o.health_listen,
                 "Also serve the standard gRPC health service alone, in plaintext, on this host:port (for "
                 "probes that cannot speak TLS or send tokens; e.g. 127.0.0.1:50052 or 0.0.0.0:50052)");
  app.add_option("--log-format", o.log_format, "Log lines as text or json")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();
  app.add_option("--log-level", o.log_level, "trace, debug, info, warn, error or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
      ->capture_default_str();
  app.add_option("--port-file", port_file, "Write the port listened on to this file once serving");
  std::string http_port_file;
  app.add_option("--http-listen", o.http_listen,
                 "Serve HTTP on HOST:PORT (off unless given): /metrics (Prometheus), /healthz, /readyz, the JSON + "
                 "Server-Sent-Events API under /v1/ and the web page (/, /jobs/JOB_ID)");
  app.add_option("--web-root", o.web_root,
                 "Directory of the web page's files (index.html, assets/). Default: 'web' beside the depathd "
                 "executable, or ../share/depath/web from it (installed), if it exists, else a plain HTML view");
  app.add_option("--http-threads", o.http_threads,
                 "HTTP worker threads; each open event stream holds one (streams beyond threads - 4 get 503)")
      ->capture_default_str()->check(CLI::Range(2, 1024));
  app.add_option("--http-port-file", http_port_file, "Write the HTTP port to this file once serving");
  CLI11_PARSE(app, argc, argv);
  try {
    o.auth_tokens = gather_tokens(tokens, token_file);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "depathd: error: %s\n", e.what());
    return 2;
  }
  if (o.store.empty() && o.data_dir.empty()) o.data_dir = default_data_dir();
  if (o.store.empty() && o.data_dir.empty()) {
    std::fprintf(stderr, "depathd: error: no --data-dir given and neither XDG_STATE_HOME nor HOME is set\n");
    return 2;
  }

  // Handle SIGTERM/SIGINT on this thread only: block them before any thread starts.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  std::unique_ptr<depath::service::Server> server;
  try {
    server = std::make_unique<depath::service::Server>(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "depathd: error: %s\n", e.what());
    return 2;
  }
  if (!port_file.empty()) {
    std::ofstream(port_file + ".tmp") << server->port() << '\n';
    std::rename((port_file + ".tmp").c_str(), port_file.c_str());
  }
  if (!http_port_file.empty() && server->http_port() > 0) {
    std::ofstream(http_port_file + ".tmp") << server->http_port() << '\n';
    std::rename((http_port_file + ".tmp").c_str(), http_port_file.c_str());
  }
  int sig = 0;
  sigwait(&signals, &sig);
  // Bounded exit: if the graceful path overruns (a job ignoring cancellation), leave anyway.
  std::thread([timeout = o.shutdown_timeout_seconds] {
    std::this_thread::sleep_for(std::chrono::duration<double>(timeout + 5.0));
    std::fprintf(stderr, "depathd: shutdown overran its bound; exiting now\n");
    _exit(3);
  }).detach();
  const bool clean = server->shutdown();
  if (!clean) {
    std::fprintf(stderr, "depathd: running jobs did not stop within --shutdown-timeout-seconds; exiting\n");
    _exit(3);
  }
  server.reset();
  return 0;
}
