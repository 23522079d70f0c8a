// SPDX-License-Identifier: MIT
// `depath render MESH RESULT.json --out picture.png`: a shaded picture of the mesh with the
// result's path and endpoints, the camera framed on the path (client/picture/).
#include <chrono>
#include <cstdio>
#include <memory>

#include "commands.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/io/vertex_data.hpp"
#include "depath/util/error.hpp"
#include "picture/camera.hpp"
#include "picture/result_path.hpp"
#include "picture/scene_painter.hpp"

namespace depath::cli {
namespace {

struct RenderOptions {
  std::string mesh, result, out, field, format;
  int width = 1200, height = 900;
};

void run_render(const RenderOptions& o) {
  if (o.out.size() < 4 || o.out.compare(o.out.size() - 4, 4, ".png") != 0)
    throw Error(ErrorCode::invalid_argument, "render output " + o.out + ": name it .png");
  if (o.width < 16 || o.height < 16 || o.width > 10000 || o.height > 10000)
    throw Error(ErrorCode::invalid_argument, "picture size must be between 16x16 and 10000x10000");
  const auto start = std::chrono::steady_clock::now();
  const Mesh mesh = load_mesh(o.mesh, o.format);
  const std::vector<Vec3> path = picture::read_result_path(o.result, mesh);
  std::vector<Vec3> field;
  if (!o.field.empty()) {
    field = read_vector_file(o.field);
    if (static_cast<int>(field.size()) != mesh.num_vertices())
      throw Error(ErrorCode::invalid_argument, "field " + o.field + " has " + std::to_string(field.size()) +
                                                   " vectors but the mesh has " +
                                                   std::to_string(mesh.num_vertices()) + " vertices");
  }
  const picture::OrthoCamera camera = picture::frame_on_path(mesh, path, o.width, o.height);
  picture::render_png(mesh, camera, path, field, o.out);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fprintf(stderr, "wrote %s (%dx%d, %d faces, %zu path points, %.2fs)\n", o.out.c_str(), o.width,
               o.height, mesh.num_faces(), path.size(), seconds);
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Draw a mesh with a result's path into a PNG picture");
  cmd->add_option("mesh", o->mesh, "Mesh file (obj, off, ply, stl)")->required();
  cmd->add_option("result", o->result, "Result JSON of a job on this mesh (depath ... --out x.json)")
      ->required();
  cmd->add_option("--out", o->out, "Picture to write (.png)")->required();
  cmd->add_option("--width", o->width, "Picture width, pixels")->capture_default_str();
  cmd->add_option("--height", o->height, "Picture height, pixels")->capture_default_str();
  cmd->add_option("--field", o->field, "Per-vertex vectors (x y z per line) drawn as an overlay");
  cmd->add_option("--format", o->format, "Mesh format when the extension does not say (obj, off, ply, stl)");
  cmd->callback([o] { run_render(*o); });
}

}  // namespace depath::cli
