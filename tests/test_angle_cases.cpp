// SPDX-License-Identifier: MIT
// The angle energies on seeded random analytic cases (tests/random_cases.hpp, issue 12):
// contour-following fields on random Gaussian terrains and constant-slope spirals on random
// cones, each with a known path of (near) zero angle energy. For every instance, at
// smoothness 0 and 0.1, `de --refine` (tests/angle_job.hpp: 8 agents x 20 generations)
// must reach
//  - contour: normalized field energy <= 0.02;
//  - spiral: mean |dz/ds - k| <= 0.05;
// and with the penalty on, the path turns no more than without it, as the penalty measures
// turning (relative to the preferred lines, Energy::turning_angle: the exact contour or
// spiral costs nothing for its own curvature), and its whole energy is no higher than the
// penalty-free result's. The plain turning within the surface is printed beside it: on the
// contours it may rise slightly, as the path follows the curved contour more closely.
// The sanitizer runs (memory and thread safety, 4-15x slower) take every 5th instance.
// DEPATH_ANGLE_FIRST_SEED=N runs seeds N..N+19 instead of 1..20.
#include "angle_job.hpp"
#include "path_checks.hpp"
#include "random_cases.hpp"
#include "time_scale.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

namespace depath {
namespace {

constexpr int kInstances = 20;
int stride() { return test::sanitized_build() ? 5 : 1; }
// The first seed: 1, or DEPATH_ANGLE_FIRST_SEED (to check seeds the code was not tuned on;
// the thresholds stay the same).
int first_seed() {
  const char* env = std::getenv("DEPATH_ANGLE_FIRST_SEED");
  return env != nullptr && std::atoi(env) > 0 ? std::atoi(env) : 1;
}

void check_family(test::AngleFamily family, const char* figure_name, double threshold) {
  for (int seed = first_seed(); seed < first_seed() + kInstances; seed += stride()) {
    const test::AngleCase c = test::random_angle_case(family, seed);
    SCOPED_TRACE("seed " + std::to_string(seed) + ": " + c.description);
    SurfacePath without;
    double charged_without = 0.0;
    for (const double lambda : {0.0, 0.1}) {
      const JobSpec job = test::angle_job(c, lambda);
      const SolveResult r = solve(c.mesh, job);
      ASSERT_TRUE(test::is_valid_path(c.mesh, r.path, c.source, c.target));
      const double figure = test::result_metric(r, figure_name);
      const double turning = test::total_turning(c.mesh, r.path);
      const double charged = test::penalty_turning(c.mesh, job.energy, r.path);
      std::printf("seed %2d lambda %.1f: %s %.4f, turning %.3f, charged %.3f  (%s)\n", seed, lambda,
                  figure_name, figure, turning, charged, c.description.c_str());
      if (lambda == 0.0) {
        EXPECT_LE(figure, threshold);
        without = r.path;
        charged_without = charged;
        continue;
      }
      // The penalty does its job: no more of the turning it charges than without it, and a
      // whole energy no higher than the penalty-free result's.
      EXPECT_LE(charged, charged_without + 1e-9) << "the penalty made the path turn more";
      const auto energy = make_energy(c.mesh, job.energy);
      EXPECT_LE(r.energy, energy->evaluate(without) + 1e-12);
      EXPECT_LE(figure, threshold) << "lambda " << lambda;
    }
  }
}

TEST(AngleCases, GeneratorIsSeededAndNudgesTOntoTheCurve) {
  for (const auto family : {test::AngleFamily::contour, test::AngleFamily::spiral}) {
    const test::AngleCase a = test::random_angle_case(family, 7), b = test::random_angle_case(family, 7);
    EXPECT_EQ(a.description, b.description);
    EXPECT_EQ(a.mesh.positions(), b.mesh.positions());
    EXPECT_EQ(a.source, b.source);
    EXPECT_EQ(a.target, b.target);
    EXPECT_NE(a.source, a.target);
    // Distinct seeds, distinct cases.
    for (int other = 1; other <= 20; ++other) {
      if (other == 7) continue;
      EXPECT_NE(test::random_angle_case(family, other).mesh.positions(), a.mesh.positions()) << other;
    }
    // The nudge is a small fraction of an edge, so the mesh stays regular.
    EXPECT_LT(a.nudge, 0.6 * a.mesh.mean_edge_length());
  }
}

TEST(AngleCases, ContourFieldsOnRandomTerrains) {
  check_family(test::AngleFamily::contour, "normalized_energy", 0.02);
}

TEST(AngleCases, ConstantSlopeSpiralsOnRandomCones) {
  check_family(test::AngleFamily::spiral, "mean_slope_error", 0.05);
}

}  // namespace
}  // namespace depath
