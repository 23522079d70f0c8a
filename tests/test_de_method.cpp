// SPDX-License-Identifier: MIT
// Method `de` end to end through solve(): reproducibility across thread counts,
// convergence, never worse than `fmm` when seeded, progress reports, stop rules.
#include "depath/util/error.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/refine/refine.hpp"
#include "depath/solve/solve.hpp"
#include "depath/generators/surfaces.hpp"

#include "analytic_meshes.hpp"
#include "job_builders.hpp"
#include "test_support.hpp"
#include "truth_tables.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace depath {
namespace {

// A path is usable only if it runs from s to t and every segment lies in its face.
void expect_valid_path(const Mesh& mesh, const SurfacePath& path, int s, int t) {
  ASSERT_GE(path.points.size(), 2u);
  ASSERT_EQ(path.segment_faces.size(), path.points.size() - 1);
  EXPECT_TRUE(path.points.front().is_vertex() && path.points.front().v0 == s);
  EXPECT_TRUE(path.points.back().is_vertex() && path.points.back().v0 == t);
  auto in_face = [&](const SurfacePoint& p, int f) {
    return mesh.corner_of(f, p.v0) >= 0 && (p.is_vertex() || mesh.corner_of(f, p.v1) >= 0);
  };
  for (int i = 0; i < path.num_segments(); ++i) {
    const int f = path.segment_faces[i];
    ASSERT_TRUE(f >= 0 && f < mesh.num_faces()) << "segment " << i;
    EXPECT_TRUE(in_face(path.points[i], f) && in_face(path.points[i + 1], f))
        << "segment " << i << " of " << path.num_segments() << " leaves its face " << f;
  }
}

Mesh grid(int n, GridHeight height) {
  GridOptions options;
  options.n = n;
  options.height = height;
  return make_grid(options);
}

using test::de_job;

TEST(DeMethod, SameSeedSameResultWhateverTheThreadCount) {
  const Mesh mesh = grid(17, GridHeight::peaks);
  for (const std::string strategy : {"rand1bin", "shade"}) {
    JobSpec job = de_job(0, 17 * 17 - 1, 10, 12, 11);
    job.de.strategy = strategy;
    job.threads = 1;
    const SolveResult one = solve(mesh, job);
    job.threads = 2;
    const SolveResult two = solve(mesh, job);
    job.threads = 4;
    const SolveResult four = solve(mesh, job);
    for (const SolveResult* r : {&two, &four}) {
      EXPECT_EQ(r->energy, one.energy) << strategy;
      EXPECT_EQ(r->evaluations, one.evaluations) << strategy;
      ASSERT_EQ(r->path.points.size(), one.path.points.size()) << strategy;
      for (size_t k = 0; k < one.path.points.size(); ++k) {
        EXPECT_EQ(r->path.points[k].v0, one.path.points[k].v0);
        EXPECT_EQ(r->path.points[k].v1, one.path.points[k].v1);
        EXPECT_EQ(r->path.points[k].t, one.path.points[k].t);
      }
    }
    EXPECT_EQ(one.generations, 12);
    EXPECT_EQ(one.evaluations, 10 * 13);
    expect_valid_path(mesh, one.path, 0, 17 * 17 - 1);
  }
}

// The paper's setting (random initial densities, rand/1/bin) on a flat grid whose optimum
// is the straight diagonal: the best energy falls steadily towards it.
TEST(DeMethod, ConvergesOnASmallFlatGrid) {
  const int n = 11;
  const Mesh mesh = grid(n, GridHeight::flat);
  const double straight = std::sqrt(2.0) * 6.0;
  std::vector<double> best;
  SolveHooks hooks;
  hooks.on_progress = [&](const Progress& p) { best.push_back(p.best_energy); };
  const SolveResult r = solve(mesh, de_job(0, n * n - 1, 20, 120), hooks);
  ASSERT_EQ(best.size(), 120u);
  EXPECT_GT(best.front(), straight * 1.02);  // random densities start well off the optimum
  EXPECT_LT(r.energy, straight * 1.005);
  EXPECT_GE(r.energy, straight * (1.0 - 1e-12));
  EXPECT_EQ(r.energy, best.back());
  expect_valid_path(mesh, r.path, 0, n * n - 1);
}

// DE seeded with the problem (16 agents x 30 generations) corner to corner across the
// 21 x 21 peaks terrain with alternating diagonals.
struct SeededOnPeaks {
  static constexpr int n = 21;
  const int target = n * n - 1;
  const Mesh mesh = test::alternating_grid(n, GridHeight::peaks);
  JobSpec job = seeded(de_job(0, target, 16, 30));

  static JobSpec seeded(JobSpec job) {
    job.de.seed_with_problem = true;
    return job;
  }
};

// On a curved surface (peaks) the fmm back-trace is off the geodesic by a fraction of a
// percent; seeded DE starts from it, so it can only end at or below it, and does better.
TEST(DeMethod, SeededWithTheProblemNeverWorseThanFmmAndImprovesOnIt) {
  const SeededOnPeaks peaks;
  const Mesh& mesh = peaks.mesh;
  JobSpec job = peaks.job;
  for (const std::string strategy : {"rand1bin", "shade"}) {
    job.de.strategy = strategy;
    const SolveResult r = solve(mesh, job);
    EXPECT_LE(r.energy, r.fmm_energy) << strategy;
    EXPECT_LT(r.energy, r.fmm_energy * 0.999) << strategy << ": DE should improve on the fmm back-trace";
    EXPECT_DOUBLE_EQ(r.energy, r.length) << "uniform density: the energy is the length";
    expect_valid_path(mesh, r.path, 0, peaks.target);
  }
}

// With refinement, the result is the best of the refined starts (DE's best path, the fmm
// path, the final population's): never above refining DE's path or the fmm path alone,
// and still the same whatever the thread count.
TEST(DeMethod, RefinedResultIsTheBestOfTheRefinedStarts) {
  const SeededOnPeaks peaks;
  const Mesh& mesh = peaks.mesh;
  JobSpec job = peaks.job;
  job.de.strategy = "shade";
  const SolveResult plain = solve(mesh, job);
  JobSpec fmm_job = job;
  fmm_job.method = Method::fmm;
  const SolveResult fmm = solve(mesh, fmm_job);
  job.refine = true;
  const SolveResult refined = solve(mesh, job);
  EXPECT_TRUE(refined.refined);
  expect_valid_path(mesh, refined.path, 0, peaks.target);
  const auto energy = make_energy(mesh, job.energy);
  RefineOptions local;
  local.max_hops = 0;
  EXPECT_LE(refined.energy, energy->evaluate(refine_path(*energy, plain.path, local)));
  EXPECT_LE(refined.energy, energy->evaluate(refine_path(*energy, fmm.path, local)));
  EXPECT_LT(refined.energy, plain.energy);
  job.threads = 2;
  const SolveResult two = solve(mesh, job);
  EXPECT_EQ(two.energy, refined.energy);
  ASSERT_EQ(two.path.points.size(), refined.path.points.size());
  for (size_t k = 0; k < two.path.points.size(); ++k) EXPECT_EQ(two.path.points[k].t, refined.path.points[k].t);
}

// Uniform geodesic on small real meshes: seeded `de` never ends above `fmm`, never below
// the exact geodesic distance.
TEST(DeMethod, UniformGeodesicOnSharedMeshesNeverWorseThanFmm) {
  DEPATH_REQUIRE_SHARED_DATA();
  std::ifstream truth(test::shared_data("truth/geodesic_exact.csv"));
  ASSERT_TRUE(truth) << "truth/geodesic_exact.csv missing";
  std::map<std::string, int> pairs_per_mesh;
  int checked = 0;
  for (const auto& row : test::read_exact_geodesics(test::shared_data("truth/geodesic_exact.csv"))) {
    const std::string& name = row.mesh;
    if (name != "kitten.off" && name != "cone.off" && name != "terrain_grid30.obj") continue;
    if (++pairs_per_mesh[name] > 3) continue;
    const int s = row.source, t = row.target;
    const double exact = row.length;
    const Mesh& mesh = test::shared_mesh(name);
    JobSpec job = de_job(s, t, 10, 8);
    job.de.seed_with_problem = true;
    job.threads = 2;
    const SolveResult r = solve(mesh, job);
    SCOPED_TRACE(name + " " + std::to_string(s) + " -> " + std::to_string(t));
    EXPECT_LE(r.energy, r.fmm_energy);
    EXPECT_GE(r.energy, exact * (1.0 - 1e-9)) << "shorter than the exact geodesic: the path is not on the surface";
    expect_valid_path(mesh, r.path, s, t);
    ++checked;
  }
  EXPECT_EQ(checked, 9);
}

TEST(DeMethod, ReportsProgressWithTheBestPathEveryKGenerations) {
  const int n = 15;
  const Mesh mesh = grid(n, GridHeight::peaks);
  JobSpec job = de_job(3, n * n - 5, 8, 9);
  job.path_every = 3;
  job.threads = 2;
  const auto energy = make_energy(mesh, job.energy);
  std::vector<Progress> reports;
  int with_path = 0;
  SolveHooks hooks;
  hooks.on_progress = [&](const Progress& p) {
    reports.push_back(p);
    if (p.best_path) {
      ++with_path;
      EXPECT_EQ(p.generation % 3, 0);
      EXPECT_DOUBLE_EQ(energy->evaluate(*p.best_path), p.best_energy);
      expect_valid_path(mesh, *p.best_path, 3, n * n - 5);
    }
  };
  const SolveResult r = solve(mesh, job, hooks);
  ASSERT_EQ(reports.size(), 9u);
  EXPECT_EQ(with_path, 3);
  for (size_t g = 0; g < reports.size(); ++g) {
    EXPECT_EQ(reports[g].generation, static_cast<int>(g) + 1);
    EXPECT_EQ(reports[g].max_generations, 9);
    EXPECT_EQ(reports[g].evaluations, 8 * static_cast<int64_t>(g + 2));
    EXPECT_GE(reports[g].mean_energy, reports[g].best_energy);
    if (g > 0) {
      EXPECT_LE(reports[g].best_energy, reports[g - 1].best_energy);
      EXPECT_GE(reports[g].elapsed_seconds, reports[g - 1].elapsed_seconds);
    }
  }
  EXPECT_EQ(r.energy, reports.back().best_energy);
  EXPECT_EQ(r.stop_reason, "max_generations");
}

TEST(DeMethod, CancellationReturnsTheBestSoFar) {
  const int n = 15;
  const Mesh mesh = grid(n, GridHeight::peaks);
  std::atomic<int> generations{0};
  SolveHooks hooks;
  hooks.on_progress = [&](const Progress&) { ++generations; };
  hooks.is_cancelled = [&] { return generations.load() >= 2; };
  const SolveResult r = solve(mesh, de_job(0, n * n - 1, 8, 50), hooks);
  EXPECT_EQ(r.stop_reason, "cancelled");
  EXPECT_EQ(r.generations, 2);
  EXPECT_EQ(r.evaluations, 8 * 3);
  EXPECT_TRUE(std::isfinite(r.energy));
  expect_valid_path(mesh, r.path, 0, n * n - 1);
}

TEST(DeMethod, StopsAfterStallGenerationsWithoutImprovement) {
  // Flat grid, uniform density: the seeded fmm path is already the straight diagonal,
  // so the best cannot improve.
  const int n = 9;
  const Mesh mesh = grid(n, GridHeight::flat);
  JobSpec job = de_job(0, n * n - 1, 8, 200);
  job.de.seed_with_problem = true;
  job.de.stall = 4;
  const SolveResult r = solve(mesh, job);
  EXPECT_EQ(r.stop_reason, "stalled");
  EXPECT_EQ(r.generations, 4);
  EXPECT_DOUBLE_EQ(r.energy, r.fmm_energy);
  EXPECT_NEAR(r.energy, std::sqrt(2.0) * 6.0, 1e-9);
}

TEST(DeMethod, UnknownStrategyIsAnInvalidArgumentNamingTheValidOnes) {
  const Mesh mesh = grid(5, GridHeight::flat);
  JobSpec job = de_job(0, 24, 8, 3);
  job.de.strategy = "best2exp";
  // Rejected by the job check itself (before any fast marching), and so by solve().
  for (const bool through_solve : {false, true}) {
    try {
      if (through_solve) {
        solve(mesh, job);
      } else {
        validate_job_options(mesh, job);
      }
      FAIL() << "no error";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
      const std::string m = e.what();
      EXPECT_NE(m.find("best2exp"), std::string::npos) << m;
      EXPECT_NE(m.find("rand1bin"), std::string::npos) << m;
      EXPECT_NE(m.find("shade"), std::string::npos) << m;
    }
  }
}

}  // namespace
}  // namespace depath
