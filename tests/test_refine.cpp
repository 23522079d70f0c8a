// SPDX-License-Identifier: MIT
// Local path refinement on hand-built meshes whose shortest paths are known exactly,
// plus the guarantees (never worse, valid path, end points kept) for every energy.
#include "depath/energy/energy.hpp"
#include "depath/util/error.hpp"
#include "depath/decode/fast_marching.hpp"
#include "depath/decode/path_decoder.hpp"
#include "depath/refine/refine.hpp"
#include "depath/generators/surfaces.hpp"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <tuple>
#include <vector>

namespace depath {
namespace {

using Faces = std::vector<std::array<int, 3>>;

// Builds a mesh from quads (corner positions in order around), merging equal corners.
Mesh mesh_from_quads(const std::vector<std::array<Vec3, 4>>& quads) {
  std::vector<Vec3> positions;
  std::map<std::tuple<long, long, long>, int> index;
  auto id = [&](const Vec3& p) {
    const auto key = std::make_tuple(std::lround(p.x() * 1e6), std::lround(p.y() * 1e6), std::lround(p.z() * 1e6));
    const auto [it, inserted] = index.emplace(key, static_cast<int>(positions.size()));
    if (inserted) positions.push_back(p);
    return it->second;
  };
  Faces faces;
  for (const auto& q : quads) {
    const int a = id(q[0]), b = id(q[1]), c = id(q[2]), d = id(q[3]);
    faces.push_back({a, b, c});
    faces.push_back({a, c, d});
  }
  return Mesh(std::move(positions), std::move(faces));
}

// Vertex closest to p.
int vertex_at(const Mesh& mesh, const Vec3& p) {
  int best = 0;
  for (int v = 1; v < mesh.num_vertices(); ++v) {
    if ((mesh.position(v) - p).norm() < (mesh.position(best) - p).norm()) best = v;
  }
  return best;
}

// A path through the given vertices, each consecutive pair joined by a mesh edge.
SurfacePath vertex_path(const Mesh& mesh, const std::vector<int>& vertices) {
  SurfacePath path;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    path.points.push_back(SurfacePoint::at_vertex(vertices[i]));
    if (i > 0) {
      const int f = mesh.face_with_edge(vertices[i - 1], vertices[i]);
      EXPECT_GE(f, 0) << vertices[i - 1] << "-" << vertices[i] << " is not an edge";
      path.segment_faces.push_back(f);
    }
  }
  return path;
}

// Checks the structural guarantees of a refined path.
void expect_valid(const Mesh& mesh, const SurfacePath& input, const SurfacePath& path) {
  ASSERT_GE(path.points.size(), 2u);
  ASSERT_EQ(path.segment_faces.size() + 1, path.points.size());
  EXPECT_TRUE(path.points.front().is_vertex());
  EXPECT_EQ(path.points.front().v0, input.points.front().v0);
  EXPECT_TRUE(path.points.back().is_vertex());
  EXPECT_EQ(path.points.back().v0, input.points.back().v0);
  for (std::size_t s = 0; s < path.segment_faces.size(); ++s) {
    const int f = path.segment_faces[s];
    ASSERT_GE(f, 0);
    ASSERT_LT(f, mesh.num_faces());
    for (const SurfacePoint* p : {&path.points[s], &path.points[s + 1]}) {
      EXPECT_GE(mesh.corner_of(f, p->v0), 0) << "segment " << s;
      if (!p->is_vertex()) {
        EXPECT_GE(mesh.corner_of(f, p->v1), 0) << "segment " << s;
        EXPECT_GE(p->t, 0.0);
        EXPECT_LE(p->t, 1.0);
      }
    }
  }
}

// Flat square grid in the z = 0 plane, spacing 1, cells split along one diagonal.
Mesh flat_grid(int nx, int ny) {
  std::vector<std::array<Vec3, 4>> quads;
  for (int y = 0; y + 1 < ny; ++y) {
    for (int x = 0; x + 1 < nx; ++x) {
      quads.push_back({Vec3(x, y, 0), Vec3(x + 1, y, 0), Vec3(x + 1, y + 1, 0), Vec3(x, y + 1, 0)});
    }
  }
  return mesh_from_quads(quads);
}

// On flat_grid(9, 7): the vertex path along the x axis from (0, 0) to (8, 0), then up to
// (8, 6): length 14, where the straight segment is 10.
SurfacePath l_shaped_path(const Mesh& mesh) {
  std::vector<int> route;
  for (int x = 0; x <= 8; ++x) route.push_back(vertex_at(mesh, Vec3(x, 0, 0)));
  for (int y = 1; y <= 6; ++y) route.push_back(vertex_at(mesh, Vec3(8, y, 0)));
  return vertex_path(mesh, route);
}

TEST(Refine, StraightensAnLShapedPathOnAFlatGrid) {
  const Mesh mesh = flat_grid(9, 7);
  const SurfacePath input = l_shaped_path(mesh);
  const auto energy = make_energy(mesh, EnergySpec{});
  ASSERT_DOUBLE_EQ(energy->evaluate(input), 14.0);
  RefineReport report;
  const SurfacePath refined = refine_path(*energy, input, {}, {}, &report);
  expect_valid(mesh, input, refined);
  // In the plane the shortest path is the straight segment: length 10.
  EXPECT_NEAR(energy->evaluate(refined), 10.0, 1e-9);
  EXPECT_NEAR(path_length(mesh, refined), 10.0, 1e-9);
  EXPECT_EQ(report.stop_reason, "converged");
  EXPECT_GT(report.reroutes, 0);
}

TEST(Refine, ZigZagAcrossFacesBecomesStraight) {
  // A path across a strip of faces, zig-zagging along the edges it crosses.
  const Mesh mesh = flat_grid(12, 2);
  const auto energy = make_energy(mesh, EnergySpec{});
  const int s = vertex_at(mesh, Vec3(0, 0, 0)), t = vertex_at(mesh, Vec3(11, 1, 0));
  // Walk from s to t crossing every edge of the strip at alternating parameters.
  SurfacePath input;
  input.points.push_back(SurfacePoint::at_vertex(s));
  for (int x = 0; x < 11; ++x) {
    const int v00 = vertex_at(mesh, Vec3(x, 0, 0)), v11 = vertex_at(mesh, Vec3(x + 1, 1, 0));
    const int v10 = vertex_at(mesh, Vec3(x + 1, 0, 0));
    if (x > 0) input.points.push_back(SurfacePoint::on_edge(v00, vertex_at(mesh, Vec3(x, 1, 0)), 0.2 + 0.6 * (x % 2)));
    // The cell's diagonal (x,0)-(x+1,1), when it is an edge of the mesh.
    if (mesh.face_with_edge(v00, v11) >= 0) input.points.push_back(SurfacePoint::on_edge(v00, v11, 0.3 + 0.4 * (x % 2)));
    (void)v10;
  }
  input.points.push_back(SurfacePoint::at_vertex(t));
  // Fill the faces: any face containing both ends of each segment.
  for (std::size_t i = 0; i + 1 < input.points.size(); ++i) {
    int face = -1;
    for (int f = 0; f < mesh.num_faces() && face < 0; ++f) {
      bool ok = true;
      for (const SurfacePoint* p : {&input.points[i], &input.points[i + 1]}) {
        ok = ok && mesh.corner_of(f, p->v0) >= 0 && (p->is_vertex() || mesh.corner_of(f, p->v1) >= 0);
      }
      if (ok) face = f;
    }
    ASSERT_GE(face, 0) << "segment " << i;
    input.segment_faces.push_back(face);
  }
  const double before = energy->evaluate(input);
  const SurfacePath refined = refine_path(*energy, input);
  expect_valid(mesh, input, refined);
  const double exact = std::hypot(11.0, 1.0);
  EXPECT_GT(before, exact + 0.1);
  EXPECT_NEAR(energy->evaluate(refined), exact, 1e-9);
}

TEST(Refine, UnitCubeCornerToOppositeCorner) {
  // Surface of [0,1]^3, each side a 4 x 4 grid of quads (flat vertices except the 8
  // corners, each with total angle 3 pi / 2). Shortest corner-to-corner path: sqrt(5).
  const int n = 4;
  std::vector<std::array<Vec3, 4>> quads;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          std::array<Vec3, 4> q;
          const int du[4] = {0, 1, 1, 0}, dw[4] = {0, 0, 1, 1};
          for (int c = 0; c < 4; ++c) {
            Vec3 p = Vec3::Zero();
            p[axis] = side;
            p[u] = double(i + du[c]) / n;
            p[w] = double(j + dw[c]) / n;
            q[c] = p;
          }
          quads.push_back(q);
        }
      }
    }
  }
  const Mesh mesh = mesh_from_quads(quads);
  ASSERT_EQ(mesh.num_vertices(), 6 * n * n + 2);
  std::vector<int> route;  // along three cube edges: x, then y, then z
  for (int i = 0; i <= n; ++i) route.push_back(vertex_at(mesh, Vec3(double(i) / n, 0, 0)));
  for (int i = 1; i <= n; ++i) route.push_back(vertex_at(mesh, Vec3(1, double(i) / n, 0)));
  for (int i = 1; i <= n; ++i) route.push_back(vertex_at(mesh, Vec3(1, 1, double(i) / n)));
  const SurfacePath input = vertex_path(mesh, route);
  const auto energy = make_energy(mesh, EnergySpec{});
  ASSERT_NEAR(energy->evaluate(input), 3.0, 1e-12);
  const SurfacePath refined = refine_path(*energy, input);
  expect_valid(mesh, input, refined);
  EXPECT_NEAR(energy->evaluate(refined), std::sqrt(5.0), 1e-9);
}

// Open prism approximating a cylinder (axis z, base at z = 0): unrolled, it is a flat
// strip, so the shortest path between two vertices is the straight line of the unrolled
// strip (a helix). Vertex (ring r, side j) is r * sides + j.
struct Prism {
  int sides, rings;
  double radius, height;
  Mesh mesh;
  Prism(int sides_, int rings_, double radius_, double height_)
      : sides(sides_), rings(rings_), radius(radius_), height(height_), mesh(build(sides_, rings_, radius_, height_)) {}
  static Mesh build(int sides, int rings, double radius, double height) {
    std::vector<Vec3> positions;
    for (int r = 0; r < rings; ++r) {
      for (int j = 0; j < sides; ++j) {
        const double a = 2 * std::numbers::pi * j / sides;
        positions.emplace_back(radius * std::cos(a), radius * std::sin(a), height * r / (rings - 1));
      }
    }
    Faces faces;
    for (int r = 0; r + 1 < rings; ++r) {
      for (int j = 0; j < sides; ++j) {
        const int a = r * sides + j, b = r * sides + (j + 1) % sides;
        faces.push_back({a, b, b + sides});
        faces.push_back({a, b + sides, a + sides});
      }
    }
    return Mesh(positions, faces);
  }
  // Length of the unrolled straight line between two vertices, the short way around.
  double helix(int u, int v) const {
    const int turn = std::abs(u % sides - v % sides);
    const int sectors = std::min(turn, sides - turn);
    const double chord = 2 * radius * std::sin(std::numbers::pi / sides);
    return std::hypot(height * (u / sides - v / sides) / (rings - 1), sectors * chord);
  }
};

TEST(Refine, HelixOnACylinder) {
  const Prism prism(24, 9, 1.0, 3.0);
  const int k = 7;  // sectors travelled around the axis
  std::vector<int> route;  // around the bottom rim, then straight up
  for (int j = 0; j <= k; ++j) route.push_back(j);
  for (int r = 1; r < prism.rings; ++r) route.push_back(r * prism.sides + k);
  const SurfacePath input = vertex_path(prism.mesh, route);
  const auto energy = make_energy(prism.mesh, EnergySpec{});
  const SurfacePath refined = refine_path(*energy, input);
  expect_valid(prism.mesh, input, refined);
  EXPECT_NEAR(energy->evaluate(refined), prism.helix(0, (prism.rings - 1) * prism.sides + k), 1e-9);
}

TEST(Refine, HelicesBetweenRandomVerticesOfRandomPrisms) {
  // Seeded random prisms and vertex pairs, at most a third of a turn apart (so the short
  // way around is the only local optimum the fmm path can start near): the refined fmm
  // path is the unrolled straight line, to round-off.
  std::mt19937 rng(20261202);
  int checked = 0;
  for (int instance = 0; instance < 8; ++instance) {
    const int sides = std::uniform_int_distribution<int>(9, 40)(rng);
    const int rings = std::uniform_int_distribution<int>(2, 15)(rng);
    const double radius = std::uniform_real_distribution<double>(0.3, 3.0)(rng);
    const double height = std::uniform_real_distribution<double>(0.2, 6.0)(rng);
    const Prism prism(sides, rings, radius, height);
    const FastMarchingStencils stencils(prism.mesh);
    PathDecoder decoder(stencils);
    const auto energy = make_energy(prism.mesh, EnergySpec{});
    std::uniform_int_distribution<int> ring(0, rings - 1), side(0, sides - 1), turn(-sides / 3, sides / 3);
    for (int pair = 0; pair < 6; ++pair) {
      const int s = ring(rng) * sides + side(rng);
      const int t = ring(rng) * sides + ((s % sides) + turn(rng) + sides) % sides;
      if (s == t) continue;
      SCOPED_TRACE(std::to_string(sides) + " sides, " + std::to_string(rings) + " rings: " + std::to_string(s) +
                   " -> " + std::to_string(t));
      SurfacePath fmm;
      ASSERT_TRUE(decoder.decode(std::vector<double>(prism.mesh.num_vertices(), 1.0), s, t, fmm));
      const SurfacePath refined = refine_path(*energy, fmm);
      expect_valid(prism.mesh, fmm, refined);
      EXPECT_NEAR(path_length(prism.mesh, refined), prism.helix(s, t), 1e-9 * prism.helix(s, t));
      ++checked;
    }
  }
  EXPECT_GE(checked, 40);
}

TEST(Refine, ReroutesAroundAConvexApex) {
  // Low open square pyramid (no base): the apex has total angle below 2 pi, so the path
  // base corner -> apex -> opposite corner is shortened by going around the apex
  // through two faces.
  const double h = 0.3;
  const std::vector<Vec3> positions = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, h)};
  const Faces faces = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  const Mesh mesh(positions, faces);
  const SurfacePath input = vertex_path(mesh, {0, 4, 2});
  const auto energy = make_energy(mesh, EnergySpec{});
  RefineReport report;
  const SurfacePath refined = refine_path(*energy, input, {}, {}, &report);
  expect_valid(mesh, input, refined);
  EXPECT_EQ(report.reroutes, 1);
  // Unfolded around the apex, corners 0 and 2 are at distance r from it, 2 alpha apart.
  const double r = std::hypot(1.0, h);
  const double alpha = mesh.corner_angle(0, mesh.corner_of(0, 4));
  EXPECT_NEAR(energy->evaluate(refined), 2 * r * std::sin(alpha), 1e-9);
  EXPECT_LT(energy->evaluate(refined), 2 * r - 1e-3);
  ASSERT_EQ(refined.points.size(), 3u);
  EXPECT_FALSE(refined.points[1].is_vertex());
}

TEST(Refine, KeepsALocallyShortestPathThroughASaddleVertex) {
  // A vertex with total angle above 2 pi (a saddle) on a straight path stays: both
  // sides have angle >= pi, so no re-route shortens it.
  std::vector<Vec3> positions = {Vec3(0, 0, 0)};
  const int ring = 6;
  for (int j = 0; j < ring; ++j) {
    const double a = 2 * std::numbers::pi * j / ring;
    positions.emplace_back(std::cos(a), std::sin(a), (j % 2 == 0) ? 0.5 : -0.5);
  }
  Faces faces;
  for (int j = 0; j < ring; ++j) faces.push_back({0, 1 + j, 1 + (j + 1) % ring});
  const Mesh mesh(positions, faces);
  const SurfacePath input = vertex_path(mesh, {1, 0, 4});
  const auto energy = make_energy(mesh, EnergySpec{});
  RefineReport report;
  const SurfacePath refined = refine_path(*energy, input, {}, {}, &report);
  expect_valid(mesh, input, refined);
  EXPECT_EQ(report.reroutes, 0);
  EXPECT_DOUBLE_EQ(energy->evaluate(refined), energy->evaluate(input));
  ASSERT_EQ(refined.points.size(), 3u);
  EXPECT_TRUE(refined.points[1].is_vertex());
}

// Open square pyramid (no base) whose apex leans towards corner 1: from corner 0 to the
// opposite corner 2 there is a locally shortest path on either side of the apex (each
// straight in the unfolding of its two faces, both spans below pi), the one past
// corner 3 about 12% shorter. Local moves never carry a path across the apex.
struct LeaningPyramid {
  Mesh mesh{{Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0.4, 0.6)},
            Faces{{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}};
  // Corner 0 -> a point of edge (w, apex) -> corner 2, through faces f0 and f1.
  SurfacePath path_past(int w, int f0, int f1) const {
    SurfacePath path;
    path.points = {SurfacePoint::at_vertex(0), SurfacePoint::on_edge(w, 4, 0.5), SurfacePoint::at_vertex(2)};
    path.segment_faces = {f0, f1};
    return path;
  }
  SurfacePath long_side() const { return path_past(1, 0, 1); }
  SurfacePath short_side() const { return path_past(3, 3, 2); }
  // Length of the straight route 0 -> 2 unfolded around the apex through the faces on
  // the side of corner w.
  double unfolded(int w) const {
    const double span = mesh.corner_angle(w == 1 ? 0 : 3, 2) + mesh.corner_angle(w == 1 ? 1 : 2, 2);
    const double r0 = (mesh.position(0) - mesh.position(4)).norm(), r2 = (mesh.position(2) - mesh.position(4)).norm();
    return std::sqrt(r0 * r0 + r2 * r2 - 2 * r0 * r2 * std::cos(span));
  }
};

TEST(Refine, LocalMovesKeepALocallyShortestPathOnItsSideOfAConvexApex) {
  const LeaningPyramid pyramid;
  const auto energy = make_energy(pyramid.mesh, EnergySpec{});
  RefineOptions options;
  options.max_hops = 0;
  RefineReport report;
  const SurfacePath refined = refine_path(*energy, pyramid.long_side(), options, {}, &report);
  expect_valid(pyramid.mesh, pyramid.long_side(), refined);
  EXPECT_NEAR(energy->evaluate(refined), pyramid.unfolded(1), 1e-9);
  EXPECT_GT(pyramid.unfolded(1), 1.1 * pyramid.unfolded(3));
  EXPECT_EQ(report.hops, 0);
}

TEST(Refine, AVertexHopCarriesThePathAcrossTheApexToTheShorterSide) {
  const LeaningPyramid pyramid;
  const auto energy = make_energy(pyramid.mesh, EnergySpec{});
  RefineReport report;
  const SurfacePath refined = refine_path(*energy, pyramid.long_side(), {}, {}, &report);
  expect_valid(pyramid.mesh, pyramid.long_side(), refined);
  EXPECT_NEAR(energy->evaluate(refined), pyramid.unfolded(3), 1e-9);
  EXPECT_EQ(report.hops, 1);
  EXPECT_DOUBLE_EQ(report.final_energy, energy->evaluate(refined));
  ASSERT_EQ(refined.points.size(), 3u);
  EXPECT_FALSE(refined.points[1].is_vertex());
}

TEST(Refine, BestOfSeveralStartsIsTheLowestLocalOptimum) {
  const LeaningPyramid pyramid;
  const auto energy = make_energy(pyramid.mesh, EnergySpec{});
  RefineOptions options;
  options.max_hops = 0;  // the starts alone must do it
  const std::vector<SurfacePath> starts = {pyramid.long_side(), pyramid.short_side()};
  RefineReport report;
  const SurfacePath best = refine_best_of(*energy, starts, options, {}, &report);
  expect_valid(pyramid.mesh, starts.front(), best);
  EXPECT_NEAR(energy->evaluate(best), pyramid.unfolded(3), 1e-9);
  EXPECT_DOUBLE_EQ(report.final_energy, energy->evaluate(best));
  EXPECT_DOUBLE_EQ(report.initial_energy, energy->evaluate(starts.front()));
  for (const SurfacePath& start : starts) EXPECT_LE(energy->evaluate(best), energy->evaluate(start));
  EXPECT_TRUE(refine_best_of(*energy, std::vector<SurfacePath>{}).empty());
}

// fmm path on a peaks terrain, for the generic-energy tests.
struct Terrain {
  GridOptions options;
  Mesh mesh;
  Terrain() : options(make_options()), mesh(make_grid(options)) {}
  static GridOptions make_options() {
    GridOptions o;
    o.n = 31;
    o.height = GridHeight::peaks;
    o.diagonals = GridDiagonals::alternating;
    return o;
  }
  // The fmm path from s to t; empty if the trace did not give a surface path (reported
  // as a failure).
  SurfacePath fmm_path(int s, int t) const {
    const FastMarchingStencils stencils(mesh);
    PathDecoder decoder(stencils);
    SurfacePath path;
    EXPECT_TRUE(decoder.decode(std::vector<double>(mesh.num_vertices(), 1.0), s, t, path));
    // The start must be a surface path (else refine_path rightly rejects it).
    for (std::size_t i = 0; i + 1 < path.points.size(); ++i) {
      const int f = path.segment_faces[i];
      for (const SurfacePoint* p : {&path.points[i], &path.points[i + 1]}) {
        if (mesh.corner_of(f, p->v0) < 0 || (!p->is_vertex() && mesh.corner_of(f, p->v1) < 0)) {
          ADD_FAILURE() << "fmm trace " << s << "->" << t << ": segment " << i << " (" << path.points[i].v0 << ","
                        << path.points[i].v1 << ") -> (" << path.points[i + 1].v0 << "," << path.points[i + 1].v1
                        << ") is not inside its face " << f;
          return {};
        }
      }
    }
    return path;
  }
};

// The path length as an energy that does not say it is one (length_factor 0): refinement
// searches for the optimum numerically, as it does for every other energy.
class UndeclaredLength final : public Energy {
 public:
  explicit UndeclaredLength(const Mesh& mesh) : Energy(mesh, 0.0) {}
  std::string_view name() const override { return "undeclared_length"; }
  double segment_energy(const SurfacePoint& a, const SurfacePoint& b, int) const override {
    return (b.position(mesh_) - a.position(mesh_)).norm();
  }
};

TEST(Refine, LengthFactorIsTheUniformDensityWithoutSmoothness) {
  const Terrain terrain;
  const Mesh& mesh = terrain.mesh;
  EXPECT_EQ(make_energy(mesh, EnergySpec{})->length_factor(), 1.0);
  EnergySpec scaled;
  scaled.density.assign(mesh.num_vertices(), 2.5);
  EXPECT_EQ(make_energy(mesh, scaled)->length_factor(), 2.5);
  EnergySpec smooth;
  smooth.smoothness = 0.1;
  EXPECT_EQ(make_energy(mesh, smooth)->length_factor(), 0.0);
  EnergySpec weighted = scaled;
  weighted.density[7] = 3.0;
  EXPECT_EQ(make_energy(mesh, weighted)->length_factor(), 0.0);
  EnergySpec field;
  field.kind = EnergyKind::vector_field;
  field.field_from_height = true;
  EXPECT_EQ(make_energy(mesh, field)->length_factor(), 0.0);
  EXPECT_EQ(UndeclaredLength(mesh).length_factor(), 0.0);
}

TEST(Refine, StraighteningMatchesTheNumericDescentOnRandomPairs) {
  // Local moves only (no hops), from the fmm paths of seeded random pairs on a peaks
  // terrain: the exact straightening of a length energy ends where the numeric descent of
  // the same length does, never longer.
  const Terrain terrain;
  const Mesh& mesh = terrain.mesh;
  const auto exact = make_energy(mesh, EnergySpec{});
  EnergySpec scaled;
  scaled.density.assign(mesh.num_vertices(), 2.5);
  const auto exact_scaled = make_energy(mesh, scaled);
  const UndeclaredLength numeric(mesh);
  RefineOptions local;
  local.max_hops = 0;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> vertex(0, mesh.num_vertices() - 1);
  int same = 0, pairs = 0;
  for (int pair = 0; pair < 24; ++pair) {
    const int s = vertex(rng), t = vertex(rng);
    if (s == t) continue;
    SCOPED_TRACE(std::to_string(s) + " -> " + std::to_string(t));
    const SurfacePath fmm = terrain.fmm_path(s, t);
    ASSERT_FALSE(fmm.empty());
    RefineReport straight_report, numeric_report;
    const SurfacePath straight = refine_path(*exact, fmm, local, {}, &straight_report);
    const SurfacePath searched = refine_path(numeric, fmm, local, {}, &numeric_report);
    expect_valid(mesh, fmm, straight);
    const double a = path_length(mesh, straight), b = path_length(mesh, searched);
    EXPECT_LE(a, b * (1 + 1e-12));
    same += a >= b * (1 - 1e-9);
    ++pairs;
    // A uniform density scales the energy, not the path.
    const SurfacePath scaled_path = refine_path(*exact_scaled, fmm, local);
    ASSERT_EQ(scaled_path.points.size(), straight.points.size());
    EXPECT_NEAR(exact_scaled->evaluate(scaled_path), 2.5 * a, 1e-12 * a);
    std::printf("  %4d -> %4d: straightened %.12f (%lld evaluations), numeric %.12f (%lld)\n", s, t, a,
                static_cast<long long>(straight_report.evaluations), b,
                static_cast<long long>(numeric_report.evaluations));
  }
  std::printf("  same optimum on %d of %d pairs\n", same, pairs);
  EXPECT_EQ(same, pairs);
}

TEST(Refine, NeverRaisesAnyEnergyAndKeepsThePathValid) {
  const Terrain terrain;
  const Mesh& mesh = terrain.mesh;
  const int n = terrain.options.n;
  const std::vector<std::pair<int, int>> pairs = {{0, n * n - 1}, {5 * n + 3, 25 * n + 27}, {n - 1, (n - 1) * n}};
  std::vector<EnergySpec> specs;
  for (double lambda : {0.0, 0.5}) {
    EnergySpec geodesic;
    geodesic.smoothness = lambda;
    specs.push_back(geodesic);
    EnergySpec weighted = geodesic;
    weighted.density.resize(mesh.num_vertices());
    for (int v = 0; v < mesh.num_vertices(); ++v) weighted.density[v] = 1.0 + std::abs(mesh.position(v).z());
    specs.push_back(weighted);
    EnergySpec field;
    field.kind = EnergyKind::vector_field;
    field.field_from_height = true;
    field.rotate_degrees = 30.0;
    field.smoothness = lambda;
    specs.push_back(field);
    EnergySpec slope;
    slope.kind = EnergyKind::constant_slope;
    slope.slope = 0.3;
    slope.smoothness = lambda;
    specs.push_back(slope);
  }
  for (const auto& [s, t] : pairs) {
    const SurfacePath fmm = terrain.fmm_path(s, t);
    if (fmm.empty()) continue;
    for (const EnergySpec& spec : specs) {
      const auto energy = make_energy(mesh, spec);
      const double before = energy->evaluate(fmm);
      RefineReport report;
      RefineOptions options;
      options.max_sweeps = 20;  // the guarantees hold after any number of sweeps
      const auto t0 = std::chrono::steady_clock::now();
      const SurfacePath refined = refine_path(*energy, fmm, options, {}, &report);
      SCOPED_TRACE(std::string(energy->name()) + " lambda " + std::to_string(spec.smoothness) + " " +
                   std::to_string(s) + "->" + std::to_string(t));
      expect_valid(mesh, fmm, refined);
      const double after = energy->evaluate(refined);
      std::printf("  %-15s lambda %.1f %4d -> %4d: %10.5f -> %10.5f  %3d sweeps %6.1f ms\n", std::string(energy->name()).c_str(),
                  spec.smoothness, s, t, before, after, report.sweeps,
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      EXPECT_LE(after, before);
      // The fmm path is optimal for none of these: refinement must find a real gain.
      EXPECT_LT(after, before * (1.0 - 1e-4));
      EXPECT_DOUBLE_EQ(report.final_energy, after);
      EXPECT_DOUBLE_EQ(report.initial_energy, before);
    }
  }
}

TEST(Refine, CancelledBeforeTheFirstSweepReturnsAnEquallyGoodPath) {
  const Terrain terrain;
  const SurfacePath fmm = terrain.fmm_path(0, terrain.mesh.num_vertices() - 1);
  const auto energy = make_energy(terrain.mesh, EnergySpec{});
  RefineReport report;
  const SurfacePath refined = refine_path(*energy, fmm, {}, [] { return true; }, &report);
  EXPECT_EQ(report.stop_reason, "cancelled");
  EXPECT_EQ(report.sweeps, 0);
  EXPECT_LE(energy->evaluate(refined), energy->evaluate(fmm));
  expect_valid(terrain.mesh, fmm, refined);
}

TEST(Refine, ReportsEachSweepAndHonoursMaxSweeps) {
  const Mesh mesh = flat_grid(9, 7);
  const SurfacePath input = l_shaped_path(mesh);
  const auto energy = make_energy(mesh, EnergySpec{});
  RefineOptions options;
  options.max_sweeps = 2;
  std::vector<double> energies;
  options.on_sweep = [&](const RefineSweep& sweep) {
    EXPECT_EQ(sweep.sweep, static_cast<int>(energies.size()) + 1);
    energies.push_back(sweep.energy);
  };
  RefineReport report;
  const SurfacePath refined = refine_path(*energy, input, options, {}, &report);
  ASSERT_EQ(energies.size(), 2u);
  EXPECT_EQ(report.sweeps, 2);
  EXPECT_EQ(report.stop_reason, "max_sweeps");
  EXPECT_LT(energies[0], 14.0);
  EXPECT_LE(energies[1], energies[0]);
  EXPECT_DOUBLE_EQ(energy->evaluate(refined), energies[1]);
  EXPECT_GT(energies[1], 10.0 + 1e-3);  // two sweeps are not enough to straighten it
}

TEST(Refine, RejectsAPathWhoseSegmentsLeaveTheMesh) {
  const Mesh mesh = flat_grid(4, 4);
  const auto energy = make_energy(mesh, EnergySpec{});
  SurfacePath broken;
  broken.points = {SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(mesh.num_vertices() - 1)};
  broken.segment_faces = {0};
  EXPECT_THROW(refine_path(*energy, broken), Error);
  SurfacePath out_of_range = broken;
  out_of_range.points[1] = SurfacePoint::at_vertex(mesh.num_vertices() + 5);
  EXPECT_THROW(refine_path(*energy, out_of_range), Error);
}

TEST(Refine, LongPathStraightensWithBoundedWork) {
  // A 201-vertex staircase (two steps in x, one in y) on a flat grid must straighten
  // to the line from (0, 0) to (133, 67), which crosses ~270 edges and passes close
  // to (not through) many vertices: each one a point where the edge sequence changes.
  // The work is bounded by counts, which are deterministic, not by wall-clock time, which
  // is not (the time goes to bench/): a refinement that re-evaluated the whole path per
  // local move would need hundreds of millions of segment evaluations here.
  const Mesh mesh = flat_grid(134, 68);
  std::vector<int> route = {0};
  for (int i = 0; i < 66; ++i) {
    route.push_back(vertex_at(mesh, Vec3(2 * i + 1, i, 0)));
    route.push_back(vertex_at(mesh, Vec3(2 * i + 2, i, 0)));
    route.push_back(vertex_at(mesh, Vec3(2 * i + 2, i + 1, 0)));
  }
  route.push_back(vertex_at(mesh, Vec3(133, 66, 0)));
  route.push_back(vertex_at(mesh, Vec3(133, 67, 0)));
  ASSERT_EQ(route.size(), 201u);
  const SurfacePath input = vertex_path(mesh, route);
  const auto energy = make_energy(mesh, EnergySpec{});
  RefineReport report;
  const SurfacePath refined = refine_path(*energy, input, {}, {}, &report);
  std::printf("201-point staircase: %d sweeps, %d hops, %lld segment evaluations\n", report.sweeps, report.hops,
              static_cast<long long>(report.evaluations));
  expect_valid(mesh, input, refined);
  EXPECT_NEAR(energy->evaluate(refined), std::hypot(133.0, 67.0), 1e-7);
  EXPECT_EQ(report.stop_reason, "converged");
  // Measured: 68 sweeps and 2,775,461 segment evaluations (about 10,000 per input point
  // and sweep, the Newton steps and vertex hops included); the bounds leave 25% for
  // legitimate changes to the moves.
  EXPECT_LE(report.sweeps, 85);
  EXPECT_LE(report.evaluations, 3'500'000);
}

}  // namespace
}  // namespace depath
