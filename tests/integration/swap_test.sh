#!/usr/bin/env bash
# Stop and restart services while the rest run, in real time: the identifier stops cleanly and
# a new instance resumes from its last snapshot (kept by the monitor) with every sample the first
# one learned; the logger and the monitor are replaced by new instances; the plant is killed
# outright, the new monitor reports it silent, and a new plant takes over; the others keep working.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7682?ttl=0'
"$SRC/deploy/make-identifier-config" --preset roll --duration 10 --build "$BUILD" --output "$OUT/id.json"
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
start monitor "$MONITOR" --lcm-url "$URL" --heartbeat-timeout 1.5 --summary-json "$OUT/monitor.json"
start plant "$PLANT" --mode realtime --preset roll --lcm-url "$URL"
start ident1 "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0 --save-model "$OUT/model1.json"
sleep 0.5
start signal "$SIGNAL" --preset roll --phase train --duration 10 --mode realtime --lcm-url "$URL"
sleep 2.5
stop_clean "$PID_ident1" "identifier (first instance)"
sleep 0.3
start ident2 "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 2 --save-model "$OUT/model.json"
sleep 1.5
stop_clean "$PID_logger" "logger (first instance)"
start logger2 "$LOGGER" record -o "$OUT/log2" --lcm-url "$URL"
stop_clean "$PID_monitor" "monitor (first instance)"
start monitor2 "$MONITOR" --lcm-url "$URL" --heartbeat-timeout 1.5 --summary-json "$OUT/monitor.json"
sleep 1.5
kill -KILL "$PID_plant"
sleep 2.2
start plant2 "$PLANT" --mode realtime --preset roll --lcm-url "$URL"
wait "$PID_signal" || fail "the signal generator failed while services were swapped"
sleep 0.5
for p in "$PID_ident2" "$PID_monitor2" "$PID_logger2" "$PID_plant2"; do
  kill -0 "$p" 2>/dev/null || fail "a service died during the swaps"
done
stop_clean "$PID_ident2" "identifier (second instance)"
stop_clean "$PID_plant2" "plant (second instance)"
stop_clean "$PID_monitor2" "monitor (second instance)"
stop_clean "$PID_logger2" "logger (second instance)"
grep -q "from the bus snapshot after" "$OUT/ident2.log" || { cat "$OUT/ident2.log"; fail "the new identifier did not resume from the snapshot"; }
resumed=$(sed -n 's/.*from the bus snapshot after \([0-9]*\) learned.*/\1/p' "$OUT/ident2.log")
# The first instance's last snapshot is the model it saved on exit: not one sample may be lost.
learned=$(sed -n 's/.*model saved to .*, \([0-9]*\) samples learned.*/\1/p' "$OUT/ident1.log")
[[ -n $learned && $resumed == "$learned" ]] || { cat "$OUT/ident1.log" "$OUT/ident2.log"; fail "resumed from sample $resumed, but the first identifier had learned ${learned:-?}"; }
((resumed > 100)) || fail "resumed from sample $resumed only"
grep -q "odonata-plant.*silent" "$OUT/monitor2.log" || { cat "$OUT/monitor2.log"; fail "the new monitor did not report the killed plant"; }
grep -q "odonata-plant.*is back" "$OUT/monitor2.log" || fail "the new monitor did not see the new plant"
[[ -s $OUT/monitor.json ]] || fail "the new monitor wrote no summary"

"$LOGGER" export "$OUT"/log.* "$OUT"/log2.* -o "$OUT/samples.csv" --predictions "$OUT/pred.csv" >"$OUT/export.log" 2>&1 || { cat "$OUT/export.log"; fail "export failed"; }
[[ $(wc -l <"$OUT/pred.csv") -gt 300 ]] || fail "too few predictions recorded across the swaps"
[[ -s $OUT/model.json ]] || fail "the second identifier did not save its model"
pass "identifier resumed from sample $resumed of $learned; logger and monitor replaced; plant killed, reported silent, replaced; generator finished"
