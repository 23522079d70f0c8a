// SPDX-License-Identifier: MIT
// How much slower than a Release build this test binary runs, for liveness bounds.
//
// Tests never bound the wall-clock time of a computation (that belongs to bench/). Where a test
// bounds liveness instead (a cancel stops a job, shutdown ends, a watcher gets its final event),
// the bound is derived from the server's configured limits with a wide margin and multiplied by
// time_scale(): sanitizers slow code down (ASan + UBSan about 2-3x, TSan 5-15x), so the build
// defines DEPATH_TEST_TIME_SCALE per sanitizer, and the environment variable of the same name
// overrides it (e.g. on a heavily loaded machine).
#pragma once

#include <cstdlib>

#ifndef DEPATH_TEST_TIME_SCALE
#define DEPATH_TEST_TIME_SCALE 1
#endif

namespace depath::test {

inline double time_scale() {
  if (const char* env = std::getenv("DEPATH_TEST_TIME_SCALE")) {
    char* end = nullptr;
    const double v = std::strtod(env, &end);
    if (end != env && v >= 1.0) return v;
  }
  return DEPATH_TEST_TIME_SCALE;
}

/// True in sanitizer builds, where the slowest tests run at a reduced size (their full size
/// runs in the Release suite).
inline bool sanitized_build() { return DEPATH_TEST_TIME_SCALE > 1; }

}  // namespace depath::test
