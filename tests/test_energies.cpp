// SPDX-License-Identifier: MIT
// Unit tests of the vector_field and constant_slope energies against analytic values.
#include "depath/energy/energy.hpp"
#include "depath/util/error.hpp"
#include "depath/generators/surfaces.hpp"
#include "depath/mesh/tangent_fields.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <memory>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

namespace depath {
namespace {

constexpr double kPi = std::numbers::pi;

// A flat n x n grid over [-1, 1]^2 (spacing 2 / (n - 1)), z up.
Mesh flat_grid(int n = 5) {
  GridOptions o;
  o.n = n;
  o.half_size = 1.0;
  return make_grid(o);
}

// The same grid lifted onto the plane z = slope_x * x.
Mesh inclined_grid(double slope_x, int n = 5) {
  const Mesh flat = flat_grid(n);
  std::vector<Vec3> p = flat.positions();
  for (Vec3& v : p) v.z() = slope_x * v.x();
  return Mesh(std::move(p), flat.faces());
}

// The chord of face f along direction d through the point c (inside f): its two end
// points on the face's edges, as surface points, ordered along d.
std::pair<SurfacePoint, SurfacePoint> chord(const Mesh& mesh, int f, const Vec3& c, const Vec3& d) {
  const FaceFrame fr = face_frame(mesh, f);
  const auto& t = mesh.face(f);
  std::optional<std::pair<double, SurfacePoint>> lo, hi;
  for (int k = 0; k < 3; ++k) {
    const int i = t[k], j = t[(k + 1) % 3];
    const Vec3 e = mesh.position(j) - mesh.position(i);
    const Vec3 r = mesh.position(i) - c;
    // c + s d = p_i + u e, in face coordinates.
    const double a11 = d.dot(fr.e1), a12 = -e.dot(fr.e1), a21 = d.dot(fr.e2), a22 = -e.dot(fr.e2);
    const double b1 = r.dot(fr.e1), b2 = r.dot(fr.e2);
    const double det = a11 * a22 - a12 * a21;
    if (std::abs(det) < 1e-14) continue;
    const double s = (b1 * a22 - a12 * b2) / det;
    const double u = (a11 * b2 - a21 * b1) / det;
    if (u < -1e-12 || u > 1 + 1e-12) continue;
    const SurfacePoint p = SurfacePoint::on_edge(i, j, std::clamp(u, 0.0, 1.0));
    if (!lo || s < lo->first) lo = std::make_pair(s, p);
    if (!hi || s > hi->first) hi = std::make_pair(s, p);
  }
  if (!lo || !hi || !(hi->first > lo->first)) {
    ADD_FAILURE() << "direction does not cross face " << f;
    return {SurfacePoint::at_vertex(t[0]), SurfacePoint::at_vertex(t[0])};
  }
  return {lo->second, hi->second};
}

Vec3 centroid(const Mesh& mesh, int f) {
  const auto& t = mesh.face(f);
  return (mesh.position(t[0]) + mesh.position(t[1]) + mesh.position(t[2])) / 3.0;
}

double seg_length(const Mesh& mesh, const SurfacePoint& a, const SurfacePoint& b) {
  return (b.position(mesh) - a.position(mesh)).norm();
}

// Exact acute angle between two 3D lines.
double line_angle(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), std::abs(a.dot(b))); }

// Builds energies through the public factory (so these tests cover it too).
std::unique_ptr<Energy> vector_field(const Mesh& mesh, std::vector<Vec3> field, double smoothness = 0.0) {
  EnergySpec spec;
  spec.kind = EnergyKind::vector_field;
  spec.field = std::move(field);
  spec.smoothness = smoothness;
  return make_energy(mesh, spec);
}

std::unique_ptr<Energy> constant_slope(const Mesh& mesh, int up_axis, double k) {
  EnergySpec spec;
  spec.kind = EnergyKind::constant_slope;
  spec.up_axis = up_axis;
  spec.slope = k;
  return make_energy(mesh, spec);
}

double metric(const Energy& energy, const SurfacePath& path, const std::string& name) {
  for (const Metric& m : energy.metrics(path))
    if (m.name == name) return m.value;
  ADD_FAILURE() << "no metric " << name;
  return -1.0;
}

SurfacePath one_segment(const SurfacePoint& a, const SurfacePoint& b, int f) {
  SurfacePath path;
  path.points = {a, b};
  path.segment_faces = {f};
  return path;
}

// ---------------------------------------------------------------- vector_field

TEST(VectorFieldEnergy, ConstantFieldAlongAcrossAndDiagonal) {
  const Mesh mesh = flat_grid();
  const auto energy = vector_field(mesh, std::vector<Vec3>(mesh.num_vertices(), Vec3(2.0, 0.0, 0.0)));
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 c = centroid(mesh, f);
    for (double deg : {0.0, 30.0, 45.0, 90.0, 135.0, 180.0, 250.0}) {
      const double r = deg * kPi / 180.0;
      const auto [a, b] = chord(mesh, f, c, Vec3(std::cos(r), std::sin(r), 0.0));
      // The acute angle to the x axis, whatever the orientation.
      const double expected_angle = std::atan2(std::abs(std::sin(r)), std::abs(std::cos(r)));
      const double len = seg_length(mesh, a, b);
      EXPECT_NEAR(energy->segment_energy(a, b, f), len * expected_angle, 1e-12) << "face " << f << " deg " << deg;
      EXPECT_NEAR(energy->segment_energy(b, a, f), len * expected_angle, 1e-12) << "reversed";
    }
  }
}

TEST(VectorFieldEnergy, PerpendicularSegmentAlongAnEdgeCostsLengthTimesHalfPi) {
  const Mesh mesh = flat_grid();
  const auto energy = vector_field(mesh, std::vector<Vec3>(mesh.num_vertices(), Vec3(0.0, 1.0, 0.0)));
  // Vertices 0 -> 1 are one grid edge along x (length 0.5).
  const int f = mesh.face_with_edge(0, 1);
  ASSERT_GE(f, 0);
  EXPECT_NEAR(energy->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(1), f), 0.5 * kPi / 2, 1e-14);
  // Part of the edge, as edge points.
  EXPECT_NEAR(energy->segment_energy(SurfacePoint::on_edge(0, 1, 0.25), SurfacePoint::at_vertex(1), f),
              0.375 * kPi / 2, 1e-14);
}

TEST(VectorFieldEnergy, FieldIsBidirectionalAndProjectedOntoTheFace) {
  const Mesh mesh = flat_grid();
  std::vector<Vec3> field(mesh.num_vertices());
  // Alternate the sign per vertex (a line field does not care) and add a normal component
  // (projected away).
  for (int v = 0; v < mesh.num_vertices(); ++v) field[v] = Vec3(v % 2 ? 1.0 : -1.0, 0.0, v % 3 ? 5.0 : -2.0);
  const auto energy = vector_field(mesh, field);
  const int f = mesh.face_with_edge(0, 1);
  EXPECT_NEAR(energy->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(1), f), 0.0, 1e-15);
}

TEST(VectorFieldEnergy, VanishingFieldHasNoPreference) {
  const Mesh mesh = flat_grid();
  std::vector<Vec3> field(mesh.num_vertices(), Vec3(1.0, 0.0, 0.0));
  const int f = 3;
  for (int v : mesh.face(f)) field[v] = Vec3::Zero();  // zero on this face only
  const auto energy = vector_field(mesh, field);
  const auto [a, b] = chord(mesh, f, centroid(mesh, f), Vec3(0.3, 1.0, 0.0));
  EXPECT_EQ(energy->segment_energy(a, b, f), 0.0);
}

// Worst relative error of the energy's quadrature against a fine midpoint rule of the
// exact angle, over chords (at 60 degrees to the radial direction) of the faces of an n x n
// grid whose centroid is at least r_min from the centre of the rotation field. The field is
// linear in the position, so its interpolation is exact on the planar grid and only the
// quadrature is measured. Chords where the angle has a kink (the field turns parallel or
// perpendicular to the chord) are skipped: the rule is for smooth integrands.
double worst_quadrature_error(int n, double r_min, int* checked) {
  const Mesh mesh = flat_grid(n);
  const auto energy = vector_field(mesh, rotation_field(mesh, Vec3::Zero(), 2));
  double worst = 0.0;
  *checked = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 c = centroid(mesh, f);
    if (c.norm() < r_min) continue;
    const Vec3 radial = c.normalized();
    const Vec3 d = std::cos(kPi / 3) * radial + std::sin(kPi / 3) * Vec3::UnitZ().cross(radial);
    const auto [a, b] = chord(mesh, f, c, d);
    const Vec3 pa = a.position(mesh), pb = b.position(mesh);
    const int steps = 4000;
    double integral = 0.0;
    bool kink = false;
    const Vec3 w0 = Vec3::UnitZ().cross(pa);
    const double cross0 = (pb - pa).cross(w0).z(), dot0 = (pb - pa).dot(w0);
    for (int i = 0; i < steps; ++i) {
      const Vec3 p = pa + (pb - pa) * ((i + 0.5) / steps);
      const Vec3 w = Vec3::UnitZ().cross(p);
      if (std::signbit((pb - pa).cross(w).z()) != std::signbit(cross0)) kink = true;
      if (std::signbit((pb - pa).dot(w)) != std::signbit(dot0)) kink = true;
      integral += line_angle(pb - pa, w);
    }
    if (kink) continue;
    integral *= (pb - pa).norm() / steps;
    worst = std::max(worst, std::abs(energy->segment_energy(a, b, f) - integral) / integral);
    ++*checked;
  }
  return worst;
}

// 3-point Gauss-Legendre: relative error O((h / r)^6), h the chord length and r the
// distance to where the field direction turns fastest (its zero).
TEST(VectorFieldEnergy, QuadratureMatchesFineIntegrationOfALinearField) {
  int checked = 0;
  // Coarse: faces 0.5 wide, some one face width from the field's zero.
  const double coarse = worst_quadrature_error(5, 0.0, &checked);
  EXPECT_GT(checked, 20);
  EXPECT_LT(coarse, 5e-5);
  // Fine: faces 0.05 wide, at least 5 face widths away.
  const double fine = worst_quadrature_error(41, 0.25, &checked);
  EXPECT_GT(checked, 2000);
  std::printf("quadrature relative error: coarse %.3g, fine %.3g\n", coarse, fine);
  EXPECT_LT(fine, 1e-8);
}

TEST(VectorFieldEnergy, NormalizedEnergyAndSmoothnessOfAnLShapedPath) {
  const Mesh mesh = flat_grid();  // 5 x 5, spacing 0.5, vertex (i, j) = 5 j + i
  const auto energy = vector_field(mesh, std::vector<Vec3>(mesh.num_vertices(), Vec3(1.0, 0.0, 0.0)), 0.25);
  SurfacePath path;
  // Along x from (0,0) to (2,0) [angle 0], then along y to (2,2) [angle pi/2].
  for (int v : {0, 1, 2, 7, 12}) path.points.push_back(SurfacePoint::at_vertex(v));
  path.segment_faces = {mesh.face_with_edge(0, 1), mesh.face_with_edge(1, 2), mesh.face_with_edge(2, 7),
                        mesh.face_with_edge(7, 12)};
  const double field_part = 1.0 * kPi / 2;
  EXPECT_NEAR(metric(*energy, path, "normalized_energy") * 2.0, field_part, 1e-14);
  EXPECT_NEAR(energy->evaluate(path), field_part + 0.25 * kPi / 2, 1e-14);  // one right-angle turn
  const auto m = energy->metrics(path);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].name, "normalized_energy");
  EXPECT_NEAR(m[0].value, field_part / 2.0, 1e-14);
}

TEST(VectorFieldEnergy, GeneratedHeightFieldOnAPlaneFollowsTheSlope) {
  // z = 0.5 x: the height gradient points along +x (tilted); rotated by 90 degrees it
  // follows the contour lines (along y).
  const Mesh mesh = inclined_grid(0.5);
  const auto along = vector_field(mesh, height_gradient_field(mesh, 2, 0.0));
  const auto contour = vector_field(mesh, height_gradient_field(mesh, 2, 90.0));
  const int f = mesh.face_with_edge(0, 1);  // edge along x
  const double len = (mesh.position(1) - mesh.position(0)).norm();
  EXPECT_NEAR(along->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(1), f), 0.0, 1e-14);
  EXPECT_NEAR(contour->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(1), f), len * kPi / 2, 1e-13);
  const int g = mesh.face_with_edge(0, 5);  // edge along y
  EXPECT_NEAR(contour->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(5), g), 0.0, 1e-14);
}

// ---------------------------------------------------------------- constant_slope

// On the plane z = x the steepest slope (per 3D arc length) is 1/sqrt(2). For k = 0.5
// the target directions make theta = 45 degrees with the gradient:
// d = (1/2, +-1/sqrt(2), 1/2), slope d.z = 1/2.
TEST(ConstantSlopeEnergy, InclinedPlaneTargetsHaveSlopeK) {
  const Mesh mesh = inclined_grid(1.0);
  const double k = 0.5;
  const auto energy = constant_slope(mesh, 2, k);
  const Vec3 d_plus(0.5, std::sqrt(0.5), 0.5), d_minus(0.5, -std::sqrt(0.5), 0.5);
  ASSERT_NEAR(d_plus.norm(), 1.0, 1e-15);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 c = centroid(mesh, f);
    for (const Vec3& d : {d_plus, d_minus, Vec3(-d_plus), Vec3(-d_minus)}) {
      const auto [a, b] = chord(mesh, f, c, d);
      EXPECT_NEAR(energy->segment_energy(a, b, f), 0.0, 1e-12) << "face " << f;
      const SurfacePath path = one_segment(a, b, f);
      EXPECT_NEAR(metric(*energy, path, "mean_slope_error"), 0.0, 1e-12);
    }
    // Any other direction: length * the smaller exact 3D line angle to d+ and d-.
    for (double deg : {0.0, 20.0, 90.0, 120.0, 200.0}) {
      const double r = deg * kPi / 180.0;
      // A tangent direction of the plane z = x with plan-view angle r.
      const Vec3 d = Vec3(std::cos(r), std::sin(r), std::cos(r)).normalized();
      const auto [a, b] = chord(mesh, f, c, d);
      const double expected = std::min(line_angle(d, d_plus), line_angle(d, d_minus));
      EXPECT_NEAR(energy->segment_energy(a, b, f), seg_length(mesh, a, b) * expected, 1e-12)
          << "face " << f << " deg " << deg;
    }
  }
  // Along the gradient (x) and along the contour (y) both are theta = 45 degrees away.
  const int fx = mesh.face_with_edge(0, 1), fy = mesh.face_with_edge(0, 5);
  EXPECT_NEAR(energy->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(1), fx),
              std::sqrt(0.5) * kPi / 4, 1e-14);
  EXPECT_NEAR(energy->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(5), fy), 0.5 * kPi / 4, 1e-14);
}

TEST(ConstantSlopeEnergy, TooFlatFacesTargetTheGradientAndZeroSlopeTheContours) {
  const Mesh mesh = inclined_grid(1.0);  // steepest slope 1/sqrt(2) ~ 0.707
  const int fx = mesh.face_with_edge(0, 1), fy = mesh.face_with_edge(0, 5);
  const auto x_edge = [&](const std::unique_ptr<Energy>& e) {
    return e->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(1), fx);
  };
  const auto y_edge = [&](const std::unique_ptr<Energy>& e) {
    return e->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(5), fy);
  };
  const auto steep = constant_slope(mesh, 2, 0.9);  // unreachable: follow the gradient
  EXPECT_NEAR(x_edge(steep), 0.0, 1e-14);
  EXPECT_NEAR(y_edge(steep), 0.5 * kPi / 2, 1e-14);
  const auto level = constant_slope(mesh, 2, 0.0);  // k = 0: contour lines
  EXPECT_NEAR(x_edge(level), std::sqrt(0.5) * kPi / 2, 1e-14);
  EXPECT_NEAR(y_edge(level), 0.0, 1e-14);
  const auto exact = constant_slope(mesh, 2, std::sqrt(0.5));  // k = |g|: theta = 0
  EXPECT_NEAR(x_edge(exact), 0.0, 1e-7);
}

TEST(ConstantSlopeEnergy, LevelTerrainHasNoPreference) {
  const Mesh mesh = flat_grid();
  const auto energy = constant_slope(mesh, 2, 0.3);
  const int f = 5;
  const auto [a, b] = chord(mesh, f, centroid(mesh, f), Vec3(0.2, 1.0, 0.0));
  EXPECT_EQ(energy->segment_energy(a, b, f), 0.0);
}

TEST(ConstantSlopeEnergy, UpAxisSelectsTheHeight) {
  // The plane y = x (height along y): a segment along z is a contour line.
  const Mesh flat = flat_grid();
  std::vector<Vec3> p;
  for (const Vec3& v : flat.positions()) p.emplace_back(v.x(), v.x(), v.y());
  const Mesh mesh(std::move(p), flat.faces());
  const auto energy = constant_slope(mesh, 1, 0.0);
  const int fz = mesh.face_with_edge(0, 5), fx = mesh.face_with_edge(0, 1);
  EXPECT_NEAR(energy->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(5), fz), 0.0, 1e-14);
  EXPECT_NEAR(energy->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(1), fx),
              std::sqrt(0.5) * kPi / 2, 1e-14);
}

TEST(ConstantSlopeEnergy, MeanSlopeErrorAndMetricsOfAPath) {
  const Mesh mesh = inclined_grid(1.0);  // z = x, spacing 0.5
  const double k = 0.5;
  const auto energy = constant_slope(mesh, 2, k);
  SurfacePath path;
  // Up the x edge 0 -> 1 (dz/ds = 1/sqrt(2), length sqrt(0.5)), then the y edge 1 -> 6
  // (dz/ds = 0, length 0.5), then back down 6 -> 5 (|dz/ds| = 1/sqrt(2)).
  for (int v : {0, 1, 6, 5}) path.points.push_back(SurfacePoint::at_vertex(v));
  path.segment_faces = {mesh.face_with_edge(0, 1), mesh.face_with_edge(1, 6), mesh.face_with_edge(6, 5)};
  const double lx = std::sqrt(0.5), ly = 0.5;
  const double expected_error = (2 * lx * (std::sqrt(0.5) - k) + ly * k) / (2 * lx + ly);
  const double expected_energy = (2 * lx + ly) * kPi / 4;  // every segment 45 degrees off
  const auto m = energy->metrics(path);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].name, "normalized_energy");
  EXPECT_NEAR(m[0].value, expected_energy / (2 * lx + ly), 1e-14);
  EXPECT_EQ(m[1].name, "mean_slope_error");
  EXPECT_NEAR(m[1].value, expected_error, 1e-14);
}

// On a cone the analytic constant-slope curve is a spiral. The faceted cone's faces are
// planes through two generators, so each face's target line should match the spiral's
// tangent at the face's mid-angle up to the faceting error O((pi / sectors)^2).
TEST(ConstantSlopeEnergy, ConeFacesFollowTheAnalyticSpiral) {
  ConeOptions o;
  o.height = 1.0;
  o.radius = 1.0;
  o.rings = 8;
  o.sectors = 256;
  const Mesh mesh = make_cone(o);
  const double k = 0.2;
  const auto energy = constant_slope(mesh, 2, k);
  // Steepest slope along a generator: h / L; the spiral makes angle alpha with the
  // generator, cos(alpha) = k L / h.
  const double L = std::hypot(o.height, o.radius);
  const double alpha = std::acos(k * L / o.height);
  double worst = 0.0;
  for (int f = o.sectors; f < mesh.num_faces(); f += 37) {  // skip the apex fan
    const Vec3 c = centroid(mesh, f);
    // The face's plane holds two generators; its normal points (in plan view) along their
    // bisector, where the faceted surface matches the cone best.
    const double phi = std::atan2(mesh.face_normal(f).y(), mesh.face_normal(f).x());
    const Vec3 down_generator = Vec3(o.radius * std::cos(phi), o.radius * std::sin(phi), -o.height) / L;
    const Vec3 around(-std::sin(phi), std::cos(phi), 0.0);
    for (double sign : {1.0, -1.0}) {
      const Vec3 d = std::cos(alpha) * down_generator + sign * std::sin(alpha) * around;
      const auto [a, b] = chord(mesh, f, c, d);
      worst = std::max(worst, energy->segment_energy(a, b, f) / seg_length(mesh, a, b));
    }
  }
  EXPECT_LT(worst, 2e-4);  // (pi / 256)^2 = 1.5e-4
}

// ---------------------------------------------------------------- smoothness: turning within the surface

// Two triangles folded about the hinge A-B (the y axis): C lies in the plane z = 0, D is
// lifted by h. The path C -> P -> D with P the hinge's midpoint is straight once D's face is
// unfolded into C's plane, so it turns by 0 within the surface, though its 3D segments meet
// at atan(h). Elsewhere on the hinge the turn is the unfolded angle.
TEST(Smoothness, TurningAtAnEdgeIsMeasuredInTheUnfolding) {
  const double h = 0.8;
  const Mesh mesh({Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0.5, 0), Vec3(1, 0.5, h)}, {{{0, 1, 2}}, {{1, 0, 3}}});
  const auto energy = vector_field(mesh, std::vector<Vec3>(4, Vec3(1, 0, 0)), 1.0);
  auto path_through = [&](double t) {
    SurfacePath path;
    path.points = {SurfacePoint::at_vertex(2), SurfacePoint::on_edge(0, 1, t), SurfacePoint::at_vertex(3)};
    path.segment_faces = {0, 1};
    return path;
  };
  EXPECT_NEAR(energy->turning_angle(path_through(0.5), 1), 0.0, 1e-14);
  const Vec3 p = path_through(0.5).points[1].position(mesh);
  const Vec3 a = p - mesh.position(2), b = mesh.position(3) - p;
  EXPECT_NEAR(std::atan2(a.cross(b).norm(), a.dot(b)), std::atan(h), 1e-14);  // what a 3D angle would charge
  // P at y = 0.25: unfolded, D sits at (sqrt(1 + h^2), 0.5); the turn is the difference of
  // the two segments' directions in that plane.
  const double d = std::hypot(1.0, h);
  const double expected = std::atan2(0.25, d) + std::atan2(0.25, 1.0);
  EXPECT_NEAR(energy->turning_angle(path_through(0.25), 1), expected, 1e-12);
  // Touching the hinge and going back into the same face: the plain angle in that face.
  SurfacePath back;
  back.points = {SurfacePoint::at_vertex(2), SurfacePoint::on_edge(0, 1, 0.5), SurfacePoint::on_edge(0, 2, 0.5)};
  back.segment_faces = {0, 0};
  EXPECT_NEAR(energy->turning_angle(back, 1), kPi - std::atan2(0.25, 0.5), 1e-12);
}

// A square pyramid: 60-degree corners at the apex, 240 degrees around it. Through the apex
// between opposite base corners the path has 120 degrees on either side: it turns by
// 180 - 120 = 60 degrees within the surface (3D: 90). Along a face boundary on a flat grid the
// vertex rule gives the plain angle.
TEST(Smoothness, TurningAtAVertexUsesTheSurfaceAnglesOnBothSides) {
  const Mesh pyramid({Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0)},
                     {{{0, 1, 2}}, {{0, 2, 3}}, {{0, 3, 4}}, {{0, 4, 1}}});
  const auto energy = vector_field(pyramid, std::vector<Vec3>(5, Vec3(1, 0, 0)), 1.0);
  SurfacePath path;
  path.points = {SurfacePoint::at_vertex(1), SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(3)};
  path.segment_faces = {0, 1};
  EXPECT_NEAR(energy->turning_angle(path, 1), kPi / 3, 1e-12);
  path.segment_faces = {3, 2};  // the same path, faces on the other side
  EXPECT_NEAR(energy->turning_angle(path, 1), kPi / 3, 1e-12);
  // To the neighbouring corner: 60 degrees on one side, so it turns by 120.
  path.points[2] = SurfacePoint::at_vertex(2);
  path.segment_faces = {0, 0};
  EXPECT_NEAR(energy->turning_angle(path, 1), 2 * kPi / 3, 1e-12);

  const Mesh grid = flat_grid();  // 5 x 5, vertex (i, j) = 5 j + i
  const auto flat = vector_field(grid, std::vector<Vec3>(grid.num_vertices(), Vec3(1, 0, 0)), 1.0);
  SurfacePath corner;  // (0,1) -> (1,1) -> (1,2): a right angle at the interior vertex 6
  corner.points = {SurfacePoint::at_vertex(5), SurfacePoint::at_vertex(6), SurfacePoint::at_vertex(11)};
  corner.segment_faces = {grid.face_with_edge(5, 6), grid.face_with_edge(6, 11)};
  EXPECT_NEAR(flat->turning_angle(corner, 1), kPi / 2, 1e-12);
  SurfacePath straight;  // (0,1) -> (1,1) -> (2,1)
  straight.points = {SurfacePoint::at_vertex(5), SurfacePoint::at_vertex(6), SurfacePoint::at_vertex(7)};
  straight.segment_faces = {grid.face_with_edge(5, 6), grid.face_with_edge(6, 7)};
  EXPECT_NEAR(flat->turning_angle(straight, 1), 0.0, 1e-12);
}

// ---------------------------------------------------------------- factory checks

void expect_invalid(const Mesh& mesh, const EnergySpec& spec, const std::string& fragment) {
  try {
    make_energy(mesh, spec);
    ADD_FAILURE() << "accepted a spec that should fail with '" << fragment << "'";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(MakeEnergy, RejectsBadVectorFieldSpecs) {
  const Mesh mesh = inclined_grid(1.0);  // 25 vertices
  EnergySpec spec;
  spec.kind = EnergyKind::vector_field;
  expect_invalid(mesh, spec, "field");  // neither a field nor --field-from-height
  spec.field.assign(24, Vec3(1, 0, 0));
  expect_invalid(mesh, spec, "24");  // wrong length, named with the counts
  spec.field.assign(25, Vec3(1, 0, 0));
  spec.field[7] = Vec3(0, std::nan(""), 0);
  expect_invalid(mesh, spec, "vertex 7");
  spec.field[7] = Vec3(1, 0, 0);
  spec.field_from_height = true;
  expect_invalid(mesh, spec, "--field-from-height");  // both given
  spec.field.clear();
  spec.up_axis = 3;
  expect_invalid(mesh, spec, "up axis");
  spec.up_axis = 2;
  spec.rotate_degrees = std::numeric_limits<double>::infinity();
  expect_invalid(mesh, spec, "rotat");
  spec.rotate_degrees = 0.0;
  spec.smoothness = -1.0;
  expect_invalid(mesh, spec, "smoothness");
  spec.smoothness = 0.0;
  EXPECT_EQ(make_energy(mesh, spec)->name(), "vector_field");
  // A generated field that vanishes everywhere (level terrain) prefers nothing: rejected.
  expect_invalid(flat_grid(), spec, "vanishes");
}

TEST(MakeEnergy, RejectsBadConstantSlopeSpecs) {
  const Mesh mesh = inclined_grid(1.0);
  EnergySpec spec;
  spec.kind = EnergyKind::constant_slope;
  spec.slope = -0.1;
  expect_invalid(mesh, spec, "slope");
  spec.slope = std::nan("");
  expect_invalid(mesh, spec, "slope");
  spec.slope = 0.2;
  spec.up_axis = -1;
  expect_invalid(mesh, spec, "up axis");
  spec.up_axis = 2;
  spec.smoothness = std::numeric_limits<double>::infinity();
  expect_invalid(mesh, spec, "smoothness");
  spec.smoothness = 0.5;
  const auto energy = make_energy(mesh, spec);
  EXPECT_EQ(energy->name(), "constant_slope");
  EXPECT_EQ(energy->smoothness(), 0.5);
}

TEST(MakeEnergy, FieldFromHeightWithRotation) {
  const Mesh mesh = inclined_grid(0.5);
  EnergySpec spec;
  spec.kind = EnergyKind::vector_field;
  spec.field_from_height = true;
  spec.rotate_degrees = 90.0;  // contour lines: along y on z = 0.5 x
  const auto energy = make_energy(mesh, spec);
  const int fy = mesh.face_with_edge(0, 5), fx = mesh.face_with_edge(0, 1);
  EXPECT_NEAR(energy->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(5), fy), 0.0, 1e-14);
  EXPECT_NEAR(energy->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(1), fx),
              (mesh.position(1) - mesh.position(0)).norm() * kPi / 2, 1e-13);
  spec.rotate_degrees = 45.0;
  const auto diagonal = make_energy(mesh, spec);
  // The gradient rotated by 45 degrees in the plane makes 45 degrees with both edges.
  EXPECT_NEAR(diagonal->segment_energy(SurfacePoint::at_vertex(0), SurfacePoint::at_vertex(5), fy), 0.5 * kPi / 4,
              1e-13);
}

}  // namespace
}  // namespace depath
