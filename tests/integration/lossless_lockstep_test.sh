#!/usr/bin/env bash
# Lossless lockstep on a loaded machine: a CPU hog on every core, and the identifier paused
# (SIGSTOP) for half a second mid-run. The generator waits for the identifier's and the logger's
# receipts, so neither loses a sample: the log holds every one, the identifier learned every one
# (its model equals odonata-fit's on the exported samples, bit for bit), and a consumer killed
# mid-run fails the run instead of passing it with samples missing.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
HOGS=()
trap 'for h in "${HOGS[@]}"; do kill "$h" 2>/dev/null || true; done; stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7687?ttl=0'
"$SRC/deploy/make-identifier-config" --preset roll --duration 10 --build "$BUILD" --output "$OUT/id.json"
for _ in $(seq "$(nproc)"); do
  (while :; do :; done) &
  HOGS+=($!)
done
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
start plant "$PLANT" --mode lockstep --preset roll --lcm-url "$URL"
start ident "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0 --save-model "$OUT/model.json"
sleep 0.5
start signal "$SIGNAL" --preset roll --phase train --duration 10 --mode lockstep --lcm-url "$URL"
# Pause the identifier once the run is under way (the discovery second is over).
wait_for_log "$OUT/signal.log" "waits for receipts" || true
grep -q "waits for receipts from: identifier logger" "$OUT/signal.log" ||
  fail "the generator did not find both consumers: $(cat "$OUT/signal.log")"
sleep 0.2
kill -STOP "$PID_ident"
sleep 0.5
kill -CONT "$PID_ident"
wait "$PID_signal" || fail "the run failed: $(cat "$OUT/signal.log")"
sleep 0.3
stop_clean "$PID_ident" identifier
stop_clean "$PID_plant" plant
stop_clean "$PID_logger" logger
"$LOGGER" export "$OUT"/log.* -o "$OUT/train.csv" --predictions "$OUT/pred.csv" >"$OUT/export.log" 2>&1 ||
  { cat "$OUT/export.log"; fail "export failed"; }
rows=$(($(wc -l <"$OUT/train.csv") - 1))
((rows == 1000)) || fail "the log lost samples: $rows of 1000"
# Every sample from the first with a full regressor (ny lags of history) on, none missing.
first=$(sed -n 2p "$OUT/pred.csv" | cut -d, -f2)
last=$(tail -1 "$OUT/pred.csv" | cut -d, -f2)
preds=$(($(wc -l <"$OUT/pred.csv") - 1))
((last == 999 && preds == 1000 - first)) ||
  fail "the identifier predicted $preds samples, $first … $last, of 1000"
offline_fit "$OUT/id.json" "$OUT/train.csv" "$OUT/offline.json"
same_model "$OUT/model.json" "$OUT/offline.json" || fail "the online model differs from the offline one"
grep -o "[0-9]* for missing receipts" "$OUT/signal.log" || true

# A consumer killed mid-run: the generator fails loudly (exit 4) instead of finishing without it.
start plant2 "$PLANT" --mode lockstep --preset roll --lcm-url "$URL"
start ident2 "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0
sleep 0.5
# A long run (30000 samples, several seconds even at the fastest lockstep rate), so the kill
# lands mid-run: a 10 s run of 1000 samples could end before it.
start signal2 "$SIGNAL" --preset roll --phase train --duration 300 --mode lockstep --lcm-url "$URL" \
  --timeout-ms 50 --max-resends 4
wait_for_log "$OUT/signal2.log" "waits for receipts" || true
sleep 0.2
kill -KILL "$PID_ident2"
rc=0
wait "$PID_signal2" || rc=$?
((rc == 4)) || fail "losing a consumer gave exit code $rc, not 4: $(cat "$OUT/signal2.log")"
grep -q "no acknowledgement of state" "$OUT/signal2.log" || fail "no clear message: $(cat "$OUT/signal2.log")"
pass "lockstep under load with a paused identifier: 1000 of 1000 samples logged and learned; a killed consumer fails the run"
