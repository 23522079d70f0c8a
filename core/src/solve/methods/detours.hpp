// SPDX-License-Identifier: MIT
// More starts for a local descent than the fmm path: the same traced the other way, and
// paths through the corridor between the end points, away from the paths already found.
#pragma once

#include "depath/decode/fast_marching.hpp"
#include "depath/mesh/surface_path.hpp"
#include "solve/methods/methods.hpp"

#include <span>
#include <vector>

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

/// The starts a local descent of ctx's problem takes besides ctx.fmm_path: the fmm path
/// traced the other way (from the source back in the target's field: round-off in the two
/// fields sends them around different saddle vertices, and a path through a saddle vertex
/// is locally shortest whichever side is shorter) and, for a length (whose refinement is
/// exact and cheap), corridor_detours off both.
std::vector<SurfacePath> descent_starts(const MethodContext& ctx);

}  // namespace depath
