#!/usr/bin/env bash
# A lockstep run whose identifier lands scheduled refits (choosing 10 steps ahead), with a
# generator whose own patience is far shorter than a refit (50 ms timeouts, 4 resends: 0.2 s,
# where 0.1 s failed once when a CPU-starved identifier — its refit worker beside it, three other
# test processes on two cores — answered a sample that landed nothing 150 ms late): the
# identifier says "refitting" on its heartbeat before a landing waits, the generator waits without
# resending, and the run ends complete, its model odonata-fit's replay of the same schedule bit
# for bit.
# Then the next phase starts while the identifier is blocked on its freeze's closing refit (a
# save-model waits for it): the identifier keeps beating "refitting", so the new generator counts
# it as a consumer and waits for it; every validation sample is predicted, and the frozen model
# is odonata-fit's frozen replay. (Before, a generator whose 1.1 s discovery fell inside that
# wait heard nothing, ran without the identifier, and the validation scored 3 samples.)
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7693?ttl=0'
"$SRC/deploy/make-identifier-config" --preset roll --duration 10 --build "$BUILD" --output "$OUT/id.json" \
  --refit-first 200 --refit-every 400 --refit-horizon 10
"$PY" - "$OUT/id.json" <<'PYEOF'
import json, sys
c = json.load(open(sys.argv[1]))
# 1000 samples through an 800-sample buffer, three quarters of it archive blocks of 100: the
# buffer spreads over the run, and the service must keep the same samples as the replay.
c.update(refit_buffer=800, refit_history=0.75)
json.dump(c, open(sys.argv[1], "w"), indent=1)
PYEOF
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
start plant "$PLANT" --mode lockstep --preset roll --lcm-url "$URL"
mkdir -p "$OUT/models"
start ident "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0 --save-model "$OUT/model.json" \
  --models-dir "$OUT/models"
wait_up "$URL" logger odonata-plant identifier -- --state running --state waiting
timeout 300 "$SIGNAL" --preset roll --phase train --duration 10 --mode lockstep --lcm-url "$URL" \
  --timeout-ms 50 --max-resends 4 >"$OUT/signal.log" 2>&1 || fail "the run failed: $(cat "$OUT/signal.log")"
ctl() { "$CONTROL" "$@" --target identifier --lcm-url "$URL" --timeout 60; }
ctl save-model trained.json >"$OUT/save-trained.log" 2>&1 || fail "save-model: $(cat "$OUT/save-trained.log")"
ctl freeze >"$OUT/freeze.log" 2>&1 || fail "freeze: $(cat "$OUT/freeze.log")"
ctl save-model frozen.json >"$OUT/save-frozen.log" 2>&1 &
saving=$!
timeout 300 "$SIGNAL" --preset roll --phase validate --duration 10 --mode lockstep --lcm-url "$URL" \
  >"$OUT/signal-validate.log" 2>&1 || fail "the validation run failed: $(cat "$OUT/signal-validate.log")"
# The run has ended, so the closing refit has landed, and once odonata-control returns the save
# is done. Its answer may not have come: under the sanitizers beside CPU hogs the closing refit
# outlasts odonata-control's longest wait (60 s), and it exits 3; the file is what counts.
wait "$saving" || true
[[ -s $OUT/models/frozen.json ]] || fail "save-model after the freeze wrote nothing: $(cat "$OUT/save-frozen.log")"
stop_clean "$PID_ident" identifier
stop_clean "$PID_plant" plant
stop_clean "$PID_logger" logger
grep -q "refit 2 landed at sample" "$OUT/ident.log" ||
  fail "the identifier did not land its two refits: $(cat "$OUT/ident.log")"
grep -q "lockstep waits for receipts from:.* identifier" "$OUT/signal-validate.log" ||
  fail "the validation run's generator did not wait for the identifier: $(cat "$OUT/signal-validate.log")"
"$LOGGER" export "$OUT"/log.* --run 0 -o "$OUT/train.csv" >"$OUT/export.log" 2>&1 || { cat "$OUT/export.log"; fail "export failed"; }
rows=$(($(wc -l <"$OUT/train.csv") - 1))
((rows == 1000)) || fail "the log holds $rows of 1000 samples"
offline_fit "$OUT/id.json" "$OUT/train.csv" "$OUT/offline.json" unfrozen
same_model "$OUT/models/trained.json" "$OUT/offline.json" || fail "the online model differs from odonata-fit's replay"
# The refits chose 10 steps ahead (refit_horizon), as the replay's --horizon did: choosing in free
# run, the same refits give another model, so the comparison above saw the key at work.
"$PY" -c "import json,sys; c=json.load(open(sys.argv[1])); c['refit_horizon']=0; json.dump(c, open(sys.argv[2], 'w'))" \
  "$OUT/id.json" "$OUT/id-free-run.json"
offline_fit "$OUT/id-free-run.json" "$OUT/train.csv" "$OUT/offline-free-run.json" unfrozen
! same_model "$OUT/offline.json" "$OUT/offline-free-run.json" ||
  fail "refits choosing in free run gave the same model: the test cannot tell whether refit_horizon was read"
offline_fit "$OUT/id.json" "$OUT/train.csv" "$OUT/offline-frozen.json"
same_model "$OUT/models/frozen.json" "$OUT/offline-frozen.json" ||
  fail "the model after the freeze differs from odonata-fit's frozen replay"
same_model "$OUT/model.json" "$OUT/offline-frozen.json" || fail "the model saved at the stop is not the frozen one"
# Both runs predicted every sample they could (the same count: the same length and lags).
"$LOGGER" export "$OUT"/log.* -o "$OUT/last.csv" --predictions "$OUT/predictions.csv" >"$OUT/export-pred.log" 2>&1 ||
  { cat "$OUT/export-pred.log"; fail "export of the predictions failed"; }
read -r train_pred valid_pred < <("$PY" -c "
import csv, sys
runs = [r['run'] for r in csv.DictReader(open(sys.argv[1]))]
print(runs.count('0'), runs.count('1'))" "$OUT/predictions.csv")
((train_pred > 0 && valid_pred == train_pred)) ||
  fail "the identifier predicted $valid_pred validation samples, against $train_pred in training"
busy=$(sed -nE 's/.*waited ([0-9]+) timeout\(s\) for consumers landing.*/\1/p' "$OUT/signal.log")
busy_valid=$(sed -nE 's/.*waited ([0-9]+) timeout\(s\) for consumers landing.*/\1/p' "$OUT/signal-validate.log")
pass "two refits landed in lockstep with 200 ms of generator patience (${busy:-0} timeouts waited, nothing lost); model == odonata-fit's replay (not its free-run choice); the next run, started during the closing refit (${busy_valid:-0} timeouts waited for it), predicted all $valid_pred samples; frozen model == odonata-fit's frozen replay"
