// SPDX-License-Identifier: MIT
// Mesh loading (all formats) and the input rules of SPEC §2.
#include "depath/util/error.hpp"
#include "depath/io/mesh_reader.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

namespace depath {
namespace {

namespace fs = std::filesystem;

std::string write_temp(const std::string& name, const std::string& bytes) {
  const fs::path dir = fs::temp_directory_path() / ("depath_mesh_io_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path path = dir / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

// Expects load_mesh to throw invalid_argument with `words` in the message.
void expect_rejected(const std::string& path, const std::string& words) {
  try {
    (void)load_mesh(path);
    ADD_FAILURE() << path << " was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << "message: " << e.what();
  }
}

const char* kCubeQuadsObj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

TEST(MeshIo, ObjQuadsAreTriangulatedAndVertexOrderKept) {
  const Mesh mesh = load_mesh(write_temp("cube.obj", kCubeQuadsObj));
  EXPECT_EQ(mesh.num_vertices(), 8);
  EXPECT_EQ(mesh.num_faces(), 12);
  EXPECT_EQ(mesh.position(6), Vec3(1, 1, 1));
  EXPECT_EQ(mesh.num_boundary_edges(), 0);
  EXPECT_EQ(mesh.num_components(), 1);
  double area = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) area += mesh.face_area(f);
  EXPECT_NEAR(area, 6.0, 1e-12);
}

TEST(MeshIo, OffAsciiPly) {
  const Mesh off = load_mesh(write_temp("tet.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"));
  EXPECT_EQ(off.num_vertices(), 4);
  EXPECT_EQ(off.num_faces(), 4);
  const Mesh ply = load_mesh(write_temp(
      "tri.ply",
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"));
  EXPECT_EQ(ply.num_vertices(), 4);
  EXPECT_EQ(ply.num_faces(), 2);
  EXPECT_EQ(ply.num_boundary_edges(), 4);
  EXPECT_EQ(ply.position(2), Vec3(1, 1, 0));
}

std::string binary_ply(float bad_value = 0.0f) {
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, bad_value};
  s.append(reinterpret_cast<const char*>(v), sizeof v);
  const uint8_t n = 3;
  s.push_back(static_cast<char>(n));
  const int32_t idx[3] = {0, 1, 2};
  s.append(reinterpret_cast<const char*>(idx), sizeof idx);
  return s;
}

TEST(MeshIo, BinaryPly) {
  const Mesh mesh = load_mesh(write_temp("bin.ply", binary_ply()));
  EXPECT_EQ(mesh.num_vertices(), 3);
  EXPECT_EQ(mesh.num_faces(), 1);
  EXPECT_EQ(mesh.position(1), Vec3(1, 0, 0));
}

std::string binary_stl(float z) {
  std::string s(80, ' ');
  const uint32_t count = 2;
  s.append(reinterpret_cast<const char*>(&count), 4);
  const float tris[2][12] = {{0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 1, z}, {0, 0, 1, 0, 0, 0, 1, 1, z, 0, 1, 0}};
  for (const auto& t : tris) {
    s.append(reinterpret_cast<const char*>(t), sizeof t);
    s.append(2, '\0');
  }
  return s;
}

TEST(MeshIo, StlAsciiAndBinaryShareVertices) {
  const Mesh ascii = load_mesh(write_temp(
      "sq.stl",
      "solid sq\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\nendfacet\n"
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid sq\n"));
  EXPECT_EQ(ascii.num_faces(), 2);
  EXPECT_EQ(ascii.num_vertices(), 4);
  EXPECT_EQ(ascii.num_components(), 1);
  const Mesh binary = load_mesh(write_temp("sq_bin.stl", binary_stl(0.0f)));
  EXPECT_EQ(binary.num_faces(), 2);
  EXPECT_EQ(binary.num_vertices(), 4);
}

TEST(MeshIo, RejectsBadFilesWithClearMessages) {
  expect_rejected(write_temp("empty.obj", ""), "empty");
  expect_rejected(write_temp("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), "no faces");
  expect_rejected(write_temp("nan.ply", binary_ply(std::numeric_limits<float>::quiet_NaN())), "non-finite");
  expect_rejected(write_temp("inf.stl", binary_stl(std::numeric_limits<float>::infinity())), "non-finite");
  expect_rejected(write_temp("garbage.off", "this is not an OFF file\n\x01\x02"), "does not parse as off");
  expect_rejected(write_temp("garbage.ply", "not a ply\n"), "does not parse as ply");
  expect_rejected(write_temp("garbage.obj", "\x01\x02\x03 nothing here\n"), "no vertices");
  expect_rejected(write_temp("truncated.ply", binary_ply().substr(0, binary_ply().size() - 5)), "truncated");
  expect_rejected(write_temp("lying.off", "OFF\n1000000000 1 0\n0 0 0\n"), "truncated");
  expect_rejected(write_temp("lying_faces.off", "OFF\n3 1000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "truncated");
  expect_rejected(write_temp("lying.stl", binary_stl(0.0f).substr(0, 100)), "truncated");
  expect_rejected(write_temp("bad_index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"), "missing vertices");
  expect_rejected(write_temp("mesh.xyz", "1 2 3\n"), "unknown mesh format");
  expect_rejected("/nonexistent/dir/mesh.obj", "cannot open");
}

TEST(MeshIo, BadIndicesAndCollapsedFaces) {
  EXPECT_THROW(Mesh({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {{0, 1, 5}}), Error);
  // A face repeating a vertex is dropped; a zero-area face is kept and reported.
  const Mesh mesh({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(2, 0, 0)}, {{0, 1, 2}, {0, 0, 1}, {0, 1, 3}});
  EXPECT_EQ(mesh.num_faces(), 2);
  EXPECT_EQ(mesh.num_degenerate_faces(), 1);
  EXPECT_FALSE(mesh.warnings().empty());
}

TEST(MeshIo, SharedMeshesLoadWithManifestCounts) {
  DEPATH_REQUIRE_SHARED_DATA();
  struct Expected {
    const char* name;
    int vertices, faces;
  };
  for (const Expected& e : {Expected{"kitten.off", 2500, 5000}, Expected{"dragon.obj", 10002, 20000},
                            Expected{"beethoven.ply", 2521, 5028}, Expected{"bimba.obj", 23112, 46220},
                            Expected{"cone.off", 1153, 2302}, Expected{"terrain_grid30.obj", 900, 1682},
                            Expected{"camelhead.off", 11381, 22704}, Expected{"bunny.off", 34835, 69666},
                            Expected{"armadillo.obj", 43243, 86482}}) {
    const Mesh mesh = load_mesh(test::shared_data(std::string("meshes/") + e.name));
    EXPECT_EQ(mesh.num_vertices(), e.vertices) << e.name;
    EXPECT_EQ(mesh.num_faces(), e.faces) << e.name;
  }
  const Mesh beethoven = load_mesh(test::shared_data("meshes/beethoven.ply"));
  EXPECT_EQ(beethoven.num_components(), 3);
  EXPECT_GT(beethoven.num_boundary_edges(), 0);
  const Mesh camel = load_mesh(test::shared_data("meshes/camelhead.off"));
  EXPECT_EQ(camel.num_components(), 1);
  EXPECT_GT(camel.num_boundary_edges(), 0);
  const Mesh kitten = load_mesh(test::shared_data("meshes/kitten.off"));
  EXPECT_EQ(kitten.num_boundary_edges(), 0);
}

TEST(MeshIo, BytesAndFileGiveTheSameMesh) {
  std::ifstream in(test::test_data("cone.off"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const Mesh a = load_mesh_from_bytes(bytes, "off", "cone.off");
  const Mesh b = load_mesh(test::test_data("cone.off"));
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  ASSERT_EQ(a.num_faces(), b.num_faces());
  EXPECT_EQ(a.positions(), b.positions());
  EXPECT_THROW(load_mesh_from_bytes(bytes, "gltf"), Error);
}


// Expects load_mesh_from_bytes to throw `code` with `words` in the message.
void expect_bytes_rejected(const std::string& bytes, const std::string& format, const std::string& words,
                           ErrorCode code = ErrorCode::invalid_argument) {
  try {
    (void)load_mesh_from_bytes(bytes, format, "m." + format);
    ADD_FAILURE() << format << " bytes were accepted, expected: " << words;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << "message: " << e.what();
  }
}

const char* kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

TEST(MeshReaders, ObjNeverOpensWhatMtllibNames) {
  for (const char* target : {"/dev/urandom", "/dev/zero", "/etc/passwd", "../../../etc/shadow"}) {
    const Mesh mesh = load_mesh_from_bytes(std::string("mtllib ") + target + "\nusemtl x\ncall /bin/sh\n" + kTriangleObj,
                                           "obj", "hostile.obj");
    EXPECT_EQ(mesh.num_vertices(), 3) << target;
    EXPECT_EQ(mesh.num_faces(), 1) << target;
    EXPECT_EQ(mesh.position(1), Vec3(1, 0, 0));
  }
}

TEST(MeshReaders, ObjCornerFormsAndNegativeIndices) {
  const Mesh mesh = load_mesh_from_bytes(
      "v 0 0 0\nvt 0 0\nvn 0 0 1\nv 1 0 0\nv 1 1 0 1.0\nv 0 1 0\nf 1/1/1 2//1 3/1\nf -4 -2 -1\n", "obj", "forms.obj");
  ASSERT_EQ(mesh.num_faces(), 2);
  EXPECT_EQ(mesh.face(0), (std::array<int, 3>{0, 1, 2}));
  EXPECT_EQ(mesh.face(1), (std::array<int, 3>{0, 2, 3}));
  expect_bytes_rejected("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "obj", "index 0");
  expect_bytes_rejected("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "obj", "missing vertices");
  expect_bytes_rejected("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "obj", "a face needs at least 3");
  expect_bytes_rejected("v 0 zero 0\n", "obj", "'zero' that is not a number (line 1)");
}

TEST(MeshReaders, NonFiniteCoordinatesAreNamedAsSuch) {
  expect_bytes_rejected("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "obj", "non-finite coordinate");
  expect_bytes_rejected("v 0 0 0\nv 1 0 0\nv 0 1e999 0\nf 1 2 3\n", "obj", "non-finite coordinate");
  expect_bytes_rejected("OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n", "off", "non-finite coordinate at vertex 1 (line 4)");
  expect_bytes_rejected(
      "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex NaN 0 0\nvertex 0 1 0\nendloop\nendfacet\n",
      "stl", "non-finite coordinate");
  // A tiny number is no problem: it underflows to (nearly) zero.
  EXPECT_EQ(load_mesh_from_bytes("v 0 0 1e-400\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "obj").position(0), Vec3(0, 0, 0));
}

TEST(MeshReaders, FaceLineGivingFewerIndicesThanItClaims) {
  expect_bytes_rejected("OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n5 0 1 2\n", "off",
                        "face line claiming 5 vertices but giving 3 (face 0, line 7)");
  expect_bytes_rejected(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n5 0 1 2\n3 0 1 2\n",
      "ply", "face claiming 5 vertices but giving 3");
  expect_bytes_rejected("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1\n3 0 1 2\n", "off", "fewer than 3 coordinates (vertex 2, line 5)");
  expect_bytes_rejected("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "off", "ends after 1 of its 2 faces");
}

TEST(MeshReaders, MessagesDoNotDependOnEarlierReads) {
  const std::string bad_off = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
  std::string first;
  try {
    (void)load_mesh_from_bytes(bad_off, "off");
  } catch (const Error& e) {
    first = e.what();
  }
  EXPECT_NE(first.find("missing vertices"), std::string::npos) << first;
  // Reads of other formats and of an OFF with colours in between change nothing.
  (void)load_mesh_from_bytes(binary_ply(), "ply");
  (void)load_mesh_from_bytes("COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n", "off");
  (void)load_mesh_from_bytes(binary_stl(0.0f), "stl");
  try {
    (void)load_mesh_from_bytes(bad_off, "off");
    ADD_FAILURE() << "bad OFF accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), first);
  }
}

// The unit square as two triangle strips in a binary PLY of the given byte order, with a restart.
std::string tristrip_ply(bool big_endian) {
  std::string s = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                  "element tristrips 1\nproperty list int int vertex_indices\nend_header\n";
  auto put = [&](const void* p, size_t n) {
    std::string b(static_cast<const char*>(p), n);
    if (big_endian) std::reverse(b.begin(), b.end());
    s += b;
  };
  const float v[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 2, 0, 0};
  for (float x : v) put(&x, 4);
  // Strip 0 1 2 3 gives (0 1 2) and (2 1 3); after the restart, 1 4 3 gives (1 4 3).
  const int32_t strip[] = {8, 0, 1, 2, 3, -1, 1, 4, 3};
  for (int32_t i : strip) put(&i, 4);
  return s;
}

TEST(MeshReaders, PlyTriangleStripsBothByteOrdersAndAscii) {
  for (bool big : {false, true}) {
    const Mesh mesh = load_mesh_from_bytes(tristrip_ply(big), "ply", "strips.ply");
    ASSERT_EQ(mesh.num_vertices(), 5) << big;
    ASSERT_EQ(mesh.num_faces(), 3) << big;
    EXPECT_EQ(mesh.face(0), (std::array<int, 3>{0, 1, 2}));
    EXPECT_EQ(mesh.face(1), (std::array<int, 3>{2, 1, 3}));
    EXPECT_EQ(mesh.face(2), (std::array<int, 3>{1, 4, 3}));
    EXPECT_EQ(mesh.position(4), Vec3(2, 0, 0));
  }
  // A strip with a repeated vertex (a joint) drops the degenerate triangles only.
  const Mesh ascii = load_mesh_from_bytes(
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
      "element tristrips 1\nproperty list uint int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n1 1 0.1\n6 0 1 2 2 2 3\n",
      "ply", "strips_ascii.ply");
  EXPECT_EQ(ascii.num_faces(), 1);
  EXPECT_EQ(ascii.position(3), Vec3(1, 1, 0.1));  // double properties keep double precision
  std::string truncated = tristrip_ply(false);
  truncated.resize(truncated.size() - 6);
  expect_bytes_rejected(truncated, "ply", "claims 8 items, more than the data holds");
}

TEST(MeshReaders, LyingCountsAreRefusedBeforeAllocating) {
  expect_bytes_rejected(
      "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n",
      "ply", "truncated");
  std::string stl(80, ' ');
  const uint32_t count = 0xffffffffu;
  stl.append(reinterpret_cast<const char*>(&count), 4);
  expect_bytes_rejected(stl, "stl", "declares 4294967295 triangles");
  expect_bytes_rejected("OFF\n99999999999999999999 1 0\n", "off", "is not a count");
}

TEST(MeshReaders, BinaryStlWhoseHeaderSaysSolid) {
  std::string s = binary_stl(0.0f);
  s.replace(0, 8, "solid xy");
  const Mesh mesh = load_mesh_from_bytes(s, "stl");
  EXPECT_EQ(mesh.num_faces(), 2);
  EXPECT_EQ(mesh.num_vertices(), 4);
}

TEST(MeshReaders, ParseDeadlineGivesResourceExhausted) {
  std::string obj;
  for (int i = 0; i < 10000; ++i) obj += "v " + std::to_string(i) + " 0 0\n";
  obj += "f 1 2 3\n";
  MeshReadLimits limits;
  limits.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  try {
    (void)load_mesh_from_bytes(obj, "obj", "slow.obj", limits);
    ADD_FAILURE() << "deadline ignored";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::resource_exhausted);
    EXPECT_NE(std::string(e.what()).find("parse time budget"), std::string::npos) << e.what();
  }
  EXPECT_EQ(load_mesh_from_bytes(obj, "obj", "slow.obj").num_vertices(), 10000);
}

TEST(MeshReaders, FormatGivenForAnyExtension) {
  const std::string path = write_temp("cube.txt", kCubeQuadsObj);
  expect_rejected(path, "unknown mesh format");
  const Mesh mesh = load_mesh(path, "obj");
  EXPECT_EQ(mesh.num_faces(), 12);
}

}  // namespace
}  // namespace depath
