// SPDX-License-Identifier: MIT
// The real binaries: depathd started as a process, driven by the `depath` client.
#include "service_test_support.hpp"
#include "time_scale.hpp"

#include <nlohmann/json.hpp>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace depath::test {
namespace {

namespace fs = std::filesystem;

constexpr int kShutdownSeconds = 5;  // every Daemon's --shutdown-timeout-seconds

struct CommandResult {
  int rc = -1;
  std::string output;  // stdout and stderr
};

CommandResult run_command(const std::string& command) {
  CommandResult r;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) r.output.append(buf, n);
  const int status = ::pclose(pipe);
  r.rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// The last non-empty line (the id a command prints on stdout after any notes).
std::string last_line(const std::string& text) {
  std::string t = text;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  return t.substr(t.find_last_of('\n') + 1);
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// depathd as a child process on 127.0.0.1 with a free port.
class Daemon {
 public:
  explicit Daemon(const fs::path& dir, std::vector<std::string> extra = {}) {
    const fs::path port_file = dir / "port";
    fs::remove(port_file);
    log_ = dir / "depathd.log";
    std::vector<std::string> args = {DEPATHD_BIN, "--listen", "127.0.0.1:0", "--port-file", port_file.string(),
                                     "--threads", "2", "--shutdown-timeout-seconds", std::to_string(kShutdownSeconds)};
    args.insert(args.end(), extra.begin(), extra.end());
    pid_ = ::fork();
    if (pid_ == 0) {
      FILE* f = std::freopen(log_.c_str(), "w", stderr);
      (void)f;
      std::vector<char*> argv;
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(argv[0], argv.data());
      std::_Exit(127);
    }
    const int polls = static_cast<int>(1000 * time_scale());  // 10 s (times the sanitizer slow-down) to start
    for (int i = 0; i < polls && !fs::exists(port_file); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    port_ = std::stoi(read_text(port_file));
  }
  ~Daemon() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  /// SIGTERM, then waits; returns the exit status and the seconds it took.
  std::pair<int, double> terminate() {
    const auto t0 = std::chrono::steady_clock::now();
    ::kill(pid_, SIGTERM);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1,
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
  }
  std::string log() const { return read_text(log_); }

 private:
  pid_t pid_ = -1;
  int port_ = 0;
  fs::path log_;
};

class BinaryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("depath_bin_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    mesh_ = (dir_ / "grid.obj").string();
    std::ofstream(mesh_) << grid_obj(20);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string client(const std::string& args, const Daemon& d) const {
    return std::string(DEPATH_BIN) + " " + args + " --server " + d.address();
  }
  fs::path dir_;
  std::string mesh_;
};

TEST_F(BinaryTest, HelpListsEveryLimit) {
  const auto r = run_command(std::string(DEPATHD_BIN) + " --help");
  EXPECT_EQ(r.rc, 0);
  for (const char* flag : {"--listen", "--threads", "--max-running-jobs", "--max-queued-jobs", "--mesh-cache-bytes",
                           "--max-upload-bytes", "--max-message-bytes", "--job-ttl-seconds",
                           "--shutdown-timeout-seconds", "--data-dir", "--auth-token", "--log-format",
                           "--max-concurrent-parses", "--parse-timeout-seconds", "--max-generations",
                           "--max-evaluations", "--max-job-memory-bytes", "--auth-token-file",
                           "--auth-failure-burst", "--auth-failure-rate", "--max-jobs-per-client",
                           "--max-requests-per-second-per-client", "--max-concurrent-uploads",
                           "--max-upload-memory-bytes", "--tls-cert",
                           "--tls-key", "--tls-client-ca", "--tls-reload-seconds", "--health-listen"}) {
    EXPECT_NE(r.output.find(flag), std::string::npos) << flag;
  }
  const auto bad = run_command(std::string(DEPATHD_BIN) + " --max-running-jobs 0 --listen 127.0.0.1:0");
  EXPECT_NE(bad.rc, 0);
  EXPECT_NE(bad.output.find("--max-running-jobs"), std::string::npos) << bad.output;
}

/// VmRSS of a process in MB (from /proc).
long rss_mb(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6)) / 1024;
  return -1;
}

// Issue 14: uploads whose OBJ names /dev/urandom, /dev/zero or /etc/passwd in mtllib end
// promptly with the 3-vertex mesh the bytes hold, the server stays SERVING with bounded memory,
// and bad files and oversized jobs get clear errors naming the problem or the limit.
TEST_F(BinaryTest, HostileUploadsAndSpecsGetClearErrorsAndTheServerStaysServing) {
  constexpr int kParseSeconds = 5;
  Daemon d(dir_, {"--parse-timeout-seconds", std::to_string(kParseSeconds)});
  // Liveness bound: a parse (and the wait for its slot) is cut at kParseSeconds; wide margin.
  const std::string limit = "timeout " + std::to_string(static_cast<int>(6 * kParseSeconds * time_scale())) + " ";
  for (const char* target : {"/dev/urandom", "/dev/zero", "/etc/passwd"}) {
    const fs::path obj = dir_ / "hostile.obj";
    std::ofstream(obj) << "mtllib " << target << "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const auto r = run_command(limit + client("upload --force " + obj.string(), d));
    EXPECT_EQ(r.rc, 0) << target << ": " << r.output;
    EXPECT_NE(r.output.find("3 vertices, 1 faces"), std::string::npos) << target << ": " << r.output;
    const auto normal = run_command(limit + client("upload --force " + mesh_, d));
    EXPECT_EQ(normal.rc, 0) << normal.output;
    EXPECT_NE(normal.output.find("400 vertices"), std::string::npos) << normal.output;
    EXPECT_LT(rss_mb(d.pid()), 512) << "after mtllib " << target;
  }

  auto expect_refused = [&](const std::string& args, const std::vector<std::string>& words) {
    const auto r = run_command(limit + client(args, d));
    EXPECT_NE(r.rc, 0) << args << ": " << r.output;
    EXPECT_EQ(r.output.find("INTERNAL"), std::string::npos) << r.output;
    for (const auto& w : words) EXPECT_NE(r.output.find(w), std::string::npos) << args << ": " << r.output;
  };
  const fs::path nan_obj = dir_ / "nan.obj";
  std::ofstream(nan_obj) << "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n";
  expect_refused("upload " + nan_obj.string(), {"non-finite coordinate at vertex 1 (line 2)"});
  const fs::path short_face = dir_ / "short.off";
  std::ofstream(short_face) << "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n5 0 1 2\n";
  expect_refused("upload " + short_face.string(), {"face line claiming 5 vertices but giving 3"});

  // A mesh named .txt uploads with --format.
  const fs::path txt = dir_ / "grid.txt";
  fs::copy_file(mesh_, txt);
  expect_refused("upload --force " + txt.string(), {"format"});
  const auto as_obj = run_command(limit + client("upload --force --format obj " + txt.string(), d));
  EXPECT_EQ(as_obj.rc, 0) << as_obj.output;
  EXPECT_NE(as_obj.output.find("400 vertices"), std::string::npos) << as_obj.output;
  const auto submit_txt =
      run_command(limit + client("submit --format obj " + txt.string() + " -s 0 -t 399 --population 8 --generations 2", d));
  EXPECT_EQ(submit_txt.rc, 0) << submit_txt.output;
  EXPECT_EQ(last_line(submit_txt.output).rfind("job-", 0), 0u) << submit_txt.output;  // prints the job id

  // A PLY of triangle strips: the unit square as one strip 0 1 2 3.
  const fs::path strips = dir_ / "strips.ply";
  std::ofstream(strips) << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                           "property float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n0 1 0\n1 1 0\n4 0 1 2 3\n";
  const auto strip_upload = run_command(limit + client("upload " + strips.string(), d));
  EXPECT_EQ(strip_upload.rc, 0) << strip_upload.output;
  EXPECT_NE(strip_upload.output.find("4 vertices, 2 faces"), std::string::npos) << strip_upload.output;

  // Job specs: limits at submit, named.
  expect_refused("submit " + mesh_ + " -s 0 -t 399 --population 1000000",
                 {"population 1000000", "--max-job-memory-bytes"});
  expect_refused("submit " + mesh_ + " -s 0 -t 399 --generations 2000000000", {"--max-generations"});
  expect_refused("submit " + mesh_ + " -s 0 -t 399 --population 5000 --generations 100000", {"--max-evaluations"});
  const fs::path zero = dir_ / "zero.density";
  {
    std::ofstream out(zero);
    for (int v = 0; v < 400; ++v) out << (v == 17 ? "0" : "1") << '\n';
  }
  expect_refused("submit " + mesh_ + " -s 0 -t 399 --density " + zero.string(),
                 {"density at vertex 17 is 0: densities must be finite and > 0"});

  const auto health = run_command(limit + client("health", d));
  EXPECT_EQ(health.rc, 0) << health.output;
  EXPECT_NE(health.output.find("SERVING"), std::string::npos) << health.output;
  EXPECT_LT(rss_mb(d.pid()), 512);
}

TEST_F(BinaryTest, ClientCommandsEndToEnd) {
  Daemon d(dir_, {"--log-format", "json"});
  auto r = run_command(client("health", d));
  EXPECT_EQ(r.rc, 0) << r.output;
  EXPECT_NE(r.output.find("SERVING"), std::string::npos);

  r = run_command(client("upload " + mesh_, d));
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_NE(r.output.find(wire::sha256_hex(grid_obj(20))), std::string::npos) << r.output;
  r = run_command(client("upload " + mesh_, d));
  EXPECT_NE(r.output.find("already on the server"), std::string::npos) << r.output;

  // run == solve, written by the same writers.
  const std::string job_flags = " -s 0 -t 399 --method de --population 8 --generations 15 --seed 3";
  r = run_command(client("run " + mesh_ + job_flags + " --out " + (dir_ / "run.json").string(), d));
  ASSERT_EQ(r.rc, 0) << r.output;
  r = run_command(std::string(DEPATH_BIN) + " solve " + mesh_ + job_flags + " --out " + (dir_ / "solve.json").string());
  ASSERT_EQ(r.rc, 0) << r.output;
  const auto run_json = nlohmann::json::parse(read_text(dir_ / "run.json"));
  const auto solve_json = nlohmann::json::parse(read_text(dir_ / "solve.json"));
  EXPECT_EQ(run_json["points"], solve_json["points"]);
  EXPECT_EQ(run_json["crossings"], solve_json["crossings"]);
  EXPECT_EQ(run_json["energy"], solve_json["energy"]);

  // submit / watch / result without the mesh file / jobs / cancel.
  r = run_command(client("submit " + mesh_ + job_flags, d));
  ASSERT_EQ(r.rc, 0) << r.output;
  std::string job = last_line(r.output);
  r = run_command(client("watch " + job + " --json", d));
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_NE(r.output.find("\"state\":\"succeeded\""), std::string::npos) << r.output;
  r = run_command(client("result " + job + " --out " + (dir_ / "remote.json").string(), d));
  ASSERT_EQ(r.rc, 0) << r.output;
  const auto remote_json = nlohmann::json::parse(read_text(dir_ / "remote.json"));
  EXPECT_EQ(remote_json["points"], solve_json["points"]);
  EXPECT_EQ(remote_json["crossings"], solve_json["crossings"]);
  r = run_command(client("result " + job + " --out " + (dir_ / "remote.csv").string(), d));
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_NE(read_text(dir_ / "remote.csv").find("index,x,y,z"), std::string::npos);
  r = run_command(client("jobs", d));
  EXPECT_EQ(r.rc, 0);
  EXPECT_NE(r.output.find(job), std::string::npos);
  r = run_command(client("cancel " + job, d));
  EXPECT_EQ(r.rc, 0) << r.output;

  // Errors exit non-zero with the server's message.
  r = run_command(client("run " + mesh_ + " -s 0 -t 0", d));
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.output.find("INVALID_ARGUMENT"), std::string::npos) << r.output;
  r = run_command(client("result job-unknown", d));
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.output.find("NOT_FOUND"), std::string::npos) << r.output;
  const auto [rc, seconds] = d.terminate();
  EXPECT_EQ(rc, 0);
  EXPECT_NE(d.log().find("\"event\":\"job.finished\""), std::string::npos);
}

TEST_F(BinaryTest, AuthToken) {
  Daemon d(dir_, {"--auth-token", "tok"});
  auto r = run_command(client("jobs", d));
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.output.find("UNAUTHENTICATED"), std::string::npos) << r.output;
  r = run_command(client("jobs --token tok", d));
  EXPECT_EQ(r.rc, 0) << r.output;
  r = run_command(client("health", d));
  EXPECT_EQ(r.rc, 0) << r.output;
}

TEST_F(BinaryTest, SigtermMidJobEndsWatchersAndExitsPromptly) {
  Daemon d(dir_);
  auto r = run_command(client("submit " + mesh_ + " -s 0 -t 399 --population 10 --generations 1000000", d));
  ASSERT_EQ(r.rc, 0) << r.output;
  const std::string job = last_line(r.output);
  // A watcher in the background.
  const fs::path watch_out = dir_ / "watch.txt";
  const fs::path watch_rc = dir_ / "watch.rc";
  // The watcher streams JSON lines into a file as they arrive, so the test can tell when it
  // is attached (under load a process start can take longer than the job's first steps).
  std::thread watcher([&] {
    const auto w = run_command(client("watch " + job + " --json", d) + " > " + watch_out.string());
    std::ofstream(watch_rc) << w.rc;
  });
  for (int i = 0; i < 1000 * time_scale(); ++i) {  // 20 s (times the sanitizer slow-down)
    if (read_text(watch_out).find("\"progress\"") != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_NE(read_text(watch_out).find("\"progress\""), std::string::npos) << "the watcher never attached";
  const auto [rc, seconds] = d.terminate();
  watcher.join();
  EXPECT_EQ(rc, 0) << d.log();
  // depathd's own bound: --shutdown-timeout-seconds 5 (kShutdownSeconds), after which it stops
  // waiting for jobs and watchers; the margin (times the sanitizer slow-down) covers process
  // exit. The assertions below check that the shutdown was the graceful one.
  EXPECT_LT(seconds, kShutdownSeconds + 2.0 * test::time_scale());
  const std::string out = read_text(watch_out);
  EXPECT_NE(out.find("\"state\":\"cancelled\""), std::string::npos) << out;
  EXPECT_NE(out.find("shutting down"), std::string::npos) << out;
  EXPECT_EQ(read_text(watch_rc), "130") << out;
}

// `health` on a multi-address target (a dns:/// name with several A records, or an ipv4:
// list) checks every replica and fails when one is down. The job commands through such a
// target need replicas sharing one store: tests/service/store_test.py runs them on PostgreSQL.
TEST_F(BinaryTest, HealthChecksEveryReplicaOfAMultiAddressTarget) {
  fs::create_directories(dir_ / "a");
  fs::create_directories(dir_ / "b");
  Daemon a(dir_ / "a");
  Daemon b(dir_ / "b");
  const std::string multi = "ipv4:127.0.0.1:" + std::to_string(a.port()) + ",127.0.0.1:" + std::to_string(b.port());
  const std::string health = std::string(DEPATH_BIN) + " health --server " + multi;
  auto r = run_command(health);
  EXPECT_EQ(r.rc, 0) << r.output;
  EXPECT_NE(r.output.find("127.0.0.1:" + std::to_string(a.port()) + " SERVING"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("127.0.0.1:" + std::to_string(b.port()) + " SERVING"), std::string::npos) << r.output;
  b.terminate();
  r = run_command(health);
  EXPECT_NE(r.rc, 0) << r.output;
  EXPECT_NE(r.output.find("127.0.0.1:" + std::to_string(a.port()) + " SERVING"), std::string::npos) << r.output;
}

// dns: targets are resolved by gRPC (here localhost: 127.0.0.1 and perhaps ::1, where nothing
// listens; calls go to the address that accepts them); a name that does not resolve is a
// clear error naming the target.
TEST_F(BinaryTest, DnsTargetIsResolved) {
  Daemon d(dir_);
  const std::string target = "dns:///localhost:" + std::to_string(d.port());
  for (int i = 0; i < 3; ++i) {
    auto r = run_command(std::string(DEPATH_BIN) + " run " + mesh_ +
                         " -s 0 -t 399 --method de --population 8 --generations 5 --seed 3 --server " + target);
    ASSERT_EQ(r.rc, 0) << r.output;
  }
  auto r = run_command(std::string(DEPATH_BIN) + " run " + mesh_ + " -s 0 -t 399 --server dns:///no-such-host.invalid:1");
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.output.find("cannot resolve 'no-such-host.invalid'"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace depath::test
