// SPDX-License-Identifier: MIT
#include "depath/solve/job.hpp"

#include "depath/de/differential_evolution.hpp"
#include "depath/util/error.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace depath {
namespace {

[[noreturn]] void invalid(const std::string& message) { throw Error(ErrorCode::invalid_argument, message); }

void check_vertex(const Mesh& mesh, int v, const char* role) {
  if (v < 0 || v >= mesh.num_vertices())
    invalid(std::string(role) + " vertex " + std::to_string(v) + " is out of range: the mesh has " +
            std::to_string(mesh.num_vertices()) + " vertices (ids 0.." + std::to_string(mesh.num_vertices() - 1) +
            ")");
  if (!mesh.is_referenced(v))
    invalid(std::string(role) + " vertex " + std::to_string(v) + " is used by no face, so no path can reach it");
}

}  // namespace

Method parse_method(std::string_view name) {
  if (name == "de") return Method::de;
  if (name == "fmm") return Method::fmm;
  if (name == "descent") return Method::descent;
  invalid("unknown method '" + std::string(name) + "': expected de, fmm or descent");
}

const char* method_name(Method method) {
  switch (method) {
    case Method::de: return "de";
    case Method::fmm: return "fmm";
    case Method::descent: return "descent";
  }
  return "unknown";
}

void validate_job_options(const Mesh& mesh, const JobSpec& job) {
  check_vertex(mesh, job.source, "source");
  check_vertex(mesh, job.target, "target");
  if (job.source == job.target)
    invalid("source and target are the same vertex (" + std::to_string(job.source) + ")");
  if (mesh.component(job.source) != mesh.component(job.target))
    throw Error(ErrorCode::failed_precondition,
                "no path: source vertex " + std::to_string(job.source) + " and target vertex " +
                    std::to_string(job.target) + " lie in different connected components of the mesh");
  const DeOptions& de = job.de;
  validate_de_parameters(de.population, de.generations, de.stall, de.F, de.CR, de.strategy);
  if (job.threads < 0) invalid("threads must be >= 0 (0 = all cores), got " + std::to_string(job.threads));
  if (job.path_every < 0) invalid("path_every must be >= 0, got " + std::to_string(job.path_every));
}

void validate_job(const Mesh& mesh, const JobSpec& job) {
  validate_job_options(mesh, job);
  (void)make_energy(mesh, job.energy);
}

}  // namespace depath
