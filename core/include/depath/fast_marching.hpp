// Fast marching for |grad u| = rho on a triangle mesh, with a reusable workspace.
#pragma once

#include "depath/mesh.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace depath {

/// Precomputed, density-independent update stencils of a mesh: for each vertex the
/// triangle updates it takes part in, with obtuse corners split by unfolding (virtual
/// edges) so that every update is causal. Build once per mesh; share between threads.
class FastMarchingStencils {
 public:
  explicit FastMarchingStencils(const Mesh& mesh);
  const Mesh& mesh() const { return mesh_; }

  /// One update "target from (this vertex, other)", stored at the accepting vertex.
  /// Geometry is kept in float: 28 bytes an update keeps the table cache-resident, and
  /// float's 1e-7 relative error is far below the method's discretisation error.
  struct Update {
    int target;       ///< vertex whose value is updated
    int other;        ///< second support vertex (must be final too), -1 for an edge-only update
    float lambda0;    ///< foot of the perpendicular from target on the support line, as parameter
    float height;     ///< distance from target to the support line
    float inv_len2;   ///< 1 / |other - this|^2 (in the unfolded plane)
    float len_this;   ///< |target - this|, +inf when target-this is no mesh edge
    float len_other;  ///< |target - other|, +inf when target-other is no mesh edge
  };
  const Update* updates_begin(int v) const { return updates_.data() + offset_[v]; }
  const Update* updates_end(int v) const { return updates_.data() + offset_[v + 1]; }
  /// Number of obtuse corners that were split with a virtual edge / left unsplit.
  int num_split_corners() const { return num_split_; }
  int num_unsplit_obtuse_corners() const { return num_unsplit_; }

 private:
  const Mesh& mesh_;
  std::vector<int> offset_;
  std::vector<Update> updates_;
  int num_split_ = 0;
  int num_unsplit_ = 0;
};

/// Fast marching workspace: solves |grad u| = rho from one source vertex, rho per
/// vertex, linear in faces (each update charges a straight segment length * mean of the
/// densities at its ends). Reuses its arrays across runs: no allocation per decode.
///
/// Guarantees: values are finite exactly for the vertices reached; the acceptance order
/// is non-decreasing in u; every accepted vertex other than the source has a mesh
/// neighbour accepted before it with a value not larger than its own.
class FastMarching {
 public:
  explicit FastMarching(const FastMarchingStencils& stencils);

  /// Runs from `source`. If `stop_vertex` >= 0, stops as soon as it and every vertex of
  /// its incident faces are final (what the back-trace from it needs). `density` has one
  /// positive finite value per vertex.
  void run(std::span<const double> density, int source, int stop_vertex = -1);

  /// Value at v: final, tentative (reached but not final) or +infinity.
  double value(int v) const { return u_[v]; }
  const std::vector<double>& values() const { return u_; }
  bool is_final(int v) const { return state_[v] == kFinal; }
  /// Position of v in the acceptance order (0 for the source), or INT32_MAX.
  int32_t order(int v) const { return order_[v]; }
  int num_final() const { return num_final_; }
  const FastMarchingStencils& stencils() const { return stencils_; }

 private:
  static constexpr uint8_t kFar = 0, kTrial = 1, kFinal = 2;
  void push_or_decrease(int v, double value);
  int pop_min();

  const FastMarchingStencils& stencils_;
  std::vector<double> u_;
  std::vector<uint8_t> state_;
  std::vector<int32_t> order_;
  struct HeapEntry {
    double key;  // copy of u_[vertex]: sifting compares without an indirection
    int32_t vertex;
  };
  std::vector<HeapEntry> heap_;    // binary min-heap on key
  std::vector<int32_t> heap_pos_;  // position of each vertex in heap_, or -1
  int num_final_ = 0;
};

}  // namespace depath
