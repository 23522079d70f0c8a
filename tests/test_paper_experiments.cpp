// SPDX-License-Identifier: MIT
// The paper's vector-field and constant-slope experiments (DE-Path, Fig. 7 and the terrain
// curves), small enough for the test suite: a 41 x 41 grid and a 961-vertex cone.
//
// Each problem has an analytic optimum of energy 0 whose end points are mesh vertices:
//  - rotation: the field is tangent to the circles around the centre; s and t lie on one
//    circle, so the arc between them follows the field exactly;
//  - converge: the field (1, -y / c) has field lines y = y0 exp(-x / c), converging towards
//    the x axis; s and t lie on one field line;
//  - constant slope: on a cone, a curve of constant slope dz/ds = k is a spiral
//    r = r0 exp(-(R / L) phi cot(alpha)), cos(alpha) = k L / h; the cone's height is chosen so
//    that the spiral from the rim (r = R, phi = 0) reaches r = R / 2 at phi = 120 degrees,
//    both mesh vertices.
// The DE runs use the adaptive strategy (SHADE) seeded with the problem's density and local
// refinement; the thresholds are the (paper: 0.053 and 0.062 normalized energy,
// mean slope errors 0.157 and 0.227 on terrains). Local descent from the fmm path gets stuck
// (paper Fig. 7), so DE must beat it.
#include "depath/solve/solve.hpp"
#include "depath/generators/surfaces.hpp"
#include "depath/mesh/tangent_fields.hpp"
#include "job_builders.hpp"
#include "time_scale.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace depath {
namespace {

constexpr double kPi = std::numbers::pi;

double metric(const SolveResult& r, const std::string& name) {
  for (const Metric& m : r.metrics)
    if (m.name == name) return m.value;
  ADD_FAILURE() << "no metric " << name;
  return -1.0;
}

// Every segment lies in its face: both end points are corners or edge points of it.
void expect_valid_path(const Mesh& mesh, const SurfacePath& path, int source, int target) {
  ASSERT_GE(path.points.size(), 2u);
  ASSERT_EQ(path.segment_faces.size() + 1, path.points.size());
  EXPECT_TRUE(path.points.front().is_vertex() && path.points.front().v0 == source);
  EXPECT_TRUE(path.points.back().is_vertex() && path.points.back().v0 == target);
  const auto on_face = [&](const SurfacePoint& p, int f) {
    return mesh.corner_of(f, p.v0) >= 0 && (p.is_vertex() || mesh.corner_of(f, p.v1) >= 0);
  };
  for (int i = 0; i < path.num_segments(); ++i) {
    const int f = path.segment_faces[i];
    ASSERT_TRUE(f >= 0 && f < mesh.num_faces()) << "segment " << i;
    EXPECT_TRUE(on_face(path.points[i], f) && on_face(path.points[i + 1], f)) << "segment " << i << " leaves face " << f;
  }
}

// The experiments' job: SHADE with refinement, population 20, seed 1, 2 threads.
JobSpec de_job(int source, int target, int generations) {
  return test::de_refine_job(source, target, 20, generations, 2);
}

JobSpec with_method(JobSpec job, Method method) {
  job.method = method;
  job.refine = false;
  return job;
}

// 41 x 41 flat grid over [-1, 1]^2 (spacing 0.05); vertex (i, j) = 41 j + i at
// (-1 + 0.05 i, -1 + 0.05 j).
Mesh grid41() {
  GridOptions o;
  o.n = 41;
  o.half_size = 1.0;
  return make_grid(o);
}
int grid_vertex(int i, int j) { return 41 * j + i; }

TEST(PaperExperiments, VectorFieldRotation) {
  const Mesh mesh = grid41();
  // s = (0.45, -0.6) and t = (-0.45, -0.6) on the circle of radius 0.75: the optimum is the
  // 73.7-degree arc below the chord; descent from the chord (symmetric about the y axis)
  // stays stuck. The best mesh path is not 0: chords of the arc cross the field lines; the
  // path through the arc's edge crossings scores 0.0096. A flattened arc (bottom on the
  // grid line y = -0.7, 0.107) traps a population of 20 early; DE must be robust to it,
  // for every seed. Measured with seeds 1-60: 0.0093 - 0.0169 (before smooth seeding and
  // restarts, 6 of seeds 1-10 ended at 0.107 or just above 0.02; with restarts on collapse
  // only, seed 32 ended at 0.107 and seed 2 at 0.024; with multi-start refinement and
  // vertex hops too, 0.0101 - 0.0169); descent 0.346.
  JobSpec job = de_job(grid_vertex(29, 8), grid_vertex(11, 8), 600);
  job.energy.kind = EnergyKind::vector_field;
  job.energy.field = rotation_field(mesh, Vec3::Zero(), 2);
  const SolveResult descent = solve(mesh, with_method(job, Method::descent));
  const double descent_norm = metric(descent, "normalized_energy");
  // Seeds 1-10 in the Release suite; sanitizer runs (memory and thread safety, 5-15x slower)
  // take seeds 1-2.
  const uint64_t last_seed = test::sanitized_build() ? 2 : 10;
  for (uint64_t seed = 1; seed <= last_seed; ++seed) {
    job.seed = seed;
    const SolveResult de = solve(mesh, job);
    expect_valid_path(mesh, de.path, job.source, job.target);
    const double de_norm = metric(de, "normalized_energy");
    std::printf("rotation seed %d: de+refine normalized %.4f (length %.4f, arc %.4f), descent %.4f, fmm energy %.4f\n",
                static_cast<int>(seed), de_norm, de.length, 0.75 * 2 * std::atan2(0.45, 0.6), descent_norm,
                de.fmm_energy);
    EXPECT_LE(de_norm, 0.02) << "seed " << seed;
    EXPECT_LT(de_norm, descent_norm) << "seed " << seed;
    // It is the arc: every point within a grid spacing of the circle.
    double worst = 0.0;
    for (const Vec3& p : path_positions(mesh, de.path)) worst = std::max(worst, std::abs(p.norm() - 0.75));
    EXPECT_LT(worst, 0.05) << "seed " << seed;
  }
}

TEST(PaperExperiments, VectorFieldConverge) {
  const Mesh mesh = grid41();
  // s = (-0.75, 0.75), t = (0.75, 0.15): on the field line y = 0.75 exp(-(x + 0.75) / c)
  // when exp(1.5 / c) = 5.
  const double c = 1.5 / std::log(5.0);
  JobSpec job = de_job(grid_vertex(5, 35), grid_vertex(35, 23), 600);
  job.energy.kind = EnergyKind::vector_field;
  job.energy.field = converge_field(mesh, Vec3::Zero(), 2, c);
  const SolveResult de = solve(mesh, job);
  expect_valid_path(mesh, de.path, job.source, job.target);
  const SolveResult descent = solve(mesh, with_method(job, Method::descent));
  const double de_norm = metric(de, "normalized_energy"), descent_norm = metric(descent, "normalized_energy");
  std::printf("converge: de+refine normalized %.4f, descent %.4f\n", de_norm, descent_norm);
  EXPECT_LE(de_norm, 0.02);
  EXPECT_LT(de_norm, descent_norm);
  double worst = 0.0;
  for (const Vec3& p : path_positions(mesh, de.path))
    worst = std::max(worst, std::abs(p.y() - 0.75 * std::exp(-(p.x() + 0.75) / c)));
  EXPECT_LT(worst, 0.05);
}

// Slope dz/ds of the spiral on a cone of height h (radius 1) making angle alpha with the
// generators, and the cone height for which the spiral of slope k turns by `phi` while
// its radius halves: ln 2 = (R / L) phi cot(alpha), found by bisection (monotone in h).
double spiral_turn(double h, double k) {
  const double L = std::hypot(h, 1.0);
  const double cos_alpha = k * L / h;
  return std::log(2.0) * L * std::sqrt(1.0 - cos_alpha * cos_alpha) / cos_alpha;
}

double cone_height_for(double k, double phi) {
  double lo = 1.0001 * k / std::sqrt(1.0 - k * k), hi = 100.0;  // cos(alpha) < 1 needs h / L > k
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (spiral_turn(mid, k) < phi ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(PaperExperiments, AnalyticConeSpiralHasSlopeK) {
  const double k = 0.2, h = cone_height_for(k, 2 * kPi / 3);
  const double L = std::hypot(h, 1.0);
  const double cot_alpha = 1.0 / std::tan(std::acos(k * L / h));
  // Sample the spiral on the exact cone z = h (1 - r) and measure its slope.
  Vec3 previous;
  double rise = 0.0, length = 0.0;
  const int steps = 100000;
  for (int i = 0; i <= steps; ++i) {
    const double phi = (2 * kPi / 3) * i / steps;
    const double r = std::exp(-phi * cot_alpha / L);
    const Vec3 p(r * std::cos(phi), r * std::sin(phi), h * (1.0 - r));
    if (i > 0) {
      rise += p.z() - previous.z();
      length += (p - previous).norm();
    }
    previous = p;
  }
  EXPECT_NEAR(previous.head<2>().norm(), 0.5, 1e-12);  // ends at half the radius
  EXPECT_NEAR(rise / length, k, 1e-8);
}

TEST(PaperExperiments, ConstantSlopeOnACone) {
  const double k = 0.2;
  ConeOptions o;
  o.height = cone_height_for(k, 2 * kPi / 3);
  o.radius = 1.0;
  o.rings = 20;
  o.sectors = 48;
  const Mesh mesh = make_cone(o);
  // s: rim, sector 0; t: ring 10 (radius 1/2), sector 16 (120 degrees).
  JobSpec job = de_job(cone_vertex(o, 20, 0), cone_vertex(o, 10, 16), 300);
  job.energy.kind = EnergyKind::constant_slope;
  job.energy.slope = k;
  const SolveResult de = solve(mesh, job);
  expect_valid_path(mesh, de.path, job.source, job.target);
  const SolveResult fmm = solve(mesh, with_method(job, Method::fmm));
  const double error = metric(de, "mean_slope_error"), fmm_error = metric(fmm, "mean_slope_error");
  std::printf("cone k = %.2f (h = %.4f): de+refine mean slope error %.4f, normalized %.4f; fmm %.4f\n", k, o.height,
              error, metric(de, "normalized_energy"), fmm_error);
  EXPECT_LE(error, 0.05);
  EXPECT_LT(error, fmm_error);
}

}  // namespace
}  // namespace depath
