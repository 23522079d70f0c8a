// SPDX-License-Identifier: MIT
// `depath jobs`: lists the jobs of the server (of the shared store, with several replicas).
#include "commands.hpp"
#include "depath/wire/job.hpp"
#include "remote_support.hpp"

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

namespace depath::cli {

void add_jobs_command(CLI::App& app) {
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
    RemoteClient client(o->remote);
    auto ctx = client.context(o->remote.connect_timeout_seconds);
    v1::ListJobsResponse reply;
    client.check(client.jobs().ListJobs(ctx.get(), req, &reply), "listing jobs");
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

}  // namespace depath::cli
