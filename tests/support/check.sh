# Sourced by the shell tests (tests/cli/, tests/gpu/test_gpu_cli.sh, tests/slurm/): counted checks,
# checks of JSON-lines status files, and the closing count. The caller sets $work (a scratch folder)
# and $python before calling them.
passed=0
failed=0

check() { # check DESCRIPTION COMMAND...: the command succeeds; its output is shown when it does not
  local what=$1
  shift
  if "$@" >"$work/check.out" 2>&1; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAILED: $what"
    sed 's/^/    /' "$work/check.out" | head -20
  fi
}

# expect CODE PATTERN -- COMMAND...: the command exits with CODE (or any non-zero for "fail") and its
# combined output matches the extended regex PATTERN (tests/cli/test_cli.sh, tests/gpu/test_gpu_cli.sh).
expect() {
  local code=$1 pattern=$2
  shift 3
  local out rc
  out=$("$@" 2>&1)
  rc=$?
  if { [ "$code" = fail ] && [ $rc -ne 0 ]; } || [ "$code" = "$rc" ]; then
    if grep -qE -- "$pattern" <<<"$out"; then
      passed=$((passed + 1))
      return
    fi
  fi
  failed=$((failed + 1))
  echo "FAILED: $* (exit $rc, wanted $code, pattern '$pattern')"
  echo "$out" | sed 's/^/    /' | head -20
}

# json_check FILE PYTHON_EXPRESSION: every line is one JSON object; `lines` (a list of them) satisfies the expression.
json_check() {
  $python -c '
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
ok = eval("(" + sys.argv[2] + ")")
if not ok:
    print("\n".join(json.dumps(l) for l in lines)); sys.exit(1)
' "$1" "$2"
}

check_summary() { # check_summary NAME: prints the counts; succeeds when no check failed
  echo "$1 test: $passed passed, $failed failed"
  [ "$failed" -eq 0 ]
}
