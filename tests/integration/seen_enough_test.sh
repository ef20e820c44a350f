#!/usr/bin/env bash
# Has the model seen enough (issue 60 point 3; docs/identifier.md §7.7), on the simulated DI-MAV
# through odonata-fit's replay of the online identifier (its default refit schedule, the train
# phase's ranges declared as an identifier configuration declares them): the selection excitation
# ends "settled"; the same excitation with the flapping frequency squeezed into the lower half of
# its range ends "short of excitation", naming the third never flown and its range.
source "$(dirname "$0")/lib.sh"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
SIM=$BUILD/services/sim/odonata-sim
ARGS=(--output fz1_n --input w1_freq_hz --input w1_amp_rad --ny 2 --nu 2)
REFITS=(--refit-first 1000 --refit-every 6000)

"$SIM" --preset actuator_fz --phase train --seed 1 --output "$OUT/train.csv" || fail "train run"
"$SIM" --preset actuator_fz --phase select --seed 1 --output "$OUT/select.csv" || fail "select run"
"$FIT" --train "$OUT/train.csv" "${ARGS[@]}" --save-ranges "$OUT/ranges.json" \
  --refit-first 1000000 >/dev/null 2>&1 || fail "the train run's ranges"

"$FIT" --train "$OUT/select.csv" "${ARGS[@]}" --ranges "$OUT/ranges.json" "${REFITS[@]}" \
  >"$OUT/select.out" 2>&1 || { cat "$OUT/select.out"; fail "the replay of the selection run"; }
grep -q "seen enough? fz1_n: settled" "$OUT/select.out" ||
  { grep -i "seen enough" "$OUT/select.out"; fail "the selection excitation did not settle"; }

# The commands of the selection run, frequency f ∈ [5.25, 6.75] Hz mapped onto [5.5, 6.0] Hz: the
# declared range is [5.5, 6.5], so its top third (6.17 to 6.5 Hz) is never flown.
python3 - "$OUT/select.csv" "$OUT/low_cmd.csv" <<'PY'
import csv, sys
rows = csv.DictReader(open(sys.argv[1]))
cols = ["t_s"] + [c for c in rows.fieldnames
                  if c[:1] == "w" and c[1:2].isdigit() and "_avg" not in c and "applied" not in c]
out = csv.writer(open(sys.argv[2], "w", newline=""))
out.writerow(cols)
for r in rows:
    out.writerow([("%.9g" % (5.5 + (float(r[c]) - 5.25) / 1.5 * 0.5)) if c.endswith("freq_hz")
                  else r[c] for c in cols])
PY
# Open loop, the free-flying vehicle tips over after some seconds; the wing force does not care.
"$SIM" --commands "$OUT/low_cmd.csv" --altitude 1 --output "$OUT/low.csv" >/dev/null 2>&1
[[ $(wc -l <"$OUT/low.csv") -gt 1200 ]] || fail "the low-frequency run is too short"
"$FIT" --train "$OUT/low.csv" "${ARGS[@]}" --ranges "$OUT/ranges.json" "${REFITS[@]}" --json \
  >"$OUT/low.json" 2>"$OUT/low.err" || { cat "$OUT/low.err"; fail "the replay of the low run"; }
python3 - "$OUT/low.json" <<'PY' || fail "the regime never flown was not named"
import json, sys
seen = json.load(open(sys.argv[1]))["refits"]["seen_enough"]
assert len(seen) == 1 and seen[0]["output"] == "fz1_n", seen
assert seen[0]["state"] == "short of excitation", seen
assert "w1_freq_hz(k) high (6.17 to 6.5): 0 samples" in seen[0]["sentence"], seen
assert "fly more there" in seen[0]["sentence"], seen
print("named:", seen[0]["sentence"])
PY
pass "seen enough: the selection run settled; the run never flown above 6 Hz names that third"
