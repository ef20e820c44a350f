#!/usr/bin/env bash
# kill -9 of the identifier mid-run (lockstep; 6000 samples, so the kill lands mid-run at the
# fastest rate), restarted at once: it resumes from the monitor's
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
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
start monitor "$MONITOR" --lcm-url "$URL"
start plant "$PLANT" --mode lockstep --preset roll --lcm-url "$URL"
start ident1 "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0
sleep 0.5
start signal "$SIGNAL" --preset roll --phase train --duration 60 --mode lockstep --lcm-url "$URL" \
  --timeout-ms 200 --max-resends 40
wait_for_log "$OUT/signal.log" "waits for receipts" || true
sleep 0.3
# Stopped first, so the run halts at a definite sample (it waits for the receipt), then killed.
kill -STOP "$PID_ident1"
sleep 0.3
kill -KILL "$PID_ident1"
start ident2 "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 3 --save-model "$OUT/model.json"
wait "$PID_signal" || fail "the run failed: $(cat "$OUT/signal.log")"
sleep 0.3
stop_clean "$PID_ident2" "restarted identifier"
stop_clean "$PID_plant" plant
stop_clean "$PID_monitor" monitor
stop_clean "$PID_logger" logger
grep -q "from the bus snapshot after" "$OUT/ident2.log" || fail "no resume: $(cat "$OUT/ident2.log")"
"$LOGGER" export "$OUT"/log.* -o "$OUT/train.csv" --predictions "$OUT/pred.csv" >"$OUT/export.log" 2>&1 ||
  { cat "$OUT/export.log"; fail "export failed"; }
"$PY" - "$OUT" "$every" "$ny" <<'PYEOF'
import csv, re, sys
out, every, ny = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
resumed = int(re.search(r"from the bus snapshot after (\d+) learned", open(f"{out}/ident2.log").read()).group(1))
final = int(re.search(r"\((\d+) rules, (\d+) samples learned\)", open(f"{out}/ident2.log").read()).group(2))
samples = [int(r["sample"]) for r in csv.DictReader(open(f"{out}/pred.csv"))]
rows = sum(1 for _ in open(f"{out}/train.csv")) - 1
jumps = [(a, b) for a, b in zip(samples, samples[1:]) if b != a + 1]
def fail(msg):
    print(f"FAIL: {msg} (resumed {resumed}, final {final}, jumps {jumps})"); sys.exit(1)
if len(jumps) != 1: fail("the predictions should have exactly one hole, at the kill")
last1, first2 = jumps[0]
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
