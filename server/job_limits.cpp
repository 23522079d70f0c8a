#include "job_limits.hpp"

#include <algorithm>
#include <string>

#include "service_error.hpp"

namespace depath::service {

namespace {
std::string megabytes(uint64_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MB"; }
}  // namespace

uint64_t estimated_job_bytes(const JobSpec& spec, int num_vertices) {
  if (spec.method != Method::de) return 0;
  return static_cast<uint64_t>(std::max(0, spec.de.population)) *
         static_cast<uint64_t>(std::max(0, num_vertices)) * kJobBytesPerAgentVertex;
}

void check_job_limits(const ServerOptions& options, const JobSpec& spec, int num_vertices) {
  if (spec.method != Method::de) return;
  const uint64_t population = static_cast<uint64_t>(std::max(0, spec.de.population));
  const uint64_t generations = static_cast<uint64_t>(std::max(0, spec.de.generations));
  if (generations > options.max_generations)
    throw ServiceError(grpc::StatusCode::RESOURCE_EXHAUSTED, "generations " + std::to_string(generations) +
                                                                 " exceeds the server's limit of " +
                                                                 std::to_string(options.max_generations) +
                                                                 " generations per job (--max-generations)");
  const uint64_t bytes = estimated_job_bytes(spec, num_vertices);
  if (bytes > options.max_job_memory_bytes)
    throw ServiceError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                       "population " + std::to_string(population) + " on a mesh of " +
                           std::to_string(num_vertices) + " vertices needs about " + megabytes(bytes) +
                           " (population x vertices x " + std::to_string(kJobBytesPerAgentVertex) +
                           " bytes), more than the server's memory limit of " +
                           megabytes(options.max_job_memory_bytes) +
                           " per job (--max-job-memory-bytes); lower the population");
  const uint64_t evaluations = population * (generations + 1);
  if (evaluations > options.max_evaluations)
    throw ServiceError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                       "population " + std::to_string(population) + " x " + std::to_string(generations + 1) +
                           " generations (with the initial one) = " + std::to_string(evaluations) +
                           " evaluations exceeds the server's limit of " +
                           std::to_string(options.max_evaluations) +
                           " evaluations per job (--max-evaluations)");
}

}  // namespace depath::service
