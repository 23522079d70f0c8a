#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) with clang-14 + ASan/UBSan into build-fuzz/ (or
# $DEPATH_FUZZ_BUILD_DIR) and runs each for a bounded time ($DEPATH_FUZZ_SECONDS, default 60)
# from the seed corpus in tests/fuzz/corpus/<name>/. New corpus entries go to a scratch
# directory, never into the repository. Exit status: non-zero if a target found a crash,
# leak, timeout or out-of-memory (the reproducer is kept in $DEPATH_FUZZ_ARTIFACTS, default
# build-fuzz/artifacts). Usage: scripts/fuzz.sh [TARGET...] (default: all).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/scripts/compiler_cache.sh"
build="${DEPATH_FUZZ_BUILD_DIR:-$root/build-fuzz}"
seconds="${DEPATH_FUZZ_SECONDS:-60}"
jobs="${DEPATH_JOBS:-$(nproc)}"
artifacts="${DEPATH_FUZZ_ARTIFACTS:-$build/artifacts}"
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(fuzz_mesh_reader fuzz_job_spec)

if [ ! -f "$build/build.ninja" ]; then
  CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DDEPATH_FUZZ=ON -DDEPATH_BUILD_TESTS=OFF -DDEPATH_BUILD_BENCH=OFF -DDEPATH_BUILD_SERVICE=OFF \
    "${depath_cache_flags[@]}"
fi
cmake --build "$build" -j "$jobs" --target "${targets[@]}"

mkdir -p "$artifacts"
status=0
for t in "${targets[@]}"; do
  name="${t#fuzz_}"
  scratch="$(mktemp -d "/tmp/depath-fuzz-$name.XXXX")"
  echo "== $t: ${seconds} s from tests/fuzz/corpus/$name"
  # -rss_limit_mb and -timeout turn unbounded memory and hangs into findings.
  if ! "$build/tests/fuzz/$t" "$scratch" "$root/tests/fuzz/corpus/$name" -max_total_time="$seconds" \
      -rss_limit_mb=2048 -timeout=10 -max_len=65536 -print_final_stats=1 -artifact_prefix="$artifacts/$t-" \
      2>"$artifacts/$t.log"; then
    echo "$t: FINDING (see $artifacts/$t.log and $artifacts/$t-*)"
    tail -40 "$artifacts/$t.log"
    status=1
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$artifacts/$t.log" | sed "s/^/$t: /" || true
  rm -rf "$scratch"
done
exit $status
