// SPDX-License-Identifier: MIT
#include "depath/decode/path_decoder.hpp"

#include "depath/decode/trace.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace depath {

PathDecoder::PathDecoder(const FastMarchingStencils& stencils)
    : fm_(stencils) {}

bool PathDecoder::decode(std::span<const double> density, int source, int target, SurfacePath& out) {
  fm_.run(density, source, target);
  return trace_steepest_descent(fm_, source, target, out);
}

bool PathDecoder::decode_log(std::span<const double> log_density, int source, int target, SurfacePath& out) {
  fm_.run_log(log_density, source, target);
  return trace_steepest_descent(fm_, source, target, out);
}

}  // namespace depath
