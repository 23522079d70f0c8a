// SPDX-License-Identifier: MIT
// Shared by the network subcommands (client/*_command.cpp that talk to depathd): Ctrl-C
// handling, request ids, showing job events, fetching and delivering results, submitting.
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/v1/job.pb.h"
#include "interrupt.hpp"
#include "job_options.hpp"
#include "progress_display.hpp"
#include "remote_client.hpp"

#include <google/protobuf/message.h>

#include <string>

namespace depath::cli {

namespace v1 = ::depath::v1;

/// A message as one JSON line (proto field names, every primitive field printed).
std::string to_json_line(const google::protobuf::Message& message);

/// A fresh random idempotency key ("req-" and 32 hex digits).
std::string new_request_id();

/// Shows one job event: JSON line, or progress bar / status line (results are left to
/// deliver_result, once).
void show_event(ProgressDisplay& display, const v1::JobEvent& ev);

/// Throws for a terminal state other than SUCCEEDED (exit code 2, or 130 when cancelled).
void check_terminal(const v1::JobEvent& terminal);

/// Writes / prints a received result like `depath solve` does; positions from `mesh` when
/// given, else from the result itself.
void deliver_result(const v1::JobResult& result, const Mesh* mesh, const std::string& out, bool json,
                    const std::string& job_id);

v1::JobResult fetch_result(RemoteClient& client, const std::string& job_id);

/// Resolves MESH (a local file, or the id of a mesh already on the server) and submits.
v1::SubmitJobResponse submit_job(RemoteClient& client, const JobOptions& options, const std::string& request_id,
                                 bool quiet);

}  // namespace depath::cli
