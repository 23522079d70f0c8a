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

/// `de --refine` from `source` to `target`: SHADE seeded with the problem (the paper's
/// setting; also the angle tests' and bench/paper_figures' job), everything else at its default.
inline JobSpec de_refine_job(int source, int target, int population, int generations, int threads,
                             uint64_t seed = 1) {
  JobSpec job = de_job(source, target, population, generations, seed, threads);
  job.refine = true;
  job.de.strategy = "shade";
  job.de.seed_with_problem = true;
  return job;
}

/// A job of `method` (fmm, descent: no DE settings needed) from `source` to `target` on one
/// thread, everything else at its default.
inline JobSpec method_job(Method method, int source, int target) {
  JobSpec job;
  job.source = source;
  job.target = target;
  job.method = method;
  job.threads = 1;
  return job;
}

}  // namespace depath::test
