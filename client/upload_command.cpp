// SPDX-License-Identifier: MIT
// `depath upload MESH`: sends a mesh to depathd (to the shared store, with several replicas)
// unless it already has it; prints the mesh id.
#include "commands.hpp"
#include "remote_support.hpp"

#include <cstdio>
#include <iostream>
#include <vector>

namespace depath::cli {

void add_upload_command(CLI::App& app) {
  struct Opts {
    RemoteOptions remote;
    std::string mesh;
    std::string format;
    bool force = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = app.add_subcommand("upload", "Upload a mesh to the server (skipped if it has it); prints its id");
  cmd->add_option("MESH", o->mesh, "Mesh file (.obj, .off, .ply, .stl)")->required();
  cmd->add_flag("--force", o->force, "Send the bytes even if the server has the mesh");
  cmd->add_option("--format", o->format, "Mesh format when the extension does not tell (e.g. a .txt file)")
      ->check(CLI::IsMember({"obj", "off", "ply", "stl"}, CLI::ignore_case));
  cmd->add_flag("--json", o->remote.json, "Print the mesh info as JSON");
  add_remote_options(*cmd, o->remote);
  cmd->callback([o] {
    RemoteClient client(o->remote);
    bool uploaded = true;
    const v1::MeshInfo info = o->force ? client.upload(o->mesh, o->format) : client.ensure_mesh(o->mesh, &uploaded, o->format);
    if (o->remote.json) {
      std::cout << to_json_line(info) << '\n';
      return;
    }
    std::fprintf(stderr, "%s %s: %d vertices, %d faces, %d boundary edges, %d components\n",
                 uploaded && !info.already_present() ? "uploaded" : "already on the server:", o->mesh.c_str(),
                 info.num_vertices(), info.num_faces(), info.num_boundary_edges(), info.num_components());
    for (const auto& w : info.warnings()) std::fprintf(stderr, "  warning: %s\n", w.c_str());
    std::cout << info.id() << '\n';
  });
}

}  // namespace depath::cli
