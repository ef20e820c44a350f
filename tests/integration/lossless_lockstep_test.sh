#!/usr/bin/env bash
# Lossless lockstep on a loaded machine: a CPU hog on every core, and the identifier paused
# (SIGSTOP) for a second at sample 500 of 1000 (the generator holds there until it is paused).
# The generator waits for the identifier's and the logger's receipts, so neither loses a sample:
# the log holds every one, the identifier learned every one (its model, refitted at fixed sample
# counts, equals odonata-fit's on the exported samples, bit for bit), and a consumer killed
# mid-run fails the run instead of passing it with samples missing.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
HOGS=()
trap 'for h in "${HOGS[@]}"; do kill "$h" 2>/dev/null || true; done; stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7687?ttl=0'
"$SRC/deploy/make-identifier-config" --preset roll --duration 10 --build "$BUILD" --output "$OUT/id.json"
# With scheduled refits (odonata-fit's learner in a worker thread, begun at 200, 400 and 800
# samples, landing at 400 and 800): the online model still equals odonata-fit's replay of the
# same schedule on the exported samples. A landing waits for its refit, so the generator is
# given patience for it (300 resends of 200 ms) beside the pause below.
"$PY" - "$OUT/id.json" <<'PYEOF'
import json, sys
c = json.load(open(sys.argv[1]))
c.update(refit_first=200, refit_every=400, refit_buffer=600)
json.dump(c, open(sys.argv[1], "w"), indent=1)
PYEOF
for _ in $(seq "$(nproc)"); do
  (while :; do :; done) &
  HOGS+=($!)
done
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
start plant "$PLANT" --mode lockstep --preset roll --lcm-url "$URL"
start ident "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0 --save-model "$OUT/model.json"
wait_up "$URL" logger odonata-plant identifier -- --state running --state waiting
start signal "$SIGNAL" --preset roll --phase train --duration 10 --mode lockstep --lcm-url "$URL" \
  --hold-at 500 --max-resends 300 --wait-for identifier --wait-for logger
# Pause the identifier at sample 500 of 1000, then let the run go on: the window must wait for it.
wait_hold "$PID_signal" "$OUT/signal.log" 500
grep -q "waits for receipts from: identifier logger" "$OUT/signal.log" ||
  fail "the generator did not find both consumers: $(cat "$OUT/signal.log")"
kill -STOP "$PID_ident"
kill -USR1 "$PID_signal"
sleep 1  # the pause itself: five of the generator's 200 ms timeouts
kill -CONT "$PID_ident"
wait "$PID_signal" || fail "the run failed: $(cat "$OUT/signal.log")"
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
offline_fit "$OUT/id.json" "$OUT/train.csv" "$OUT/offline.json" unfrozen
same_model "$OUT/model.json" "$OUT/offline.json" || fail "the online model differs from the offline one"
grep -q "refit 2 landed at sample" "$OUT/ident.log" ||
  fail "the identifier did not land its two refits: $(cat "$OUT/ident.log")"
# The pause landed mid-run: the generator resent for the receipts it missed meanwhile.
waited=$(sed -nE 's/.* ([0-9]+) for missing receipts.*/\1/p' "$OUT/signal.log")
((${waited:-0} > 0)) || fail "no resend for missing receipts: the pause did not land mid-run ($(cat "$OUT/signal.log"))"

# A consumer killed mid-run: the generator fails loudly (exit 4) instead of finishing without it.
# (No refits here: the generator's short patience is for the kill, not for a refit landing.)
"$PY" -c "import json,sys; c=json.load(open(sys.argv[1])); c['refit_first']=0; json.dump(c, open(sys.argv[2], 'w'))" \
  "$OUT/id.json" "$OUT/id2.json"
start plant2 "$PLANT" --mode lockstep --preset roll --lcm-url "$URL"
start ident2 "$IDENT" --config "$OUT/id2.json" --lcm-url "$URL" --resume-wait 0 --instance ident2
wait_up "$URL" odonata-plant ident2 -- --state running --state waiting
start signal2 "$SIGNAL" --preset roll --phase train --duration 20 --mode lockstep --lcm-url "$URL" \
  --timeout-ms 50 --max-resends 4 --hold-at 1000
wait_hold "$PID_signal2" "$OUT/signal2.log" 1000
grep -q "waits for receipts from: ident2" "$OUT/signal2.log" ||
  fail "the generator did not find the identifier: $(cat "$OUT/signal2.log")"
kill -KILL "$PID_ident2"
kill -USR1 "$PID_signal2"
rc=0
wait "$PID_signal2" || rc=$?
((rc == 4)) || fail "losing a consumer gave exit code $rc, not 4: $(cat "$OUT/signal2.log")"
grep -q "no acknowledgement of state" "$OUT/signal2.log" || fail "no clear message: $(cat "$OUT/signal2.log")"
# ... and it names a state past the kill: the kill came mid-run, not after the end.
grep -qE "no acknowledgement of state 10[0-9][0-9] " "$OUT/signal2.log" ||
  fail "the failure is not at the kill (command 1000): $(cat "$OUT/signal2.log")"
pass "lockstep under load with a paused identifier: 1000 of 1000 samples logged and learned; a killed consumer fails the run"
