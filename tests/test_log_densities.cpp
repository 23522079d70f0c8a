// SPDX-License-Identifier: MIT
// Densities from DE's log-densities: the vectorised exp against std::exp, its clamping,
// and fast marching on log-densities against fast marching on the densities themselves.
#include "../core/src/decode/log_densities.hpp"
#include "depath/decode/fast_marching.hpp"
#include "depath/generators/surfaces.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace depath {
namespace {

double ulps_apart(double a, double b) {
  if (a == b) return 0.0;
  return std::abs(a - b) / (std::nextafter(std::max(a, b), INFINITY) - std::max(a, b));
}

TEST(LogDensities, WithinOneUlpOfStdExpClampedToTheNormalRange) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> wide(-760.0, 720.0), typical(-25.0, 3.0);
  std::vector<double> logs(200000);
  for (size_t i = 0; i < logs.size(); ++i) logs[i] = i % 2 ? wide(rng) : typical(rng);
  std::vector<double> rho(logs.size());
  densities_from_logs(logs, rho);
  double worst = 0.0;
  for (size_t i = 0; i < logs.size(); ++i) {
    const double expected = std::clamp(std::exp(logs[i]), DBL_MIN, DBL_MAX);
    worst = std::max(worst, ulps_apart(rho[i], expected));
  }
  EXPECT_LE(worst, 1.0);
  std::printf("densities_from_logs vs std::exp over %zu values: worst %.2f ulp\n", logs.size(), worst);
}

TEST(LogDensities, ExtremesAndNonFiniteValuesAreClamped) {
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<double> logs{0.0, -1e4, 1e4, -inf, inf, std::nan(""), std::log(DBL_MIN) - 1.0,
                                 std::log(DBL_MAX) + 1.0, -0.0};
  std::vector<double> rho(logs.size());
  densities_from_logs(logs, rho);
  EXPECT_EQ(rho[0], 1.0);
  EXPECT_EQ(rho[1], DBL_MIN);
  EXPECT_EQ(rho[2], DBL_MAX);
  EXPECT_EQ(rho[3], DBL_MIN);
  EXPECT_EQ(rho[4], DBL_MAX);
  EXPECT_EQ(rho[5], DBL_MIN);  // NaN counts as -inf
  EXPECT_EQ(rho[6], DBL_MIN);
  EXPECT_EQ(rho[7], DBL_MAX);
  EXPECT_EQ(rho[8], 1.0);
}

TEST(LogDensities, MarchingOnLogsMatchesMarchingOnTheirExponentials) {
  GridOptions options;
  options.n = 31;
  options.height = GridHeight::peaks;
  const Mesh mesh = make_grid(options);
  const FastMarchingStencils stencils(mesh);
  FastMarching on_logs(stencils), on_densities(stencils);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> uniform(1e-9, 1.0);
  std::vector<double> logs(mesh.num_vertices()), rho(mesh.num_vertices());
  for (double& l : logs) l = std::log(uniform(rng));
  for (size_t v = 0; v < logs.size(); ++v) rho[v] = std::exp(logs[v]);
  on_logs.run_log(logs, 0);
  on_densities.run(rho, 0);
  ASSERT_EQ(on_logs.num_final(), mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    EXPECT_NEAR(on_logs.value(v), on_densities.value(v), 1e-12 * on_densities.value(v)) << v;
  }
  // A span shorter than the mesh: the vertices past its end (the upper half of the grid)
  // have density 0, so they all share the value where the front enters them, and the far
  // corner costs less than the end of the bottom row.
  const std::vector<double> ones_then_free(mesh.num_vertices() / 2, 0.0);
  on_logs.run_log(ones_then_free, 0);
  const int far_corner = mesh.num_vertices() - 1, first_free = static_cast<int>(ones_then_free.size());
  EXPECT_EQ(on_logs.value(far_corner), on_logs.value(first_free));
  EXPECT_LT(on_logs.value(far_corner), on_logs.value(options.n - 1));
}

}  // namespace
}  // namespace depath
