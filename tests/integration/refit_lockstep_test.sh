#!/usr/bin/env bash
# A lockstep run whose identifier lands scheduled refits, with a generator whose own patience is
# far shorter than a refit (50 ms timeouts, 2 resends): the identifier says "refitting" on its
# heartbeat before a landing waits, the generator waits without resending, and the run ends
# complete, its model odonata-fit's replay of the same schedule bit for bit.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7693?ttl=0'
"$SRC/deploy/make-identifier-config" --preset roll --duration 10 --build "$BUILD" --output "$OUT/id.json" \
  --refit-first 200 --refit-every 400
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
start ident "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0 --save-model "$OUT/model.json"
wait_up "$URL" logger odonata-plant identifier -- --state running --state waiting
timeout 300 "$SIGNAL" --preset roll --phase train --duration 10 --mode lockstep --lcm-url "$URL" \
  --timeout-ms 50 --max-resends 2 >"$OUT/signal.log" 2>&1 || fail "the run failed: $(cat "$OUT/signal.log")"
stop_clean "$PID_ident" identifier
stop_clean "$PID_plant" plant
stop_clean "$PID_logger" logger
grep -q "refit 2 landed at sample" "$OUT/ident.log" ||
  fail "the identifier did not land its two refits: $(cat "$OUT/ident.log")"
"$LOGGER" export "$OUT"/log.* -o "$OUT/train.csv" >"$OUT/export.log" 2>&1 || { cat "$OUT/export.log"; fail "export failed"; }
rows=$(($(wc -l <"$OUT/train.csv") - 1))
((rows == 1000)) || fail "the log holds $rows of 1000 samples"
offline_fit "$OUT/id.json" "$OUT/train.csv" "$OUT/offline.json" unfrozen
same_model "$OUT/model.json" "$OUT/offline.json" || fail "the online model differs from odonata-fit's replay"
busy=$(sed -nE 's/.*waited ([0-9]+) timeout\(s\) for consumers landing.*/\1/p' "$OUT/signal.log")
pass "two refits landed in lockstep with 100 ms of generator patience (${busy:-0} timeouts waited, nothing lost); model == odonata-fit's replay"
