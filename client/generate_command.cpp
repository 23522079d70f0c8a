// SPDX-License-Identifier: MIT
// `depath generate grid|peaks|cone`: writes the paper's test surfaces (SPEC §4) to OBJ, OFF
// or PLY, optionally with a per-vertex field file for the vector_field experiments.
#include "commands.hpp"
#include "depath/util/error.hpp"
#include "depath/io/mesh_writer.hpp"
#include "depath/generators/surfaces.hpp"
#include "depath/mesh/tangent_fields.hpp"
#include "job_options.hpp"

#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

namespace depath::cli {
namespace {

// Options common to every surface.
struct OutputOptions {
  std::string out;
  bool binary = false;
  std::string up = "z";
  std::string field_out;
  std::string field = "rotation";
  double rotate_degrees = 0.0;
  double converge_length = 1.0;
};

void add_output_options(CLI::App& cmd, OutputOptions& o) {
  cmd.add_option("--out", o.out, "Mesh file to write (.obj, .off or .ply)")->required();
  cmd.add_flag("--binary", o.binary, "Write PLY as binary little-endian (default ascii)");
  cmd.add_option("--up", o.up, "Height axis x | y | z")->capture_default_str();
  cmd.add_option("--field-out", o.field_out,
                 "Also write a per-vertex field ('x y z' per line, for solve --field)");
  cmd.add_option("--field", o.field,
                 "Field for --field-out: rotation (circles around the up axis through the origin), "
                 "converge ((1, -v / L) in plane coordinates (u, v): field lines v0 exp(-u / L) "
                 "converging towards v = 0) or height (height gradient, see --rotate)")
      ->capture_default_str();
  cmd.add_option("--converge-length", o.converge_length, "L of the converge field")->capture_default_str();
  cmd.add_option("--rotate", o.rotate_degrees, "Rotate the height field in the tangent plane (degrees)")
      ->capture_default_str();
}

void write_field(const std::string& path, const std::vector<Vec3>& field) {
  std::ofstream file(path, std::ios::trunc);
  if (!file) throw Error(ErrorCode::invalid_argument, "cannot open '" + path + "' for writing");
  char line[96];
  for (const Vec3& v : field) {
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", v.x(), v.y(), v.z());
    file << line;
  }
  file.close();
  if (!file) throw Error(ErrorCode::invalid_argument, "failed writing '" + path + "'");
}

void emit(const Mesh& mesh, const OutputOptions& o, int up_axis) {
  write_mesh(o.out, mesh, o.binary);
  std::fprintf(stderr, "wrote %s: %d vertices, %d faces\n", o.out.c_str(), mesh.num_vertices(), mesh.num_faces());
  if (o.field_out.empty()) return;
  std::vector<Vec3> field;
  if (o.field == "rotation") {
    field = rotation_field(mesh, Vec3::Zero(), up_axis);
  } else if (o.field == "converge") {
    field = converge_field(mesh, Vec3::Zero(), up_axis, o.converge_length);
  } else if (o.field == "height") {
    field = height_gradient_field(mesh, up_axis, o.rotate_degrees);
  } else {
    throw Error(ErrorCode::invalid_argument,
                "unknown --field '" + o.field + "' (expected rotation, converge or height)");
  }
  write_field(o.field_out, field);
  std::fprintf(stderr, "wrote %s: %s field, %zu vectors\n", o.field_out.c_str(), o.field.c_str(), field.size());
}

void add_grid_command(CLI::App& generate, const char* name, const char* description, GridHeight default_height) {
  struct State {
    GridOptions grid;
    OutputOptions output;
    std::string terrain;
    std::string diagonals = "uniform";
  };
  auto s = std::make_shared<State>();
  s->terrain = default_height == GridHeight::peaks ? "peaks" : "flat";
  CLI::App* cmd = generate.add_subcommand(name, description);
  cmd->add_option("--n", s->grid.n, "Vertices per side (n x n vertices)")->capture_default_str();
  cmd->add_option("--half-size", s->grid.half_size, "The grid spans [-h, h]^2 (3 = MATLAB's peaks domain)")
      ->capture_default_str();
  cmd->add_option("--terrain", s->terrain, "Height function: flat | peaks")->capture_default_str();
  cmd->add_option("--height-scale", s->grid.height_scale, "Multiplies the heights")->capture_default_str();
  cmd->add_option("--diagonals", s->diagonals, "Cell split: uniform | alternating")->capture_default_str();
  add_output_options(*cmd, s->output);
  cmd->callback([s] {
    GridOptions o = s->grid;
    o.height = parse_grid_height(s->terrain);
    o.diagonals = parse_grid_diagonals(s->diagonals);
    o.up_axis = parse_up_axis(s->output.up);
    emit(make_grid(o), s->output, o.up_axis);
  });
}

void add_cone_command(CLI::App& generate) {
  struct State {
    ConeOptions cone;
    OutputOptions output;
  };
  auto s = std::make_shared<State>();
  CLI::App* cmd = generate.add_subcommand("cone", "Cone around the up axis, apex on top (vertex 0)");
  cmd->add_option("--height", s->cone.height, "Apex height above the base")->capture_default_str();
  cmd->add_option("--radius", s->cone.radius, "Base radius")->capture_default_str();
  cmd->add_option("--rings", s->cone.rings, "Rings of vertices from apex to rim")->capture_default_str();
  cmd->add_option("--sectors", s->cone.sectors, "Vertices per ring")->capture_default_str();
  cmd->add_flag("--cap", s->cone.cap, "Close the base");
  add_output_options(*cmd, s->output);
  cmd->callback([s] {
    ConeOptions o = s->cone;
    o.up_axis = parse_up_axis(s->output.up);
    emit(make_cone(o), s->output, o.up_axis);
  });
}

}  // namespace

void add_generate_command(CLI::App& app) {
  CLI::App* generate = app.add_subcommand("generate", "Write the paper's test surfaces: grid, peaks, cone");
  generate->require_subcommand(1);
  add_grid_command(*generate, "grid", "Regular n x n grid (flat unless --terrain peaks)", GridHeight::flat);
  add_grid_command(*generate, "peaks", "Regular n x n grid lifted to MATLAB's peaks terrain", GridHeight::peaks);
  add_cone_command(*generate);
}

}  // namespace depath::cli
