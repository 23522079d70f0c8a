// SPDX-License-Identifier: MIT
// Surface generators (grids, MATLAB peaks, cones), the mesh writer, and the tangent-field
// generators, against analytic values.
#include "depath/util/error.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/io/mesh_writer.hpp"
#include "depath/generators/surfaces.hpp"
#include "depath/mesh/tangent_fields.hpp"
#include "analytic_meshes.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <unistd.h>

namespace depath {
namespace {

constexpr double kPi = std::numbers::pi;

double total_area(const Mesh& mesh) {
  double a = 0.0;
  for (int f = 0; f < mesh.num_faces(); ++f) a += mesh.face_area(f);
  return a;
}

// ---------------------------------------------------------------- grids

TEST(Grid, CountsCoordinatesAndOrientation) {
  for (GridDiagonals diagonals : {GridDiagonals::uniform, GridDiagonals::alternating}) {
    GridOptions o;
    o.n = 41;
    o.diagonals = diagonals;
    const Mesh mesh = make_grid(o);
    EXPECT_EQ(mesh.num_vertices(), 41 * 41);
    EXPECT_EQ(mesh.num_faces(), 2 * 40 * 40);
    EXPECT_EQ(mesh.num_boundary_edges(), 4 * 40);
    EXPECT_EQ(mesh.num_components(), 1);
    EXPECT_EQ(mesh.num_degenerate_faces(), 0);
    // Default domain [-3, 3]^2; vertex (i, j) = j n + i; the centre is exactly 0.
    EXPECT_EQ(mesh.position(0), Vec3(-3, -3, 0));
    EXPECT_EQ(mesh.position(40), Vec3(3, -3, 0));
    EXPECT_EQ(mesh.position(41 * 41 - 1), Vec3(3, 3, 0));
    EXPECT_EQ(mesh.position(20 * 41 + 20), Vec3(0, 0, 0));
    EXPECT_DOUBLE_EQ(mesh.position(20 * 41 + 21).x(), 0.15);
    EXPECT_NEAR(total_area(mesh), 36.0, 1e-12);
    for (int f = 0; f < mesh.num_faces(); ++f) ASSERT_NEAR(mesh.face_normal(f).z(), 1.0, 1e-12) << f;
  }
}

TEST(Grid, UpAxisChoosesThePlane) {
  GridOptions o;
  o.n = 3;
  o.half_size = 1.0;
  o.up_axis = 0;  // height on x, plane spanned by (y, z)
  o.height = GridHeight::peaks;
  const Mesh mesh = make_grid(o);
  // Vertex (i, j) = (1, 2): u = 0, v = 1 -> y = 0, z = 1, x = peaks(0, 3) / 3.
  EXPECT_EQ(mesh.position(2 * 3 + 1).y(), 0.0);
  EXPECT_EQ(mesh.position(2 * 3 + 1).z(), 1.0);
  EXPECT_DOUBLE_EQ(mesh.position(2 * 3 + 1).x(), matlab_peaks(0.0, 3.0) / 3.0);
  GridOptions flat = o;
  flat.height = GridHeight::flat;
  const Mesh plane = make_grid(flat);
  for (int f = 0; f < plane.num_faces(); ++f) EXPECT_NEAR(plane.face_normal(f).x(), 1.0, 1e-12);
}

TEST(Grid, MatlabPeaks) {
  const double e = std::exp(1.0);
  // peaks(0, 0) = 3 e^-1 - 0 - e^-1 / 3; peaks(1, 0) = 0 + 8 e^-1 - e^-4 / 3.
  EXPECT_NEAR(matlab_peaks(0.0, 0.0), (3.0 - 1.0 / 3.0) / e, 1e-15);
  EXPECT_NEAR(matlab_peaks(1.0, 0.0), 8.0 / e - std::exp(-4.0) / 3.0, 1e-15);
  // peaks(0, 1) = 3 e^-4 - 10 (-1) e^-1 - e^-2 / 3.
  EXPECT_NEAR(matlab_peaks(0.0, 1.0), 3.0 * std::exp(-4.0) + 10.0 / e - std::exp(-2.0) / 3.0, 1e-14);
  // The well-known extremes of MATLAB's peaks: max 8.1062 near (-0.0093, 1.5814),
  // min -6.5511 near (0.2283, -1.6255).
  EXPECT_NEAR(matlab_peaks(-0.0093, 1.5814), 8.1062, 1e-4);
  EXPECT_NEAR(matlab_peaks(0.2283, -1.6255), -6.5511, 1e-4);

  GridOptions o;
  o.n = 49;
  o.height = GridHeight::peaks;  // MATLAB's own domain [-3, 3]^2: heights are peaks(x, y)
  const Mesh mesh = make_grid(o);
  for (int v = 0; v < mesh.num_vertices(); v += 7) {
    const Vec3& p = mesh.position(v);
    ASSERT_DOUBLE_EQ(p.z(), matlab_peaks(p.x(), p.y())) << v;
  }
  // Half size 1.5 and height scale 2: uniformly scaled by 1/2, then heights doubled.
  o.half_size = 1.5;
  o.height_scale = 2.0;
  const Mesh small = make_grid(o);
  for (int v = 0; v < small.num_vertices(); v += 7) {
    const Vec3& p = small.position(v);
    ASSERT_NEAR(p.z(), 2.0 * 0.5 * matlab_peaks(2.0 * p.x(), 2.0 * p.y()), 1e-12) << v;
  }
}

TEST(Grid, RejectsBadOptions) {
  GridOptions o;
  o.n = 1;
  EXPECT_THROW(make_grid(o), Error);
  o.n = 5;
  o.half_size = -1.0;
  EXPECT_THROW(make_grid(o), Error);
  o.half_size = std::nan("");
  EXPECT_THROW(make_grid(o), Error);
  o.half_size = 1.0;
  o.up_axis = 3;
  EXPECT_THROW(make_grid(o), Error);
  EXPECT_THROW(parse_grid_height("hills"), Error);
  EXPECT_EQ(parse_grid_height("peaks"), GridHeight::peaks);
  EXPECT_EQ(parse_grid_diagonals("alternating"), GridDiagonals::alternating);
}

// ---------------------------------------------------------------- cones

TEST(Cone, GeometryAndTopology) {
  ConeOptions o;
  o.height = 2.0;
  o.radius = 1.5;
  o.rings = 6;
  o.sectors = 32;
  const Mesh mesh = make_cone(o);
  EXPECT_EQ(mesh.num_vertices(), 1 + 6 * 32);
  EXPECT_EQ(mesh.num_faces(), 32 + 2 * 32 * 5);
  EXPECT_EQ(mesh.num_boundary_edges(), 32);
  EXPECT_EQ(mesh.num_components(), 1);
  EXPECT_EQ(mesh.position(0), Vec3(0, 0, 2));
  for (int r = 1; r <= 6; ++r) {
    for (int j = 0; j < 32; j += 5) {
      const Vec3& p = mesh.position(cone_vertex(o, r, j));
      EXPECT_NEAR(std::hypot(p.x(), p.y()), 1.5 * r / 6, 1e-14);
      EXPECT_NEAR(p.z(), 2.0 * (1.0 - r / 6.0), 1e-14);
      EXPECT_NEAR(std::atan2(p.y(), p.x()), std::remainder(2 * kPi * j / 32, 2 * kPi), 1e-14);
    }
  }
  // The faceted lateral surface is a pyramid over a regular 32-gon: area
  // = 32 * (1/2) * chord * slant, chord = 2 R sin(pi/32), slant = sqrt(h^2 + (R cos(pi/32))^2).
  const double chord = 2 * 1.5 * std::sin(kPi / 32);
  const double slant = std::hypot(2.0, 1.5 * std::cos(kPi / 32));
  EXPECT_NEAR(total_area(mesh), 32 * 0.5 * chord * slant, 1e-12);
  // Outward and upward normals.
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto& t = mesh.face(f);
    const Vec3 c = (mesh.position(t[0]) + mesh.position(t[1]) + mesh.position(t[2])) / 3.0;
    const Vec3& n = mesh.face_normal(f);
    EXPECT_GT(n.z(), 0.0) << f;
    EXPECT_GT(n.x() * c.x() + n.y() * c.y(), 0.0) << f;
  }
}

TEST(Cone, CapClosesTheBaseAndUpAxisTurnsIt) {
  ConeOptions o;
  o.rings = 3;
  o.sectors = 12;
  o.cap = true;
  o.up_axis = 1;
  const Mesh mesh = make_cone(o);
  EXPECT_EQ(mesh.num_vertices(), 1 + 3 * 12 + 1);
  EXPECT_EQ(mesh.num_boundary_edges(), 0);
  EXPECT_EQ(mesh.position(0), Vec3(0, 1, 0));
  EXPECT_EQ(mesh.position(mesh.num_vertices() - 1), Vec3(0, 0, 0));
  // Closed and outward: the divergence theorem gives the enclosed volume
  // (1/3) * base polygon area * height; base = (1/2) * 12 * R^2 sin(2 pi / 12).
  double volume = 0.0;
  for (const auto& t : mesh.faces())
    volume += mesh.position(t[0]).dot(mesh.position(t[1]).cross(mesh.position(t[2]))) / 6.0;
  EXPECT_NEAR(volume, (0.5 * 12 * std::sin(2 * kPi / 12)) * 1.0 / 3.0, 1e-12);
}

TEST(Cone, RejectsBadOptions) {
  ConeOptions o;
  o.sectors = 2;
  EXPECT_THROW(make_cone(o), Error);
  o.sectors = 8;
  o.rings = 0;
  EXPECT_THROW(make_cone(o), Error);
  o.rings = 2;
  o.height = 0.0;
  EXPECT_THROW(make_cone(o), Error);
  o.height = 1.0;
  o.radius = std::numeric_limits<double>::infinity();
  EXPECT_THROW(make_cone(o), Error);
}

// ---------------------------------------------------------------- writer

class MeshWriter : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("depath_writer_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(MeshWriter, RoundTripsThroughTheReaders) {
  const Mesh grid = test::alternating_grid(9, GridHeight::peaks);
  ConeOptions c;
  c.rings = 4;
  c.sectors = 10;
  c.cap = true;
  const Mesh cone = make_cone(c);
  for (const Mesh* mesh : {&grid, &cone}) {
    for (const char* name : {"m.obj", "m.off", "m.ply", "m_binary.ply", "M.OBJ"}) {
      const std::string path = (dir_ / name).string();
      write_mesh(path, *mesh, std::string(name) == "m_binary.ply");
      const Mesh back = load_mesh(path);
      ASSERT_EQ(back.num_vertices(), mesh->num_vertices()) << name;
      ASSERT_EQ(back.num_faces(), mesh->num_faces()) << name;
      // The OBJ and OFF readers deliver single-precision coordinates, so the round trip is
      // exact to float precision; the text itself is exact (checked below).
      for (int v = 0; v < mesh->num_vertices(); ++v)
        ASSERT_NEAR((back.position(v) - mesh->position(v)).norm(), 0.0, 1e-7 * (1.0 + mesh->position(v).norm()))
            << name << " " << v;
      for (int f = 0; f < mesh->num_faces(); ++f) ASSERT_EQ(back.face(f), mesh->face(f)) << name << " " << f;
    }
  }
}

// %.17g round-trips every double: parse the OBJ and OFF text and the binary PLY body back.
TEST(MeshWriterText, CoordinatesAreExact) {
  GridOptions o;
  o.n = 7;
  o.height = GridHeight::peaks;
  const Mesh mesh = make_grid(o);
  {
    std::istringstream obj(write_mesh_to_string(mesh, "obj"));
    std::string tag;
    std::string line;
    int v = 0, f = 0;
    while (std::getline(obj, line)) {
      std::istringstream in(line);
      in >> tag;
      if (tag == "v") {
        Vec3 p;
        in >> p.x() >> p.y() >> p.z();
        ASSERT_EQ(p, mesh.position(v)) << v;
        ++v;
      } else if (tag == "f") {
        std::array<int, 3> t;
        in >> t[0] >> t[1] >> t[2];
        ASSERT_EQ(t, (std::array<int, 3>{mesh.face(f)[0] + 1, mesh.face(f)[1] + 1, mesh.face(f)[2] + 1}));
        ++f;
      }
    }
    EXPECT_EQ(v, mesh.num_vertices());
    EXPECT_EQ(f, mesh.num_faces());
  }
  {
    std::istringstream off(write_mesh_to_string(mesh, "off"));
    std::string magic;
    int nv, nf, ne;
    off >> magic >> nv >> nf >> ne;
    ASSERT_EQ(magic, "OFF");
    ASSERT_EQ(nv, mesh.num_vertices());
    for (int v = 0; v < nv; ++v) {
      Vec3 p;
      off >> p.x() >> p.y() >> p.z();
      ASSERT_EQ(p, mesh.position(v)) << v;
    }
  }
  {
    const std::string ply = write_mesh_to_string(mesh, "ply", true);
    const std::string end = "end_header\n";
    const size_t body = ply.find(end) + end.size();
    ASSERT_NE(ply.find("format binary_little_endian 1.0"), std::string::npos);
    ASSERT_EQ(ply.size(), body + mesh.num_vertices() * 24 + mesh.num_faces() * 13);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      double xyz[3];
      std::memcpy(xyz, ply.data() + body + 24 * v, 24);  // the test machines are little-endian
      ASSERT_EQ(Vec3(xyz[0], xyz[1], xyz[2]), mesh.position(v)) << v;
    }
  }
}

TEST_F(MeshWriter, RejectsUnknownExtensionsAndUnwritablePaths) {
  GridOptions o;
  o.n = 2;
  const Mesh mesh = make_grid(o);
  EXPECT_THROW(write_mesh((dir_ / "m.stl").string(), mesh), Error);
  EXPECT_THROW(write_mesh((dir_ / "noext").string(), mesh), Error);
  EXPECT_THROW(write_mesh((dir_ / "missing" / "m.obj").string(), mesh), Error);
  const std::string off = write_mesh_to_string(mesh, "off");
  EXPECT_EQ(off.rfind("OFF\n4 2 0\n", 0), 0u);
}

// ---------------------------------------------------------------- tangent fields

TEST(TangentFields, GradientOfALinearFunctionIsExact) {
  const Mesh mesh = test::alternating_grid(6);
  std::vector<double> f(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) f[v] = 2.0 * mesh.position(v).x() - 3.0 * mesh.position(v).y() + 7.0;
  for (const Vec3& g : face_gradients(mesh, f)) EXPECT_NEAR((g - Vec3(2, -3, 0)).norm(), 0.0, 1e-13);
  // Per vertex: the same constant, also at boundary vertices; rotated by 90 degrees CCW.
  for (const Vec3& g : scalar_gradient_field(mesh, f, 90.0)) EXPECT_NEAR((g - Vec3(3, 2, 0)).norm(), 0.0, 1e-13);
  EXPECT_THROW(face_gradients(mesh, std::vector<double>(3, 0.0)), Error);
}

TEST(TangentFields, HeightGradientOnAnInclinedPlane) {
  // On z = a x the height gradient is the up vector projected onto the plane:
  // (a, 0, a^2) / (1 + a^2), of length a / sqrt(1 + a^2) = the steepest dz/ds.
  const double a = 0.75;
  GridOptions o;
  o.n = 5;
  const Mesh flat = make_grid(o);
  std::vector<Vec3> p = flat.positions();
  for (Vec3& v : p) v.z() = a * v.x();
  const Mesh mesh(std::move(p), flat.faces());
  const Vec3 expected = Vec3(a, 0, a * a) / (1 + a * a);
  for (const Vec3& g : height_gradients(mesh, 2)) EXPECT_NEAR((g - expected).norm(), 0.0, 1e-14);
  for (const Vec3& g : height_gradient_field(mesh, 2, 0.0)) EXPECT_NEAR((g - expected).norm(), 0.0, 1e-14);
  // Rotated by +90 degrees about the (upward) normal: along +y, same length.
  const Vec3 rotated = Vec3(0, 1, 0) * expected.norm();
  for (const Vec3& g : height_gradient_field(mesh, 2, 90.0)) EXPECT_NEAR((g - rotated).norm(), 0.0, 1e-14);
  EXPECT_THROW(height_gradients(mesh, 5), Error);
}

TEST(TangentFields, RotationAndConvergeFields) {
  GridOptions o;
  o.n = 5;
  o.half_size = 1.0;
  const Mesh mesh = make_grid(o);
  const Vec3 origin(0.5, 0.0, 0.0);
  const auto rot = rotation_field(mesh, origin, 2);
  const auto conv = converge_field(mesh, origin, 2, 2.0);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 r = mesh.position(v) - origin;
    EXPECT_NEAR((rot[v] - Vec3(-r.y(), r.x(), 0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((conv[v] - Vec3(1.0, -r.y() / 2.0, 0)).norm(), 0.0, 1e-15);
  }
  EXPECT_EQ(rot[2 * 5 + 3], Vec3::Zero());  // (0.5, 0) is the origin
  // Up axis y: plane coordinates (u, v) = (z, x).
  const auto conv_y = converge_field(mesh, Vec3::Zero(), 1, 1.0);
  EXPECT_EQ(conv_y[0], Vec3(1.0, 0.0, 1.0));  // vertex 0 at x = -1: v = -1
  EXPECT_THROW(converge_field(mesh, origin, 2, 0.0), Error);
}

}  // namespace
}  // namespace depath
