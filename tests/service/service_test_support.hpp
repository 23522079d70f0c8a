// SPDX-License-Identifier: MIT
// Helpers for the service tests: an in-process depathd on 127.0.0.1:0 reached through real
// gRPC, small generated meshes, and blocking helpers for the RPCs.
#pragma once

#include "time_scale.hpp"

#include "depath/v1/job.grpc.pb.h"
#include "depath/v1/mesh.grpc.pb.h"
#include "depath/util/error.hpp"
#include "depath/wire/wire.hpp"
#include "server.hpp"

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace depath::test {

namespace v1 = ::depath::v1;

/// An n x n grid on [0,1]^2 lifted to a smooth height field, as OBJ text.
inline std::string grid_obj(int n, double height = 0.3) {
  std::ostringstream out;
  out.precision(17);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = double(i) / (n - 1), y = double(j) / (n - 1);
      out << "v " << x << ' ' << y << ' ' << height * std::sin(3 * x) * std::cos(2 * y) << '\n';
    }
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i + 1, b = a + 1, c = a + n, d = c + 1;
      out << "f " << a << ' ' << b << ' ' << d << "\nf " << a << ' ' << d << ' ' << c << '\n';
    }
  }
  return out.str();
}

/// Two separate triangles: vertices 0-2 and 3-5 lie in different components.
inline std::string two_components_obj() {
  return "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\nf 1 2 3\nf 4 5 6\n";
}

inline service::ServerOptions quiet_options() {
  service::ServerOptions o;
  o.listen = "127.0.0.1:0";
  o.threads = 2;
  o.log_level = "warn";
  o.shutdown_timeout_seconds = 5;
  return o;
}

/// Starting a server with `options` is refused: the constructor throws an Error whose message
/// contains `words`. `what` names the options for the failure message.
inline void expect_server_refused(const service::ServerOptions& options, const std::string& words,
                                  const std::string& what) {
  try {
    service::Server server(options);
    ADD_FAILURE() << "started with " << what;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

/// A server in this process plus stubs on a real channel to it.
class TestServer {
 public:
  explicit TestServer(service::ServerOptions options = quiet_options()) : options_(std::move(options)) {
    server_ = std::make_unique<service::Server>(options_);
    address_ = "127.0.0.1:" + std::to_string(server_->port());
    channel_ = grpc::CreateChannel(address_, grpc::InsecureChannelCredentials());
    meshes_ = v1::MeshService::NewStub(channel_);
    jobs_ = v1::JobService::NewStub(channel_);
  }
  service::Server& server() { return *server_; }
  v1::MeshService::Stub& meshes() { return *meshes_; }
  v1::JobService::Stub& jobs() { return *jobs_; }
  const std::string& address() const { return address_; }
  const std::shared_ptr<grpc::Channel>& channel() const { return channel_; }
  const service::ServerOptions& options() const { return options_; }

  std::unique_ptr<grpc::ClientContext> context(double timeout = 60) const {
    auto ctx = std::make_unique<grpc::ClientContext>();
    // Deadlines are liveness bounds: scaled by the sanitizer slow-down (time_scale.hpp).
    ctx->set_deadline(std::chrono::system_clock::now() +
                      std::chrono::milliseconds(static_cast<int>(timeout * time_scale() * 1000)));
    if (!token.empty()) ctx->AddMetadata("authorization", "Bearer " + token);
    return ctx;
  }

  /// Uploads bytes in chunks of `chunk` bytes; returns the status, fills `info`.
  grpc::Status upload(const std::string& bytes, const std::string& name, v1::MeshInfo* info, size_t chunk = 4096,
                      bool header = true, const std::string& format = "") {
    auto ctx = context();
    auto writer = meshes_->UploadMesh(ctx.get(), info);
    v1::UploadMeshRequest req;
    bool ok = true;
    if (header) {
      req.mutable_header()->set_file_name(name);
      req.mutable_header()->set_format(format);
      ok = writer->Write(req);
    }
    for (size_t off = 0; ok && off < bytes.size(); off += chunk) {
      req.Clear();
      req.set_chunk(bytes.substr(off, chunk));
      ok = writer->Write(req);
    }
    if (ok) writer->WritesDone();
    return writer->Finish();
  }

  std::string upload_ok(const std::string& bytes, const std::string& name = "grid.obj") {
    v1::MeshInfo info;
    const auto status = upload(bytes, name, &info);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return info.id();
  }

  grpc::Status submit(const v1::JobSpec& spec, v1::SubmitJobResponse* reply, const std::string& request_id = "") {
    v1::SubmitJobRequest req;
    *req.mutable_spec() = spec;
    req.set_client_request_id(request_id);
    auto ctx = context();
    return jobs_->SubmitJob(ctx.get(), req, reply);
  }

  std::string submit_ok(const v1::JobSpec& spec) {
    v1::SubmitJobResponse reply;
    const auto status = submit(spec, &reply);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return reply.job_id();
  }

  /// Reads a whole watch stream.
  grpc::Status watch(const std::string& job_id, uint64_t after, std::vector<v1::JobEvent>* events,
                     double timeout = 120) {
    auto ctx = context(timeout);
    v1::WatchJobRequest req;
    req.set_job_id(job_id);
    req.set_after_sequence(after);
    auto reader = jobs_->WatchJob(ctx.get(), req);
    v1::JobEvent ev;
    while (reader->Read(&ev)) events->push_back(ev);
    return reader->Finish();
  }

  /// Reads the job's watch stream until an event satisfies `stop` (then cancels the stream)
  /// or the stream ends; the status is OK in the first case.
  template <class Stop>
  grpc::Status watch_until(const std::string& job_id, Stop stop, std::vector<v1::JobEvent>* events,
                           double timeout = 120) {
    auto ctx = context(timeout);
    v1::WatchJobRequest req;
    req.set_job_id(job_id);
    auto reader = jobs_->WatchJob(ctx.get(), req);
    v1::JobEvent ev;
    while (reader->Read(&ev)) {
      events->push_back(ev);
      if (stop(ev)) {
        ctx->TryCancel();
        while (reader->Read(&ev)) {
        }
        reader->Finish();
        return grpc::Status::OK;
      }
    }
    const grpc::Status s = reader->Finish();
    return s.ok() ? grpc::Status(grpc::StatusCode::NOT_FOUND, "the stream ended before the awaited event") : s;
  }

  grpc::Status get_job(const std::string& job_id, v1::JobInfo* info) {
    v1::GetJobRequest req;
    req.set_job_id(job_id);
    auto ctx = context();
    return jobs_->GetJob(ctx.get(), req, info);
  }

  grpc::Status get_result(const std::string& job_id, v1::JobResult* result) {
    v1::GetResultRequest req;
    req.set_job_id(job_id);
    auto ctx = context();
    return jobs_->GetResult(ctx.get(), req, result);
  }

  grpc::Status cancel(const std::string& job_id, v1::JobInfo* info = nullptr) {
    v1::CancelJobRequest req;
    req.set_job_id(job_id);
    v1::JobInfo tmp;
    auto ctx = context();
    return jobs_->CancelJob(ctx.get(), req, info ? info : &tmp);
  }

  std::string token;

 private:
  service::ServerOptions options_;
  std::unique_ptr<service::Server> server_;
  std::string address_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::MeshService::Stub> meshes_;
  std::unique_ptr<v1::JobService::Stub> jobs_;
};

/// A small job spec: fmm unless said otherwise.
inline v1::JobSpec job_spec(const std::string& mesh_id, int s, int t, v1::Method method = v1::METHOD_FMM) {
  v1::JobSpec spec;
  spec.set_mesh_id(mesh_id);
  spec.set_source(s);
  spec.set_target(t);
  spec.set_method(method);
  spec.mutable_de()->set_population(8);
  spec.mutable_de()->set_generations(10);
  spec.set_seed(7);
  return spec;
}

/// A DE job that runs for a long time unless cancelled.
inline v1::JobSpec long_job(const std::string& mesh_id, int s, int t) {
  auto spec = job_spec(mesh_id, s, t, v1::METHOD_DE);
  spec.mutable_de()->set_population(10);
  spec.mutable_de()->set_generations(1000000);
  return spec;
}

inline const v1::JobEvent* find_terminal(const std::vector<v1::JobEvent>& events) {
  for (const auto& e : events) {
    if (e.has_state() && wire::is_terminal(e.state().state())) return &e;
  }
  return nullptr;
}

inline const v1::JobResult* find_result(const std::vector<v1::JobEvent>& events) {
  for (const auto& e : events) {
    if (e.has_result()) return &e.result();
  }
  return nullptr;
}

}  // namespace depath::test
