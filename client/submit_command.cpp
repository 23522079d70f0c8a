// SPDX-License-Identifier: MIT
// `depath submit MESH ...`: submits a job (uploading the mesh if needed); prints the job id.
#include "commands.hpp"
#include "remote_support.hpp"

#include <iostream>

namespace depath::cli {

void add_submit_command(CLI::App& app) {
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
    RemoteClient client(o->remote);
    const auto reply = submit_job(client, o->job, o->request_id.empty() ? new_request_id() : o->request_id, false);
    if (o->job.json) {
      std::cout << to_json_line(reply) << '\n';
    } else {
      std::cout << reply.job_id() << '\n';
    }
  });
}

}  // namespace depath::cli
