// SPDX-License-Identifier: MIT
#include "depath/decode/fast_marching.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace depath {
namespace {

using Vec2 = Eigen::Vector2d;

constexpr int next(int k) { return k == 2 ? 0 : k + 1; }
constexpr int prev(int k) { return k == 0 ? 2 : k - 1; }
inline double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// How far the unfolding walks across neighbouring faces looking for a vertex that
// splits an obtuse corner into two acute ones. Kimmel & Sethian show a few steps suffice
// on reasonable meshes; slivers may need more, beyond which we keep the plain update.
constexpr int kMaxUnfoldSteps = 12;
// Corners a hair above 90 degrees are numerically fine as they are.
constexpr double kObtuseCos = -1e-9;

std::atomic<uint64_t> stencil_builds{0};

// One triangle update "c from (x, other)" as the march uses it (see FastMarchingStencils::Update).
struct Tri {
  int32_t other;
  float lambda0, height, inv_len2;
};

// A triangle update "target c from supports x, y", all in one (unfolded) plane, c at the origin.
struct PlanarUpdate {
  int c, x, y;
  Vec2 px, py;
  bool x_is_neighbor = true;  // false for an unfolded vertex: c-x is no mesh edge
  bool y_is_neighbor = true;
};

// Places the third vertex of a face across the edge (pa, pb), on the side away from `away`.
Vec2 unfold_vertex(const Vec2& pa, const Vec2& pb, double len_a, double len_b, const Vec2& away) {
  const Vec2 e = pb - pa;
  const double len = e.norm();
  const Vec2 dir = e / len;
  const Vec2 normal(-dir.y(), dir.x());
  const double along = (len_a * len_a - len_b * len_b + len * len) / (2.0 * len);
  const double off = std::sqrt(std::max(0.0, len_a * len_a - along * along));
  const double side = normal.dot(away - pa) > 0 ? -1.0 : 1.0;
  return pa + along * dir + side * off * normal;
}

}  // namespace

FastMarchingStencils::FastMarchingStencils(const Mesh& mesh) : mesh_(mesh) {
  const int nv = mesh.num_vertices();
  std::vector<PlanarUpdate> planar;
  std::vector<std::pair<int, int>> edge_only;  // (x, c): edges of degenerate faces
  planar.reserve(3 * mesh.num_faces() + 64);

  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto& t = mesh.face(f);
    if (mesh.face_area(f) <= 0.0 || mesh.face_normal(f).squaredNorm() == 0.0) {
      for (int k = 0; k < 3; ++k) {
        edge_only.emplace_back(t[k], t[next(k)]);
        edge_only.emplace_back(t[next(k)], t[k]);
      }
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const int c = t[k], a = t[next(k)], b = t[prev(k)];
      const double lca = mesh.edge_length(f, prev(k));  // edge opposite b: (c, a)
      const double lcb = mesh.edge_length(f, next(k));  // edge opposite a: (c, b)
      const double angle = mesh.corner_angle(f, k);
      const Vec2 pa(lca, 0.0);
      const Vec2 pb(lcb * std::cos(angle), lcb * std::sin(angle));
      if (std::cos(angle) >= kObtuseCos) {
        planar.push_back({c, a, b, pa, pb});
        continue;
      }
      // Obtuse at c: unfold faces across the opposite edge until a vertex d lies in the
      // cone where both (c; a, d) and (c; d, b) are acute at c.
      int face = f, ea = a, eb = b;
      Vec2 qa = pa, qb = pb;
      bool split = false;
      for (int step = 0; step < kMaxUnfoldSteps; ++step) {
        const int ka = mesh.corner_of(face, ea), kb = mesh.corner_of(face, eb);
        const int kd = 3 - ka - kb;
        const int g = mesh.face_neighbor(face, kd);
        if (g < 0 || mesh.face_area(g) <= 0.0) break;
        const int ga = mesh.corner_of(g, ea), gb = mesh.corner_of(g, eb);
        if (ga < 0 || gb < 0) break;
        const int gd = 3 - ga - gb;
        const int d = mesh.face(g)[gd];
        if (d == c) break;
        // |ea d| is the edge of g opposite eb, |eb d| the one opposite ea.
        const Vec2 pd = unfold_vertex(qa, qb, mesh.edge_length(g, gb), mesh.edge_length(g, ga), Vec2(0, 0));
        const bool past_a = pd.dot(pa) > 0.0;  // angle(a, c, d) acute
        const bool past_b = pd.dot(pb) > 0.0;  // angle(d, c, b) acute
        if (past_a && past_b) {
          planar.push_back({c, a, d, pa, pd, true, false});
          planar.push_back({c, d, b, pd, pb, false, true});
          split = true;
          break;
        }
        // Keep unfolding across the edge of g that the acute cone still crosses.
        if (!past_a) {  // d lies beyond the cone on b's side: the cone crosses edge (ea, d)
          eb = d;
          qb = pd;
        } else {  // d lies beyond the cone on a's side: the cone crosses edge (d, eb)
          ea = d;
          qa = pd;
        }
        face = g;
      }
      if (split) {
        ++num_split_;
      } else {
        ++num_unsplit_;
        planar.push_back({c, a, b, pa, pb});
      }
    }
  }

  // Each planar update is triggered by either support vertex (whichever is accepted
  // last), so it is stored at both; then grouped by accepting vertex (CSR) and, within a
  // vertex, by target (stable: the face order is kept inside a group).
  // The straight "edge" update along c-x is only a surface path when c-x is a mesh edge;
  // an infinite length disables it for unfolded vertices, so every vertex takes its first
  // value from a mesh neighbour (the back-trace relies on that).
  constexpr float kNoEdge = std::numeric_limits<float>::infinity();
  struct Raw {
    int x, c;
    float len;  // |c - x| or kNoEdge
    bool has_tri;
    Tri tri;
  };
  std::vector<Raw> raw;
  std::vector<Tri> tris;  // the triangle updates of one (x, target)
  raw.reserve(2 * planar.size() + edge_only.size());
  auto store = [&](int c, int x, int y, const Vec2& px, const Vec2& py, bool x_near) {
    const Vec2 e = py - px;
    const double len2 = e.squaredNorm();
    Raw r;
    r.x = x;
    r.c = c;
    r.len = x_near ? float(px.norm()) : kNoEdge;
    r.has_tri = true;
    r.tri.other = y;
    r.tri.inv_len2 = len2 > 0 ? float(1.0 / len2) : 0.0f;
    r.tri.lambda0 = len2 > 0 ? float(-px.dot(e) / len2) : 0.0f;
    r.tri.height = len2 > 0 ? float(std::abs(cross2(e, -px)) / std::sqrt(len2)) : 0.0f;
    raw.push_back(r);
  };
  for (const auto& p : planar) {
    store(p.c, p.x, p.y, p.px, p.py, p.x_is_neighbor);
    store(p.c, p.y, p.x, p.py, p.px, p.y_is_neighbor);
  }
  for (const auto& [x, c] : edge_only) {
    Raw r{};
    r.x = x;
    r.c = c;
    r.len = float((mesh.position(c) - mesh.position(x)).norm());
    r.has_tri = false;
    raw.push_back(r);
  }
  // The order of a stable sort by (x, c), at linear cost (the merge sort was a fifth of the
  // build): a counting sort by x, then an insertion sort by c within each vertex's few entries.
  {
    std::vector<int> start(nv + 1, 0);
    for (const Raw& r : raw) ++start[r.x + 1];
    for (int x = 0; x < nv; ++x) start[x + 1] += start[x];
    std::vector<Raw> sorted(raw.size());
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (const Raw& r : raw) sorted[fill[r.x]++] = r;
    for (int x = 0; x < nv; ++x) {
      for (int i = start[x] + 1; i < start[x + 1]; ++i) {
        const Raw r = sorted[i];
        int j = i - 1;
        for (; j >= start[x] && sorted[j].c > r.c; --j) sorted[j + 1] = sorted[j];  // strict: stable
        sorted[j + 1] = r;
      }
    }
    raw.swap(sorted);
  }

  // Records of at most two triangle updates each, one target after another; the first
  // record of a target carries its edge candidate.
  const int32_t sentinel = nv;
  offset_.assign(nv + 1, 0);
  updates_.clear();
  updates_.reserve(raw.size() / 2 + nv);
  size_t k = 0;
  for (int x = 0; x < nv; ++x) {
    offset_[x] = static_cast<int>(updates_.size());
    while (k < raw.size() && raw[k].x == x) {
      const int c = raw[k].c;
      float len = kNoEdge;
      tris.clear();
      for (; k < raw.size() && raw[k].x == x && raw[k].c == c; ++k) {
        len = std::min(len, raw[k].len);
        if (raw[k].has_tri) tris.push_back(raw[k].tri);
      }
      for (size_t i = 0; i == 0 || i < tris.size(); i += 2) {
        Update u{};
        u.target = c;
        u.len = i == 0 ? len : kNoEdge;
        for (int slot = 0; slot < 2; ++slot) {
          const bool used = i + slot < tris.size();
          u.other[slot] = used ? tris[i + slot].other : sentinel;
          u.lambda0[slot] = used ? tris[i + slot].lambda0 : 0.0f;
          u.height[slot] = used ? tris[i + slot].height : 0.0f;
          u.inv_len2[slot] = used ? tris[i + slot].inv_len2 : 0.0f;
        }
        updates_.push_back(u);
      }
    }
  }
  offset_[nv] = static_cast<int>(updates_.size());
  build_incoming();
  stencil_builds.fetch_add(1, std::memory_order_relaxed);
}

// For each target c, the vertices x whose first 64 records include some targeting c, with
// those records' bits: a target's records are consecutive in x's list, so each (x, c) is one
// run of records and one entry.
void FastMarchingStencils::build_incoming() {
  const int nv = mesh_.num_vertices();
  record_bits_.assign(nv, 0);
  in_offset_.assign(nv + 1, 0);
  const auto runs = [this](int x, auto&& visit) {
    const int count = std::min(offset_[x + 1] - offset_[x], kMaskedRecords);
    const Update* g = updates_.data() + offset_[x];
    for (int i = 0; i < count; ++i) visit(g[i].target, i, i == 0 || g[i].target != g[i - 1].target);
  };
  for (int x = 0; x < nv; ++x) {
    runs(x, [&](int c, int, bool first) { in_offset_[c + 1] += first; });
  }
  for (int c = 0; c < nv; ++c) in_offset_[c + 1] += in_offset_[c];
  incoming_.assign(in_offset_[nv], Incoming{});
  std::vector<int> fill(in_offset_.begin(), in_offset_.end() - 1);
  for (int x = 0; x < nv; ++x) {
    runs(x, [&](int c, int i, bool first) {
      if (first) incoming_[fill[c]++] = Incoming{x, 0};
      incoming_[fill[c] - 1].records |= uint64_t{1} << i;
      record_bits_[x] |= uint64_t{1} << i;
    });
  }
}

uint64_t FastMarchingStencils::memory_bytes() const {
  return sizeof(*this) + (offset_.capacity() + in_offset_.capacity()) * sizeof(int) +
         updates_.capacity() * sizeof(Update) + incoming_.capacity() * sizeof(Incoming) +
         record_bits_.capacity() * sizeof(uint64_t);
}

uint64_t FastMarchingStencils::builds() { return stencil_builds.load(std::memory_order_relaxed); }

}  // namespace depath
