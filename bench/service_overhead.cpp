// SPDX-License-Identifier: MIT
// bench/service_overhead: what the network service costs over the embedded engine.
//
// Prints: the same job via `depath run` (through depathd) vs `depath solve` (in-process);
// the same job with 100 watchers attached; depathd's memory with 100 watchers; the time
// from SIGTERM to exit with a running job.
//
//   service_overhead --depathd build/server/depathd --depath build/client/depath
//                    [--mesh FILE -s S -t T] [--generations G] [--population P]
//                    [--threads N] [--watchers 100] [--repeat 3]
#include "depath/v1/job.grpc.pb.h"
#include "depath/v1/mesh.grpc.pb.h"
#include "bench_stats.hpp"
#include "depath/wire/wire.hpp"

#include <CLI/CLI.hpp>
#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;
namespace v1 = depath::v1;
using depath::bench::Clock;
using depath::bench::median;
using depath::bench::seconds_since;

namespace {

double run_timed(const std::string& command) {
  const auto t0 = Clock::now();
  const int rc = std::system((command + " > /dev/null 2>&1").c_str());
  const double s = seconds_since(t0);
  if (rc != 0) {
    std::fprintf(stderr, "command failed (%d): %s\n", rc, command.c_str());
    std::exit(1);
  }
  return s;
}

long rss_kib(pid_t pid, const char* field = "VmRSS:") {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(field, 0) == 0) return std::stol(line.substr(std::strlen(field)));
  }
  return -1;
}

struct Daemon {
  pid_t pid = -1;
  int port = 0;
  Daemon(const std::string& bin, const fs::path& dir, int threads) {
    const fs::path port_file = dir / "port";
    fs::remove(port_file);
    pid = ::fork();
    if (pid == 0) {
      const std::string t = std::to_string(threads);
      const std::string pf = port_file.string();
      FILE* f = std::freopen("/dev/null", "w", stderr);
      (void)f;
      ::execl(bin.c_str(), bin.c_str(), "--listen", "127.0.0.1:0", "--port-file", pf.c_str(), "--threads", t.c_str(),
              "--log-level", "warn", static_cast<char*>(nullptr));
      std::_Exit(127);
    }
    for (int i = 0; i < 1000 && !fs::exists(port_file); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::ifstream(port_file) >> port;
    if (port == 0) {
      std::fprintf(stderr, "depathd did not start\n");
      std::exit(1);
    }
  }
  std::string address() const { return "127.0.0.1:" + std::to_string(port); }
  double terminate() {
    const auto t0 = Clock::now();
    ::kill(pid, SIGTERM);
    ::waitpid(pid, nullptr, 0);
    pid = -1;
    return seconds_since(t0);
  }
  ~Daemon() {
    if (pid > 0) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
  }
};

/// A watcher on the client callback API (no thread per watcher here either).
class Watcher final : public grpc::ClientReadReactor<v1::JobEvent> {
 public:
  Watcher(v1::JobService::Stub* stub, const std::string& job_id) {
    request_.set_job_id(job_id);
    stub->async()->WatchJob(&context_, &request_, this);
    StartRead(&event_);
    StartCall();
  }
  void OnReadDone(bool ok) override {
    if (!ok) return;
    ++events_;
    if (event_.has_result()) energy_ = event_.result().energy();
    StartRead(&event_);
  }
  void OnDone(const grpc::Status& status) override {
    std::lock_guard lock(mutex_);
    ok_ = status.ok();
    done_ = true;
    cv_.notify_all();
  }
  void wait() {
    std::unique_lock lock(mutex_);
    cv_.wait(lock, [&] { return done_; });
  }
  int events() const { return events_; }
  double energy() const { return energy_; }
  bool ok() const { return ok_; }

 private:
  grpc::ClientContext context_;
  v1::WatchJobRequest request_;
  v1::JobEvent event_;
  std::atomic<int> events_{0};
  double energy_ = 0;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool done_ = false, ok_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  std::string depathd, depath, mesh;
  int source = 0, target = -1, generations = 60, population = 20, threads = 2, watchers = 100, repeat = 3;
  CLI::App app{"Overhead of the depath service over the embedded engine"};
  app.add_option("--depathd", depathd, "depathd binary")->required();
  app.add_option("--depath", depath, "depath binary")->required();
  app.add_option("--mesh", mesh, "Mesh file (default: ../shared/data/meshes/kitten.off)");
  app.add_option("-s,--source", source);
  app.add_option("-t,--target", target);
  app.add_option("--generations", generations)->capture_default_str();
  app.add_option("--population", population)->capture_default_str();
  app.add_option("--threads", threads, "Evaluation threads, for solve and for the server")->capture_default_str();
  app.add_option("--watchers", watchers)->capture_default_str();
  app.add_option("--repeat", repeat)->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (mesh.empty()) mesh = DEPATH_SHARED_DATA "/meshes/kitten.off";
  if (target < 0) target = 1250;

  const fs::path dir = fs::temp_directory_path() / ("depath_bench_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::printf("service overhead: mesh %s, %d -> %d, DE population %d, %d generations, %d threads\n", mesh.c_str(),
              source, target, population, generations, threads);
  char flags[256];
  std::snprintf(flags, sizeof flags, " -s %d -t %d --population %d --generations %d --seed 1", source, target,
                population, generations);
  const std::string out = (dir / "r.json").string();

  // 1. depath solve vs depath run.
  std::vector<double> solve_s, run_s;
  Daemon d(depathd, dir, threads);
  run_timed(depath + " upload " + mesh + " --server " + d.address());  // the mesh is on the server from now on
  for (int i = 0; i < repeat; ++i) {
    solve_s.push_back(run_timed(depath + " solve " + mesh + flags + " --threads " + std::to_string(threads) +
                                " --out " + out));
    run_s.push_back(run_timed(depath + " run " + mesh + flags + " --out " + out + " --server " + d.address()));
  }
  const double solve_med = median(solve_s), run_med = median(run_s);
  std::printf("depath solve          %8.3f s (median of %d)\n", solve_med, repeat);
  std::printf("depath run            %8.3f s (median of %d)  overhead %+.1f%%\n", run_med, repeat,
              100.0 * (run_med / solve_med - 1.0));

  // 2. The same job with `watchers` watchers attached (plus depath run's own).
  auto channel = grpc::CreateChannel(d.address(), grpc::InsecureChannelCredentials());
  auto jobs = v1::JobService::NewStub(channel);
  const std::string bytes = [&] {
    std::ifstream in(mesh, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }();
  depath::JobSpec job;
  job.source = source;
  job.target = target;
  job.de.population = population;
  job.de.generations = generations;
  job.seed = 1;
  const long rss_idle = rss_kib(d.pid);
  std::vector<double> watched_s;
  long rss_watched = 0;
  int min_events = 1 << 30;
  for (int i = 0; i < repeat; ++i) {
    v1::SubmitJobRequest req;
    *req.mutable_spec() = depath::wire::job_to_proto(job, depath::wire::sha256_hex(bytes));
    v1::SubmitJobResponse reply;
    const auto t0 = Clock::now();
    grpc::ClientContext ctx;
    if (!jobs->SubmitJob(&ctx, req, &reply).ok()) {
      std::fprintf(stderr, "submit failed\n");
      return 1;
    }
    std::vector<std::unique_ptr<Watcher>> ws;
    for (int w = 0; w < watchers; ++w) ws.push_back(std::make_unique<Watcher>(jobs.get(), reply.job_id()));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    rss_watched = std::max(rss_watched, rss_kib(d.pid));
    for (auto& w : ws) w->wait();
    watched_s.push_back(seconds_since(t0));
    for (auto& w : ws) {
      min_events = std::min(min_events, w->events());
      if (!w->ok()) std::fprintf(stderr, "a watcher failed\n");
    }
  }
  const double watched_med = median(watched_s);
  std::printf("%3d watchers attached %8.3f s (median of %d)  overhead %+.1f%% vs solve, %+.1f%% vs run; "
              "fewest events one watcher got: %d\n",
              watchers, watched_med, repeat, 100.0 * (watched_med / solve_med - 1.0),
              100.0 * (watched_med / run_med - 1.0), min_events);
  std::printf("depathd memory        %8.1f MiB idle, %.1f MiB with %d watchers (%.1f KiB per watcher), peak %.1f MiB\n",
              rss_idle / 1024.0, rss_watched / 1024.0, watchers,
              watchers > 0 ? double(rss_watched - rss_idle) / watchers : 0.0, rss_kib(d.pid, "VmHWM:") / 1024.0);

  // 3. SIGTERM with a running job.
  job.de.generations = 1000000;
  v1::SubmitJobRequest req;
  *req.mutable_spec() = depath::wire::job_to_proto(job, depath::wire::sha256_hex(bytes));
  v1::SubmitJobResponse reply;
  grpc::ClientContext ctx;
  jobs->SubmitJob(&ctx, req, &reply);
  Watcher w(jobs.get(), reply.job_id());
  while (w.events() < 5) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const double term = d.terminate();
  w.wait();
  std::printf("SIGTERM to exit       %8.3f s with a running job and a watcher (watcher ended %s)\n", term,
              w.ok() ? "cleanly" : "with an error");
  fs::remove_all(dir);
  return 0;
}
