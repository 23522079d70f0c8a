// SPDX-License-Identifier: MIT
// Detour starts for a local descent: paths through the corridor between the end points,
// away from the paths already found.
#pragma once

#include <span>
#include <vector>

#include "depath/decode/fast_marching.hpp"
#include "depath/mesh/surface_path.hpp"

namespace depath {

/// Paths source -> m -> target through up to `count` vertices m of the corridor
/// {v : d_s(v) + d_t(v) <= (1 + slack) d_s(target)}, d_s and d_t the two marches' fields;
/// each half is the steepest-descent trace of its end's field. The m are chosen one by
/// one, each the corridor vertex farthest in space from the paths in `known` and from the
/// m chosen before it; fewer when the corridor has no vertex off those.
///
/// Why: a locally shortest path stays in its homotopy class, and a shorter path of another
/// class that the fast-marching traces miss still runs through the corridor (its length is
/// within the marches' error of d_s(target)), away from the paths found.
/// Both marches must have run to completion from `source` and `target` (no early stop).
std::vector<SurfacePath> corridor_detours(const FastMarching& from_source, const FastMarching& from_target,
                                          int source, int target, std::span<const SurfacePath> known,
                                          int count, double slack);

}  // namespace depath
