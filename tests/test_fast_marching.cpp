// SPDX-License-Identifier: MIT
// Fast marching and back-tracing on surfaces with analytic geodesics.
#include "analytic_meshes.hpp"
#include "depath/energy/energy.hpp"
#include "depath/decode/fast_marching.hpp"
#include "depath/decode/path_decoder.hpp"
#include "depath/decode/trace.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/generators/surfaces.hpp"
#include "path_checks.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <span>
#include <vector>

namespace depath {
namespace {

struct Decoded {
  double value;   // fast-marching value at the target
  double length;  // length of the traced path
};

Decoded decode_uniform(const Mesh& mesh, int s, int t) {
  const FastMarchingStencils stencils(mesh);
  PathDecoder decoder(stencils);
  SurfacePath path;
  const std::vector<double> ones(mesh.num_vertices(), 1.0);
  EXPECT_TRUE(decoder.decode(ones, s, t, path));
  EXPECT_TRUE(test::is_valid_path(mesh, path, s, t));
  return {decoder.fast_marching().value(t), path_length(mesh, path)};
}

TEST(FastMarching, PlaneStraightLinesAndDistances) {
  const Mesh mesh = test::alternating_grid(41);
  const int centre = 20 * 41 + 20;
  // Targets in several directions, including ones no mesh edge follows.
  for (const auto& [i, j] : std::vector<std::pair<int, int>>{{40, 20}, {40, 40}, {35, 0}, {0, 33}, {27, 40}, {3, 9}}) {
    const int t = j * 41 + i;
    const double exact = (mesh.position(t) - mesh.position(centre)).norm();
    const Decoded d = decode_uniform(mesh, centre, t);
    EXPECT_NEAR(d.length, exact, 0.005 * exact) << "target (" << i << "," << j << ")";
    EXPECT_GE(d.length, exact - 1e-9);
    EXPECT_NEAR(d.value, exact, 0.03 * exact) << "target (" << i << "," << j << ")";
  }
}

TEST(FastMarching, SphereGreatCircleErrorFallsWithRefinement) {
  const Vec3 a = Vec3(0.3, 0.2, 1.0).normalized();
  const Vec3 b = Vec3(-0.4, 0.9, -0.5).normalized();
  std::vector<double> errors;
  for (int level : {3, 4, 5}) {
    const Mesh mesh = test::make_icosphere(level);
    const int s = test::nearest_vertex(mesh, a), t = test::nearest_vertex(mesh, b);
    const double exact = std::acos(mesh.position(s).dot(mesh.position(t)));
    const Decoded d = decode_uniform(mesh, s, t);
    errors.push_back(std::abs(d.length / exact - 1.0));
    std::printf("  icosphere level %d (%d vertices): path %+.4f%%, fmm value %+.4f%%\n", level, mesh.num_vertices(),
                100 * (d.length / exact - 1), 100 * (d.value / exact - 1));
  }
  EXPECT_LT(errors[2], errors[0]);
  EXPECT_LT(errors[2], 0.005);
}

TEST(FastMarching, CylinderHelixMatchesUnrolledLength) {
  std::vector<double> errors;
  for (int sectors : {32, 64, 128}) {
    const int rings = sectors / 2 + 1;
    const double radius = 1.0, height = 3.0;
    const Mesh mesh = test::make_cylinder(radius, height, rings, sectors);
    const int s = 0, t = (rings - 1) * sectors + sectors / 4;
    // The polyhedral cylinder unrolls exactly: a quarter turn is sectors/4 chords.
    const double around = (sectors / 4) * 2 * radius * std::sin(M_PI / sectors);
    const double exact = std::hypot(around, height);
    const Decoded d = decode_uniform(mesh, s, t);
    EXPECT_GE(d.length, exact - 1e-9);
    errors.push_back(d.length / exact - 1.0);
    std::printf("  cylinder %d sectors: path %+.4f%%, fmm value %+.4f%%\n", sectors, 100 * errors.back(),
                100 * (d.value / exact - 1));
  }
  EXPECT_LT(errors[2], errors[0]);
  EXPECT_LT(errors[2], 0.003);
}

TEST(FastMarching, ConstantDensityScalesValuesExactly) {
  const Mesh mesh = test::make_icosphere(3);
  const FastMarchingStencils stencils(mesh);
  FastMarching fm1(stencils), fm2(stencils);
  fm1.run(std::vector<double>(mesh.num_vertices(), 1.0), 5);
  fm2.run(std::vector<double>(mesh.num_vertices(), 2.5), 5);
  for (int v = 0; v < mesh.num_vertices(); ++v) EXPECT_NEAR(fm2.value(v), 2.5 * fm1.value(v), 1e-12 * (1 + fm2.value(v)));
}

// Every vertex below the stop vertex is final with the full march's value; so is each pair
// of its neighbours across a corner wider than a right angle of which one is (what the
// trace's first step may read above it).
void expect_early_stop_keeps_what_the_trace_needs(const Mesh& mesh, std::span<const double> rho, int s, int t) {
  const FastMarchingStencils stencils(mesh);
  FastMarching full(stencils), early(stencils);
  full.run(rho, s);
  early.run(rho, s, t);
  ASSERT_TRUE(early.is_final(t));
  EXPECT_EQ(early.value(t), full.value(t));
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (full.value(v) >= full.value(t)) continue;
    EXPECT_TRUE(early.is_final(v)) << v;
    EXPECT_EQ(early.value(v), full.value(v)) << v;
  }
  for (const int* f = mesh.vertex_faces_begin(t); f != mesh.vertex_faces_end(t); ++f) {
    const auto& c = mesh.face(*f);
    const int i = mesh.corner_of(*f, t), a = c[(i + 1) % 3], b = c[(i + 2) % 3];
    if ((mesh.position(a) - mesh.position(t)).dot(mesh.position(b) - mesh.position(t)) >= 0.0) continue;
    EXPECT_EQ(early.is_final(a), early.is_final(b));
    if (early.is_final(a)) {
      EXPECT_EQ(early.value(a), full.value(a));
      EXPECT_EQ(early.value(b), full.value(b));
    }
  }
}

TEST(FastMarching, EarlyStopKeepsEverythingBelowTheTarget) {
  const Mesh mesh = test::make_icosphere(4);
  std::vector<double> rho(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) rho[v] = 1.0 + 0.5 * std::sin(3.0 * v);
  expect_early_stop_keeps_what_the_trace_needs(mesh, rho, 0, 400);
  const FastMarchingStencils stencils(mesh);
  FastMarching early(stencils);
  early.run(rho, 0, 400);
  EXPECT_LT(early.num_final(), mesh.num_vertices());
}

// DE's agents: densities uniform in (0, 1] per vertex, random source and target.
TEST(FastMarching, EarlyStopTracesTheFullMarchsPathOnRandomDensities) {
  const Mesh kitten = load_mesh(test::test_data("kitten.off"));  // obtuse corners too
  const Mesh grid = test::alternating_grid(41);                    // right angles
  const Mesh sphere = test::make_icosphere(3);
  std::mt19937_64 rng(20261207);
  int early_total = 0, full_total = 0;
  for (const Mesh* mesh : {&kitten, &grid, &sphere}) {
    const FastMarchingStencils stencils(*mesh);
    FastMarching full(stencils);
    PathDecoder early(stencils);
    std::uniform_int_distribution<int> vertex(0, mesh->num_vertices() - 1);
    std::uniform_real_distribution<double> density(0.0, 1.0);
    std::vector<double> rho(mesh->num_vertices());
    for (int trial = 0; trial < 100; ++trial) {
      for (double& r : rho) r = 1.0 - density(rng);  // (0, 1]
      const int s = vertex(rng);
      int t = vertex(rng);
      if (t == s) t = (s + 1) % mesh->num_vertices();
      expect_early_stop_keeps_what_the_trace_needs(*mesh, rho, s, t);
      SurfacePath by_early, by_full;
      ASSERT_TRUE(early.decode(rho, s, t, by_early));
      full.run(rho, s);
      ASSERT_TRUE(trace_steepest_descent(full, s, t, by_full));
      ASSERT_EQ(by_early.points.size(), by_full.points.size()) << "s " << s << " t " << t;
      for (size_t i = 0; i < by_full.points.size(); ++i) {
        EXPECT_EQ(by_early.points[i].v0, by_full.points[i].v0);
        EXPECT_EQ(by_early.points[i].v1, by_full.points[i].v1);
        EXPECT_EQ(by_early.points[i].t, by_full.points[i].t);
      }
      EXPECT_EQ(by_early.segment_faces, by_full.segment_faces);
      early_total += early.fast_marching().num_final();
      full_total += full.num_final();
    }
  }
  EXPECT_LT(early_total, full_total);
}

TEST(FastMarching, CountsTheVerticesItsRunsMakeFinal) {
  // The process-wide count the Table 1 benchmark reads: every run adds what it made final.
  const Mesh mesh = test::make_icosphere(3);
  const FastMarchingStencils stencils(mesh);
  FastMarching march(stencils);
  const std::vector<double> rho(mesh.num_vertices(), 1.0);
  const uint64_t before = FastMarching::vertices_made_final();
  march.run(rho, 0, 100);
  const int early = march.num_final();
  march.run(rho, 0);
  EXPECT_LT(early, mesh.num_vertices());
  EXPECT_EQ(FastMarching::vertices_made_final() - before, uint64_t(early) + uint64_t(mesh.num_vertices()));
}

TEST(FastMarching, VertexOfHighDegreeUpdatesEveryNeighbour) {
  // The apex of a 100-sector cone has more records than the march tracks by bit (its
  // records past kMaskedRecords are tested one by one): every ring vertex must still get
  // the straight generator from the apex, one edge long, and twice that on the next ring.
  ConeOptions o;
  o.rings = 4;
  o.sectors = 100;
  const Mesh mesh = make_cone(o);
  const FastMarchingStencils stencils(mesh);
  ASSERT_GT(stencils.updates_end(0) - stencils.updates_begin(0), FastMarchingStencils::kMaskedRecords);
  FastMarching march(stencils);
  march.run(std::vector<double>(mesh.num_vertices(), 1.0), 0);
  const double generator = std::hypot(o.radius / o.rings, o.height / o.rings);
  for (int j = 0; j < o.sectors; ++j) {
    EXPECT_NEAR(march.value(cone_vertex(o, 1, j)), generator, 1e-6) << "sector " << j;
    EXPECT_NEAR(march.value(cone_vertex(o, 2, j)), 2 * generator, 1e-6) << "sector " << j;
  }
}

TEST(FastMarching, EveryVertexHasAnEarlierNeighbourNotAbove) {
  const Mesh mesh = test::make_icosphere(3);
  const FastMarchingStencils stencils(mesh);
  FastMarching fm(stencils);
  std::vector<double> rho(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) rho[v] = std::exp(std::cos(7.0 * v) * 5.0);  // wild, like DE agents
  fm.run(rho, 17);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    ASSERT_TRUE(fm.is_final(v));
    if (v == 17) continue;
    bool found = false;
    for (const int* n = mesh.vertex_neighbors_begin(v); n != mesh.vertex_neighbors_end(v); ++n)
      found |= fm.order(*n) < fm.order(v) && fm.value(*n) <= fm.value(v);
    EXPECT_TRUE(found) << "vertex " << v;
  }
}

TEST(FastMarching, WeightedGeodesicEnergyMatchesFieldAlongAStraightChannel) {
  // On a flat grid with density varying only across the path direction (rho = 1 + y^2),
  // the best path between two points on y = 0 stays on y = 0 with cost = length.
  const Mesh mesh = test::alternating_grid(41);
  std::vector<double> rho(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) rho[v] = 1.0 + mesh.position(v).y() * mesh.position(v).y();
  const FastMarchingStencils stencils(mesh);
  PathDecoder decoder(stencils);
  SurfacePath path;
  const int s = 20 * 41 + 2, t = 20 * 41 + 38;
  ASSERT_TRUE(decoder.decode(rho, s, t, path));
  EnergySpec spec;
  spec.density = rho;
  const double cost = make_energy(mesh, spec)->evaluate(path);
  const double exact = (mesh.position(t) - mesh.position(s)).norm();
  EXPECT_NEAR(cost, exact, 1e-9 * exact);
}

}  // namespace
}  // namespace depath
