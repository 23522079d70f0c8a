#include "depath/path_decoder.hpp"

#include "depath/trace_path.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace depath {

PathDecoder::PathDecoder(const FastMarchingStencils& stencils)
    : fm_(stencils), density_(stencils.mesh().num_vertices()) {}

bool PathDecoder::decode(std::span<const double> density, int source, int target, SurfacePath& out) {
  fm_.run(density, source, target);
  return trace_steepest_descent(fm_, source, target, out);
}

bool PathDecoder::decode_log(std::span<const double> log_density, int source, int target, SurfacePath& out) {
  const size_t n = std::min(log_density.size(), density_.size());
  for (size_t i = 0; i < n; ++i) density_[i] = std::clamp(std::exp(log_density[i]), DBL_MIN, DBL_MAX);
  return decode(density_, source, target, out);
}

}  // namespace depath
