// SPDX-License-Identifier: MIT
// `depath health`: the standard gRPC health check (of every replica); exit 0 when SERVING.
#include "commands.hpp"
#include "grpc/health/v1/health.grpc.pb.h"
#include "remote_support.hpp"

#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace depath::cli {

void add_health_command(CLI::App& app) {
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

}  // namespace depath::cli
