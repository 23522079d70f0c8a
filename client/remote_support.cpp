// SPDX-License-Identifier: MIT
#include "remote_support.hpp"

#include "depath/util/error.hpp"
#include "depath/wire/wire.hpp"
#include "result_output.hpp"

#include <google/protobuf/util/json_util.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>

namespace depath::cli {

std::string to_json_line(const google::protobuf::Message& message) {
  std::string out;
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  (void)google::protobuf::util::MessageToJsonString(message, &out, options);
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
    display.update(wire::progress_from_proto(ev.progress()));
  } else if (ev.has_state()) {
    std::string msg = "job " + ev.job_id() + ": " + wire::state_name(ev.state().state());
    if (ev.state().state() == v1::JOB_STATE_FAILED || ev.state().state() == v1::JOB_STATE_CANCELLED) {
      msg += " (" + ev.state().message() + ")";
    }
    display.status(msg);
  }
}

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

void deliver_result(const v1::JobResult& result, const Mesh* mesh, const std::string& out, bool json,
                    const std::string& job_id) {
  const wire::ReceivedResult received = wire::received_result(result, mesh);
  deliver_result(received.points, received.result, out, json, job_id);
}

v1::JobResult fetch_result(RemoteClient& client, const std::string& job_id) {
  auto ctx = client.context(60);
  v1::GetResultRequest req;
  req.set_job_id(job_id);
  v1::JobResult result;
  client.check(client.jobs().GetResult(ctx.get(), req, &result), "fetching the result of job " + job_id);
  return result;
}

v1::SubmitJobResponse submit_job(RemoteClient& client, const JobOptions& options, const std::string& request_id,
                                 bool quiet) {
  const JobSpec job = make_job_spec(options);
  const bool is_file = std::filesystem::exists(options.mesh_path);
  if (!is_file && !wire::is_mesh_id(options.mesh_path)) {
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
}  // namespace depath::cli
