#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Prints the Debian packages that provide the shared libraries the given binaries load,
# one per line. The Dockerfile's runtime stage installs exactly these, so it never carries
# a hand-kept list that drifts from what the build actually links (a missing library would
# only show up when the container starts).
#
#   deploy/runtime-packages.sh build/server/depathd build/client/depath
set -euo pipefail
[ $# -gt 0 ] || { echo "usage: $0 BINARY..." >&2; exit 2; }

# ldd lines look like "libfoo.so.1 => /lib/x86_64-linux-gnu/libfoo.so.1 (0x...)".
mapfile -t libs < <(ldd "$@" | awk '$2 == "=>" && $3 ~ /^\// { print $3 }' | sort -u)
for lib in "${libs[@]}"; do
  # With merged /usr, dpkg may know the file under /lib, /usr/lib or its real path.
  owner=""
  for path in "$lib" "/usr$lib" "$(readlink -f "$lib")"; do
    owner="$(dpkg-query -S "$path" 2>/dev/null | head -n1)" && [ -n "$owner" ] && break
  done
  [ -n "$owner" ] || { echo "runtime-packages: no package owns $lib" >&2; exit 1; }
  echo "${owner%%[:,]*}" # "libfoo1:amd64: /path" -> "libfoo1"
done | sort -u
