// Decoding a density field into a path: fast marching from the source, then back-tracing.
#pragma once

#include "depath/decode/fast_marching.hpp"
#include "depath/mesh/surface_path.hpp"

#include <span>
#include <vector>

namespace depath {

/// Per-thread decoder with its own fast-marching workspace (no allocation per decode).
class PathDecoder {
 public:
  explicit PathDecoder(const FastMarchingStencils& stencils);

  /// Decodes a per-vertex density (> 0) into the path source -> target.
  /// Returns false if the target cannot be reached.
  bool decode(std::span<const double> density, int source, int target, SurfacePath& out);

  /// Same for log-densities: each is exponentiated and clamped to [DBL_MIN, DBL_MAX].
  bool decode_log(std::span<const double> log_density, int source, int target, SurfacePath& out);

  const FastMarching& fast_marching() const { return fm_; }

 private:
  FastMarching fm_;
};

}  // namespace depath
