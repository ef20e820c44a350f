#!/usr/bin/env bash
# Stop and restart services while the rest run, in real time: the identifier stops cleanly and
# a new instance resumes from its last snapshot (kept by the monitor); the plant is killed
# outright, the monitor reports it silent, and a new plant takes over; the others keep working.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7682?ttl=0'
"$SRC/deploy/make-identifier-config" --preset roll --duration 8 --build "$BUILD" --output "$OUT/id.json"
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
start monitor "$MONITOR" --lcm-url "$URL" --heartbeat-timeout 1.5 --summary-json "$OUT/monitor.json"
start plant "$PLANT" --mode realtime --preset roll --lcm-url "$URL"
start ident1 "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0
sleep 0.5
start signal "$SIGNAL" --preset roll --phase train --duration 8 --mode realtime --lcm-url "$URL"
sleep 2.5
stop_clean "$PID_ident1" "identifier (first instance)"
sleep 0.3
start ident2 "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 2 --save-model "$OUT/model.json"
sleep 1.5
kill -KILL "$PID_plant"
sleep 2.2
start plant2 "$PLANT" --mode realtime --preset roll --lcm-url "$URL"
wait "$PID_signal" || fail "the signal generator failed while services were swapped"
sleep 0.5
for p in "$PID_ident2" "$PID_monitor" "$PID_logger" "$PID_plant2"; do
  kill -0 "$p" 2>/dev/null || fail "a service died during the swaps"
done
stop_clean "$PID_ident2" "identifier (second instance)"
stop_clean "$PID_plant2" "plant (second instance)"
stop_clean "$PID_monitor" monitor
stop_clean "$PID_logger" logger
grep -q "from the bus snapshot of sample" "$OUT/ident2.log" || { cat "$OUT/ident2.log"; fail "the new identifier did not resume from the snapshot"; }
resumed=$(sed -n 's/.*from the bus snapshot of sample \([0-9]*\).*/\1/p' "$OUT/ident2.log")
((resumed > 100)) || fail "resumed from sample $resumed only"
grep -q "odonata-plant.*silent" "$OUT/monitor.log" || { cat "$OUT/monitor.log"; fail "the monitor did not report the killed plant"; }
grep -q "odonata-plant.*is back" "$OUT/monitor.log" || fail "the monitor did not see the new plant"

"$LOGGER" export "$OUT"/log.* -o "$OUT/samples.csv" --predictions "$OUT/pred.csv" >/dev/null 2>&1 || fail "export failed"
[[ $(wc -l <"$OUT/pred.csv") -gt 300 ]] || fail "too few predictions recorded across the swaps"
[[ -s $OUT/model.json ]] || fail "the second identifier did not save its model"
pass "identifier resumed from sample $resumed; plant killed, reported silent, replaced; generator finished"
