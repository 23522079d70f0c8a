#!/usr/bin/env bash
# Builds and runs the test suite under sanitizers, in its own build folder.
#   bash scripts/sanitize.sh              # AddressSanitizer + UndefinedBehaviorSanitizer
#   bash scripts/sanitize.sh thread       # ThreadSanitizer: core, server, service tests, CLI
# Any sanitizer report fails the test that produced it (the process stops at the first one).
# Debian's gRPC, Abseil and protobuf are not built with TSan, so TSan cannot see gRPC's own
# synchronisation: scripts/tsan.supp hides the reports that come from that (gRPC's code
# only, each entry explained there), server/grpc_handoff.hpp tells TSan the ordering gRPC
# guarantees our reactors, and the tsan_canary tests check that a deliberate race in a gRPC
# handler or reaction is still reported. The deploy tests (manifests, Dockerfile) are left
# out of the TSan run: they start none of our threads; so is the browser test of the web page
# (it drives Chromium through the same HTTP routes service_http already runs under TSan, at
# many times the cost).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
kind="${1:-address,undefined}"
build="$root/build-${kind//,/-}"
bash "$root/scripts/setup.sh"
source "$root/scripts/compiler_cache.sh"
# -g1: line tables only, all a sanitizer report's stacks need (and what the suppressions
# match); full debug info made the build 1.3x longer. -O1 under UBSan: its checks made -O2
# compile 2.2x slower than ASan alone (service_test.cpp: 98 s at -O2 -g, 37 s at -O1 -g1);
# at -O1 GCC 12 warns of std::regex's own members as maybe uninitialized (a false positive
# the sanitizers' instrumentation is known to provoke), so that warning is off there.
if [[ "$kind" == *undefined* ]]; then
  opt="-O1 -g1 -DNDEBUG -Wno-maybe-uninitialized"
else
  opt="-O2 -g1 -DNDEBUG"
fi
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDEPATH_SANITIZE="$kind" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$opt" -DDEPATH_BUILD_BENCH=OFF "${depath_cache_flags[@]}"
cmake --build "$build" -j "${DEPATH_JOBS:-$(nproc)}"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$root/scripts/lsan.supp"  # third-party leaks, each explained there
# history_size=7: TSan keeps enough history to restore both stacks of a report, so that the
# suppressions (which match frames) apply; with the default, a gRPC-internal access whose
# stack was lost is reported unsuppressed.
export TSAN_OPTIONS="suppressions=$root/scripts/tsan.supp:halt_on_error=1:history_size=7"
cd "$build"
if [ "$kind" = thread ]; then
  ctest --output-on-failure -j "${DEPATH_JOBS:-$(nproc)}" -E "^deploy|^web_view_browser" --timeout 1800
else
  ctest --output-on-failure -j "${DEPATH_JOBS:-$(nproc)}" --timeout 1800
fi
