#!/usr/bin/env bash
# Configures and builds depath (Release) into build/ (or $DEPATH_BUILD_DIR). Idempotent.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${DEPATH_BUILD_DIR:-$root/build}"
jobs="${DEPATH_JOBS:-$(nproc)}"
if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
fi
cmake --build "$build" -j "$jobs"
