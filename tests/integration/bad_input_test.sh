#!/usr/bin/env bash
# Foreign and corrupt traffic on every channel during a lockstep run: nothing crashes, the
# problems are counted in the heartbeats, the model is exactly what the clean samples give, and
# the logger keeps everything (the garbage included).
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7683?ttl=0'
"$SRC/deploy/make-identifier-config" --preset roll --duration 10 --build "$BUILD" --output "$OUT/id.json"
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
start monitor "$MONITOR" --lcm-url "$URL" --summary-json "$OUT/monitor.json"
start plant "$PLANT" --mode lockstep --preset roll --lcm-url "$URL"
start ident "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0 --save-model "$OUT/model.json"
wait_up "$URL" logger monitor odonata-plant identifier
start bad "$BUILD/tests/integration/bad_input_publisher" "$URL" 600 5
# The garbage is on the bus before the run starts: the plant has already counted some.
wait_count "$URL" odonata-plant decode_errors 1
timeout 120 "$SIGNAL" --preset roll --phase train --duration 10 --mode lockstep --lcm-url "$URL" \
  >"$OUT/signal.log" 2>&1 || { cat "$OUT/signal.log"; fail "the run did not complete under bad input"; }
# The monitor's summary takes the counters from heartbeats: wait for ones that carry them.
wait_up "$URL" identifier odonata-plant logger -- --fresh --at-least decode_errors=1
wait_count "$URL" odonata-plant dropped 1
for p in "$PID_logger" "$PID_monitor" "$PID_plant" "$PID_ident"; do
  kill -0 "$p" 2>/dev/null || fail "a service crashed under bad input"
done
kill -TERM "$PID_bad" 2>/dev/null || true
stop_clean "$PID_ident" identifier
stop_clean "$PID_plant" plant
stop_clean "$PID_monitor" monitor
stop_clean "$PID_logger" logger
for s in identifier odonata-plant; do
  n=$(json_get "$OUT/monitor.json" "j['services']['$s']['decode_errors']")
  ((n > 0)) || fail "$s reported no decode errors"
done
# Forged predictions (one far ahead) must not split the run or open a gap in its score.
scored=$(json_get "$OUT/monitor.json" "'previous_runs' not in j and j['gaps'] == 0 and j['last_sample'] >= 990")
[[ $scored == True ]] || fail "the monitor's score was disturbed by forged predictions: $(cat "$OUT/monitor.json")"
# Datagrams LCM hands on with a negative size never reach the log file.
n=$(json_get "$OUT/monitor.json" "j['services']['logger']['decode_errors']")
((n > 0)) || fail "the logger counted no malformed datagram"
d=$(json_get "$OUT/monitor.json" "j['services']['odonata-plant']['dropped']")
((d > 0)) || fail "the plant dropped no NaN/out-of-range command"
"$LOGGER" export "$OUT"/log.* -o "$OUT/train.csv" >"$OUT/export.log" 2>&1 || { cat "$OUT/export.log"; fail "export failed"; }
rows=$(($(wc -l <"$OUT/train.csv") - 1))
((rows == 1000)) || fail "the logger lost samples: $rows of 1000"
grep -q "skipped [1-9][0-9]* undecodable" "$OUT/export.log" || fail "the log does not hold the bad messages"
offline_fit "$OUT/id.json" "$OUT/train.csv" "$OUT/offline.json"
same_model "$OUT/model.json" "$OUT/offline.json" || fail "bad input changed the model"
pass "bad input counted and dropped; model == clean-sample model; log kept all $rows samples and the garbage"
