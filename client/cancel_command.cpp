// SPDX-License-Identifier: MIT
// `depath cancel JOB`: cancels a job (a running one stops promptly).
#include "commands.hpp"
#include "depath/wire/job.hpp"
#include "remote_support.hpp"

#include <cstdio>
#include <iostream>

namespace depath::cli {

void add_cancel_command(CLI::App& app) {
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
    RemoteClient client(o->remote);
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

}  // namespace depath::cli
