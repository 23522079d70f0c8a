// SPDX-License-Identifier: MIT
// The job flags of SPEC §4, shared by `solve`, `submit` and `run` so they mean the same.
#pragma once

#include "depath/solve/job.hpp"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace depath::cli {

/// Raw flag values as parsed from the command line.
struct JobOptions {
  std::string mesh_path;
  std::string mesh_format;  ///< "obj", "off", "ply", "stl"; empty: from the extension
  int source = -1;
  int target = -1;
  std::string energy = "geodesic";
  std::string density_file;
  std::string field_file;
  bool field_from_height = false;
  double rotate_degrees = 0.0;
  double slope = 0.0;
  std::string up = "z";
  double smoothness = 0.0;
  std::string method = "de";
  bool refine = false;
  DeOptions de;
  uint64_t seed = 1;
  int threads = 0;
  int path_every = 0;
  std::string out;
  bool json = false;
};

/// Registers the job flags (and the MESH positional) on a subcommand.
/// `with_threads`: add --threads (only the embedded engine has its own threads).
void add_job_options(CLI::App& command, JobOptions& options, bool with_threads);

/// Builds the job spec: parses names, reads --density / --field files. Throws
/// depath::Error(invalid_argument) naming the bad flag or file.
JobSpec make_job_spec(const JobOptions& options);

/// "x" | "y" | "z" -> 0 | 1 | 2; throws Error(invalid_argument).
int parse_up_axis(const std::string& axis);

}  // namespace depath::cli
