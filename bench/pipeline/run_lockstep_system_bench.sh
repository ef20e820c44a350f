#!/usr/bin/env bash
# The whole lockstep system's rate: odonata-plant, an odonata-identifier learning the roll loop,
# odonata-logger recording everything, and odonata-signal waiting for every receipt (the lossless
# protocol, docs/lcm.md §10), over udpm in a private namespace. Prints samples/s per run, with
# receipts and without (--discover-consumers 0), for each command window (WINDOWS, default
# "1 4 8 16"), through odonata's own udpm path and through LCM's receive thread
# (ODONATA_LCM_RECEIVE=lcm; PATHS="own lcm" by default); SIGNED=1 gives every program a shared
# key, so every message is signed and verified (docs/lcm.md §15). As root:
#   bench/pipeline/run_lockstep_system_bench.sh [BUILD] [RUNS]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${1:-$ROOT/build}
RUNS=${2:-3}
source "$ROOT/bench/lib.sh"
bench_enter_netns "$@"
URL='udpm://239.255.76.67:7694?ttl=0'
bench_scratch
"$ROOT/deploy/make-identifier-config" --preset roll --duration 60 --build "$BUILD" --output "$TMP/id.json" >/dev/null
KEY=()
if [[ ${SIGNED:-0} == 1 ]]; then
  (umask 077 && od -An -tx1 -N32 /dev/urandom | tr -d ' \n' >"$TMP/bus.key")
  KEY=(--key "$TMP/bus.key")
fi
one_run() {  # one_run EXTRA_SIGNAL_FLAGS...: prints "RATE(commands/receipts per sample)"
  rm -f "$TMP"/log.*
  "$BUILD/services/logger/odonata-logger" record -o "$TMP/log" --lcm-url "$URL" "${KEY[@]}" 2>/dev/null &
  local logger=$!
  "$BUILD/services/plant/odonata-plant" --mode lockstep --preset roll --lcm-url "$URL" "${KEY[@]}" 2>/dev/null &
  local plant=$!
  "$BUILD/services/identifier/odonata-identifier" --config "$TMP/id.json" --lcm-url "$URL" --resume-wait 0 "${KEY[@]}" 2>/dev/null &
  local ident=$!
  sleep 0.5
  "$BUILD/services/signal/odonata-signal" --preset roll --phase train --duration 60 --mode lockstep \
    --lcm-url "$URL" "${KEY[@]}" "$@" 2>"$TMP/signal.log" || { cat "$TMP/signal.log"; exit 1; }
  kill $logger $plant $ident; wait $logger $plant $ident 2>/dev/null || true
  local rate per
  rate=$(grep -o "[0-9]* samples/s" "$TMP/signal.log" | cut -d' ' -f1)
  per=$(sed -nE 's/.*per sample ([0-9.]+) commands sent, [0-9.]+ states and ([0-9.]+) receipts.*/\1\/\2/p' "$TMP/signal.log")
  echo "$rate($per)"
}
echo "Each sample crosses, one after the other: the command (generator -> plant), the state and"
echo "beat state (plant -> identifier, logger, generator: one sendmmsg) and, with receipts, one"
echo "receipt per consumer (identifier, logger -> generator): 3 hops, 2 without receipts. A window"
echo "of W commands in flight overlaps the hops of W samples. Per run: samples/s(commands sent /"
echo "receipts received, per sample; above 1 and 2 are resends and repeated receipts)."
for path in ${PATHS:-own lcm}; do
  [[ $path == lcm ]] && export ODONATA_LCM_RECEIVE=lcm
  for window in ${WINDOWS:-1 4 8 16}; do
    for mode in receipts plant-only; do
      rates=()
      for _ in $(seq "$RUNS"); do
        if [[ $mode == receipts ]]; then
          rates+=("$(one_run --window "$window")")
        else
          rates+=("$(one_run --window "$window" --discover-consumers 0)")
        fi
      done
      echo "whole lockstep system, 6000 samples, $path udpm path, window $window, $mode$([[ ${#KEY[@]} -gt 0 ]] && echo ", signed"): ${rates[*]}"
    done
  done
done
