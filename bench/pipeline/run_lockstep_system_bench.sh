#!/usr/bin/env bash
# The whole lockstep system's rate: odonata-plant, an odonata-identifier learning the roll loop,
# odonata-logger recording everything, and odonata-signal waiting for every receipt (the lossless
# protocol, docs/lcm.md §10), over udpm in a private namespace. Prints samples/s per run, with
# receipts and without (--discover-consumers 0), through odonata's own udpm path and through
# LCM's receive thread (ODONATA_LCM_RECEIVE=lcm). As root:
#   bench/pipeline/run_lockstep_system_bench.sh [BUILD] [RUNS]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${1:-$ROOT/build}
RUNS=${2:-3}
if [[ ${ODONATA_IN_NETNS:-0} != 1 ]]; then
  export ODONATA_IN_NETNS=1
  exec unshare -n sh -c 'ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec "$0" "$@"' bash "$0" "$@"
fi
URL='udpm://239.255.76.67:7694?ttl=0'
TMP=$(mktemp -d)
cleanup() { kill $(jobs -p) 2>/dev/null || true; rm -rf "$TMP"; }
trap cleanup EXIT
"$ROOT/deploy/make-identifier-config" --preset roll --duration 60 --build "$BUILD" --output "$TMP/id.json" >/dev/null
one_run() {  # one_run EXTRA_SIGNAL_FLAGS...: prints the generator's samples/s
  rm -f "$TMP"/log.*
  "$BUILD/services/logger/odonata-logger" record -o "$TMP/log" --lcm-url "$URL" 2>/dev/null &
  local logger=$!
  "$BUILD/services/plant/odonata-plant" --mode lockstep --preset roll --lcm-url "$URL" 2>/dev/null &
  local plant=$!
  "$BUILD/services/identifier/odonata-identifier" --config "$TMP/id.json" --lcm-url "$URL" --resume-wait 0 2>/dev/null &
  local ident=$!
  sleep 0.5
  "$BUILD/services/signal/odonata-signal" --preset roll --phase train --duration 60 --mode lockstep \
    --lcm-url "$URL" "$@" 2>"$TMP/signal.log" || { cat "$TMP/signal.log"; exit 1; }
  kill $logger $plant $ident; wait $logger $plant $ident 2>/dev/null || true
  grep -o "[0-9]* samples/s" "$TMP/signal.log" | cut -d' ' -f1
}
for path in own lcm; do
  [[ $path == lcm ]] && export ODONATA_LCM_RECEIVE=lcm
  for mode in receipts plant-only; do
    rates=()
    for _ in $(seq "$RUNS"); do
      if [[ $mode == receipts ]]; then rates+=("$(one_run)"); else rates+=("$(one_run --discover-consumers 0)"); fi
    done
    echo "whole lockstep system, 6000 samples, $path udpm path, $mode: ${rates[*]} samples/s"
  done
done
