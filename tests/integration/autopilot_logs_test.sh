#!/usr/bin/env bash
# Logs of every autopilot where a ULog is taken (issue 58 point 2): an ArduPilot DataFlash log and
# a Crazyflie micro-SD log are listed by odonata-log, exported, and fitted by odonata-fit as they
# are — told by their content, even under a misleading name — with signals named as each
# ecosystem names them, units from FMTU, the nearest names for a typo, and one grid said.
source "$(dirname "$0")/lib.sh"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
LOG=$BUILD/services/log/odonata-log
BIN=${ODONATA_MAVLINK:?}/ardusub_small.BIN
USD=${ODONATA_USD:?}/log06

"$LOG" topics "$BIN" --match ATT. >"$OUT/bin_topics.txt" || fail "topics of the DataFlash log"
grep -q "ArduPilot DataFlash" "$OUT/bin_topics.txt" || fail "the DataFlash log was not told by content"
grep -qE "^ATT\.Pitch +deg +[0-9]+ +10\.00" "$OUT/bin_topics.txt" || { cat "$OUT/bin_topics.txt"; fail "ATT.Pitch in degrees at 10 Hz"; }
"$LOG" topics "$USD" --match gyro. >"$OUT/usd_topics.txt" || fail "topics of the micro-SD log"
grep -q "Crazyflie micro-SD, version 2" "$OUT/usd_topics.txt" && grep -q "CRC valid" "$OUT/usd_topics.txt" ||
  { cat "$OUT/usd_topics.txt"; fail "the micro-SD log header"; }
grep -qE "^gyro\.x +float +7930 " "$OUT/usd_topics.txt" || fail "gyro.x's 7930 samples"

# A ground station's MAVLink telemetry log, as ArduPilot and PX4 users record it.
TLOG=$ODONATA_MAVLINK/ardusub_small.tlog
"$LOG" topics "$TLOG" --match ATTITUDE. >"$OUT/tlog_topics.txt" || fail "topics of the .tlog"
grep -qE "^ATTITUDE\.pitchspeed +float +5245 +20\.00" "$OUT/tlog_topics.txt" ||
  { cat "$OUT/tlog_topics.txt"; fail "ATTITUDE.pitchspeed's 5245 frames at 20 Hz"; }
"$FIT" --train "$TLOG" --output ATTITUDE.pitchspeed --input SERVO_OUTPUT_RAW.servo5_raw --ny 2 --nu 2 \
  --horizon 5 >"$OUT/tlog_fit.out" 2>&1 || { cat "$OUT/tlog_fit.out"; fail "odonata-fit on the .tlog"; }
grep -q "one grid at 2 Hz (the slowest signal's rate" "$OUT/tlog_fit.out" ||
  { cat "$OUT/tlog_fit.out"; fail "the .tlog's grid"; }

# Content, not name: the DataFlash log under a CSV's name.
ln -s "$BIN" "$OUT/flight.csv"
"$FIT" --train "$OUT/flight.csv" --output ATT.Pitch --input RCOU.C3 --ny 2 --nu 2 --horizon 5 --json \
  >"$OUT/bin_fit.json" 2>"$OUT/bin_fit.err" || { cat "$OUT/bin_fit.err"; fail "odonata-fit on the DataFlash log"; }
grep -q "one grid at 10 Hz" "$OUT/bin_fit.err" || { cat "$OUT/bin_fit.err"; fail "the grid was not said"; }
"$PY" - "$OUT/bin_fit.json" <<'PY' || fail "the DataFlash fit"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["verdict"]["mode"] == "k_step", r["verdict"]
assert r["excitation"]["targets"] > 200, r["excitation"]  # 23.5 s where both are logged
PY

# A typo is answered with the nearest names, in either format.
set +e
"$FIT" --train "$BIN" --output ATT.Ptch --input RCOU.C3 >"$OUT/typo.out" 2>&1
"$FIT" --train "$USD" --output gyro.xx --input acc.x >>"$OUT/typo.out" 2>&1
set -e
grep -q "nearest: ATT.Pitch" "$OUT/typo.out" && grep -q "nearest: gyro.x" "$OUT/typo.out" ||
  { cat "$OUT/typo.out"; fail "no nearest names for a typo"; }

# The micro-SD log fits straight from the raw file, and exports as a plain CSV.
"$FIT" --train "$USD" --output gyro.x --input acc.y --ny 2 --nu 2 --horizon 10 --no-select --epochs 1 \
  >"$OUT/usd_fit.out" 2>&1 || { cat "$OUT/usd_fit.out"; fail "odonata-fit on the micro-SD log"; }
grep -q "verdict: training file" "$OUT/usd_fit.out" || fail "no verdict on the micro-SD fit"
"$LOG" export "$USD" --signals gyro.x,stateEstimate.z -o "$OUT/usd.csv" 2>/dev/null || fail "export of the micro-SD log"
"$PY" - "$OUT/usd.csv" <<'PY' || fail "the exported micro-SD CSV"
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) > 1500, len(rows)  # on stateEstimate's 253 Hz grid, the slower of the two
assert all(math.isfinite(float(r["stateEstimate.z"])) for r in rows[5:-5])
PY
pass "DataFlash, micro-SD and MAVLink telemetry logs: listed with units and rates, told by content under a CSV's name, fitted and exported as they are, typos answered with the nearest names"
