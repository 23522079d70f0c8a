// SPDX-License-Identifier: MIT
// `depath result JOB`: fetches a finished job's result; writes or prints it.
#include "commands.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/io/result_writer.hpp"
#include "depath/wire/result.hpp"
#include "remote_support.hpp"

#include <iostream>
#include <memory>

namespace depath::cli {

void add_result_command(CLI::App& app) {
  struct Opts {
    RemoteOptions remote;
    std::string job_id;
    std::string out;
    std::string mesh;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = app.add_subcommand("result", "Fetch a finished job's result");
  cmd->add_option("JOB", o->job_id, "Job id")->required();
  cmd->add_option("--out,-o", o->out, "Write the result: .json, .obj, .ply or .csv (else JSON on stdout)");
  cmd->add_option("--mesh", o->mesh, "The job's mesh file (optional; else the result's own vertex positions are used)");
  cmd->add_flag("--json", o->remote.json, "Print the result as one JSON line on stdout");
  add_remote_options(*cmd, o->remote);
  cmd->callback([o] {
    if (!o->out.empty()) check_result_path(o->out);
    RemoteClient client(o->remote);
    const v1::JobResult result = fetch_result(client, o->job_id);
    std::unique_ptr<Mesh> mesh;
    if (!o->mesh.empty()) mesh = std::make_unique<Mesh>(load_mesh(o->mesh));
    if (o->out.empty() && !o->remote.json) {
      std::cout << wire::result_message_to_json(result, mesh.get()).dump(1) << '\n';
      return;
    }
    deliver_result(result, mesh.get(), o->out, o->remote.json, o->job_id);
  });
}

}  // namespace depath::cli
