// SPDX-License-Identifier: MIT
// The triangle mesh that every algorithm of the core works on.
//
// A plain indexed triangle mesh plus the connectivity the decode loop needs, kept in
// compact arrays (CSR one-rings, per-face edge lengths, face neighbours). Built once
// per upload/load; immutable afterwards and safe to share between threads.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <string>
#include <vector>

namespace depath {

using Vec3 = Eigen::Vector3d;

/// Axis-aligned bounding box.
struct BoundingBox {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
  double diagonal() const { return (max - min).norm(); }
};

/// Immutable triangle mesh with precomputed connectivity.
///
/// Vertex ids are 0-based in file order. Faces are triangles (polygons were fan- or
/// ear-triangulated on load). Edges shared by more than two faces (non-manifold) are
/// treated as boundary edges by the neighbour table and reported in `warnings`.
class Mesh {
 public:
  /// Builds the mesh and all connectivity. Throws depath::Error(invalid_argument) for
  /// an empty mesh, no faces, non-finite coordinates or face indices out of range.
  /// Zero-area faces are kept (they carry connectivity) and counted in warnings.
  Mesh(std::vector<Vec3> positions, std::vector<std::array<int, 3>> faces);

  int num_vertices() const { return static_cast<int>(positions_.size()); }
  int num_faces() const { return static_cast<int>(faces_.size()); }

  const std::vector<Vec3>& positions() const { return positions_; }
  const Vec3& position(int v) const { return positions_[v]; }
  const std::vector<std::array<int, 3>>& faces() const { return faces_; }
  const std::array<int, 3>& face(int f) const { return faces_[f]; }

  /// Face across the edge opposite corner k of face f (edge face(f)[k+1], face(f)[k+2]),
  /// or -1 on a boundary or non-manifold edge.
  int face_neighbor(int f, int k) const { return face_neighbors_[f][k]; }
  /// Length of the edge opposite corner k of face f.
  double edge_length(int f, int k) const { return edge_lengths_[f][k]; }
  /// Interior angle at corner k of face f, radians (0 for degenerate faces).
  double corner_angle(int f, int k) const { return corner_angles_[f][k]; }
  /// Face f laid out in its own plane, as {x1, x2, y2}: corner 0 at (0, 0), corner 1 at
  /// (x1, 0), corner 2 at (x2, y2) (from the edge lengths and the angle at corner 0; y2 >= 0).
  /// The back-trace works in this layout, face after face.
  const std::array<double, 3>& face_layout(int f) const { return face_layouts_[f]; }
  /// Unit normal of face f (zero for degenerate faces).
  const Vec3& face_normal(int f) const { return face_normals_[f]; }
  double face_area(int f) const { return face_areas_[f]; }

  /// Faces incident to vertex v (CSR range).
  const int* vertex_faces_begin(int v) const { return vf_index_.data() + vf_offset_[v]; }
  const int* vertex_faces_end(int v) const { return vf_index_.data() + vf_offset_[v + 1]; }
  /// Neighbour vertices of v (CSR range, each once).
  const int* vertex_neighbors_begin(int v) const { return vv_index_.data() + vv_offset_[v]; }
  const int* vertex_neighbors_end(int v) const { return vv_index_.data() + vv_offset_[v + 1]; }

  /// Corner index (0..2) of vertex v in face f, or -1.
  int corner_of(int f, int v) const {
    const auto& t = faces_[f];
    return t[0] == v ? 0 : t[1] == v ? 1 : t[2] == v ? 2 : -1;
  }
  /// A face containing both vertices a and b (an edge), or -1 if they share none.
  int face_with_edge(int a, int b) const;

  /// Connected component of each vertex (via faces); unreferenced vertices get their own.
  int component(int v) const { return component_[v]; }
  int num_components() const { return num_components_; }
  int num_boundary_edges() const { return num_boundary_edges_; }
  int num_nonmanifold_edges() const { return num_nonmanifold_edges_; }
  int num_degenerate_faces() const { return num_degenerate_faces_; }
  int num_unreferenced_vertices() const { return num_unreferenced_vertices_; }
  /// True if vertex v is used by at least one face.
  bool is_referenced(int v) const { return vf_offset_[v + 1] > vf_offset_[v]; }
  const BoundingBox& bounding_box() const { return bbox_; }
  double mean_edge_length() const { return mean_edge_length_; }
  /// Human-readable notes about what was handled (degenerate faces, boundaries, ...).
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  std::vector<Vec3> positions_;
  std::vector<std::array<int, 3>> faces_;
  std::vector<std::array<int, 3>> face_neighbors_;
  std::vector<std::array<double, 3>> edge_lengths_;
  std::vector<std::array<double, 3>> corner_angles_;
  std::vector<std::array<double, 3>> face_layouts_;
  std::vector<Vec3> face_normals_;
  std::vector<double> face_areas_;
  std::vector<int> vf_offset_, vf_index_;
  std::vector<int> vv_offset_, vv_index_;
  std::vector<int> component_;
  int num_components_ = 0;
  int num_boundary_edges_ = 0;
  int num_nonmanifold_edges_ = 0;
  int num_degenerate_faces_ = 0;
  int num_unreferenced_vertices_ = 0;
  double mean_edge_length_ = 0;
  BoundingBox bbox_;
  std::vector<std::string> warnings_;
};

}  // namespace depath
