// SPDX-License-Identifier: MIT
// ThreadSanitizer canary, built and run only in the TSan build (DEPATH_SANITIZE=thread).
//
// scripts/tsan.supp hides the reports that come from gRPC's own, uninstrumented
// synchronisation. This program checks that it hides nothing of ours: a gRPC service whose
// unary handler ("unary") or whose stream reactions ("reaction") bump one counter without a
// lock, called from several client threads at once. Run under the suppressions, TSan must
// report that race on g_canary_counter; ctest passes only when it does. A suppression that
// blinds TSan to races in our handlers or reactions (race:libgrpc++.so, say) fails it.
#include "depath/v1/job.grpc.pb.h"
#include "depath/v1/mesh.grpc.pb.h"
#include "grpc_handoff.hpp"

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/security/server_credentials.h>
#include <grpcpp/server.h>
#include <grpcpp/server_builder.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace v1 = depath::v1;

namespace {

long g_canary_counter = 0;  // touched by gRPC's threads with no synchronisation: the race

class CanaryMeshes final : public v1::MeshService::CallbackService {
  grpc::ServerUnaryReactor* ListMeshes(grpc::CallbackServerContext* ctx, const v1::ListMeshesRequest*,
                                       v1::ListMeshesResponse*) override {
    ++g_canary_counter;
    // Keep this gRPC thread busy (no synchronisation) so that other calls run on others.
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    auto* reactor = ctx->DefaultReactor();
    reactor->Finish(grpc::Status::OK);
    return reactor;
  }
};

/// Streams a few events; each OnWriteDone bumps the counter (the reactor itself is handed
/// to gRPC the way server/job_service.cpp does it).
class CanaryStream final : public grpc::ServerWriteReactor<v1::JobEvent> {
 public:
  CanaryStream() {
    event_.set_sequence(1);
    StartWrite(&event_);
    depath::service::grpc_handoff(this);
  }
  void OnWriteDone(bool ok) override {
    depath::service::grpc_reaction(this);
    ++g_canary_counter;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // as in ListMeshes
    const bool more = ok && ++sent_ < 5;
    depath::service::grpc_handoff(this);  // right before the operation, as in job_service.cpp
    if (more) StartWrite(&event_);
    else Finish(grpc::Status::OK);
  }
  void OnDone() override {
    depath::service::grpc_reaction(this);
    delete this;
  }

 private:
  v1::JobEvent event_;
  int sent_ = 0;
};

class CanaryJobs final : public v1::JobService::CallbackService {
  grpc::ServerWriteReactor<v1::JobEvent>* WatchJob(grpc::CallbackServerContext*, const v1::WatchJobRequest*) override {
    return new CanaryStream();
  }
};

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "unary";
  if (mode != "unary" && mode != "reaction") {
    std::fprintf(stderr, "usage: tsan_canary unary|reaction\n");
    return 2;
  }
  CanaryMeshes meshes;
  CanaryJobs jobs;
  int port = 0;
  grpc::ServerBuilder builder;
  builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port);
  builder.RegisterService(&meshes);
  builder.RegisterService(&jobs);
  auto server = builder.BuildAndStart();
  if (!server || port == 0) {
    std::fprintf(stderr, "tsan_canary: cannot start a server\n");
    return 2;
  }
  auto channel = grpc::CreateChannel("127.0.0.1:" + std::to_string(port), grpc::InsecureChannelCredentials());
  std::vector<std::thread> clients;
  for (int c = 0; c < 4; ++c) {
    clients.emplace_back([&] {
      auto mesh_stub = v1::MeshService::NewStub(channel);
      auto job_stub = v1::JobService::NewStub(channel);
      for (int i = 0; i < 25; ++i) {
        grpc::ClientContext ctx;
        if (mode == "unary") {
          v1::ListMeshesResponse reply;
          (void)mesh_stub->ListMeshes(&ctx, v1::ListMeshesRequest(), &reply);
        } else {
          auto reader = job_stub->WatchJob(&ctx, v1::WatchJobRequest());
          v1::JobEvent ev;
          while (reader->Read(&ev)) {
          }
          (void)reader->Finish();
        }
      }
    });
  }
  for (auto& t : clients) t.join();
  server->Shutdown();
  std::printf("tsan_canary %s: %ld calls counted and no race reported\n", mode.c_str(), g_canary_counter);
  return 0;
}
