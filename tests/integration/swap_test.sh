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
wait_up "$URL" logger monitor odonata-plant identifier
# 60 s of commands: long enough for every swap below on a slow machine; the test stops the
# generator once the last swap is done, and fails if its run ended before that.
start signal "$SIGNAL" --preset roll --phase train --duration 60 --mode realtime --lcm-url "$URL"
# The first identifier stops once it has learned a few hundred samples (its heartbeat's count).
wait_count "$URL" identifier messages_in 600
stop_clean "$PID_ident1" "identifier (first instance)"
start ident2 "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 2 --save-model "$OUT/model.json"
wait_up "$URL" identifier -- --state running --fresh
stop_clean "$PID_logger" "logger (first instance)"
start logger2 "$LOGGER" record -o "$OUT/log2" --lcm-url "$URL"
stop_clean "$PID_monitor" "monitor (first instance)"
start monitor2 "$MONITOR" --lcm-url "$URL" --heartbeat-timeout 1.5 --summary-json "$OUT/monitor.json"
wait_up "$URL" logger monitor -- --fresh
# A plant heartbeat sent after the new monitor was up: the monitor knows the plant it will miss.
wait_up "$URL" odonata-plant -- --fresh
kill -KILL "$PID_plant"
wait_for_log "$OUT/monitor2.log" "odonata-plant.*silent" 30 || { cat "$OUT/monitor2.log"; fail "the new monitor did not report the killed plant"; }
start plant2 "$PLANT" --mode realtime --preset roll --lcm-url "$URL"
wait_for_log "$OUT/monitor2.log" "odonata-plant.*is back" 30 || { cat "$OUT/monitor2.log"; fail "the new monitor did not see the new plant"; }
# The new plant has taken over once it has applied commands (its heartbeat's count): its first
# state comes after its heartbeat, and a run with no commands would leave nothing to export.
wait_up "$URL" odonata-plant -- --fresh --at-least messages_in=20
# Every swap happened while the generator was still sending: it must still run, and stop cleanly.
kill -0 "$PID_signal" 2>/dev/null || fail "the generator's run ended before the swaps did: $(cat "$OUT/signal.log")"
# Stopped before its last command, the generator says the run is not complete (exit 5).
stop_clean "$PID_signal" "the signal generator, still running after the swaps" 5
grep -q "stopped by a signal after" "$OUT/signal.log" || fail "the interrupted generator did not say so"
# The plant that took over numbers its states from 0: the generator flags the split run.
grep -q "odonata-plant restarted at command" "$OUT/signal.log" ||
  fail "the generator did not flag the plant's restart: $(cat "$OUT/signal.log")"
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
[[ -s $OUT/monitor.json ]] || fail "the new monitor wrote no summary"

"$LOGGER" export "$OUT"/log.* "$OUT"/log2.* -o "$OUT/samples.csv" --predictions "$OUT/pred.csv" >"$OUT/export.log" 2>&1 || { cat "$OUT/export.log"; fail "export failed"; }
[[ $(wc -l <"$OUT/pred.csv") -gt 300 ]] || fail "too few predictions recorded across the swaps"
[[ -s $OUT/model.json ]] || fail "the second identifier did not save its model"
pass "identifier resumed from sample $resumed of $learned; logger and monitor replaced; plant killed, reported silent, replaced; all while the generator ran"
