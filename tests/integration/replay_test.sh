#!/usr/bin/env bash
# A recorded flight replayed onto the bus (issue 48 point 2): odonata-replay publishes a CSV as
# VEHICLE_SIGNALS. In lockstep with the identifier's and the logger's receipts nothing is lost
# and the live model is odonata-fit's replay of the identifier on the same CSV, bit for bit; the
# monitor scores it and the logger's export gives the CSV back. Paced (--speed), the accounting
# holds: every sample is learned or counted as a gap. A consumer that never answers is named.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7688?ttl=0'
REPLAY=$BUILD/services/replay/odonata-replay
CFG=$SRC/examples/own_vehicle/identifier.json
N=1500
# A flight: vertical speed from throttle, a first-order lag with a drag that grows with speed,
# logged at 100 Hz with its own time column and a signal the identifier does not use.
"$PY" - "$OUT/flight.csv" $N <<'PYEOF'
import math, random, sys
path, n = sys.argv[1], int(sys.argv[2])
rng = random.Random(5)
vz, u, rows = 0.0, 0.65, []
for k in range(n):
    if k % 40 == 0:
        u = rng.uniform(0.4, 0.9)
    rows.append((0.01 * k, vz, u, 11.1 - 0.0002 * k))
    vz += 0.01 * (14.0 * (u - 0.65) - 0.8 * vz - 0.15 * vz * abs(vz))
with open(path, "w") as f:
    f.write("t_s,vz_mps,throttle,battery_v\n")
    for r in rows:
        f.write("%.2f,%.17g,%.17g,%.17g\n" % r)
PYEOF
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
start monitor "$MONITOR" --lcm-url "$URL" --summary-json "$OUT/monitor.json"
start ident "$IDENT" --config "$CFG" --lcm-url "$URL" --save-model "$OUT/model.json"
wait_up "$URL" logger monitor own-vehicle-id -- --state running
"$REPLAY" "$OUT/flight.csv" --lockstep --lcm-url "$URL" --summary-json "$OUT/replay.json" \
  >"$OUT/replay.out" 2>"$OUT/replay.err" || { cat "$OUT/replay.err"; fail "the lockstep replay failed"; }
grep -q "sent $N of $N samples" "$OUT/replay.out" || fail "summary: $(cat "$OUT/replay.out")"
consumers=$(json_get "$OUT/replay.json" "','.join(sorted(j['consumers']))")
[[ $consumers == "logger,own-vehicle-id" ]] || fail "waited for '$consumers', not the logger and the identifier"
GAPS=0
vehicle_accounting "$URL" own-vehicle-id $N
((LEARNED == N - 1)) || fail "lockstep: $LEARNED of $((N - 1)) samples learned"
stop_clean "$PID_ident" "identifier"
stop_clean "$PID_monitor" "monitor"
stop_clean "$PID_logger" "logger"
# The live model is odonata-fit's on the file it was replayed from (not frozen: no closing refit).
offline_fit "$CFG" "$OUT/flight.csv" "$OUT/offline.json" unfrozen
same_model "$OUT/model.json" "$OUT/offline.json" || fail "the replayed live model differs from odonata-fit on the CSV"
"$LOGGER" export "$OUT"/log.* --signals -o "$OUT/back.csv" >"$OUT/export.log" 2>&1 || { cat "$OUT/export.log"; fail "export failed"; }
rows=$(($(grep -vc '^#' "$OUT/back.csv") - 1))
((rows == N)) || fail "the log holds $rows of $N samples"
fit=$(json_get "$OUT/monitor.json" "round(j['outputs']['vz_mps']['one_step']['fit'], 2)")

# Paced, four times the flight's speed: every sample learned or counted.
PIDS=()
start ident "$IDENT" --config "$CFG" --lcm-url "$URL" --resume-wait 0
wait_up "$URL" own-vehicle-id -- --state running
"$REPLAY" "$OUT/flight.csv" --speed 4 --lcm-url "$URL" >"$OUT/paced.out" 2>"$OUT/paced.err" ||
  { cat "$OUT/paced.err"; fail "the paced replay failed"; }
grep -q "at 4× the flight's pace" "$OUT/paced.out" || fail "paced summary: $(cat "$OUT/paced.out")"
vehicle_accounting "$URL" own-vehicle-id $N
paced=$LEARNED
stop_clean "$PID_ident" "identifier"

# Waiting for a consumer that is not there ends with its name, not a hang.
rc=0
"$REPLAY" "$OUT/flight.csv" --lockstep --discover 0 --wait-for ghost-id --timeout-ms 20 --max-resends 5 \
  --lcm-url "$URL" >"$OUT/ghost.out" 2>"$OUT/ghost.err" || rc=$?
((rc == 4)) || fail "a missing consumer: exit $rc, not 4"
grep -q "ghost-id did not acknowledge sample 0" "$OUT/ghost.err" || fail "ghost: $(cat "$OUT/ghost.err")"
pass "replay: lockstep $LEARNED of $((N - 1)) learned, model identical to odonata-fit's, log complete, live FIT $fit %; at 4× pace $paced learned; a missing consumer named"
