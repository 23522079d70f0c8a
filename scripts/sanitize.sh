#!/usr/bin/env bash
# Builds and runs the test suite under sanitizers, in its own build folder.
#   bash scripts/sanitize.sh              # AddressSanitizer + UndefinedBehaviorSanitizer
#   bash scripts/sanitize.sh thread       # ThreadSanitizer (the server and the thread pool)
# Debian's gRPC is not built with TSan, so TSan reports inside gRPC frames are not ours.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
kind="${1:-address,undefined}"
build="$root/build-${kind//,/-}"
bash "$root/scripts/setup.sh"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDEPATH_SANITIZE="$kind" \
  -DDEPATH_BUILD_BENCH=OFF
cmake --build "$build" -j "${DEPATH_JOBS:-$(nproc)}"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export TSAN_OPTIONS="halt_on_error=0"
cd "$build"
if [ "$kind" = thread ]; then
  ctest --output-on-failure -j "${DEPATH_JOBS:-$(nproc)}" -E "python|deploy" --timeout 1800
else
  ctest --output-on-failure -j "${DEPATH_JOBS:-$(nproc)}" --timeout 1800
fi
