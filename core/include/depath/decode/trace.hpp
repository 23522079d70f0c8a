// SPDX-License-Identifier: MIT
// Back-tracing: steepest descent of a fast-marching field from the target to the source.
//
// Inputs: a finished (or early-stopped) fast march and the two end vertices. Outputs: the
// path from source to target. Guarantees: always terminates, and reaches the source when
// the target was reached (see trace_steepest_descent).
#pragma once

#include "depath/decode/fast_marching.hpp"
#include "depath/mesh/surface_path.hpp"

namespace depath {

/// Traces the steepest descent of the piecewise-linear field `fm.values()` from `target`
/// to `source` across faces, writing the path from source to target into `out`.
///
/// Interior points lie on edges or at vertices. Where no face step descends (valleys,
/// saddles, boundaries, degenerate faces) the trace moves along an edge or to an earlier
/// accepted neighbour vertex, so it always terminates and reaches the source.
/// Returns false (and leaves `out` empty) only if the target was not reached by `fm`.
bool trace_steepest_descent(const FastMarching& fm, int source, int target, SurfacePath& out);

}  // namespace depath
