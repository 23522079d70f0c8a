// SPDX-License-Identifier: MIT
#include "job_options.hpp"

#include "depath/util/error.hpp"
#include "depath/io/vertex_data.hpp"

namespace depath::cli {

void add_job_options(CLI::App& cmd, JobOptions& o, bool with_threads) {
  cmd.add_option("MESH", o.mesh_path, "Mesh file (.obj, .off, .ply, .stl)")->required();
  cmd.add_option("--format", o.mesh_format, "Mesh format when the extension does not tell (e.g. a .txt file)")
      ->check(CLI::IsMember({"obj", "off", "ply", "stl"}, CLI::ignore_case));
  cmd.add_option("--source,-s", o.source, "Source vertex id (0-based, file order)")->required();
  cmd.add_option("--target,-t", o.target, "Target vertex id (0-based, file order)")->required();
  cmd.add_option("--energy", o.energy, "geodesic | vector_field | constant_slope")->capture_default_str();
  cmd.add_option("--density", o.density_file, "Per-vertex density, one value per line (geodesic)");
  cmd.add_option("--field", o.field_file, "Per-vertex vectors, 'x y z' per line (vector_field)");
  cmd.add_flag("--field-from-height", o.field_from_height, "Generate the field as the height gradient");
  cmd.add_option("--rotate", o.rotate_degrees, "Rotate a generated field in the tangent plane (degrees)");
  cmd.add_option("--slope", o.slope, "Target slope k (constant_slope)");
  cmd.add_option("--up", o.up, "Height axis: x | y | z")->capture_default_str();
  cmd.add_option("--smoothness", o.smoothness, "Smoothness penalty weight (sum of turning angles)");
  cmd.add_option("--method", o.method, "de | fmm | descent")->capture_default_str();
  cmd.add_flag("--refine", o.refine, "Refine the path locally after the method (energy never rises)");
  cmd.add_option("--population", o.de.population, "DE agents (>= 4)")->capture_default_str();
  cmd.add_option("--generations", o.de.generations, "Maximum DE generations")->capture_default_str();
  cmd.add_option("--stall", o.de.stall, "Stop after this many generations without improvement (0 = never)")
      ->capture_default_str();
  cmd.add_option("--F", o.de.F, "DE mutation scale, in (0, 2]")->capture_default_str();
  cmd.add_option("--CR", o.de.CR, "DE crossover rate, in [0, 1]")->capture_default_str();
  cmd.add_option("--strategy", o.de.strategy, "DE strategy (rand1bin = the paper's)")->capture_default_str();
  cmd.add_flag("--seed-with-problem", o.de.seed_with_problem,
               "Seed DE with the problem's own density and perturbations of it");
  cmd.add_option("--seed", o.seed, "Random seed (same seed, same result)")->capture_default_str();
  if (with_threads) cmd.add_option("--threads", o.threads, "Evaluation threads (0 = all cores)")->capture_default_str();
  cmd.add_option("--path-every", o.path_every, "Report the best path every K generations (0 = never)");
  cmd.add_option("--out,-o", o.out, "Write the result: .json, .obj, .ply or .csv");
  cmd.add_flag("--json", o.json, "Print JSON lines instead of a progress bar");
}

int parse_up_axis(const std::string& axis) {
  if (axis == "x" || axis == "X") return 0;
  if (axis == "y" || axis == "Y") return 1;
  if (axis == "z" || axis == "Z") return 2;
  throw Error(ErrorCode::invalid_argument, "--up must be x, y or z, got '" + axis + "'");
}

JobSpec make_job_spec(const JobOptions& o) {
  JobSpec job;
  job.source = o.source;
  job.target = o.target;
  job.energy.kind = parse_energy_kind(o.energy);
  if (!o.density_file.empty()) {
    if (job.energy.kind != EnergyKind::geodesic)
      throw Error(ErrorCode::invalid_argument, "--density applies to the geodesic energy only");
    job.energy.density = read_scalar_file(o.density_file);
  }
  if (!o.field_file.empty()) job.energy.field = read_vector_file(o.field_file);
  job.energy.field_from_height = o.field_from_height;
  job.energy.rotate_degrees = o.rotate_degrees;
  job.energy.slope = o.slope;
  job.energy.up_axis = parse_up_axis(o.up);
  job.energy.smoothness = o.smoothness;
  job.method = parse_method(o.method);
  job.refine = o.refine;
  job.de = o.de;
  job.seed = o.seed;
  job.threads = o.threads;
  job.path_every = o.path_every;
  return job;
}

}  // namespace depath::cli
