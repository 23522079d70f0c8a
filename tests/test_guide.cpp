// SPDX-License-Identifier: MIT
// The guide channels' geometry (solve/methods/guide.hpp): the vertices near a traced curve,
// found through VertexCubes, against testing every vertex against every chord, on seeded
// random curves over flat, peaked, conical and scanned meshes.
#include "mesh/vertex_cubes.hpp"
#include "solve/methods/guide.hpp"
#include "depath/generators/surfaces.hpp"
#include "depath/io/mesh_reader.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace depath {
namespace {

struct Named {
  std::string name;
  Mesh mesh;
};

std::vector<Named> meshes() {
  std::vector<Named> all;
  all.push_back({"flat grid", make_grid({.n = 41, .half_size = 3.0, .height = GridHeight::flat})});
  all.push_back({"peaks grid", make_grid({.n = 61, .half_size = 3.0, .height = GridHeight::peaks})});
  all.push_back({"cone", make_cone({})});
  all.push_back({"kitten", load_mesh(test::test_data("kitten.off"))});
  return all;
}

Vec3 uniform_in(std::mt19937_64& rng, const Vec3& lo, const Vec3& hi) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return lo + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo);
}

TEST(VertexCubes, VisitsEveryVertexInsideABoxOnce) {
  std::mt19937_64 rng(13);
  for (const Named& m : meshes()) {
    const double edge = m.mesh.mean_edge_length();
    const BoundingBox& box = m.mesh.bounding_box();
    const Vec3 pad = Vec3::Constant(2.0 * edge);
    for (const double side : {0.3 * edge, edge, 3.0 * edge, 0.0}) {
      const VertexCubes cubes(m.mesh, side);
      int answered = 0;
      for (int trial = 0; trial < 200; ++trial) {
        const Vec3 c = uniform_in(rng, box.min - pad, box.max + pad);
        const Vec3 half = uniform_in(rng, Vec3::Zero(), Vec3::Constant(4.0 * edge));
        const Vec3 lo = c - half, hi = c + half;
        std::vector<int> seen(m.mesh.num_vertices(), 0);
        if (!cubes.for_each_in_box(lo, hi, [&](int v) { ++seen[v]; })) {
          EXPECT_EQ(std::count(seen.begin(), seen.end(), 0), m.mesh.num_vertices()) << "called on refusal";
          continue;
        }
        ++answered;
        for (int v = 0; v < m.mesh.num_vertices(); ++v) {
          const Vec3& p = m.mesh.position(v);
          const bool inside = (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
          ASSERT_LE(seen[v], 1) << m.name << ": vertex " << v << " visited twice";
          if (inside) {
            ASSERT_EQ(seen[v], 1) << m.name << ", side " << side << ": vertex " << v << " missed";
          }
        }
      }
      // Side 0 means unit cubes: as many as the mesh's extent, all answered on these meshes.
      EXPECT_GT(answered, 100) << m.name << ", side " << side;
    }
    // A box over the whole mesh with cubes far smaller than the edges spans more cubes than
    // there are vertices: refused.
    const VertexCubes fine(m.mesh, 0.01 * edge);
    EXPECT_FALSE(fine.for_each_in_box(box.min - pad, box.max + pad, [](int) {})) << m.name;
  }
}

// Every vertex against every chord, in chord order.
std::vector<int> first_close_chord_by_scan(const Mesh& mesh, const std::vector<Vec3>& points, int last,
                                           double width) {
  std::vector<int> first(mesh.num_vertices(), std::numeric_limits<int>::max());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.position(v);
    for (int i = 1; i <= last && first[v] == std::numeric_limits<int>::max(); ++i) {
      const Vec3& a = points[i - 1];
      const Vec3 ab = points[i] - a;
      const double l2 = ab.squaredNorm();
      const double u = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
      if ((a + u * ab - p).squaredNorm() <= width * width) first[v] = i;
    }
  }
  return first;
}

TEST(GuideChannels, FirstCloseChordMatchesTestingEveryVertex) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const Named& m : meshes()) {
    const double edge = m.mesh.mean_edge_length();
    const VertexCubes cubes(m.mesh, 1.5 * edge);
    for (int trial = 0; trial < 12; ++trial) {
      // A random walk over the mesh's vertices, each point off its vertex by up to 0.3 edges,
      // with now and then a repeated point (a chord of length 0) or a jump to any vertex (a
      // long chord, whose box may span more cubes than the mesh has vertices).
      std::uniform_int_distribution<int> any_vertex(0, m.mesh.num_vertices() - 1);
      const auto off = [&](int v) {
        return Vec3(m.mesh.position(v) +
                    0.3 * edge * uniform_in(rng, Vec3::Constant(-1.0), Vec3::Constant(1.0)));
      };
      int at = any_vertex(rng);
      std::vector<Vec3> points{off(at)};
      const int chords = 20 + static_cast<int>(unit(rng) * 300);
      for (int i = 0; i < chords; ++i) {
        const double kind = unit(rng);
        if (kind < 0.05) {
          points.push_back(points.back());
          continue;
        }
        if (kind < 0.08) {
          at = any_vertex(rng);
        } else {
          const int* faces = m.mesh.vertex_faces_begin(at);
          const int degree = static_cast<int>(m.mesh.vertex_faces_end(at) - faces);
          const auto& corners = m.mesh.face(faces[static_cast<int>(unit(rng) * degree) % degree]);
          at = corners[static_cast<int>(unit(rng) * 3) % 3];
        }
        points.push_back(off(at));
      }
      const double width = (0.5 + 2.5 * unit(rng)) * edge;
      const int last = 1 + static_cast<int>(unit(rng) * chords);
      const std::vector<int> expected = first_close_chord_by_scan(m.mesh, points, last, width);
      const std::vector<int> got = first_close_chord(m.mesh, cubes, points, last, width);
      const auto near = std::count_if(expected.begin(), expected.end(),
                                      [](int i) { return i != std::numeric_limits<int>::max(); });
      EXPECT_GT(near, 0) << m.name << " trial " << trial << ": a case without a near vertex checks little";
      ASSERT_EQ(got, expected) << m.name << " trial " << trial;
    }
  }
}

}  // namespace
}  // namespace depath
