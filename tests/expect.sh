# SPDX-License-Identifier: MIT
# Sourced by the command-line tests: expect NAME EXIT_CODE TEXT -- command... runs the
# command (at most $expect_timeout seconds, default 600), checks its exit code and that its
# stdout+stderr contain TEXT, and counts the result in $passed / $failed.
passed=0
failed=0
expect() {
  local name="$1" code="$2" text="$3"
  shift 4
  local out rc
  out="$(timeout "${expect_timeout:-600}" "$@" 2>&1)"
  rc=$?
  if [ "$rc" -eq "$code" ] && grep -qF -- "$text" <<<"$out"; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAILED: $name (exit $rc, expected $code; wanted '$text')"
    echo "$out" | head -5 | sed 's/^/    /'
  fi
}
