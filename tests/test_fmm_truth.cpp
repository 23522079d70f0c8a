// SPDX-License-Identifier: MIT
// The `fmm` method against exact polyhedral geodesics and weighted Steiner-graph references.
#include "depath/io/mesh_reader.hpp"
#include "depath/io/vertex_data.hpp"
#include "depath/solve/solve.hpp"
#include "test_support.hpp"
#include "truth_tables.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>

namespace depath {
namespace {

SolveResult solve_fmm(const Mesh& mesh, int s, int t, std::vector<double> density = {}) {
  JobSpec job;
  job.source = s;
  job.target = t;
  job.method = Method::fmm;
  job.threads = 1;
  job.energy.density = std::move(density);
  return solve(mesh, job);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

TEST(FmmTruth, PathLengthsCloseToExactGeodesics) {
  DEPATH_REQUIRE_SHARED_DATA();
  const auto rows = test::read_exact_geodesics(test::shared_data("truth/geodesic_exact.csv"));
  ASSERT_GT(rows.size(), 50u);
  std::vector<double> errors;
  std::map<std::string, double> worst_per_mesh;
  for (const auto& row : rows) {
    const Mesh& mesh = test::shared_mesh(row.mesh);
    const SolveResult r = solve_fmm(mesh, row.source, row.target);
    const double error = r.length / row.length - 1.0;
    // A surface path can never be shorter than the exact geodesic.
    EXPECT_GT(error, -1e-6) << row.mesh << " " << row.source << "->" << row.target;
    errors.push_back(error);
    worst_per_mesh[row.mesh] = std::max(worst_per_mesh[row.mesh], error);
  }
  for (const auto& [mesh, worst] : worst_per_mesh) std::printf("  %-20s worst %+.3f%%\n", mesh.c_str(), 100 * worst);
  const double med = median(errors);
  const double worst = *std::max_element(errors.begin(), errors.end());
  std::printf("fmm vs exact over %zu pairs: median %+.3f%%, worst %+.3f%%\n", errors.size(), 100 * med, 100 * worst);
  EXPECT_LE(med, 0.01);
  EXPECT_LE(worst, 0.05);
}

TEST(FmmTruth, WeightedCostsCloseToSteinerReferences) {
  DEPATH_REQUIRE_SHARED_DATA();
  const auto rows = test::read_weighted_references(test::shared_data("truth/weighted_steiner.csv"));
  ASSERT_GT(rows.size(), 20u);
  std::vector<double> errors;
  for (const auto& row : rows) {
    const Mesh& mesh = test::shared_mesh(row.mesh);
    const auto density = read_scalar_file(test::shared_data("fields/" + row.density));
    const SolveResult r = solve_fmm(mesh, row.source, row.target, density);
    errors.push_back(r.energy / row.cost_k16 - 1.0);
  }
  const double med = median(errors);
  const double worst = *std::max_element(errors.begin(), errors.end());
  const double best = *std::min_element(errors.begin(), errors.end());
  std::printf("weighted fmm vs Steiner k16 over %zu pairs: median %+.3f%%, best %+.3f%%, worst %+.3f%%\n",
              errors.size(), 100 * med, 100 * best, 100 * worst);
  EXPECT_LE(med, 0.03);
  EXPECT_LE(worst, 0.10);
}

}  // namespace
}  // namespace depath
