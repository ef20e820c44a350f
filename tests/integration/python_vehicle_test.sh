#!/usr/bin/env bash
# A vehicle written in Python with the standard library only (python/odonata_signals.py,
# examples/own_vehicle/vehicle.py) is identified over udpm as the C++ one is (issue 23 point 2):
# the identifier learns every sample, the logger records them, and odonata-fit on the exported
# log gives the online model bit for bit. A message too large for one datagram goes out in LC03
# fragments that odonata's receiver and the logger put back together byte for byte. Everything is
# signed with a shared key (docs/lcm.md §15): the module's signature is the services' own.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7692?ttl=0'
CFG=$SRC/examples/own_vehicle/identifier.json
export PYTHONPATH=$SRC/python
N=1500
BUS_KEY=$OUT/bus.key
new_bus_key "$BUS_KEY"
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL" --key "$BUS_KEY"
start ident "$IDENT" --config "$CFG" --lcm-url "$URL" --resume-wait 0 --save-model "$OUT/model.json" \
  --key "$BUS_KEY"
wait_up "$URL" logger own-vehicle-id
# 400 Hz: faster than a flight loop, slow enough that no process falls behind on a busy machine.
"$PY" "$SRC/examples/own_vehicle/vehicle.py" --samples $N --rate 400 --lcm-url "$URL" --key "$BUS_KEY" \
  >"$OUT/vehicle.log" 2>&1 || { cat "$OUT/vehicle.log"; fail "vehicle.py failed"; }
# One large message (20 000 signals, about 380 kB: six LC03 fragments).
"$PY" - "$URL" "$BUS_KEY" >"$OUT/large.log" 2>&1 <<'PYEOF' || { cat "$OUT/large.log"; fail "the large publish failed"; }
import sys
from odonata_signals import SignalsPublisher, encode_signals
pub = SignalsPublisher(sys.argv[1], source="python-large", channel="LARGE_SIGNALS", key_path=sys.argv[2])
names = [f"s{i:05d}" for i in range(20000)]
pub.publish(0, names, [i * 0.5 for i in range(20000)], utime=1)
print(len(pub.udpm.datagrams("LARGE_SIGNALS", encode_signals(1, 0, "python-large", names, [0.0] * 20000))))
PYEOF
[[ $(cat "$OUT/large.log") -ge 6 ]] || fail "the large message was not fragmented: $(cat "$OUT/large.log")"
wait_up "$URL" own-vehicle-id -- --fresh
vehicle_accounting "$URL" own-vehicle-id $N
stop_clean "$PID_ident" "identifier"
stop_clean "$PID_logger" "logger"
"$LOGGER" export "$OUT"/log.* --signals -o "$OUT/samples.csv" >"$OUT/export.log" 2>&1 || { cat "$OUT/export.log"; fail "export --signals failed"; }
head -1 "$OUT/samples.csv" | grep -q "^seq,t_s,vz_mps,throttle,battery_v$" || fail "unexpected columns: $(head -1 "$OUT/samples.csv")"
# The large message, as the logger recorded it, decodes to what was sent.
"$LOGGER" export "$OUT"/log.* --signals --signals-channel LARGE_SIGNALS -o "$OUT/large.csv" >"$OUT/export_large.log" 2>&1 ||
  { cat "$OUT/export_large.log"; fail "the fragmented message is not in the log"; }
"$PY" - "$OUT/large.csv" <<'PYEOF' || fail "the fragmented message arrived changed"
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
assert len(rows) == 2, f"{len(rows) - 1} rows"
head, vals = rows[0], rows[1]
assert head[2:] == [f"s{i:05d}" for i in range(20000)], "names"
assert [float(v) for v in vals[2:]] == [i * 0.5 for i in range(20000)], "values"
PYEOF
vehicle_offline_equal "$CFG" "$OUT/samples.csv" "$OUT/model.json" $N
pass "a Python vehicle over udpm: $LEARNED samples learned, a 20 000-signal message in fragments intact, $SAME"
