#!/usr/bin/env bash
# A current PX4 flight log, as a user meets it (issue 57): signals at several rates (gyro 400 Hz,
# torque setpoint 100 Hz, motors 50 Hz, land detector 1 Hz), read by their real names. The
# README's pitch-rate recipe chooses one grid every named signal fills and says so, holds the
# landed flag, keeps only the airborne part with --airborne, cuts with --from/--to, and answers a
# ground test at zero thrust with "nothing to identify" (exit 3), never a constant model.
source "$(dirname "$0")/lib.sh"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
ULOG=$BUILD/services/log/odonata-log
W=$BUILD/tests/ulog/write_px4_flight_ulog
"$W" "$OUT/flight.ulg" 40 || fail "could not write the flight"
"$W" "$OUT/ground.ulg" 10 --ground || fail "could not write the ground test"
Y='vehicle_angular_velocity.xyz[1]'
recipe=(--output "$Y" --input 'vehicle_torque_setpoint.xyz[1]' --ny 2 --nu 2 --horizon 10)

# The recipe on the flight: one grid at the slowest named signal's rate, said with each rate.
"$FIT" --train "$OUT/flight.ulg" --airborne "${recipe[@]}" --json >"$OUT/fit.json" 2>"$OUT/fit.err" ||
  { cat "$OUT/fit.err"; fail "the recipe failed on the flight"; }
grep -q "one grid at 100 Hz (the slowest signal's rate" "$OUT/fit.err" || { cat "$OUT/fit.err"; fail "the grid was not said"; }
grep -q "vehicle_angular_velocity.xyz\[1\] 400 Hz" "$OUT/fit.err" || fail "the gyro's own rate was not said"
grep -q "vehicle_land_detected.landed 1 Hz (held, a flag)" "$OUT/fit.err" || fail "the flag is not held"
"$PY" - "$OUT/fit.json" <<'PY' || fail "the recipe's model"
import json, sys
r = json.load(open(sys.argv[1]))
d = next(iter(r["data"].values()))
v = r["verdict"]
assert abs(d["rate_hz"] - 100) < 1e-6, d
assert d["missing"] == 0, d  # no input mostly gaps
assert d["first_s"] >= 2.0 - 1e-9 and d["last_s"] <= 38.0 + 1e-9, d  # the airborne part only
assert d["cut_by_condition"] > 300, d
assert v["mode"] == "k_step" and "constant" not in v["flags"], v
assert v["fit"]["fit"] >= v["arx"]["fit"] - 0.5, v  # scored beside ARX, K steps ahead
assert r["local_models"], r.keys()
PY

# A window in seconds since the log's start.
"$FIT" --train "$OUT/flight.ulg" --from 10 --to 30 "${recipe[@]}" --json >"$OUT/win.json" 2>/dev/null ||
  fail "--from/--to failed"
"$PY" -c "import json,sys; d=next(iter(json.load(open(sys.argv[1]))['data'].values())); sys.exit(0 if abs(d['first_s']-10)<0.02 and abs(d['last_s']-30)<0.02 else 1)" "$OUT/win.json" ||
  fail "the window was not kept: $(grep -o '"first_s[^,]*,' "$OUT/win.json")"

# A threshold on thrust (a float at 100 Hz) keeps the airborne part too; the condition's signal is
# held and does not choose the grid.
"$FIT" --train "$OUT/flight.ulg" --keep-when 'vehicle_thrust_setpoint.xyz[2]<-0.1' --output "$Y" \
  --input 'actuator_motors.control[0]' --ny 2 --nu 2 --horizon 5 >"$OUT/thrust.out" 2>&1 ||
  { cat "$OUT/thrust.out"; fail "--keep-when on thrust failed"; }
grep -q "one grid at 50 Hz" "$OUT/thrust.out" && grep -q "vehicle_thrust_setpoint.xyz\[2\] 100 Hz (held" "$OUT/thrust.out" ||
  { cat "$OUT/thrust.out"; fail "the thrust condition was not held apart from the grid"; }

# Motors at 50 Hz: the grid follows them; a --rate far above is refused naming them.
"$FIT" --train "$OUT/flight.ulg" --airborne --output "$Y" --input 'actuator_motors.control[0]' --ny 2 --nu 2 \
  --horizon 5 >"$OUT/motors.out" 2>&1 || { cat "$OUT/motors.out"; fail "the motors' recipe failed"; }
grep -q "one grid at 50 Hz" "$OUT/motors.out" || fail "the grid did not follow the 50 Hz motors"
set +e
"$FIT" --train "$OUT/flight.ulg" --output "$Y" --input 'actuator_motors.control[0]' --rate 400 >"$OUT/fast.out" 2>&1
rc=$?
set -e
[[ $rc != 0 ]] && grep -q "'actuator_motors.control\[0\]' is logged at 50 Hz, too slow for a 400 Hz grid" "$OUT/fast.out" ||
  { cat "$OUT/fast.out"; fail "a grid too fast for the motors was not refused by name"; }

# The ground test: nothing to identify, exit 3, with and without --airborne.
for extra in "" "--airborne"; do
  set +e
  "$FIT" --train "$OUT/ground.ulg" $extra "${recipe[@]}" >"$OUT/ground.out" 2>&1
  rc=$?
  set -e
  [[ $rc == 3 ]] && grep -q "nothing to identify" "$OUT/ground.out" ||
    { cat "$OUT/ground.out"; fail "the ground test ($extra) gave exit $rc"; }
done

# Replaying the ground test's airborne part: nothing to send, exit 3, before any bus is joined.
set +e
"$BUILD/services/replay/odonata-replay" "$OUT/ground.ulg" --signals "$Y" --airborne >"$OUT/replay.out" 2>&1
rc=$?
set -e
[[ $rc == 3 ]] && grep -q "nothing to send" "$OUT/replay.out" || { cat "$OUT/replay.out"; fail "replay of no airborne part gave exit $rc"; }

# Old names are answered with where a current log holds them; Euler angles come from q.
set +e
"$FIT" --train "$OUT/flight.ulg" --output vehicle_attitude.pitchspeed --input 'vehicle_torque_setpoint.xyz[1]' >"$OUT/old.out" 2>&1
set -e
grep -q "current PX4 logs hold body rates in vehicle_angular_velocity.xyz" "$OUT/old.out" || { cat "$OUT/old.out"; fail "no hint for an old name"; }
"$ULOG" export "$OUT/flight.ulg" --airborne --signals "vehicle_attitude.pitch_rad,$Y" -o "$OUT/air.csv" 2>"$OUT/export.err" ||
  { cat "$OUT/export.err"; fail "export --airborne failed"; }
"$PY" - "$OUT/air.csv" <<'PY' || fail "the exported CSV"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))  # no comment line breaks DictReader
assert rows and set(r["vehicle_land_detected.landed"] for r in rows) == {"0"}, rows[0]
assert all(abs(float(r["vehicle_attitude.pitch_rad"])) < 1.6 for r in rows)
assert abs(float(rows[0]["t_s"]) - 2.0) < 0.05, rows[0]["t_s"]
PY
pass "current PX4 log: one grid at the slowest signal's rate, the flag held, the airborne part and a window kept, a too-fast grid refused by name, a ground test exit 3, old names answered"
