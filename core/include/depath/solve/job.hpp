// SPDX-License-Identifier: MIT
// A job: what to solve on a mesh, with which method and options. Shared by CLI and server.
//
// Inputs: the job's fields (from flags or from a depath.v1.JobSpec). Outputs:
// validate_job's verdict. Guarantees: validate_job is the one check of a job against its
// mesh; it throws Error(invalid_argument / failed_precondition) naming the field.
#pragma once

#include "depath/energy/energy.hpp"
#include "depath/mesh/mesh.hpp"

#include <cstdint>
#include <string>
#include <string_view>

namespace depath {

/// How the path is found.
enum class Method {
  de,       ///< DE-Path: differential evolution over density fields
  fmm,      ///< decode the problem's own density once (classic FMM geodesic)
  descent,  ///< local descent on the path, started from the `fmm` path
};
Method parse_method(std::string_view name);  ///< throws Error(invalid_argument)
const char* method_name(Method method);

/// Differential evolution options (SPEC §1).
struct DeOptions {
  int population = 20;       ///< agents, >= 4
  int generations = 100;     ///< maximum generations, >= 1
  int stall = 0;             ///< stop after this many generations without improvement (0 = never)
  double F = 0.5;            ///< mutation scale, in (0, 2]
  double CR = 0.9;           ///< crossover rate, in [0, 1]
  std::string strategy = "rand1bin";  ///< "rand1bin" (paper) or an adaptive strategy name
  bool seed_with_problem = false;     ///< seed agents with the problem's density + perturbations
};

/// Everything a job needs besides the mesh.
struct JobSpec {
  int source = -1;  ///< vertex id, 0-based in file order
  int target = -1;
  EnergySpec energy;
  Method method = Method::de;
  bool refine = false;  ///< local refinement after the method (never raises the energy)
  DeOptions de;
  uint64_t seed = 1;
  int threads = 0;      ///< evaluation threads when solve() makes its own pool (0 = all cores)
  int path_every = 0;   ///< attach the best path to progress every K generations (0 = never)
};

/// Checks a job against a mesh. Throws Error(invalid_argument) naming the problem
/// (vertex out of range, s == t, bad DE options, field/density length ...) or
/// Error(failed_precondition) when s and t lie in different connected components.
/// Also builds the energy once to check its spec (see make_energy).
void validate_job(const Mesh& mesh, const JobSpec& job);

/// The checks of validate_job that do not concern the energy spec.
void validate_job_options(const Mesh& mesh, const JobSpec& job);

}  // namespace depath
