// SPDX-License-Identifier: MIT
// Refinement step 1: optimise where the path's points sit on their edges, with the
// edge sequence fixed.
#pragma once

#include "refine/common.hpp"

namespace depath::refine {

/// Moves the interior edge points of `path` along their edges (t in [0, 1]; vertex
/// points and the end points stay) to lower the energy.
///
/// Projected Newton on all edge parameters at once: the energy is a sum of terms that
/// each involve 2 (segment) or 3 (turning angle) consecutive points, so the Hessian is
/// banded (half-bandwidth 2) and a Newton step costs O(n). Derivatives come from finite
/// differences of segment_energy / turning_angle, so any Energy works. Every step is
/// accepted only if the whole-path energy strictly drops (backtracking line search);
/// when Newton stalls, one golden-section pass per point (a robust 1-D minimiser for
/// kinked energies) takes over. Points may end at t = 0 or 1 (the caller turns them
/// into vertices).
///
/// Returns the new energy (<= `energy`, the path's current energy).
double optimize_edge_points(Evaluator& eval, SurfacePath& path, double energy, int max_newton_iterations,
                            const std::function<bool()>& cancelled);

/// One golden-section pass: each listed point (indices of interior edge points) is
/// moved to the best t found on its edge if that lowers its local energy. Returns the
/// total decrease (>= 0).
double golden_pass(Evaluator& eval, SurfacePath& path, const std::vector<int>& points);

}  // namespace depath::refine
