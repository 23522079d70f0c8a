// Network subcommands of `depath` (SPEC §4): upload, submit, watch, result, jobs, cancel,
// run, health. They talk to depathd through RemoteClient.
#include "commands.hpp"
#include "depath/util/error.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/io/result_writer.hpp"
#include "depath/wire/wire.hpp"
#include "grpc/health/v1/health.grpc.pb.h"
#include "job_options.hpp"
#include "progress_display.hpp"
#include "remote_client.hpp"

#include <google/protobuf/util/json_util.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <random>

namespace depath::cli {
namespace {

namespace v1 = ::depath::v1;

std::atomic<bool> g_interrupted{false};
extern "C" void on_remote_interrupt(int) { g_interrupted.store(true); }

/// Ctrl-C asks the server to cancel the job instead of killing the client.
class InterruptGuard {
 public:
  InterruptGuard() {
    g_interrupted = false;
    previous_ = std::signal(SIGINT, on_remote_interrupt);
  }
  ~InterruptGuard() { std::signal(SIGINT, previous_); }

 private:
  void (*previous_)(int);
};

std::string to_json_line(const google::protobuf::Message& message) {
  std::string out;
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  (void)google::protobuf::util::MessageToJsonString(message, &out, options);
  return out;
}

Progress progress_from_proto(const v1::Progress& p) {
  Progress out;
  out.generation = p.generation();
  out.max_generations = p.max_generations();
  out.best_energy = p.best_energy();
  out.mean_energy = p.mean_energy();
  out.evaluations = p.evaluations();
  out.improvements = p.improvements();
  out.elapsed_seconds = p.elapsed_seconds();
  return out;
}

std::string new_request_id() {
  std::random_device rd;
  std::mt19937_64 rng((static_cast<uint64_t>(rd()) << 32) ^ rd() ^
                      static_cast<uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()));
  char buf[40];
  std::snprintf(buf, sizeof buf, "req-%016llx%016llx", static_cast<unsigned long long>(rng()),
                static_cast<unsigned long long>(rng()));
  return buf;
}

bool looks_like_mesh_id(const std::string& s) {
  if (s.size() != 64) return false;
  for (char c : s) {
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  }
  return true;
}

/// Shows one job event: JSON line, or progress bar / status line.
void show_event(ProgressDisplay& display, const v1::JobEvent& ev) {
  if (display.json()) {
    nlohmann::json line = {{"job_id", ev.job_id()}, {"sequence", ev.sequence()}};
    if (ev.has_progress()) {
      const auto& p = ev.progress();
      line["event"] = "progress";
      line["generation"] = p.generation();
      line["max_generations"] = p.max_generations();
      line["best_energy"] = p.best_energy();
      line["mean_energy"] = p.mean_energy();
      line["evaluations"] = p.evaluations();
      line["improvements"] = p.improvements();
      line["elapsed_seconds"] = p.elapsed_seconds();
      if (p.has_best_path()) {
        nlohmann::json points = nlohmann::json::array();
        for (const auto& q : p.best_path().points()) points.push_back({q.x(), q.y(), q.z()});
        line["best_path"] = std::move(points);
      }
    } else if (ev.has_state()) {
      line["event"] = "state";
      line["state"] = wire::state_name(ev.state().state());
      line["message"] = ev.state().message();
      if (ev.state().error_code() != 0) {
        line["code"] = wire::status_code_name(static_cast<grpc::StatusCode>(ev.state().error_code()));
      }
    } else {
      return;  // the result is printed by the caller, once
    }
    display.emit_json(line);
    return;
  }
  if (ev.has_progress()) {
    display.update(progress_from_proto(ev.progress()));
  } else if (ev.has_state()) {
    std::string msg = "job " + ev.job_id() + ": " + wire::state_name(ev.state().state());
    if (ev.state().state() == v1::JOB_STATE_FAILED || ev.state().state() == v1::JOB_STATE_CANCELLED) {
      msg += " (" + ev.state().message() + ")";
    }
    display.status(msg);
  }
}

/// Throws for a terminal state other than SUCCEEDED (exit code 2, or 130 when cancelled).
void check_terminal(const v1::JobEvent& terminal) {
  const auto& st = terminal.state();
  if (st.state() == v1::JOB_STATE_SUCCEEDED) return;
  if (st.state() == v1::JOB_STATE_CANCELLED) {
    throw Error(ErrorCode::cancelled, "job " + terminal.job_id() + " was cancelled: " + st.message());
  }
  const auto code = static_cast<grpc::StatusCode>(st.error_code());
  throw RemoteError(code == grpc::StatusCode::OK ? grpc::StatusCode::INTERNAL : code,
                    "job " + terminal.job_id() + " failed: " + st.message());
}

void print_summary(const v1::JobResult& r) {
  std::fprintf(stderr,
               "method %s%s: energy %.10g  length %.10g  fmm energy %.10g  generations %d  evaluations %lld  "
               "time %.3fs  (%s)\n",
               method_name(wire::result_from_proto(r).method), r.refined() ? "+refine" : "", r.energy(), r.length(),
               r.fmm_energy(), r.generations(), static_cast<long long>(r.evaluations()), r.seconds(),
               r.stop_reason().c_str());
  for (const auto& m : r.metrics()) std::fprintf(stderr, "  %s %.6g\n", m.name().c_str(), m.value());
}

/// Writes / prints a received result like `depath solve` does.
void deliver_result(const v1::JobResult& result, const Mesh* mesh, const std::string& out, bool json,
                    const std::string& job_id) {
  if (!out.empty()) wire::write_result_message(out, result, mesh);
  if (json) {
    nlohmann::json line = wire::result_message_to_json(result, mesh);
    line["event"] = "result";
    line["job_id"] = job_id;
    std::cout << line.dump() << '\n' << std::flush;
  } else {
    print_summary(result);
    if (!out.empty()) std::fprintf(stderr, "wrote %s\n", out.c_str());
  }
}

v1::JobResult fetch_result(RemoteClient& client, const std::string& job_id) {
  auto ctx = client.context(60);
  v1::GetResultRequest req;
  req.set_job_id(job_id);
  v1::JobResult result;
  client.check(client.jobs().GetResult(ctx.get(), req, &result), "fetching the result of job " + job_id);
  return result;
}

/// Resolves MESH (a local file, or the id of a mesh already on the server) and submits.
v1::SubmitJobResponse submit_job(RemoteClient& client, const JobOptions& options, const std::string& request_id,
                                 bool quiet) {
  const JobSpec job = make_job_spec(options);
  const bool is_file = std::filesystem::exists(options.mesh_path);
  if (!is_file && !looks_like_mesh_id(options.mesh_path)) {
    throw Error(ErrorCode::invalid_argument, "mesh '" + options.mesh_path + "' is neither a file nor a mesh id");
  }
  std::string mesh_id = options.mesh_path;
  for (int attempt = 0;; ++attempt) {
    if (is_file) {
      bool uploaded = false;
      mesh_id = client.ensure_mesh(options.mesh_path, &uploaded, options.mesh_format).id();
      if (uploaded && !quiet && !options.json) std::fprintf(stderr, "uploaded %s as %s\n", options.mesh_path.c_str(), mesh_id.c_str());
    }
    v1::SubmitJobRequest req;
    *req.mutable_spec() = wire::job_to_proto(job, mesh_id);
    req.set_client_request_id(request_id);
    v1::SubmitJobResponse reply;
    auto ctx = client.context(client.options().connect_timeout_seconds + 60);
    ctx->set_wait_for_ready(true);
    const grpc::Status status = client.jobs().SubmitJob(ctx.get(), req, &reply);
    // The mesh was evicted between the lookup and the submit: upload again, once.
    if (status.error_code() == grpc::StatusCode::NOT_FOUND && is_file && attempt == 0) continue;
    client.check(status, "submitting the job");
    return reply;
  }
}

// ---- subcommands -----------------------------------------------------------------------------

void add_upload(CLI::App& app) {
  struct Opts {
    RemoteOptions remote;
    std::string mesh;
    std::string format;
    bool force = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = app.add_subcommand("upload", "Upload a mesh to the server (skipped if it has it); prints its id");
  cmd->add_option("MESH", o->mesh, "Mesh file (.obj, .off, .ply, .stl)")->required();
  cmd->add_flag("--force", o->force, "Send the bytes even if the server has the mesh");
  cmd->add_option("--format", o->format, "Mesh format when the extension does not tell (e.g. a .txt file)")
      ->check(CLI::IsMember({"obj", "off", "ply", "stl"}, CLI::ignore_case));
  cmd->add_flag("--json", o->remote.json, "Print the mesh info as JSON");
  add_remote_options(*cmd, o->remote);
  cmd->callback([o] {
    // A multi-replica target (dns:, ipv4:a,b): every replica gets the mesh, so a later
    // `submit MESH_ID` works wherever it lands.
    const std::vector<RemoteOptions> replicas = replica_options(o->remote);
    std::optional<v1::MeshInfo> first;
    for (const auto& replica : replicas) {
      RemoteClient client(replica);
      bool uploaded = true;
      const v1::MeshInfo info = o->force ? client.upload(o->mesh, o->format) : client.ensure_mesh(o->mesh, &uploaded, o->format);
      if (!first) first = info;
      if (o->remote.json) continue;
      const std::string where = replicas.size() > 1 ? " (" + replica.server + ")" : "";
      std::fprintf(stderr, "%s %s%s: %d vertices, %d faces, %d boundary edges, %d components\n",
                   uploaded && !info.already_present() ? "uploaded" : "already on the server:", o->mesh.c_str(),
                   where.c_str(), info.num_vertices(), info.num_faces(), info.num_boundary_edges(),
                   info.num_components());
      if (&replica == &replicas.front()) {
        for (const auto& w : info.warnings()) std::fprintf(stderr, "  warning: %s\n", w.c_str());
      }
    }
    if (o->remote.json) {
      std::cout << to_json_line(*first) << '\n';
      return;
    }
    std::cout << first->id() << '\n';
  });
}

void add_submit(CLI::App& app) {
  struct Opts {
    RemoteOptions remote;
    JobOptions job;
    std::string request_id;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = app.add_subcommand("submit", "Submit a job to the server (uploading the mesh if needed); prints its id");
  add_job_options(*cmd, o->job, /*with_threads=*/false);
  cmd->add_option("--request-id", o->request_id, "Idempotency key: resubmitting with it returns the same job");
  add_remote_options(*cmd, o->remote);
  cmd->callback([o] {
    o->remote.json = o->job.json;
    // One replica for the whole job (mesh lookup/upload and submit); `watch`/`result`/`cancel`
    // find it again by asking each replica.
    RemoteClient client(pin_to_random_replica(o->remote));
    const auto reply = submit_job(client, o->job, o->request_id.empty() ? new_request_id() : o->request_id, false);
    if (o->job.json) {
      std::cout << to_json_line(reply) << '\n';
    } else {
      std::cout << reply.job_id() << '\n';
    }
  });
}

void add_watch(CLI::App& app) {
  struct Opts {
    RemoteOptions remote;
    std::string job_id;
    uint64_t after = 0;
    std::string out;
    std::string mesh;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = app.add_subcommand("watch", "Follow a job's progress until it ends");
  cmd->add_option("JOB", o->job_id, "Job id")->required();
  cmd->add_option("--after", o->after, "Only events after this sequence number (resume)");
  cmd->add_option("--out,-o", o->out, "Write the result: .json, .obj, .ply or .csv");
  cmd->add_option("--mesh", o->mesh, "The job's mesh file (optional; else the result's own vertex positions are used)");
  cmd->add_flag("--json", o->remote.json, "Print JSON lines instead of a progress bar");
  add_remote_options(*cmd, o->remote);
  cmd->callback([o] {
    if (!o->out.empty()) check_result_path(o->out);
    RemoteClient client(pin_to_job_replica(o->remote, o->job_id));
    ProgressDisplay display(o->remote.json);
    std::optional<v1::JobResult> result;
    InterruptGuard guard;
    const auto terminal = client.watch(
        o->job_id, o->after,
        [&](const v1::JobEvent& ev) {
          if (ev.has_result()) result = ev.result();
          show_event(display, ev);
        },
        &g_interrupted);
    display.finish();
    if (result) {
      std::unique_ptr<Mesh> mesh;
      if (!o->mesh.empty()) mesh = std::make_unique<Mesh>(load_mesh(o->mesh));
      deliver_result(*result, mesh.get(), o->out, o->remote.json, o->job_id);
    }
    check_terminal(terminal);
  });
}

void add_result(CLI::App& app) {
  struct Opts {
    RemoteOptions remote;
    std::string job_id;
    std::string out;
    std::string mesh;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = app.add_subcommand("result", "Fetch a finished job's result");
  cmd->add_option("JOB", o->job_id, "Job id")->required();
  cmd->add_option("--out,-o", o->out, "Write the result: .json, .obj, .ply or .csv (else JSON on stdout)");
  cmd->add_option("--mesh", o->mesh, "The job's mesh file (optional; else the result's own vertex positions are used)");
  cmd->add_flag("--json", o->remote.json, "Print the result as one JSON line on stdout");
  add_remote_options(*cmd, o->remote);
  cmd->callback([o] {
    if (!o->out.empty()) check_result_path(o->out);
    RemoteClient client(pin_to_job_replica(o->remote, o->job_id));
    const v1::JobResult result = fetch_result(client, o->job_id);
    std::unique_ptr<Mesh> mesh;
    if (!o->mesh.empty()) mesh = std::make_unique<Mesh>(load_mesh(o->mesh));
    if (o->out.empty() && !o->remote.json) {
      std::cout << wire::result_message_to_json(result, mesh.get()).dump(1) << '\n';
      return;
    }
    deliver_result(result, mesh.get(), o->out, o->remote.json, o->job_id);
  });
}

void add_jobs(CLI::App& app) {
  struct Opts {
    RemoteOptions remote;
    std::vector<std::string> states;
    std::string mesh_id;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = app.add_subcommand("jobs", "List the server's jobs");
  cmd->add_option("--state", o->states, "Only these states (queued, running, succeeded, failed, cancelled)")
      ->check(CLI::IsMember({"queued", "running", "succeeded", "failed", "cancelled"}));
  cmd->add_option("--mesh", o->mesh_id, "Only jobs on this mesh id");
  cmd->add_flag("--json", o->remote.json, "One JSON line per job");
  add_remote_options(*cmd, o->remote);
  cmd->callback([o] {
    v1::ListJobsRequest req;
    for (const auto& s : o->states) {
      for (int st = v1::JOB_STATE_QUEUED; st <= v1::JOB_STATE_CANCELLED; ++st) {
        if (s == wire::state_name(static_cast<v1::JobState>(st))) req.add_states(static_cast<v1::JobState>(st));
      }
    }
    req.set_mesh_id(o->mesh_id);
    // A multi-replica target: every replica's jobs, merged. A replica that cannot be asked is
    // reported on stderr; only when none answers does the command fail.
    const std::vector<RemoteOptions> replicas = replica_options(o->remote);
    v1::ListJobsResponse reply;
    std::optional<RemoteError> failure;
    size_t answered = 0;
    for (const auto& replica : replicas) {
      RemoteClient one(replica);
      auto ctx = one.context(o->remote.connect_timeout_seconds);
      v1::ListJobsResponse part;
      try {
        one.check(one.jobs().ListJobs(ctx.get(), req, &part), "listing jobs");
      } catch (const RemoteError& e) {
        if (replicas.size() == 1) throw;
        std::fprintf(stderr, "warning: %s\n", e.what());
        if (!failure) failure = e;
        continue;
      }
      ++answered;
      for (auto& job : *part.mutable_jobs()) *reply.add_jobs() = std::move(job);
    }
    if (answered == 0 && failure) throw *failure;
    if (o->remote.json) {
      for (const auto& job : reply.jobs()) std::cout << to_json_line(job) << '\n';
      return;
    }
    std::printf("%-28s %-10s %-14s %-9s %-16s %s\n", "JOB", "STATE", "MESH", "GEN", "BEST ENERGY", "NOTE");
    for (const auto& job : reply.jobs()) {
      char gen[32] = "-";
      char best[32] = "-";
      if (job.has_last_progress()) {
        std::snprintf(gen, sizeof gen, "%d/%d", job.last_progress().generation(), job.last_progress().max_generations());
        std::snprintf(best, sizeof best, "%.8g", job.last_progress().best_energy());
      }
      std::string note = job.error_message();
      if (job.queue_position() > 0) note = "queue position " + std::to_string(job.queue_position());
      std::printf("%-28s %-10s %-14s %-9s %-16s %s\n", job.job_id().c_str(), wire::state_name(job.state()),
                  job.mesh_id().substr(0, 12).c_str(), gen, best, note.c_str());
    }
  });
}

void add_cancel(CLI::App& app) {
  struct Opts {
    RemoteOptions remote;
    std::string job_id;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = app.add_subcommand("cancel", "Cancel a job (a running one stops promptly)");
  cmd->add_option("JOB", o->job_id, "Job id")->required();
  cmd->add_flag("--json", o->remote.json, "Print the job info as JSON");
  add_remote_options(*cmd, o->remote);
  cmd->callback([o] {
    RemoteClient client(pin_to_job_replica(o->remote, o->job_id));
    auto ctx = client.context(o->remote.connect_timeout_seconds);
    v1::CancelJobRequest req;
    req.set_job_id(o->job_id);
    v1::JobInfo info;
    client.check(client.jobs().CancelJob(ctx.get(), req, &info), "cancelling job " + o->job_id);
    if (o->remote.json) std::cout << to_json_line(info) << '\n';
    else std::fprintf(stderr, "job %s: %s%s\n", info.job_id().c_str(), wire::state_name(info.state()),
                      info.state() == v1::JOB_STATE_RUNNING ? " (cancellation requested)" : "");
  });
}

void add_run(CLI::App& app) {
  struct Opts {
    RemoteOptions remote;
    JobOptions job;
    std::string request_id;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = app.add_subcommand(
      "run", "Run a job on the server: upload the mesh if needed, submit, watch, fetch and write the result");
  add_job_options(*cmd, o->job, /*with_threads=*/false);
  cmd->add_option("--request-id", o->request_id, "Idempotency key (default: a fresh random one)");
  add_remote_options(*cmd, o->remote);
  cmd->callback([o] {
    o->remote.json = o->job.json;
    if (!o->job.out.empty()) check_result_path(o->job.out);  // fail before the work, not after
    const Mesh mesh = load_mesh(o->job.mesh_path, o->job.mesh_format);  // validates locally and writes the result later
    // Every call of this job (mesh lookup/upload, submit, watch and its reconnects, result)
    // goes to one replica, chosen at random among a multi-replica target's addresses.
    RemoteClient client(pin_to_random_replica(o->remote));
    ProgressDisplay display(o->job.json);
    InterruptGuard guard;
    const auto reply = submit_job(client, o->job, o->request_id.empty() ? new_request_id() : o->request_id, false);
    if (!o->job.json) display.status("job " + reply.job_id() + " submitted to " + client.options().server);
    std::optional<v1::JobResult> result;
    const auto terminal = client.watch(
        reply.job_id(), 0,
        [&](const v1::JobEvent& ev) {
          if (ev.has_result()) result = ev.result();
          show_event(display, ev);
        },
        &g_interrupted);
    display.finish();
    if (terminal.state().state() == v1::JOB_STATE_SUCCEEDED && !result) result = fetch_result(client, reply.job_id());
    if (result) deliver_result(*result, &mesh, o->job.out, o->job.json, reply.job_id());
    check_terminal(terminal);
  });
}

void add_health(CLI::App& app) {
  struct Opts {
    RemoteOptions remote;
    std::string service;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = app.add_subcommand("health", "Check the server's health (exit 0 when SERVING)");
  cmd->add_option("--service", o->service, "Service name (default: the whole server)");
  cmd->add_flag("--json", o->remote.json, "Print JSON");
  add_remote_options(*cmd, o->remote);
  cmd->callback([o] {
    // A multi-replica target: every replica is checked and printed ("ADDRESS STATUS");
    // exit 0 only when all are SERVING.
    const std::vector<RemoteOptions> replicas = replica_options(o->remote);
    const bool many = replicas.size() > 1;
    std::optional<RemoteError> failure;
    for (const auto& replica : replicas) {
      RemoteClient client(replica);
      auto stub = grpc::health::v1::Health::NewStub(client.channel());
      auto ctx = client.context(o->remote.connect_timeout_seconds);
      grpc::health::v1::HealthCheckRequest req;
      req.set_service(o->service);
      grpc::health::v1::HealthCheckResponse reply;
      std::string status;
      try {
        client.check(stub->Check(ctx.get(), req, &reply), "checking health of " + replica.server);
        status = grpc::health::v1::HealthCheckResponse::ServingStatus_Name(reply.status());
      } catch (const RemoteError& e) {
        if (!many) throw;
        std::fprintf(stderr, "%s\n", e.what());
        status = "UNREACHABLE";
        if (!failure) failure = e;
      }
      if (o->remote.json) std::cout << nlohmann::json{{"server", replica.server}, {"status", status}}.dump() << '\n';
      else if (many) std::cout << replica.server << ' ' << status << '\n';
      else std::cout << status << '\n';
      if (status != "UNREACHABLE" && reply.status() != grpc::health::v1::HealthCheckResponse::SERVING && !failure) {
        failure = RemoteError(grpc::StatusCode::UNAVAILABLE, "server " + replica.server + " is " + status);
      }
    }
    if (failure) throw *failure;
  });
}

}  // namespace

void add_remote_commands(CLI::App& app) {
  add_upload(app);
  add_submit(app);
  add_watch(app);
  add_result(app);
  add_jobs(app);
  add_cancel(app);
  add_run(app);
  add_health(app);
}

}  // namespace depath::cli
