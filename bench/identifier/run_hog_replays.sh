#!/usr/bin/env bash
# Issue 61's reliability figures, beside two CPU hogs on the Flapper's training flight
# (../shared/realdata/flapper_level1.csv) with the configuration odonata-fit --save-config writes:
#   - RUNS real-time replays (tests/integration/cpu_hog_replay_test.sh, SECONDS of the flight
#     each, 71 = all of it): samples unaccounted and services stuck past the bound, per run;
#   - kill -9 of the identifier mid-flight (real time, monitor running): restarted at once, it
#     resumes from the monitor's copy of its last snapshot; the samples it missed are printed as
#     it counts them ("samples missed on resume").
# Usage: run_hog_replays.sh [BUILD] [RUNS] [SECONDS] [REALDATA]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${1:-$ROOT/build}
RUNS=${2:-20}
SECS=${3:-71}
REALDATA=${4:-$ROOT/../shared/realdata}
export ODONATA_BUILD=$BUILD ODONATA_SOURCE=$ROOT ODONATA_REALDATA=$REALDATA ODONATA_HOG_SECONDS=$SECS
ok=0
for ((i = 1; i <= RUNS; i++)); do
  if line=$("$ROOT/tests/integration/cpu_hog_replay_test.sh" 2>&1 | grep -E "beside two hogs|FAIL"); then
    echo "run $i: $line"
    [[ $line == *FAIL* ]] || ok=$((ok + 1))
  else
    echo "run $i: no result"
  fi
done
echo "hog replays: $ok of $RUNS with every sample accounted and SIGTERM obeyed"
"$ROOT/bench/identifier/kill9_loss.sh" "$BUILD" "$REALDATA"
