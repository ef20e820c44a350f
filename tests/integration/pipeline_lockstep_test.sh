#!/usr/bin/env bash
# End to end through real processes over udpm: plant -> identifier -> monitor -> logger, in
# lockstep; the identifier's model equals odonata-fit's on the logged samples, bit for bit.
source "$(dirname "$0")/lib.sh"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
odonata_run 120 --preset roll --duration 3
R=$OUT/run
for f in model.json train.csv validate.csv predictions.csv snapshots.json monitor-summary.json odonata.lcmlog.00000; do
  [[ -s $R/$f ]] || fail "missing $f"
done
# Named saves go to models/, never into the run folder beside the event log (issue 24 point 4).
[[ -d $R/models ]] || fail "odonata-run gave the identifier no models/ directory"
rows=$(($(wc -l <"$R/predictions.csv") - 1))
((rows >= 590)) || fail "only $rows predictions (expected 2 x 297)"
fit=$(json_get "$R/monitor-summary.json" 'j["outputs"]["roll_rad"]["one_step"]["fit"]')
"$PY" -c "import sys; sys.exit(0 if float('$fit') > 80 else 1)" || fail "validation FIT $fit"
[[ $(json_get "$R/monitor-summary.json" 'len(j["previous_runs"])') == 1 ]] || fail "monitor did not score training and validation separately"
# The identifier's live ARX is scored beside the fuzzy model on the same samples, and logged.
o='j["outputs"]["roll_rad"]'
[[ $(json_get "$R/monitor-summary.json" "$o[\"arx\"][\"one_step\"][\"samples\"] == $o[\"one_step\"][\"samples\"] and $o[\"arx\"][\"one_step\"][\"fit\"] > 80") == True ]] ||
  fail "the monitor did not score the live ARX on the validation samples"
head -1 "$R/predictions.csv" | grep -q roll_rad_arx_predicted || fail "predictions.csv has no ARX column"
offline_fit "$R/identifier.json" "$R/train.csv" "$OUT/offline.json"
same_model "$R/model.json" "$OUT/offline.json" || fail "online (lockstep) and offline models differ"
pass "lockstep pipeline: $rows predictions, validation FIT $fit %, online model == odonata-fit model"
