// SPDX-License-Identifier: MIT
#include "depath/io/mesh_reader.hpp"

#include "depath/util/error.hpp"
#include "io/header_check.hpp"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <mutex>
#include <sstream>

namespace depath {
namespace {

using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::VertexHandle;

// Collects OpenMesh's parse into a plain polygon soup: no manifold checks, no vertex
// reordering, so vertex ids stay in file order and nothing the file holds is dropped
// silently (OpenMesh's own mesh kernels refuse non-manifold faces).
class SoupImporter final : public OpenMesh::IO::BaseImporter {
 public:
  std::vector<Vec3> positions;
  std::vector<std::vector<int>> polygons;
  int bad_face_refs = 0;

  VertexHandle add_vertex(const OpenMesh::Vec3f& p) override { return add_vertex(OpenMesh::Vec3d(p)); }
  VertexHandle add_vertex(const OpenMesh::Vec3d& p) override {
    positions.emplace_back(p[0], p[1], p[2]);
    return VertexHandle(static_cast<int>(positions.size()) - 1);
  }
  VertexHandle add_vertex() override { return add_vertex(OpenMesh::Vec3d(0, 0, 0)); }
  FaceHandle add_face(const VHandles& handles) override {
    std::vector<int> polygon;
    polygon.reserve(handles.size());
    for (const auto& h : handles) {
      if (!h.is_valid() || h.idx() >= static_cast<int>(positions.size())) {
        ++bad_face_refs;
        return FaceHandle();
      }
      polygon.push_back(h.idx());
    }
    polygons.push_back(std::move(polygon));
    return FaceHandle(static_cast<int>(polygons.size()) - 1);
  }
  void set_point(VertexHandle vh, const OpenMesh::Vec3f& p) override {
    if (vh.is_valid() && vh.idx() < static_cast<int>(positions.size())) positions[vh.idx()] = Vec3(p[0], p[1], p[2]);
  }
  size_t n_vertices() const override { return positions.size(); }
  size_t n_faces() const override { return polygons.size(); }
  size_t n_edges() const override { return 0; }

  // Attributes we do not use.
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<OpenMesh::Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(VertexHandle, const OpenMesh::Vec3d&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec4f&) override {}
  void set_texcoord(VertexHandle, const OpenMesh::Vec2f&) override {}
  void set_status(VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const OpenMesh::Vec2f&) override {}
  void set_texcoord(VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const OpenMesh::Vec3f&) override {}
  void set_status(HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4f&) override {}
  void set_status(OpenMesh::EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(FaceHandle, const OpenMesh::Vec3d&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec4f&) override {}
  void set_status(FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
};

// OpenMesh's reader registry is global and its readers keep per-call state in some
// versions: serialise parsing (it is fast next to everything else we do with a mesh).
std::mutex& reader_mutex() {
  static std::mutex m;
  return m;
}

// Fan triangulation keeps file order and needs no geometry; meshes with polygons are
// rare in this domain and usually convex (quads).
std::vector<std::array<int, 3>> triangulate(const std::vector<std::vector<int>>& polygons) {
  std::vector<std::array<int, 3>> tris;
  tris.reserve(polygons.size());
  for (const auto& p : polygons) {
    for (size_t i = 1; i + 1 < p.size(); ++i) tris.push_back({p[0], p[i], p[i + 1]});
  }
  return tris;
}

}  // namespace

std::string mesh_format_from_path(std::string_view path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  std::string ext;
  if (dot != std::string_view::npos && (slash == std::string_view::npos || dot > slash))
    ext = std::string(path.substr(dot + 1));
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == "obj" || ext == "off" || ext == "ply" || ext == "stl") return ext;
  throw Error(ErrorCode::invalid_argument, "unknown mesh format for '" + std::string(path) +
                                               "': expected a .obj, .off, .ply or .stl file");
}

Mesh load_mesh_from_bytes(std::string_view bytes, std::string_view format, std::string_view name) {
  std::string fmt(format);
  std::transform(fmt.begin(), fmt.end(), fmt.begin(), [](unsigned char c) { return std::tolower(c); });
  if (fmt != "obj" && fmt != "off" && fmt != "ply" && fmt != "stl")
    throw Error(ErrorCode::invalid_argument,
                "unknown mesh format '" + fmt + "' for " + std::string(name) + ": expected obj, off, ply or stl");
  const std::string label = std::string(name);
  if (bytes.empty()) throw Error(ErrorCode::invalid_argument, "mesh " + label + " is empty (0 bytes)");

  check_declared_sizes(bytes, fmt, label);
  SoupImporter importer;
  {
    std::lock_guard lock(reader_mutex());
    static const bool quiet = [] {
      // OpenMesh prints its own parse complaints; our error messages replace them.
      omerr().disable();
      omlog().disable();
      omout().disable();
      return true;
    }();
    (void)quiet;
    std::istringstream stream{std::string(bytes), std::ios::in | std::ios::binary};
    OpenMesh::IO::Options options;
    if (fmt == "stl" && bytes.substr(0, 5) != "solid") options += OpenMesh::IO::Options::Binary;
    if (fmt == "ply" && bytes.find("format ascii") == std::string_view::npos)
      options += OpenMesh::IO::Options::Binary;
    bool ok = false;
    try {
      ok = OpenMesh::IO::IOManager().read(stream, "." + fmt, importer, options);
    } catch (const std::exception& e) {
      throw Error(ErrorCode::invalid_argument, "mesh " + label + " does not parse as " + fmt + ": " + e.what());
    }
    if (!ok)
      throw Error(ErrorCode::invalid_argument, "mesh " + label + " does not parse as " + fmt);
  }
  if (importer.bad_face_refs > 0)
    throw Error(ErrorCode::invalid_argument, "mesh " + label + " has " + std::to_string(importer.bad_face_refs) +
                                                 " face(s) referring to missing vertices");
  if (importer.positions.empty())
    throw Error(ErrorCode::invalid_argument,
                "mesh " + label + " has no vertices (an empty mesh, or the file does not parse as " + fmt + ")");
  if (importer.polygons.empty())
    throw Error(ErrorCode::invalid_argument, "mesh " + label + " has no faces");
  try {
    return Mesh(std::move(importer.positions), triangulate(importer.polygons));
  } catch (const Error& e) {
    throw Error(e.code(), label + ": " + e.what());
  }
}

Mesh load_mesh(const std::string& path) {
  const std::string fmt = mesh_format_from_path(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorCode::invalid_argument, "cannot open mesh file '" + path + "'");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return load_mesh_from_bytes(bytes, fmt, "'" + path + "'");
}

}  // namespace depath
