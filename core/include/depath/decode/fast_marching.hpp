// SPDX-License-Identifier: MIT
// Fast marching for |grad u| = rho on a triangle mesh, with a reusable workspace.
//
// Inputs: a mesh (through its density-independent stencils), one positive density per
// vertex (or its logarithm), a source vertex and optionally a vertex to stop at.
// Outputs: u, the weighted geodesic distance from the source, at every vertex reached.
// Guarantees: first-order upwind updates, causal on obtuse triangles by unfolding; values
// finite exactly for the vertices reached; no allocation per run once the workspace has
// grown. Cost: O(V) per run (an untidy bucket queue, bucket_queue.hpp).
// Reference: R. Kimmel, J. A. Sethian, "Computing geodesic paths on manifolds", PNAS 95
// (1998) — fast marching on triangulated domains, obtuse angles by unfolding.
#pragma once

#include "depath/decode/bucket_queue.hpp"
#include "depath/mesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace depath {

/// Precomputed, density-independent update stencils of a mesh: for each vertex the
/// triangle updates it takes part in, with obtuse corners split by unfolding (virtual
/// edges) so that every update is causal. Build once per mesh; share between threads (a
/// server keeps them with its cached meshes: building costs up to several full marches).
/// Holds a reference to the mesh, which must outlive it.
class FastMarchingStencils {
 public:
  explicit FastMarchingStencils(const Mesh& mesh);
  const Mesh& mesh() const { return mesh_; }
  /// Heap memory of the tables, in bytes (for cache budgets).
  uint64_t memory_bytes() const;
  /// Stencil tables built in this process so far (all threads): lets tests and benchmarks
  /// check that a cached table spared a rebuild, without a clock.
  static uint64_t builds();

  /// The updates an accepting vertex x triggers, grouped by target c: one straight edge
  /// candidate x -> c (shortest |c - x| over the faces, +inf when c-x is no mesh edge) and
  /// the triangle updates "c from (x, other)", two to a record so that both are computed at
  /// once (as the two lanes of one vector). A target with more than two triangle
  /// updates (a split obtuse corner) continues in the next record, whose `len` is +inf; an
  /// unused slot names the sentinel vertex num_vertices(), which is never final. The edge
  /// candidate other -> c is not repeated here: it was applied when `other` was accepted and
  /// always dominates. Geometry is kept in float: the table stays cache-resident, and
  /// float's 1e-7 relative error is far below the method's discretisation error.
  struct Update {
    int32_t target;     ///< vertex whose value is updated
    float len;          ///< |target - x|, +inf when target-x is no mesh edge (or a continuation)
    int32_t other[2];   ///< second support vertex of each triangle update (must be final too)
    float lambda0[2];   ///< foot of the perpendicular from target on the support line, as parameter
    float height[2];    ///< distance from target to the support line
    float inv_len2[2];  ///< 1 / |other - x|^2 (in the unfolded plane)
  };
  const Update* updates_begin(int v) const { return updates_.data() + offset_[v]; }
  const Update* updates_end(int v) const { return updates_.data() + offset_[v + 1]; }
  /// A vertex's first kMaskedRecords records are tracked by bit in a mask of those whose
  /// target is not final yet, so that the march visits only those instead of testing each
  /// target (a branch the predictor mostly misses on DE's random densities); the records
  /// after them (vertices of very high degree) are tested one by one.
  static constexpr int kMaskedRecords = 64;
  /// The vertices with records targeting c, each with the bits of those records.
  struct Incoming {
    int32_t vertex;
    uint64_t records;
  };
  const Incoming* incoming_begin(int c) const { return incoming_.data() + in_offset_[c]; }
  const Incoming* incoming_end(int c) const { return incoming_.data() + in_offset_[c + 1]; }
  /// Per vertex, the bits of its masked records (all of its first kMaskedRecords).
  std::span<const uint64_t> record_bits() const { return record_bits_; }
  /// Number of obtuse corners that were split with a virtual edge / left unsplit.
  int num_split_corners() const { return num_split_; }
  int num_unsplit_obtuse_corners() const { return num_unsplit_; }

 private:
  void build_incoming();

  const Mesh& mesh_;
  std::vector<int> offset_;
  std::vector<Update> updates_;
  std::vector<int> in_offset_;
  std::vector<Incoming> incoming_;
  std::vector<uint64_t> record_bits_;
  int num_split_ = 0;
  int num_unsplit_ = 0;
};

/// Fast marching workspace: solves |grad u| = rho from one source vertex, rho per
/// vertex, linear in faces (each update charges a straight segment length * mean of the
/// densities at its ends). Reuses its arrays across runs: no allocation per decode.
///
/// Guarantees: values are finite exactly for the vertices reached; the acceptance order
/// is non-decreasing in u up to a relative 2^-8 (the queue's bucket width); every
/// accepted vertex other than the source has a mesh neighbour accepted before it with a
/// value not larger than its own.
class FastMarching {
 public:
  explicit FastMarching(const FastMarchingStencils& stencils);

  /// Runs from `source`. If `stop_vertex` >= 0, stops once it is final, every vertex whose
  /// value is below its own is final, and so is each pair of neighbours across a corner
  /// wider than a right angle of which one is: what the back-trace's first step from it
  /// reads (on random densities the traced paths are a full march's). `density` has one
  /// positive finite value per vertex.
  void run(std::span<const double> density, int source, int stop_vertex = -1);

  /// Same with the density given as logarithms: vertex v's density is
  /// clamp(exp(log_density[v]), DBL_MIN, DBL_MAX) (within 1 ulp; NaN counts as -inf), 0
  /// past the end of the span.
  void run_log(std::span<const double> log_density, int source, int stop_vertex = -1);

  /// Value at v: final, tentative (reached but not final) or +infinity.
  double value(int v) const { return u_[v]; }
  std::span<const double> values() const { return {u_.data(), u_.size() - 1}; }
  bool is_final(int v) const { return state_[v] == kFinal; }
  /// Position of v in the acceptance order (0 for the source), or INT32_MAX.
  int32_t order(int v) const { return order_[v]; }
  int num_final() const { return num_final_; }
  /// The final vertices in acceptance order.
  std::span<const int32_t> accepted() const { return {accepted_.data(), size_t(num_final_)}; }
  const FastMarchingStencils& stencils() const { return stencils_; }
  /// Vertices made final by every run in this process so far (all threads): lets a
  /// benchmark report how much of the mesh a whole DE run's decodes march, which grows as
  /// the population evolves, without a hook in the solver.
  static uint64_t vertices_made_final();

  /// A vertex's state during a run: not final (not reached or tentative), final.
  static constexpr uint8_t kOpen = 0, kFinal = 1;

 private:
  // `density` has num_vertices() + 1 entries (the sentinel's last; never used as a cost).
  void march(const double* density, int source, int stop_vertex);
  void accept(int x, const double* density);
  void gather_wide_corners(int t);
  void reset();
  void push_or_decrease(int v, double value);

  const FastMarchingStencils& stencils_;
  std::vector<double> u_;  // one per vertex, then the sentinel's (+inf)
  std::vector<uint8_t> state_;
  std::vector<uint64_t> open_records_;  // per vertex: its masked records whose target is not final
  std::vector<int32_t> order_;
  std::vector<int32_t> accepted_;  // final vertices in acceptance order
  std::vector<double> rho_;        // the run's densities, then the sentinel's (0)
  BucketQueue queue_;              // the tentative vertices
  int num_final_ = 0;
  std::vector<std::array<int32_t, 2>> wide_corners_;  // the stop vertex's: see march()
};

}  // namespace depath
