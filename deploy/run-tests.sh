#!/usr/bin/env bash
# Sets up, builds, and runs every test through ctest: a Release build, then an ASan+UBSan build.
# Both suites run even when the first fails, and the last line gives both counts; the exit code is
# non-zero when anything failed.
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
"$ROOT/deploy/setup.sh" || { echo "run-tests: setup failed" >&2; exit 1; }

# suite NAME BUILD_KIND DIR [CTEST_ARGS...]: builds and runs one suite; sets RESULT to its line.
suite() {
  local name=$1 kind=$2 dir=$3
  shift 3
  if ! "$ROOT/deploy/build.sh" "$kind"; then
    RESULT="$name: BUILD FAILED"
    return 1
  fi
  local log="$dir/ctest-summary.log" rc
  (cd "$dir" && ctest --output-on-failure -j 2 "$@") 2>&1 | tee "$log"
  rc=${PIPESTATUS[0]}
  local line
  line=$(grep -E "tests passed, [0-9]+ tests? failed out of [0-9]+" "$log" | tail -1)
  if [[ -z $line ]]; then
    RESULT="$name: ctest ended with code $rc and no summary"
    return 1
  fi
  local failed total
  failed=$(sed -E 's/.*, ([0-9]+) tests? failed out of ([0-9]+).*/\1/' <<<"$line")
  total=$(sed -E 's/.*, ([0-9]+) tests? failed out of ([0-9]+).*/\2/' <<<"$line")
  RESULT="$name: $((total - failed)) of $total passed"
  ((failed == 0 && rc == 0))
}

status=0
suite Release release "$ROOT/build" || status=1
release=$RESULT
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  suite ASan+UBSan sanitize "$ROOT/build-sanitize" -LE slow || status=1
sanitize=$RESULT
echo "run-tests: $release; $sanitize; $([[ $status == 0 ]] && echo PASSED || echo FAILED)"
exit $status
