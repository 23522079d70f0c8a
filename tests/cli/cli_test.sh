#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The `depath` command line as a user drives it: outputs, exit codes and error messages.
#   cli_test.sh DEPATH_BINARY TEST_DATA_DIR
set -uo pipefail
depath="$1"
data="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
source "$(dirname "$0")/../expect.sh"

cone="$data/cone.off"
expect "fmm solve writes json" 0 "wrote $work/p.json" -- "$depath" solve "$cone" -s 0 -t 348 --method fmm --out "$work/p.json"
expect "json has the contract fields" 0 "ok" -- python3 -c "
import json, sys
r = json.load(open('$work/p.json'))
need = ['points', 'crossings', 'energy', 'length', 'method', 'generations', 'evaluations', 'seconds', 'fmm_energy']
missing = [k for k in need if k not in r]
assert not missing, missing
assert r['crossings'][0] == {'vertex': 0} and r['crossings'][-1] == {'vertex': 348}, r['crossings'][:1]
assert len(r['points']) == len(r['crossings'])
print('ok')"
expect "de --json prints progress and result lines" 0 '"event":"result"' -- \
  "$depath" solve "$cone" -s 0 -t 348 --generations 5 --population 6 --json --threads 2
expect "csv output" 0 "wrote" -- "$depath" solve "$cone" -s 0 -t 348 --method fmm --out "$work/p.csv"
expect "obj output" 0 "wrote" -- "$depath" solve "$cone" -s 0 -t 348 --method fmm --out "$work/p.obj"
expect "ply output" 0 "wrote" -- "$depath" solve "$cone" -s 0 -t 348 --method fmm --out "$work/p.ply"

expect "missing mesh" 2 "cannot open mesh file" -- "$depath" solve "$work/nope.off" -s 0 -t 1
expect "unknown format" 2 "unknown mesh format" -- "$depath" solve "$work/p.json" -s 0 -t 1
expect "source out of range" 2 "source vertex 99999 is out of range" -- "$depath" solve "$cone" -s 99999 -t 1
expect "s == t" 2 "same vertex" -- "$depath" solve "$cone" -s 5 -t 5
expect "population" 2 "population must be at least 4" -- "$depath" solve "$cone" -s 0 -t 5 --population 3
expect "F" 2 "F must be in (0, 2]" -- "$depath" solve "$cone" -s 0 -t 5 --F 3
expect "CR" 2 "CR must be in [0, 1]" -- "$depath" solve "$cone" -s 0 -t 5 --CR -0.1
expect "generations" 2 "generations must be at least 1" -- "$depath" solve "$cone" -s 0 -t 5 --generations 0
expect "energy name" 2 "unknown energy" -- "$depath" solve "$cone" -s 0 -t 5 --energy magnetic
expect "method name" 2 "unknown method" -- "$depath" solve "$cone" -s 0 -t 5 --method astar
printf '1\n2\n3\n' > "$work/short.density"
expect "density length" 2 "density has 3 values but the mesh has 1153" -- \
  "$depath" solve "$cone" -s 0 -t 5 --density "$work/short.density"
expect "output extension checked before solving" 2 "the output extension must be" -- \
  "$depath" solve "$cone" -s 0 -t 5 --out "$work/p.txt"
printf 'OFF\n1000000000 1 0\n0 0 0\n' > "$work/lying.off"
expect "lying header" 2 "truncated or malformed" -- "$depath" solve "$work/lying.off" -s 0 -t 1
printf '' > "$work/empty.obj"
expect "empty file" 2 "empty" -- "$depath" solve "$work/empty.obj" -s 0 -t 1
expect "generate + solve" 0 "wrote" -- "$depath" generate grid --n 11 --out "$work/g.obj"
expect "solve on generated grid" 0 "energy" -- "$depath" solve "$work/g.obj" -s 0 -t 120 --method fmm

# depath render / depath plot (pictures with Cairo; pixel checks are in tests/test_pictures.cpp)
expect "render writes a png" 0 "wrote $work/p.png (320x200" -- \
  "$depath" render "$cone" "$work/p.json" --out "$work/p.png" --width 320 --height 200
expect "render output is a 320x200 png" 0 "ok" -- python3 -c "
import struct
d = open('$work/p.png', 'rb').read()
assert d[:8] == b'\\x89PNG\\r\\n\\x1a\\n' and struct.unpack('>II', d[16:24]) == (320, 200)
print('ok')"
expect "render: missing result" 2 "cannot open the file" -- "$depath" render "$cone" "$work/none.json" --out "$work/x.png"
expect "render: result of another mesh" 2 "not on this mesh" -- "$depath" render "$work/g.obj" "$work/p.json" --out "$work/x.png"
expect "render: not a png name" 2 "name it .png" -- "$depath" render "$cone" "$work/p.json" --out "$work/x.jpg"
expect "render: field of the wrong length" 2 "field $work/short.field has 1 vectors but the mesh has 1153" -- \
  bash -c "echo '1 0 0' > '$work/short.field' && '$depath' render '$cone' '$work/p.json' --out '$work/x.png' --field '$work/short.field'"
"$depath" solve "$cone" -s 0 -t 348 --generations 9 --population 6 --threads 2 --json > "$work/progress.jsonl" 2>/dev/null
expect "plot writes an svg" 0 "wrote $work/c.svg (9 generations)" -- "$depath" plot "$work/progress.jsonl" --out "$work/c.svg"
expect "plot svg: valid XML, 9 markers per series" 0 "ok" -- python3 -c "
import re, xml.etree.ElementTree as ET
root = ET.parse('$work/c.svg').getroot()
assert root.tag.endswith('svg'), root.tag
fills = [e.get('style', '') for e in root.iter() if e.tag.endswith('path')]
best = sum('fill:rgb(86%,8%,8%)' in f for f in fills)
mean = sum('fill:rgb(20%,40%,85%)' in f for f in fills)
assert (best, mean) == (9, 9), (best, mean)
print('ok')"
echo '{"event":"status","message":"queued"}' > "$work/status.jsonl"
expect "plot: no progress lines" 2 "no progress lines" -- "$depath" plot "$work/status.jsonl" --out "$work/c.svg"
expect "plot: not JSON lines" 2 "line 1: not a JSON object" -- "$depath" plot "$work/p.json" --out "$work/c.svg"
expect "plot: missing file" 2 "cannot open the file" -- "$depath" plot "$work/none.jsonl" --out "$work/c.svg"

echo "cli: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
