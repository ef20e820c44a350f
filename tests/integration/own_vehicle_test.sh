#!/usr/bin/env bash
# Your own vehicle: a process written only against signals_t (examples/own_vehicle) is
# identified end to end over udpm: the identifier (source "signals") learns every sample, the
# monitor scores it, the logger records it, `odonata-logger export --signals` turns the log into
# the CSV odonata-fit reads, and odonata-fit on that CSV gives the online model bit for bit.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7686?ttl=0'
VEHICLE=$BUILD/examples/own_vehicle/own-vehicle
CFG=$SRC/examples/own_vehicle/identifier.json
N=2000
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
start monitor "$MONITOR" --lcm-url "$URL" --summary-json "$OUT/monitor.json"
start ident "$IDENT" --config "$CFG" --lcm-url "$URL" --resume-wait 0 --save-model "$OUT/model.json"
wait_up "$URL" logger monitor own-vehicle-id
# 400 Hz: faster than a flight loop, slow enough that no process falls behind on a busy machine.
"$VEHICLE" --samples $N --rate 400 --lcm-url "$URL" >"$OUT/vehicle.log" 2>&1 || fail "the vehicle failed"
wait_up "$URL" own-vehicle-id -- --fresh
# On this machine none is lost, even with both cores busy, but that is a benchmark figure, not a
# promise: the test asserts the accounting (lib.sh).
vehicle_accounting "$URL" own-vehicle-id $N
stop_clean "$PID_ident" "identifier"
stop_clean "$PID_monitor" "monitor"
stop_clean "$PID_logger" "logger"
fit=$(json_get "$OUT/monitor.json" "j['outputs']['vz_mps']['one_step']['fit']")
"$PY" -c "import sys; sys.exit(0 if float(sys.argv[1]) >= 95 else 1)" "$fit" || fail "live one-step FIT $fit % < 95 %"
"$LOGGER" export "$OUT"/log.* --signals -o "$OUT/samples.csv" >"$OUT/export.log" 2>&1 || { cat "$OUT/export.log"; fail "export --signals failed"; }
head -1 "$OUT/samples.csv" | grep -q "^seq,t_s,vz_mps,throttle,battery_v$" || fail "unexpected columns: $(head -1 "$OUT/samples.csv")"
vehicle_offline_equal "$CFG" "$OUT/samples.csv" "$OUT/model.json" $N
rules=$(json_get "$OUT/model.json" "len(j['models'][0]['rules'])")
# The live ARX beside it, scored on the same samples (docs/identifier.md §6.4).
live=$(json_get "$OUT/monitor.json" "'free run %.2f %% against the live ARX %.2f %%' % (j['outputs']['vz_mps']['free_run']['fit'], j['outputs']['vz_mps']['arx']['free_run']['fit'])")
pass "own vehicle over signals_t: $LEARNED samples learned, $rules rules, live one-step FIT $fit %, $live, $SAME"
