// SPDX-License-Identifier: MIT
// Decoding a density field into a path: fast marching from the source, then back-tracing.
//
// Inputs: the mesh's stencils, one density (or log-density) per vertex, source and target.
// Outputs: the path source -> target on the surface (points on vertices or edges), or
// false when the target is not reached. Guarantees: deterministic for given inputs; no
// allocation per decode once its buffers have grown; one decoder per thread.
// Reference: the decoding step of DE-Path (Ye, Liu, Zheng, Hormann, He): a density field
// is an individual, its path the fast-marching geodesic traced back from the target.
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
