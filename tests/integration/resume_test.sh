#!/usr/bin/env bash
# kill -9 of the identifier mid-run (lockstep, 6000 samples, the generator holding at command
# 3000 while the kill lands), restarted at once: it resumes from the monitor's
# copy of its last snapshot with that snapshot's learned-sample count, the generator waits for it
# meanwhile, and the samples the kill costs are exactly those learned since that snapshot plus
# those the resumed history needs: ny = 3 to refill the regressor, and one more when the process
# died after predicting a sample but before its receipt went out (the generator then resends the
# answer it already had, and the resumed history starts one state earlier).
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7688?ttl=0'
"$SRC/deploy/make-identifier-config" --preset roll --duration 60 --build "$BUILD" --output "$OUT/id.json"
every=$(json_get "$OUT/id.json" "j['snapshot_every_samples']")
ny=$(json_get "$OUT/id.json" "j['ny']")
HOLD=3000  # of 6000: the kill lands here, whatever the machine's speed
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
start monitor "$MONITOR" --lcm-url "$URL"
start plant "$PLANT" --mode lockstep --preset roll --lcm-url "$URL"
start ident1 "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0
wait_up "$URL" logger monitor odonata-plant identifier -- --state running --state waiting
start signal "$SIGNAL" --preset roll --phase train --duration 60 --mode lockstep --lcm-url "$URL" \
  --timeout-ms 200 --max-resends 40 --hold-at $HOLD
# The run stands still at command HOLD with every state up to it learned and acknowledged: the
# kill lands there, mid-run, at any speed.
wait_hold "$PID_signal" "$OUT/signal.log" $HOLD
grep -q "waits for receipts from: identifier logger" "$OUT/signal.log" ||
  fail "the generator did not find both consumers: $(cat "$OUT/signal.log")"
kill -KILL "$PID_ident1"
start ident2 "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 3 --save-model "$OUT/model.json"
# The run goes on once the new identifier has resumed and learns: a consumer that starts in the
# middle of a burst of states would take the first it hears for the start of its history, and
# the generator cannot tell it missed the ones before (the receipt names only the newest held).
wait_up "$URL" identifier -- --state running --fresh
kill -USR1 "$PID_signal"
wait "$PID_signal" || fail "the run failed: $(cat "$OUT/signal.log")"
stop_clean "$PID_ident2" "restarted identifier"
stop_clean "$PID_plant" plant
stop_clean "$PID_monitor" monitor
stop_clean "$PID_logger" logger
grep -q "from the bus snapshot after" "$OUT/ident2.log" || fail "no resume: $(cat "$OUT/ident2.log")"
"$LOGGER" export "$OUT"/log.* -o "$OUT/train.csv" --predictions "$OUT/pred.csv" >"$OUT/export.log" 2>&1 ||
  { cat "$OUT/export.log"; fail "export failed"; }
"$PY" - "$OUT" "$every" "$ny" "$HOLD" <<'PYEOF'
import csv, re, sys
out, every, ny, hold = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
resumed = int(re.search(r"from the bus snapshot after (\d+) learned", open(f"{out}/ident2.log").read()).group(1))
final = int(re.search(r"\((\d+) rules, (\d+) samples learned\)", open(f"{out}/ident2.log").read()).group(2))
samples = [int(r["sample"]) for r in csv.DictReader(open(f"{out}/pred.csv"))]
rows = sum(1 for _ in open(f"{out}/train.csv")) - 1
jumps = [(a, b) for a, b in zip(samples, samples[1:]) if b != a + 1]
def fail(msg):
    print(f"FAIL: {msg} (resumed {resumed}, final {final}, jumps {jumps})"); sys.exit(1)
if len(jumps) != 1: fail("the predictions should have exactly one hole, at the kill")
last1, first2 = jumps[0]
# The kill came while the run stood at the hold: the first identifier's last prediction is the
# newest state it had acknowledged, the one just before the held command.
if not 0 < last1 < rows - 1: fail(f"the kill did not land mid-run (last prediction {last1} of {rows})")
if last1 != hold - 1: fail(f"the first identifier's last prediction is {last1}, not {hold - 1} at the hold")
n1 = sum(1 for s in samples if s <= last1)
n2 = len(samples) - n1
learnable = rows - ny  # every sample with a full regressor, had nothing been lost
since_snapshot = n1 - resumed
hole = first2 - last1 - 1
if hole not in (ny, ny + 1): fail(f"the hole should be ny or ny + 1 samples, not {hole}")
if not 0 <= since_snapshot < every: fail(f"{since_snapshot} samples learned since the last snapshot")
if final != resumed + n2: fail("the resumed count does not carry on from the snapshot's")
if learnable - final != since_snapshot + hole: fail("samples lost do not add up")
print(f"kill -9 cost {learnable - final} samples: {since_snapshot} learned since the last snapshot "
      f"(< {every}) + {hole} to resume the history; {final} of {learnable} learned")
PYEOF
pass "kill -9 and restart: resumed from the last snapshot, every lost sample accounted for"
