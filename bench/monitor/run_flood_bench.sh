#!/usr/bin/env bash
# Bounded resources under forged floods (issue 24 point 5): odonata-monitor and odonata-logger
# (--max-mb 200) run while flood_publisher sends, for SECONDS (default 30), predictions of 1000
# new outputs, 14 MB snapshots of new instances, heartbeats of new peers and garbage on new
# channels, in a private network namespace. Prints the monitor's peak resident memory (VmHWM)
# and the logger's, and the bytes the logger wrote against its budget. Targets: monitor ≤ 200 MB,
# logger within its budget. `snapshots` as MODE floods with the 14 MB snapshots alone. As root:
#   bench/monitor/run_flood_bench.sh [BUILD] [SECONDS] [snapshots]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${1:-$ROOT/build}
SECONDS_FLOOD=${2:-30}
MODE=${3:-}
source "$ROOT/bench/lib.sh"
bench_enter_netns "$@"
URL='udpm://239.255.76.67:7696?ttl=0'
bench_scratch
BUDGET_MB=200
"$BUILD/services/monitor/odonata-monitor" --lcm-url "$URL" --summary-json "$TMP/summary.json" \
  >"$TMP/monitor.log" 2>&1 &
monitor=$!
"$BUILD/services/logger/odonata-logger" record -o "$TMP/log" --max-mb $BUDGET_MB --lcm-url "$URL" \
  >"$TMP/logger.log" 2>&1 &
logger=$!
sleep 1
"$BUILD/tests/integration/flood_publisher" "$URL" "$SECONDS_FLOOD" $MODE >"$TMP/flood.log" &
flood=$!
peak() { awk '/VmHWM/ {print int($2 / 1024)}' "/proc/$1/status"; }
while kill -0 $flood 2>/dev/null; do sleep 1; done
kill -0 $monitor || { cat "$TMP/monitor.log"; echo "the monitor died under the flood"; exit 1; }
kill -0 $logger || { cat "$TMP/logger.log"; echo "the logger died under the flood"; exit 1; }
m=$(peak $monitor) l=$(peak $logger)
kill -TERM $monitor $logger; wait $monitor $logger 2>/dev/null || true
written=$(du -cm "$TMP"/log* | tail -1 | cut -f1)
cat "$TMP/flood.log"
echo "monitor: peak RSS $m MB (target <= 200 MB); summary $(du -k "$TMP/summary.json" | cut -f1) kB"
echo "logger: peak RSS $l MB; wrote $written MB of its $BUDGET_MB MB budget"
