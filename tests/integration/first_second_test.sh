#!/usr/bin/env bash
# The first second of a flight is learned (issue 47 point 3). An identifier started without a
# model waits resume_wait_s for a snapshot to resume from; a vehicle that takes off meanwhile
# (here: it starts streaming as soon as the identifier is up and waiting) must not lose those
# samples. They are kept while it waits and learned, in order, once it starts: every sample sent
# is learned or counted as a gap, and odonata-fit on the exported log gives the same model.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7697?ttl=0'
CFG=$SRC/examples/own_vehicle/identifier.json
export PYTHONPATH=$SRC/python
N=800
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
# Three seconds of waiting: at 400 Hz the vehicle's first 1 200 samples would all arrive in it.
start ident "$IDENT" --config "$CFG" --lcm-url "$URL" --resume-wait 3 --save-model "$OUT/model.json"
wait_up "$URL" logger
wait_up "$URL" own-vehicle-id -- --state waiting
"$PY" "$SRC/examples/own_vehicle/vehicle.py" --samples $N --rate 400 --lcm-url "$URL" \
  >"$OUT/vehicle.log" 2>&1 || { cat "$OUT/vehicle.log"; fail "vehicle.py failed"; }
# Every sample was sent while the identifier waited: it learns them once the wait ends.
wait_up "$URL" own-vehicle-id -- --state running --fresh
vehicle_accounting "$URL" own-vehicle-id $N
# ny = nu = 1: sample 0 starts the history, every later one is learned or counted as lost.
((LEARNED + GAPS == N - 1)) ||
  { cat "$OUT/get.out"; fail "learned $LEARNED and lost $GAPS of the $((N - 1)) samples after the first"; }
grep -q "samples that came in while it waited" "$OUT/ident.log" ||
  { cat "$OUT/ident.log"; fail "the identifier did not say it learned what came in while it waited"; }
stop_clean "$PID_ident" "identifier"
stop_clean "$PID_logger" "logger"
"$LOGGER" export "$OUT"/log.* --signals -o "$OUT/samples.csv" >"$OUT/export.log" 2>&1 ||
  { cat "$OUT/export.log"; fail "export --signals failed"; }
vehicle_offline_equal "$CFG" "$OUT/samples.csv" "$OUT/model.json" $N
pass "a flight that starts while the identifier waits for a snapshot: $LEARNED of $((N - 1)) samples learned, $GAPS lost; $SAME"
