// SPDX-License-Identifier: MIT
// `depath watch JOB`: follows a job's events until it ends; writes the result with --out.
#include "commands.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/io/result_writer.hpp"
#include "remote_support.hpp"

#include <memory>
#include <optional>

namespace depath::cli {

void add_watch_command(CLI::App& app) {
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
    RemoteClient client(o->remote);
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

}  // namespace depath::cli
