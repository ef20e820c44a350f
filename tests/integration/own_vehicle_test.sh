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
sleep 0.8
# 400 Hz: faster than a flight loop, slow enough that no process falls behind on a busy machine.
"$VEHICLE" --samples $N --rate 400 --lcm-url "$URL" >"$OUT/vehicle.log" 2>&1 || fail "the vehicle failed"
sleep 0.5
"$CONTROL" get --target own-vehicle-id --lcm-url "$URL" >"$OUT/get.out" 2>&1 || { cat "$OUT/get.out"; fail "the identifier did not answer get"; }
learned=$(sed -nE 's/.*samples_learned=([0-9]+).*/\1/p' "$OUT/get.out")
gaps=$(sed -nE 's/.* gaps=([0-9]+).*/\1/p' "$OUT/get.out")
# Sample 0 has no regressor yet (ny = nu = 1): every later one is learned.
[[ $learned == $((N - 1)) && $gaps == 0 ]] || { cat "$OUT/get.out"; fail "learned $learned of $((N - 1)) samples, $gaps gaps"; }
stop_clean "$PID_ident" "identifier"
stop_clean "$PID_monitor" "monitor"
stop_clean "$PID_logger" "logger"
fit=$(json_get "$OUT/monitor.json" "j['outputs']['vz_mps']['one_step']['fit']")
"$PY" -c "import sys; sys.exit(0 if float(sys.argv[1]) >= 95 else 1)" "$fit" || fail "live one-step FIT $fit % < 95 %"
"$LOGGER" export "$OUT"/log.* --signals -o "$OUT/samples.csv" >"$OUT/export.log" 2>&1 || { cat "$OUT/export.log"; fail "export --signals failed"; }
rows=$(($(wc -l <"$OUT/samples.csv") - 1))
((rows == N)) || fail "the export holds $rows of $N samples"
head -1 "$OUT/samples.csv" | grep -q "^seq,t_s,vz_mps,throttle,battery_v$" || fail "unexpected columns: $(head -1 "$OUT/samples.csv")"
offline_fit "$CFG" "$OUT/samples.csv" "$OUT/offline.json"
same_model "$OUT/model.json" "$OUT/offline.json" || fail "the online model differs from odonata-fit on the exported log"
rules=$(json_get "$OUT/model.json" "len(j['models'][0]['rules'])")
pass "own vehicle over signals_t: $learned samples learned, $rules rules, live one-step FIT $fit %, offline model identical"
