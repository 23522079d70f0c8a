// SPDX-License-Identifier: MIT
// Method `fmm`: the classic fast-marching geodesic of the problem's own density, which
// solve() has already decoded as every method's baseline. One report, as generation 0.
#include "solve/methods/methods.hpp"

namespace depath {

MethodOutcome run_fmm_method(const MethodContext& ctx) {
  MethodOutcome outcome{ctx.fmm_path, ctx.fmm_energy, 0, 1, "converged", {}};
  Progress figures;
  figures.best_energy = figures.mean_energy = ctx.fmm_energy;
  figures.evaluations = 1;
  report_progress(ctx, figures, &outcome.path);
  return outcome;
}

}  // namespace depath
