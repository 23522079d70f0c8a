// SPDX-License-Identifier: MIT
#include "depath/solve/progress.hpp"

#include "solve/methods/methods.hpp"

#include <chrono>

namespace depath {

void report_progress(const MethodContext& ctx, Progress figures, const SurfacePath* path) {
  if (!ctx.hooks.on_progress) return;
  figures.elapsed_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - ctx.start).count();
  const int every = ctx.job.path_every;
  figures.best_path = every > 0 && figures.generation % every == 0 ? path : nullptr;
  ctx.hooks.on_progress(figures);
}

}  // namespace depath
