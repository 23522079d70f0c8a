// SPDX-License-Identifier: MIT
// The job the angle-energy tests and bench/angle_cases run on a random case
// (tests/random_cases.hpp), and the figures they read off a result.
#pragma once

#include "depath/energy/energy.hpp"
#include "depath/energy/surface_turning.hpp"
#include "depath/solve/solve.hpp"
#include "job_builders.hpp"
#include "random_cases.hpp"

#include <string>

namespace depath::test {

/// DE sizes for the random angle cases: small on purpose, the guide curves (traced field /
/// constant-slope lines, solve/methods/guide.hpp), the seeding and the refinement must do
/// the work; the refinement takes most of a solve's time.
inline constexpr int kAnglePopulation = 8;
inline constexpr int kAngleGenerations = 20;

/// de_refine_job on `c` with its energy at smoothness `lambda`.
inline JobSpec angle_job(const AngleCase& c, double lambda, int population = kAnglePopulation,
                         int generations = kAngleGenerations, int threads = 2) {
  JobSpec job = de_refine_job(c.source, c.target, population, generations, threads);
  job.energy = c.energy;
  job.energy.smoothness = lambda;
  return job;
}

/// A named metric of a result (NaN if absent).
inline double result_metric(const SolveResult& r, const std::string& name) {
  for (const Metric& m : r.metrics)
    if (m.name == name) return m.value;
  return std::nan("");
}

/// Total turning of a path within the surface (radians): what a user sees of its bending.
/// (The penalty of the angle energies charges the turning relative to their preferred
/// lines instead: penalty_turning.)
inline double total_turning(const Mesh& mesh, const SurfacePath& path) {
  return total_surface_turning(mesh, path);
}

/// Total turning as the smoothness penalty of the job's energy charges it
/// (Energy::turning_angle).
inline double penalty_turning(const Mesh& mesh, EnergySpec spec, const SurfacePath& path) {
  spec.smoothness = 1.0;
  const auto energy = make_energy(mesh, spec);
  double sum = 0.0;
  for (int i = 1; i + 1 < static_cast<int>(path.points.size()); ++i) sum += energy->turning_angle(path, i);
  return sum;
}

}  // namespace depath::test
