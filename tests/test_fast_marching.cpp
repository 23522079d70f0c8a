// SPDX-License-Identifier: MIT
// Fast marching and back-tracing on surfaces with analytic geodesics.
#include "analytic_meshes.hpp"
#include "depath/energy/energy.hpp"
#include "depath/decode/fast_marching.hpp"
#include "depath/decode/path_decoder.hpp"
#include "depath/generators/surfaces.hpp"
#include "path_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>
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

TEST(FastMarching, EarlyStopKeepsTheTargetValueAndItsRing) {
  const Mesh mesh = test::make_icosphere(4);
  const FastMarchingStencils stencils(mesh);
  FastMarching full(stencils), early(stencils);
  std::vector<double> rho(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) rho[v] = 1.0 + 0.5 * std::sin(3.0 * v);
  const int s = 0, t = 400;
  full.run(rho, s);
  early.run(rho, s, t);
  EXPECT_EQ(full.num_final(), mesh.num_vertices());
  EXPECT_LT(early.num_final(), mesh.num_vertices());
  EXPECT_TRUE(early.is_final(t));
  EXPECT_EQ(early.value(t), full.value(t));
  for (const int* n = mesh.vertex_neighbors_begin(t); n != mesh.vertex_neighbors_end(t); ++n) {
    EXPECT_TRUE(early.is_final(*n));
    EXPECT_EQ(early.value(*n), full.value(*n));
  }
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
