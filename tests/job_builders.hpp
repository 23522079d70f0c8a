// SPDX-License-Identifier: MIT
// Jobs the tests (and bench/table1) build again and again.
#pragma once

#include "depath/solve/job.hpp"

#include <cstdint>

namespace depath::test {

/// A `de` job from `source` to `target` with the given population, generations, seed and
/// evaluation threads (0 = all cores); everything else at its default.
inline JobSpec de_job(int source, int target, int population, int generations, uint64_t seed = 3, int threads = 1) {
  JobSpec job;
  job.source = source;
  job.target = target;
  job.method = Method::de;
  job.de.population = population;
  job.de.generations = generations;
  job.seed = seed;
  job.threads = threads;
  return job;
}

}  // namespace depath::test
