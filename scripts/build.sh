#!/usr/bin/env bash
# Configures and builds depath (Release) into build/ (or $DEPATH_BUILD_DIR). Idempotent.
# Extra arguments go to the first cmake configure (e.g. -DDEPATH_BUILD_BENCH=OFF).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/scripts/compiler_cache.sh"
build="${DEPATH_BUILD_DIR:-$root/build}"
jobs="${DEPATH_JOBS:-$(nproc)}"
if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release "${depath_cache_flags[@]}" "$@"
fi
cmake --build "$build" -j "$jobs"
