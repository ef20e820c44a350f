#!/usr/bin/env bash
# Sets up, builds, and runs every test through ctest: a Release build, then an ASan+UBSan build.
# Both suites run even when the first fails, and the last line gives both counts; the exit code is
# non-zero when anything failed.
#
# The Release suite keeps about one core of two busy on average (its multi-process tests wait on
# their services), so the sanitizer build runs beside it and uses the idle core: on two cores the
# two together took 13.6 min instead of 14.6. The tests wait for states, not the clock, and pass
# beside CPU hogs (docs/guide/live-system.md, reliability). The build is not niced: on a machine that other jobs keep
# busy, a niced build would get almost no CPU.
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
# Where the time goes, for whoever has to make the command faster: each phase says when it ended.
SECONDS=0
stamp() { echo "run-tests: $1 at $((SECONDS / 60)) min $((SECONDS % 60)) s"; }
"$ROOT/deploy/setup.sh" || { echo "run-tests: setup failed" >&2; exit 1; }
stamp "set-up done"

# run_ctest NAME DIR [CTEST_ARGS...]: runs one built suite; sets RESULT to its line.
run_ctest() {
  local name=$1 dir=$2
  shift 2
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
release="Release: BUILD FAILED"
release_built=0
"$ROOT/deploy/build.sh" release && release_built=1
stamp "Release build ended"

# The sanitizer build, in the background, its output into a log (printed if it fails).
mkdir -p "$ROOT/build-sanitize"
sanitize_log="$ROOT/build-sanitize/build.log"
echo "run-tests: building the ASan+UBSan tree in the background (log: $sanitize_log)"
set -m  # its own process group, so that the compilers it starts can be stopped with it
"$ROOT/deploy/build.sh" sanitize >"$sanitize_log" 2>&1 &
sanitize_build=$!
set +m
# Whatever ends this script (a failure, Ctrl-C), the background build does not outlive it.
trap 'kill -- -"$sanitize_build" 2>/dev/null' EXIT
trap 'exit 130' INT TERM

if ((release_built)); then
  run_ctest Release "$ROOT/build" || status=1
  release=$RESULT
  stamp "Release tests ended"
else
  status=1
fi

echo "run-tests: waiting for the ASan+UBSan build"
if wait "$sanitize_build"; then
  stamp "ASan+UBSan build done"
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    run_ctest ASan+UBSan "$ROOT/build-sanitize" -LE slow || status=1
  sanitize=$RESULT
  stamp "ASan+UBSan tests ended"
else
  echo "run-tests: the ASan+UBSan build failed; the end of its log ($sanitize_log):" >&2
  tail -n 60 "$sanitize_log" >&2
  sanitize="ASan+UBSan: BUILD FAILED"
  status=1
fi
trap - EXIT
echo "run-tests: $release; $sanitize; $([[ $status == 0 ]] && echo PASSED || echo FAILED) in $SECONDS s"
exit $status
