#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite (unit, accuracy against ../shared/data/truth
# when present, end-to-end gRPC, Python client, deploy static checks). Used by .ci/run.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh"
cd "${DEPATH_BUILD_DIR:-$root/build}"
ctest --output-on-failure -j "${DEPATH_JOBS:-$(nproc)}" --timeout 900
