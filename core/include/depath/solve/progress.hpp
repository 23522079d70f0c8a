// SPDX-License-Identifier: MIT
// What a running job reports after each generation (or refinement sweep): the figures
// `depath` shows as a bar or JSON lines and depathd streams as events.
//
// Built in one place (core/src/solve/progress.cpp) for every method, so that the figures
// mean the same whatever the method.
#pragma once

#include "depath/mesh/surface_path.hpp"

#include <cstdint>

namespace depath {

/// Per-generation report (methods without generations report once, as generation 0).
struct Progress {
  int generation = 0;            ///< 1-based generation just finished
  int max_generations = 0;
  double best_energy = 0.0;
  double mean_energy = 0.0;
  int64_t evaluations = 0;       ///< energy evaluations so far
  int improvements = 0;          ///< agents replaced by a better trial in this generation
  double elapsed_seconds = 0.0;
  const SurfacePath* best_path = nullptr;  ///< set every `path_every` generations, else null
};

}  // namespace depath
