// SPDX-License-Identifier: MIT
// `depath run MESH ...`: upload if needed, submit, watch, fetch and write the result, on one
// replica.
#include "commands.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/io/result_writer.hpp"
#include "remote_support.hpp"

#include <optional>

namespace depath::cli {

void add_run_command(CLI::App& app) {
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
    // With several replicas on one shared store, any of them serves any call of the job.
    RemoteClient client(o->remote);
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

}  // namespace depath::cli
