#!/usr/bin/env bash
# The main job, end to end: set up, build, start depathd on loopback, run a DE-Path job on a
# bundled mesh through the client with live progress, write the path, stop the server.
#
#   bash scripts/demo.sh     # kitten.off, vertices 0 -> 320, writes out/kitten_path.{json,obj}
#
# The exact polyhedral geodesic for this pair is 59.1160524045 (../shared/data/truth).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh"
bin="${DEPATH_BUILD_DIR:-$root/build}"
out="$root/out"
mkdir -p "$out"
port_file="$(mktemp)"
"$bin/server/depathd" --listen 127.0.0.1:0 --port-file "$port_file" --threads "$(nproc)" --data-dir "$out/depathd-data" \
  2> "$out/depathd.log" &
server=$!
trap 'kill -TERM $server 2>/dev/null; wait $server 2>/dev/null || true; rm -f "$port_file"' EXIT
for _ in $(seq 100); do [ -s "$port_file" ] && break; sleep 0.1; done
[ -s "$port_file" ] || { echo "depathd did not start" >&2; exit 1; }
server_address="127.0.0.1:$(cat "$port_file")"
"$bin/client/depath" health --server "$server_address"
# DE-Path (the paper's rand/1/bin, seeded with the problem's density) then local refinement.
"$bin/client/depath" run "$root/tests/data/kitten.off" --server "$server_address" \
  --source 0 --target 320 --population 24 --generations 400 --seed-with-problem --refine \
  --out "$out/kitten_path.json"
# The same path as an OBJ polyline (fetched again from the server: same mesh, same seed).
"$bin/client/depath" run "$root/tests/data/kitten.off" --server "$server_address" \
  --source 0 --target 320 --population 24 --generations 400 --seed-with-problem --refine \
  --out "$out/kitten_path.obj" --json > /dev/null
echo "exact geodesic length for this pair: 59.1160524045"
echo "wrote $out/kitten_path.json and $out/kitten_path.obj (server log: $out/depathd.log)"
