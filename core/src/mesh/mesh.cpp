// SPDX-License-Identifier: MIT
#include "depath/mesh/mesh.hpp"

#include "depath/util/error.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace depath {
namespace {

constexpr int next(int k) { return k == 2 ? 0 : k + 1; }
constexpr int prev(int k) { return k == 0 ? 2 : k - 1; }

// Union-find with path halving, for connected components.
struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
};

// Builds a CSR table from (key, value) pairs.
void build_csr(int num_keys, std::vector<std::pair<int, int>>& pairs, std::vector<int>& offset,
               std::vector<int>& index) {
  std::sort(pairs.begin(), pairs.end());
  offset.assign(num_keys + 1, 0);
  for (const auto& [key, value] : pairs) ++offset[key + 1];
  std::partial_sum(offset.begin(), offset.end(), offset.begin());
  index.resize(pairs.size());
  for (size_t i = 0; i < pairs.size(); ++i) index[i] = pairs[i].second;
}

}  // namespace

Mesh::Mesh(std::vector<Vec3> positions, std::vector<std::array<int, 3>> faces)
    : positions_(std::move(positions)) {
  const int nv = static_cast<int>(positions_.size());
  if (nv == 0) throw Error(ErrorCode::invalid_argument, "mesh is empty: it has no vertices");
  for (int v = 0; v < nv; ++v) {
    if (!positions_[v].allFinite())
      throw Error(ErrorCode::invalid_argument,
                  "mesh has a non-finite coordinate at vertex " + std::to_string(v));
  }
  int collapsed = 0;
  faces_.reserve(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto& t = faces[f];
    for (int v : t) {
      if (v < 0 || v >= nv)
        throw Error(ErrorCode::invalid_argument, "mesh face " + std::to_string(f) + " refers to vertex " +
                                                     std::to_string(v) + ", but the mesh has " +
                                                     std::to_string(nv) + " vertices");
    }
    // A face that repeats a vertex has no interior and breaks corner lookups: drop it.
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      ++collapsed;
      continue;
    }
    faces_.push_back(t);
  }
  if (faces_.empty()) throw Error(ErrorCode::invalid_argument, "mesh has no faces");
  const int nf = num_faces();

  // Geometry per face.
  edge_lengths_.resize(nf);
  corner_angles_.resize(nf);
  face_normals_.resize(nf);
  face_areas_.resize(nf);
  double edge_sum = 0.0;
  double max_edge = 0.0;
  for (int f = 0; f < nf; ++f) {
    const auto& t = faces_[f];
    for (int k = 0; k < 3; ++k) {
      const double len = (positions_[t[next(k)]] - positions_[t[prev(k)]]).norm();
      edge_lengths_[f][k] = len;
      edge_sum += len;
      max_edge = std::max(max_edge, len);
      const Vec3 a = positions_[t[next(k)]] - positions_[t[k]];
      const Vec3 b = positions_[t[prev(k)]] - positions_[t[k]];
      corner_angles_[f][k] = std::atan2(a.cross(b).norm(), a.dot(b));
    }
    const Vec3 n = (positions_[t[1]] - positions_[t[0]]).cross(positions_[t[2]] - positions_[t[0]]);
    face_areas_[f] = 0.5 * n.norm();
    face_normals_[f] = n.norm() > 0 ? Vec3(n.normalized()) : Vec3(Vec3::Zero());
  }
  mean_edge_length_ = edge_sum / (3.0 * nf);
  // Zero-area faces (relative to the mesh scale) are kept for connectivity and counted.
  const double area_eps = 1e-12 * max_edge * max_edge;
  for (int f = 0; f < nf; ++f) {
    if (face_areas_[f] <= area_eps) {
      ++num_degenerate_faces_;
      face_normals_[f] = Vec3::Zero();
      corner_angles_[f] = {0.0, 0.0, 0.0};
    }
  }
  face_layouts_.resize(nf);
  for (int f = 0; f < nf; ++f) {
    const double l01 = edge_lengths_[f][2], l02 = edge_lengths_[f][1], angle = corner_angles_[f][0];
    face_layouts_[f] = {l01, l02 * std::cos(angle), l02 * std::sin(angle)};
  }

  // Face neighbours via sorted undirected edges; > 2 faces on an edge = non-manifold.
  struct EdgeRef {
    int64_t key;
    int corner;  // f * 3 + k
  };
  std::vector<EdgeRef> edges;
  edges.reserve(3 * nf);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = faces_[f][next(k)], b = faces_[f][prev(k)];
      edges.push_back({int64_t(std::min(a, b)) * nv + std::max(a, b), 3 * f + k});
    }
  }
  std::sort(edges.begin(), edges.end(),
            [](const EdgeRef& x, const EdgeRef& y) { return x.key != y.key ? x.key < y.key : x.corner < y.corner; });
  face_neighbors_.assign(nf, {-1, -1, -1});
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    const size_t count = j - i;
    if (count == 1) {
      ++num_boundary_edges_;
    } else if (count == 2) {
      const int c0 = edges[i].corner, c1 = edges[i + 1].corner;
      face_neighbors_[c0 / 3][c0 % 3] = c1 / 3;
      face_neighbors_[c1 / 3][c1 % 3] = c0 / 3;
    } else {
      ++num_nonmanifold_edges_;
    }
    i = j;
  }

  // Vertex -> faces and vertex -> vertices (CSR).
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(3 * nf);
  for (int f = 0; f < nf; ++f)
    for (int v : faces_[f]) pairs.emplace_back(v, f);
  build_csr(nv, pairs, vf_offset_, vf_index_);
  pairs.clear();
  pairs.reserve(6 * nf);
  for (const auto& t : faces_) {
    for (int k = 0; k < 3; ++k) {
      pairs.emplace_back(t[k], t[next(k)]);
      pairs.emplace_back(t[next(k)], t[k]);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  build_csr(nv, pairs, vv_offset_, vv_index_);

  // Components and unreferenced vertices.
  DisjointSets sets(nv);
  for (const auto& t : faces_) {
    sets.unite(t[0], t[1]);
    sets.unite(t[1], t[2]);
  }
  component_.assign(nv, -1);
  std::vector<int> root_id(nv, -1);
  for (int v = 0; v < nv; ++v) {
    const int r = sets.find(v);
    if (root_id[r] < 0) root_id[r] = num_components_++;
    component_[v] = root_id[r];
    if (!is_referenced(v)) ++num_unreferenced_vertices_;
  }

  bbox_.min = bbox_.max = positions_[0];
  for (const auto& p : positions_) {
    bbox_.min = bbox_.min.cwiseMin(p);
    bbox_.max = bbox_.max.cwiseMax(p);
  }

  auto note = [this](int count, const std::string& what) {
    if (count > 0) warnings_.push_back(std::to_string(count) + " " + what);
  };
  note(collapsed, "face(s) repeating a vertex were dropped");
  note(num_degenerate_faces_, "zero-area face(s) kept for connectivity (paths do not cross them)");
  note(num_unreferenced_vertices_, "vertex(es) used by no face (unreachable)");
  note(num_nonmanifold_edges_, "non-manifold edge(s) (more than two faces) treated as boundary");
  note(num_boundary_edges_, "boundary edge(s)");
  const int face_components = num_components_ - num_unreferenced_vertices_;
  if (face_components > 1)
    warnings_.push_back(std::to_string(face_components) + " connected components");
}

int Mesh::face_with_edge(int a, int b) const {
  for (const int* f = vertex_faces_begin(a); f != vertex_faces_end(a); ++f) {
    if (corner_of(*f, b) >= 0) return *f;
  }
  return -1;
}

}  // namespace depath
