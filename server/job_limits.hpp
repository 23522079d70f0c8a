// Per-job limits of depathd, checked at submit (after the core's validate_job): they protect
// the machine, not the algorithm, so they live in the server and are flags (ServerOptions).
#pragma once

#include <cstdint>

#include "depath/solve/job.hpp"
#include "options.hpp"

namespace depath::service {

/// Bytes a DE job holds per agent and vertex: the population's log-densities and the trial
/// population (2 x 8 bytes); measured: population 5000 on bunny (34,835 vertices) took 2.8 GB.
constexpr uint64_t kJobBytesPerAgentVertex = 16;

/// Up-front memory estimate of a job on a mesh of `num_vertices` vertices.
uint64_t estimated_job_bytes(const JobSpec& spec, int num_vertices);

/// Throws ServiceError(RESOURCE_EXHAUSTED) naming the limit and its flag when the job asks for
/// more generations (--max-generations), evaluations (population x generations,
/// --max-evaluations) or memory (estimated_job_bytes, --max-job-memory-bytes) than allowed.
void check_job_limits(const ServerOptions& options, const JobSpec& spec, int num_vertices);

}  // namespace depath::service
