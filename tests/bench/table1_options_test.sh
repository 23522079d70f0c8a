#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# bench_table1 refuses bad options with exit code 2, and a malformed table with exit code 1,
# each with a message naming the problem,
# instead of clamping them or running some other set of rows.
#   table1_options_test.sh BENCH_TABLE1_BINARY
set -uo pipefail
bench="$1"
source "$(dirname "$0")/../expect.sh"
expect_timeout=60  # a refused option ends at once; this bounds a regression that runs the table

expect "threads 0" 2 "--threads needs a whole number of at least 1, got '0'" -- "$bench" --threads 0
expect "threads with a suffix" 2 "got '2x'" -- "$bench" --threads 2x
expect "negative iterations" 2 "--max-iterations needs a whole number of at least 1, got '-3'" -- \
  "$bench" --max-iterations -3
expect "iterations beyond int" 2 "--max-iterations value '99999999999' is too large" -- \
  "$bench" --max-iterations 99999999999
expect "repeat empty" 2 "--repeat needs a whole number" -- "$bench" --repeat ""
expect "seed not a number" 2 "--seed needs a whole number of at least 0, got 'abc'" -- "$bench" --seed abc
expect "seed negative" 2 "got '-1'" -- "$bench" --seed -1
expect "unknown option" 2 "usage:" -- "$bench" --nosuch
expect "unknown strategy" 2 "--strategy 'bogus' is none of: rand1bin, shade" -- "$bench" --strategy bogus

# A malformed table (--data DIR/paper/table1.csv) is refused naming its line and field.
data="$(mktemp -d)"
trap 'rm -rf "$data"' EXIT
mkdir "$data/paper"
table() { printf 'application,category,vertices,agents,iterations,seconds\n%s\n' "$1" >"$data/paper/table1.csv"; }
table "vector field,simple converge,41x41,1000,300,354.2"
expect "vertices not a number" 1 "table1.csv line 2: vertices is not a positive number: '41x41'" -- \
  "$bench" --data "$data" --rows 1
table "vector field,simple converge,1681,1000,300"
expect "missing column" 1 "line 2: seconds is not a positive number: ''" -- "$bench" --data "$data" --rows 1
table "vector field,simple converge,1681,-1000,300,354.2"
expect "negative agents" 1 "line 2: agents is not a positive number: '-1000'" -- "$bench" --data "$data" --rows 1
table "vector field,simple converge,1681,1000,99999999999,354.2"
expect "iterations beyond int" 1 "line 2: iterations is not a positive number" -- "$bench" --data "$data" --rows 1
table "vector field,simple converge,1681,1000,300,nan"
expect "seconds not finite" 1 "line 2: seconds is not a positive number: 'nan'" -- "$bench" --data "$data" --rows 1

# --rows is checked against the paper's table, which is shared data.
if "$bench" --rows 1 --max-iterations 1 --threads 1 2>&1 | grep -q "shared data absent"; then
  echo "skipped the --rows checks: ../shared/data/paper/table1.csv is absent"
else
  expect "row number too large for an int" 2 "--rows item '99999999999'" -- "$bench" --rows 99999999999
  expect "row number past the table" 2 "names none of the 12 rows" -- "$bench" --rows 13
  expect "empty item" 2 "--rows item '' (of '1,,2')" -- "$bench" --rows 1,,2
  expect "misspelt row" 2 "--rows item 'kiten'" -- "$bench" --rows 7,kiten
  # Words match ignoring case; numbers and words mix: exactly rows 7 and 9 run.
  out="$(timeout 120 "$bench" --rows 7,KITTEN --max-iterations 1 --threads 1 2>&1)"
  rows="$(grep -oE '^ ?[0-9]+ ' <<<"$out" | tr -d ' ' | paste -sd, -)"
  if [ "$rows" = "7,9" ]; then passed=$((passed + 1)); else
    failed=$((failed + 1))
    echo "FAILED: --rows 7,KITTEN ran rows '$rows', expected 7,9"
  fi
fi

echo "bench_table1 options: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
