// SPDX-License-Identifier: MIT
// The back-trace always terminates with a valid path: every shared mesh (slivers,
// boundaries, stray components), DE-like random densities, degenerate faces.
#include "depath/energy/energy.hpp"
#include "depath/decode/fast_marching.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/decode/path_decoder.hpp"
#include "depath/generators/surfaces.hpp"
#include "path_checks.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace depath {
namespace {

// Decodes `pairs` random pairs in the source's component with uniform and with wild
// log-uniform densities (what DE agents look like), checking every path.
void check_mesh(const Mesh& mesh, int pairs, uint64_t seed) {
  const FastMarchingStencils stencils(mesh);
  PathDecoder decoder(stencils);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> vertex(0, mesh.num_vertices() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> log_rho(mesh.num_vertices());
  SurfacePath path;
  for (int k = 0; k < pairs; ++k) {
    const int s = vertex(rng);
    int t = vertex(rng);
    if (s == t || !mesh.is_referenced(s) || !mesh.is_referenced(t) || mesh.component(s) != mesh.component(t)) continue;
    for (int trial = 0; trial < 3; ++trial) {
      // trial 0: uniform; 1: log U(0,1] (paper's initial agents); 2: spread over e^(+-20).
      for (double& x : log_rho) x = trial == 0 ? 0.0 : trial == 1 ? std::log(1.0 - unit(rng)) : 40.0 * (unit(rng) - 0.5);
      ASSERT_TRUE(decoder.decode_log(log_rho, s, t, path)) << s << "->" << t;
      ASSERT_TRUE(test::is_valid_path(mesh, path, s, t)) << s << "->" << t << " trial " << trial;
      EXPECT_TRUE(std::isfinite(path_length(mesh, path)));
    }
  }
}

TEST(TraceRobustness, EverySharedMesh) {
  DEPATH_REQUIRE_SHARED_DATA();
  for (const char* name : {"kitten.off", "dragon.obj", "beethoven.ply", "bimba.obj", "cone.off", "terrain_grid30.obj",
                           "camelhead.off", "bunny.off", "armadillo.obj"}) {
    SCOPED_TRACE(name);
    const Mesh mesh = load_mesh(test::shared_data(std::string("meshes/") + name));
    check_mesh(mesh, mesh.num_vertices() > 20000 ? 4 : 12, 99);
  }
}

TEST(TraceRobustness, BundledMeshes) {
  for (const char* name : {"kitten.off", "cone.off", "terrain_grid30.obj"}) {
    SCOPED_TRACE(name);
    check_mesh(load_mesh(test::test_data(name)), 20, 7);
  }
}

TEST(TraceRobustness, DegenerateFacesAndVertexCrossings) {
  // A flat grid with a column of vertices collapsed onto their neighbours: zero-area faces
  // the trace must not step into, and paths along grid lines that hit vertices exactly.
  GridOptions grid;
  grid.n = 21;
  Mesh flat = make_grid(grid);
  std::vector<Vec3> positions = flat.positions();
  for (int j = 0; j < 21; ++j) positions[j * 21 + 10] = positions[j * 21 + 9];
  const Mesh mesh(positions, flat.faces());
  EXPECT_GT(mesh.num_degenerate_faces(), 0);
  check_mesh(mesh, 30, 3);
  const FastMarchingStencils stencils(mesh);
  PathDecoder decoder(stencils);
  SurfacePath path;
  const std::vector<double> ones(mesh.num_vertices(), 1.0);
  ASSERT_TRUE(decoder.decode(ones, 10 * 21 + 0, 10 * 21 + 20, path));
  EXPECT_TRUE(test::is_valid_path(mesh, path, 210, 230));
  // Still the straight grid line across the collapsed column: length 6 (the grid spans [-3, 3]).
  EXPECT_NEAR(path_length(mesh, path), 6.0, 1e-9);
}

}  // namespace
}  // namespace depath
