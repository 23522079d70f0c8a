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
  if (de.population < 4)
    invalid("population must be at least 4 (DE needs 3 other agents), got " + std::to_string(de.population));
  if (de.generations < 1) invalid("generations must be at least 1, got " + std::to_string(de.generations));
  if (de.stall < 0) invalid("stall must be >= 0 (0 = never stop early), got " + std::to_string(de.stall));
  if (!std::isfinite(de.F) || de.F <= 0.0 || de.F > 2.0)
    invalid("F must be in (0, 2], got " + std::to_string(de.F));
  if (!std::isfinite(de.CR) || de.CR < 0.0 || de.CR > 1.0)
    invalid("CR must be in [0, 1], got " + std::to_string(de.CR));
  const auto& strategies = de_strategy_names();
  if (std::find(strategies.begin(), strategies.end(), de.strategy) == strategies.end()) {
    std::string list;
    for (const auto& name : strategies) list += (list.empty() ? "" : ", ") + name;
    invalid("unknown DE strategy '" + de.strategy + "' (valid strategies: " + list + ")");
  }
  if (job.threads < 0) invalid("threads must be >= 0 (0 = all cores), got " + std::to_string(job.threads));
  if (job.path_every < 0) invalid("path_every must be >= 0, got " + std::to_string(job.path_every));
}

void validate_job(const Mesh& mesh, const JobSpec& job) {
  validate_job_options(mesh, job);
  (void)make_energy(mesh, job.energy);
}

}  // namespace depath
