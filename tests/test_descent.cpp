// SPDX-License-Identifier: MIT
// The `descent` method through solve(): local refinement started from the fmm path traced
// both ways.
#include "depath/solve/job.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/solve/solve.hpp"
#include "depath/generators/surfaces.hpp"
#include "analytic_meshes.hpp"
#include "job_builders.hpp"
#include "test_support.hpp"
#include "truth_tables.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace depath {
namespace {

TEST(DescentMethod, ImprovesOnTheFmmPathAndReportsProgress) {
  const Mesh mesh = test::alternating_grid(31, GridHeight::peaks);
  JobSpec job = test::method_job(Method::descent, 0, mesh.num_vertices() - 1);
  job.path_every = 1;
  std::vector<Progress> reports;
  int with_path = 0;
  SolveHooks hooks;
  hooks.on_progress = [&](const Progress& p) {
    reports.push_back(p);
    with_path += p.best_path != nullptr;
  };
  const SolveResult result = solve(mesh, job, hooks);
  EXPECT_EQ(result.method, Method::descent);
  EXPECT_EQ(result.stop_reason, "converged");
  EXPECT_LT(result.energy, result.fmm_energy);
  EXPECT_NEAR(result.energy, result.length, 1e-9 * result.length);  // uniform density
  ASSERT_FALSE(reports.empty());
  EXPECT_EQ(static_cast<int>(reports.size()), result.generations);
  EXPECT_EQ(with_path, result.generations);
  for (std::size_t i = 0; i < reports.size(); ++i) {
    EXPECT_EQ(reports[i].generation, static_cast<int>(i) + 1);
    if (i > 0) {
      EXPECT_LE(reports[i].best_energy, reports[i - 1].best_energy);
      EXPECT_GE(reports[i].evaluations, reports[i - 1].evaluations);
    }
  }
  EXPECT_DOUBLE_EQ(reports.back().best_energy, result.energy);
  EXPECT_GT(result.evaluations, 0);
  EXPECT_EQ(result.path.points.front().v0, job.source);
  EXPECT_EQ(result.path.points.back().v0, job.target);
}

TEST(DescentMethod, CancelledStopsAtOnceWithTheFmmQuality) {
  const Mesh mesh = test::alternating_grid(31, GridHeight::peaks);
  JobSpec job = test::method_job(Method::descent, 0, mesh.num_vertices() - 1);
  SolveHooks hooks;
  hooks.is_cancelled = [] { return true; };
  const SolveResult result = solve(mesh, job, hooks);
  EXPECT_EQ(result.stop_reason, "cancelled");
  EXPECT_LE(result.energy, result.fmm_energy);
}

TEST(DescentMethod, ReachesTheExactGeodesicOnKitten) {
  DEPATH_REQUIRE_SHARED_DATA();
  const Mesh mesh = load_mesh(test::shared_data("meshes/kitten.off"));
  JobSpec job = test::method_job(Method::descent, 0, 755);
  const SolveResult result = solve(mesh, job);
  const double exact = 38.7146873422;  // geodesic_exact.csv: kitten.off,0,755
  EXPECT_GT(result.fmm_energy, exact * 1.005);  // the fmm path is 0.9% long
  EXPECT_LE(result.energy, exact * 1.001);
  EXPECT_GE(result.energy, exact * (1 - 1e-6));
}

TEST(DescentMethod, ExactGeodesicsOfTheSmallerSharedMeshes) {
  // Every pair of geodesic_exact.csv on the meshes below 12k vertices (60 pairs; the three
  // larger meshes are for bench_geodesic_table). Measured: all 60 (worst beethoven
  // 369 -> 595, +0.094%). Without the corridor detours 58 (beethoven 369 -> 595 +0.196%,
  // dragon 1862 -> 6698 +0.222%: local geodesics in another homotopy class than the exact
  // one, more than a vertex hop away); from the fmm path alone 56 (also dragon 1 -> 1281
  // +0.445% and 1467 -> 923 +0.124%).
  DEPATH_REQUIRE_SHARED_DATA();
  const std::vector<std::string> meshes = {"kitten.off", "cone.off", "beethoven.ply", "terrain_grid30.obj",
                                           "dragon.obj"};
  int pairs = 0, within = 0;
  for (const auto& row : test::read_exact_geodesics(test::shared_data("truth/geodesic_exact.csv"))) {
    if (std::find(meshes.begin(), meshes.end(), row.mesh) == meshes.end()) continue;
    const JobSpec job = test::method_job(Method::descent, row.source, row.target);
    const SolveResult result = solve(test::shared_mesh(row.mesh), job);
    const double error = result.length / row.length - 1.0;
    // A path on the mesh is never shorter than the exact geodesic (whose values carry
    // ~1e-7 relative error of their own).
    EXPECT_GE(error, -1e-6) << row.mesh << " " << row.source << " -> " << row.target;
    EXPECT_NEAR(result.energy, result.length, 1e-12 * result.length);
    ++pairs;
    within += error <= 1e-3;
    if (error > 1e-3) {
      std::printf("  above 0.1%%: %s %d -> %d %+.4f%%\n", row.mesh.c_str(), row.source, row.target, 100 * error);
    }
  }
  std::printf("  %d of %d pairs within 0.1%% of exact\n", within, pairs);
  EXPECT_EQ(pairs, 60);
  EXPECT_EQ(within, pairs);
}

TEST(DescentMethod, RefineAfterDescentChangesNothingForTheWorse) {
  const Mesh mesh = test::alternating_grid(31, GridHeight::peaks);
  JobSpec job = test::method_job(Method::descent, 40, 900);
  job.energy.kind = EnergyKind::constant_slope;
  job.energy.slope = 0.3;
  const SolveResult plain = solve(mesh, job);
  job.refine = true;
  const SolveResult refined = solve(mesh, job);
  EXPECT_TRUE(refined.refined);
  EXPECT_LT(plain.energy, plain.fmm_energy);
  EXPECT_LE(refined.energy, plain.energy);
}

}  // namespace
}  // namespace depath
