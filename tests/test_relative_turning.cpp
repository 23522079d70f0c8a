// SPDX-License-Identifier: MIT
// The smoothness penalty's turning (Energy::turning_angle) against the plain turning within
// the surface (surface_turning): for the angle energies it is the turning relative to the
// preferred lines, so a path along a curved field line costs nothing while a zig-zag across
// the lines is charged; for the geodesic energy it is the plain turning, unchanged.
#include "depath/energy/energy.hpp"
#include "depath/energy/surface_turning.hpp"
#include "depath/generators/surfaces.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

namespace depath {
namespace {

constexpr double kPi = std::numbers::pi;

// A flat n x n grid over [-1, 1]^2 in the plane z = 0.
Mesh flat_grid(int n) {
  GridOptions o;
  o.n = n;
  o.half_size = 1.0;
  return make_grid(o);
}

std::unique_ptr<Energy> field_energy(const Mesh& mesh, std::vector<Vec3> field) {
  EnergySpec spec;
  spec.kind = EnergyKind::vector_field;
  spec.field = std::move(field);
  spec.smoothness = 1.0;
  return make_energy(mesh, spec);
}

std::unique_ptr<Energy> geodesic_energy(const Mesh& mesh) {
  EnergySpec spec;
  spec.smoothness = 1.0;
  return make_energy(mesh, spec);
}

// The rotation field (-y, x, 0): its field lines are the circles about the origin.
std::vector<Vec3> rotation_field(const Mesh& mesh) {
  std::vector<Vec3> field;
  for (const Vec3& p : mesh.positions()) field.emplace_back(-p.y(), p.x(), 0.0);
  return field;
}

// The path along the circle of radius r about the origin (r chosen to miss the grid's
// vertices) through its crossings with the mesh's edges, in order of angle from the positive x axis, over
// `turn` radians: the chords of the circle between consecutive crossings (which share a face on a grid).
SurfacePath circle_path(const Mesh& mesh, double r, double turn) {
  struct Crossing {
    double angle;
    SurfacePoint point;
  };
  std::vector<Crossing> crossings;
  std::vector<std::pair<int, int>> edges;
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int i = mesh.face(f)[k], j = mesh.face(f)[(k + 1) % 3];
      edges.emplace_back(std::min(i, j), std::max(i, j));
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& [i, j] : edges) {
    // |p_i + t (p_j - p_i)| = r, 0 < t < 1.
    const Vec3 p = mesh.position(i), d = mesh.position(j) - p;
    const double a = d.squaredNorm(), b = 2 * p.dot(d), c = p.squaredNorm() - r * r;
    const double disc = b * b - 4 * a * c;
    if (disc <= 0) continue;
    for (const double s : {-1.0, 1.0}) {
      const double t = (-b + s * std::sqrt(disc)) / (2 * a);
      if (t <= 1e-9 || t >= 1 - 1e-9) continue;
      const Vec3 x = p + t * d;
      double angle = std::atan2(x.y(), x.x());
      if (angle < 0) angle += 2 * kPi;
      if (angle <= turn) crossings.push_back({angle, SurfacePoint::on_edge(i, j, t)});
    }
  }
  std::sort(crossings.begin(), crossings.end(),
            [](const Crossing& x, const Crossing& y) { return x.angle < y.angle; });
  SurfacePath path;
  for (const Crossing& c : crossings) path.points.push_back(c.point);
  for (size_t k = 0; k + 1 < path.points.size(); ++k) {
    const SurfacePoint &a = path.points[k], &b = path.points[k + 1];
    int face = -1;
    for (int f = 0; f < mesh.num_faces() && face < 0; ++f)
      if (mesh.corner_of(f, a.v0) >= 0 && mesh.corner_of(f, a.v1) >= 0 && mesh.corner_of(f, b.v0) >= 0 &&
          mesh.corner_of(f, b.v1) >= 0)
        face = f;
    EXPECT_GE(face, 0) << "consecutive crossings " << k << " share no face";
    path.segment_faces.push_back(face);
  }
  return path;
}

// The same path with every other point moved along its edge by `shift` (clamped inside it):
// a zig-zag about the circle.
SurfacePath zig_zag(SurfacePath path, double shift) {
  for (size_t k = 1; k + 1 < path.points.size(); k += 2) {
    SurfacePoint& p = path.points[k];
    p.t = std::clamp(p.t + shift, 0.05, 0.95);
  }
  return path;
}

double total(const Energy& energy, const SurfacePath& path) {
  double sum = 0.0;
  for (int i = 1; i + 1 < static_cast<int>(path.points.size()); ++i) sum += energy.turning_angle(path, i);
  return sum;
}

TEST(RelativeTurning, UniformFieldOnAFlatGridChargesThePlainTurning) {
  const Mesh mesh = flat_grid(21);
  const auto energy = field_energy(mesh, std::vector<Vec3>(mesh.num_vertices(), Vec3(1, 0.3, 0)));
  for (const SurfacePath& path :
       {circle_path(mesh, 0.73, 1.5 * kPi), zig_zag(circle_path(mesh, 0.73, 1.5 * kPi), 0.2)}) {
    ASSERT_GT(path.points.size(), 40u);
    for (int i = 1; i + 1 < static_cast<int>(path.points.size()); ++i)
      EXPECT_NEAR(energy->turning_angle(path, i), surface_turning(mesh, path, i), 1e-12) << i;
  }
}

// On a flat grid the rotation field is linear, so its interpolation is exact and every chord
// of a circle about the origin runs exactly along the field at its midpoint: the path follows
// the field, and only its (large) plain turning would have been charged.
TEST(RelativeTurning, APathAlongACurvedFieldCostsNothing) {
  const Mesh mesh = flat_grid(21);
  const auto energy = field_energy(mesh, rotation_field(mesh));
  const SurfacePath path = circle_path(mesh, 0.73, 1.5 * kPi);
  ASSERT_GT(path.points.size(), 40u);
  const double plain = total_surface_turning(mesh, path);
  // The chords turn by the angle they subtend: 1.5 pi less the two half-chords left out at
  // the ends, so within a few chords' angle of it.
  EXPECT_NEAR(plain, 1.5 * kPi, 0.3);
  EXPECT_NEAR(total(*energy, path), 0.0, 1e-9);
}

// Moving every other point along its edge makes the path zig-zag about the circle: the
// relative turning charges the zig-zag, at least the plain turning it adds (triangle
// inequality: |dphi - dpsi| >= |dphi| - |dpsi|, and the lines rotate by the circle's turning).
TEST(RelativeTurning, AZigZagAcrossTheFieldIsCharged) {
  const Mesh mesh = flat_grid(21);
  const auto energy = field_energy(mesh, rotation_field(mesh));
  const SurfacePath circle = circle_path(mesh, 0.73, 1.5 * kPi);
  const SurfacePath zz = zig_zag(circle, 0.03);
  const double circle_plain = total_surface_turning(mesh, circle), zz_plain = total_surface_turning(mesh, zz);
  const double charged = total(*energy, zz);
  std::printf("plain turning: circle %.3f, zig-zag %.3f; charged: circle %.2e, zig-zag %.3f\n", circle_plain,
              zz_plain, total(*energy, circle), charged);
  ASSERT_GT(zz_plain, circle_plain + 5.0);  // the zig-zag adds several radians of turning
  EXPECT_GE(charged, zz_plain - circle_plain - 0.3);
  EXPECT_LE(charged, zz_plain + circle_plain);
  // Each zig-zag point is charged about as much as the plain turn it makes there, less the
  // field's small rotation.
  for (int i = 2; i + 2 < static_cast<int>(zz.points.size()); ++i)
    EXPECT_NEAR(energy->turning_angle(zz, i), surface_turning(mesh, zz, i), 0.25) << i;
}

// The geodesic energy prefers no direction: its penalty is exactly the plain turning, at edge
// points and at vertices, on a flat grid and on a curved surface.
TEST(RelativeTurning, GeodesicEnergyKeepsThePlainTurning) {
  const Mesh flat = flat_grid(21);
  const auto energy = geodesic_energy(flat);
  for (const SurfacePath& path :
       {circle_path(flat, 0.73, 1.5 * kPi), zig_zag(circle_path(flat, 0.73, 1.5 * kPi), 0.2)})
    for (int i = 1; i + 1 < static_cast<int>(path.points.size()); ++i)
      EXPECT_EQ(energy->turning_angle(path, i), surface_turning(flat, path, i)) << i;

  // A square pyramid (60-degree apex corners): through the apex between opposite base
  // corners the path turns by 60 degrees within the surface, for every energy (vertex
  // points keep the plain vertex turning).
  const Mesh pyramid({Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0)},
                     {{{0, 1, 2}}, {{0, 2, 3}}, {{0, 3, 4}}, {{0, 4, 1}}});
  SurfacePath apex;
  apex.points = {SurfacePoint::at_vertex(1), SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(3)};
  apex.segment_faces = {0, 1};
  EXPECT_NEAR(geodesic_energy(pyramid)->turning_angle(apex, 1), kPi / 3, 1e-12);
  EXPECT_NEAR(field_energy(pyramid, std::vector<Vec3>(5, Vec3(1, 0, 0)))->turning_angle(apex, 1), kPi / 3,
              1e-12);
}

}  // namespace
}  // namespace depath
