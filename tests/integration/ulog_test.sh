#!/usr/bin/env bash
# A PX4 flight log as a user meets it (issue 48 point 1): `odonata-ulog topics` lists its signals
# with their rates, `odonata-ulog export` writes chosen ones as CSV, odonata-fit identifies from
# the .ulg itself exactly as from that CSV, a log cut mid-message is still used up to the cut (and
# said so), and odonata-replay streams the .ulg to the live identifier in lockstep, which learns
# odonata-fit's model bit for bit. The log is synthetic (write_flight_ulog: a pitch rate at 100 Hz
# driven by a command logged at 50 Hz); PX4's own logs are read by tests/ulog.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7689?ttl=0'
ULOG=$BUILD/services/log/odonata-ulog
REPLAY=$BUILD/services/replay/odonata-replay
LOG=$OUT/flight.ulg
"$BUILD/tests/ulog/write_flight_ulog" "$LOG" 40 || fail "could not write the synthetic log"
Y=vehicle_rates.pitch
U='actuator_controls.control[1]'

"$ULOG" topics "$LOG" >"$OUT/topics.txt" || fail "topics failed"
grep -qE "^actuator_controls\.control\[1\] +float +2000 +50\.00" "$OUT/topics.txt" || { cat "$OUT/topics.txt"; fail "topics: the 50 Hz command"; }
grep -qE "^vehicle_rates\.pitch +float +4000 +100\.00" "$OUT/topics.txt" || { cat "$OUT/topics.txt"; fail "topics: the 100 Hz rate"; }
"$ULOG" export "$LOG" --signals "$Y,$U" -o "$OUT/flight.csv" >"$OUT/export.out" 2>&1 || { cat "$OUT/export.out"; fail "export failed"; }
grep -q "^t_s,$Y,actuator_controls.control\[1\]$" "$OUT/flight.csv" || fail "export header: $(grep -v '^#' "$OUT/flight.csv" | head -1)"

# The .ulg itself and its CSV give one model.
common=(--output "$Y" --input "$U" --ny 1 --nu 1 --no-select --epochs 2)
"$FIT" --train "$LOG" "${common[@]}" --save-model "$OUT/from_ulog.json" >"$OUT/fit_ulog.out" 2>&1 || { cat "$OUT/fit_ulog.out"; fail "odonata-fit on the .ulg failed"; }
"$FIT" --train "$OUT/flight.csv" --time t_s "${common[@]}" --save-model "$OUT/from_csv.json" >"$OUT/fit_csv.out" 2>&1 || { cat "$OUT/fit_csv.out"; fail "odonata-fit on the exported CSV failed"; }
same_model "$OUT/from_ulog.json" "$OUT/from_csv.json" || fail "the .ulg and its exported CSV gave different models"
fit=$(sed -nE 's/^  train +free_run +fuzzy +([-0-9.]+).*/\1/p' "$OUT/fit_ulog.out")
"$PY" -c "import sys; sys.exit(0 if float(sys.argv[1]) >= 90 else 1)" "$fit" || fail "free-run FIT $fit % on the synthetic flight"

# A log cut in the middle of a message: what came before is used, and the damage is said.
head -c 200000 "$LOG" >"$OUT/cut.ulg"
"$FIT" --train "$OUT/cut.ulg" "${common[@]}" >"$OUT/fit_cut.out" 2>&1 || { cat "$OUT/fit_cut.out"; fail "odonata-fit on a cut log failed"; }
grep -q "damaged at byte" "$OUT/fit_cut.out" || { cat "$OUT/fit_cut.out"; fail "the cut was not reported"; }
"$ULOG" topics "$OUT/cut.ulg" | grep -q "DAMAGED at byte" || fail "topics did not report the cut"

# Streamed from the .ulg to the live identifier, in lockstep: odonata-fit's model, bit for bit.
"$FIT" --train "$LOG" --output "$Y" --input "$U" --ny 1 --nu 1 --no-select --save-config "$OUT/id.json" >/dev/null 2>&1 ||
  fail "--save-config failed"
start ident "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0 --save-model "$OUT/live.json"
wait_up "$URL" identifier -- --state running
"$REPLAY" "$LOG" --signals "$Y,$U" --lockstep --lcm-url "$URL" >"$OUT/replay.out" 2>"$OUT/replay.err" ||
  { cat "$OUT/replay.err"; fail "odonata-replay of the .ulg failed"; }
n=$(($(grep -vc '^#' "$OUT/flight.csv") - 1))
grep -q "sent $n of $n samples" "$OUT/replay.out" || fail "replay: $(cat "$OUT/replay.out")"
stop_clean "$PID_ident" "identifier"
offline_fit "$OUT/id.json" "$OUT/flight.csv" "$OUT/offline.json" unfrozen
same_model "$OUT/live.json" "$OUT/offline.json" || fail "the live model learned from the .ulg differs from odonata-fit's"
pass "ULog: topics and export, the .ulg and its CSV give one model (free-run FIT $fit %), a cut log used up to its damage, replayed in lockstep to the identifier: odonata-fit's model bit for bit ($n samples)"
