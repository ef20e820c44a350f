#!/usr/bin/env bash
# Your own vehicle: a process written only against signals_t (examples/own_vehicle) is
# identified end to end over udpm: the identifier (source "signals") learns every sample, the
# monitor scores it, the logger records it, `odonata-logger export --signals` turns the log into
# the CSV odonata-fit reads, and odonata-fit on that CSV gives the online model bit for bit.
# A vertical velocity integrates the throttle, so the config asks for refits scored 20 steps
# ahead: the monitor then scores the model and the live ARX 20 steps ahead too (issue 47 point
# 5), over the very predictions the logger recorded.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7686?ttl=0'
VEHICLE=$BUILD/examples/own_vehicle/own-vehicle
CFG=$OUT/identifier.json
K=20
"$PY" -c "import json,sys; c=json.load(open(sys.argv[1])); c['refit_horizon']=$K; json.dump(c, open(sys.argv[2], 'w'))" \
  "$SRC/examples/own_vehicle/identifier.json" "$CFG"
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
# K steps ahead: the monitor's scores are the FIT of the logged ŷ(k | k−K), the model's and the
# live ARX's, recomputed here from the exported predictions.
"$LOGGER" export "$OUT"/log.* --signals -o "$OUT/again.csv" --predictions "$OUT/pred.csv" >"$OUT/export2.log" 2>&1 ||
  { cat "$OUT/export2.log"; fail "export --predictions failed"; }
ahead=$("$PY" - "$OUT/monitor.json" "$OUT/pred.csv" $K <<'PYEOF'
import csv, json, math, sys
summary, pred, k = json.load(open(sys.argv[1])), sys.argv[2], sys.argv[3]
out = summary["outputs"]["vz_mps"]
assert out["horizon"] == int(k) and out["arx"]["horizon"] == int(k), out.get("horizon")
rows = list(csv.DictReader(l for l in open(pred) if not l.startswith("#")))
def fit(col):
    y = [float(r["vz_mps_measured"]) for r in rows]
    e = [float(r["vz_mps_" + col]) - v for r, v in zip(rows, y)]
    m = sum(y) / len(y)
    return 100 * (1 - math.sqrt(sum(x * x for x in e)) / math.sqrt(sum((v - m) ** 2 for v in y)))
for mine, col in ((out["ahead"], "ahead_" + k), (out["arx"]["ahead"], "arx_ahead_" + k)):
    assert mine["samples"] == len(rows), (mine["samples"], len(rows))
    assert abs(mine["fit"] - fit(col)) < 1e-6, (col, mine["fit"], fit(col))
# The live intervals (issue 60): the monitor's coverage is that of the logged widths.
iv = out["interval"]
for mode, pcol, wcol in (("one_step", "predicted", "half_width"),
                         ("k_step", "ahead_" + k, "ahead_half_width_" + k),
                         ("free_run", "free_run", "free_run_half_width")):
    known = [r for r in rows if float(r["vz_mps_" + wcol]) >= 0]
    cov = sum(abs(float(r["vz_mps_" + pcol]) - float(r["vz_mps_measured"]))
              <= float(r["vz_mps_" + wcol]) for r in known) / len(known)
    assert iv[mode]["samples"] == len(known), (mode, iv[mode]["samples"], len(known))
    assert abs(iv[mode]["coverage"] - cov) <= 1.0 / len(known), (mode, iv[mode]["coverage"], cov)
# "Seen enough" per sample (0 short, 1 learning, 2 settled): the monitor keeps the last one logged.
seen = [int(float(r["vz_mps_seen_enough"])) for r in rows]
assert set(seen) <= {0, 1, 2}, set(seen)
assert out["seen_enough"] == seen[-1], (out["seen_enough"], seen[-1])
print("%d steps ahead %.2f %% against the live ARX %.2f %%, 90 %% interval covers %.1f %%" % (
    int(k), out["ahead"]["fit"], out["arx"]["ahead"]["fit"], 100 * iv["k_step"]["coverage"]))
PYEOF
) || fail "the monitor's K-step scores are not those of the logged predictions"
rules=$(json_get "$OUT/model.json" "len(j['models'][0]['rules'])")
# The live ARX beside it, scored on the same samples (docs/identifier.md §6.4).
live=$(json_get "$OUT/monitor.json" "'free run %.2f %% against the live ARX %.2f %%' % (j['outputs']['vz_mps']['free_run']['fit'], j['outputs']['vz_mps']['arx']['free_run']['fit'])")
pass "own vehicle over signals_t: $LEARNED samples learned, $rules rules, live one-step FIT $fit %, $live, $ahead, $SAME"
