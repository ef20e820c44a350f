#!/usr/bin/env bash
# odonata-mavlink, the bridge from a vehicle's MAVLink link to the bus (issue 58 points 1 and 3),
# fed a real ArduSub .tlog (ODONATA_MAVLINK) by a Python vehicle written apart from the C++
# (mavlink_vehicle.py), with the identifier, monitor and logger running:
#  1. UDP, each record with its stamp (--udp-stamped): the logged signals equal odonata-log's
#     reading of the .tlog on the same grid, value for value; every grid sample not logged is a
#     counted gap or a counted drop.
#  2. UDP under 5 % datagram loss and a flood of 10 datagrams of junk per record (bad checksums,
#     unknown messages, another vehicle, cut frames, noise, incompatible flags): the frames lost
#     on the link are counted exactly (the sender's own count), each kind of junk is counted,
#     none reaches the log, and --request-rate's command reaches the vehicle well formed and its
#     answer is understood.
#  3. A serial link through a pseudo-terminal pair (socat): frames read, losses counted, the
#     command written to the radio and answered.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
TLOG=${ODONATA_MAVLINK:?}/ardusub_small.tlog
MAVLINK=$BUILD/services/mavlink/odonata-mavlink
LOG=$BUILD/services/log/odonata-log
VEHICLE="$PY $SRC/tests/integration/mavlink_vehicle.py"
command -v socat >/dev/null || fail "socat is missing (deploy/setup.sh installs it)"
OUT=$(mktemp -d)
trap 'stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
URL="udpm://239.255.76.68:7802?ttl=0"
FIELDS=ATTITUDE.pitchspeed,ATTITUDE.roll
SECONDS_SENT=30

# The offline reading the live one must equal, and an identifier configuration for its fields.
"$LOG" export "$TLOG" --signals "$FIELDS" --rate 20 --to $SECONDS_SENT -o "$OUT/offline.csv" \
  >"$OUT/offline.log" 2>&1 || fail "odonata-log export: $(cat "$OUT/offline.log")"
"$FIT" --train "$OUT/offline.csv" --output ATTITUDE.pitchspeed --input ATTITUDE.roll --ny 1 \
  --nu 1 --no-select --save-config "$OUT/id.json" >"$OUT/fit.log" 2>&1 ||
  fail "--save-config: $(cat "$OUT/fit.log")"

# run NAME BRIDGE_FLAGS -- VEHICLE_FLAGS: the bridge, logger, identifier and monitor, the vehicle
# sends, everything stops; the bridge's summary in $OUT/NAME/bridge.json, the vehicle's report in
# $OUT/NAME/vehicle.json, the logged samples in $OUT/NAME/live.csv.
run() {
  local name=$1 bridge=() vehicle=()
  shift
  while [[ $1 != -- ]]; do bridge+=("$1"); shift; done
  shift
  vehicle=("$@")
  mkdir -p "$OUT/$name"
  start "logger_$name" "$LOGGER" record -o "$OUT/$name/log" --lcm-url "$URL"
  start "ident_$name" "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0 \
    --save-model "$OUT/$name/model.json"
  start "monitor_$name" "$MONITOR" --lcm-url "$URL"
  start "bridge_$name" "$MAVLINK" --field "$FIELDS" --rate 20 --lcm-url "$URL" \
    --summary-json "$OUT/$name/bridge.json" "${bridge[@]}"
  wait_up "$URL" logger identifier mavlink
  $VEHICLE "$TLOG" --seconds $SECONDS_SENT --report "$OUT/$name/vehicle.json" "${vehicle[@]}" \
    >"$OUT/$name/vehicle.log" 2>&1 || fail "the vehicle ($name): $(cat "$OUT/$name/vehicle.log")"
  # Asked on the bus, the bridge answers with its counts.
  "$CONTROL" get --target mavlink --lcm-url "$URL" >"$OUT/$name/get.out" 2>&1 ||
    fail "the bridge did not answer get: $(cat "$OUT/$name/get.out")"
  grep -q "frames=" "$OUT/$name/get.out" || fail "get: $(cat "$OUT/$name/get.out")"
  eval "stop_clean \$PID_bridge_$name bridge; stop_clean \$PID_ident_$name identifier"
  eval "stop_clean \$PID_monitor_$name monitor; stop_clean \$PID_logger_$name logger"
  "$LOGGER" export "$OUT/$name"/log.* --signals -o "$OUT/$name/live.csv" \
    >"$OUT/$name/export.log" 2>&1 || fail "export ($name): $(cat "$OUT/$name/export.log")"
}

# 1. Stamped, no loss: live equals offline.
run stamped --udp 127.0.0.1:14561 --udp-stamped -- --udp 127.0.0.1:14561 --stamped --speed 20
"$PY" - "$OUT/stamped" "$OUT/offline.csv" <<'PYEOF' || fail "stamped run: see above"
import csv, json, re, sys
out, offline = sys.argv[1], sys.argv[2]
bridge = json.load(open(out + '/bridge.json'))
vehicle = json.load(open(out + '/vehicle.json'))
live = {int(r['seq']): r for r in csv.DictReader(open(out + '/live.csv'))}
off = list(csv.DictReader(open(offline)))
export = open(out + '/export.log').read()
lost, out_of_seq = (int(x) for x in re.search(r'(\d+) lost, \d+ undecodable, (\d+) out of sequence', export).groups())
grid = bridge['grid']['samples']
fields = ['ATTITUDE.pitchspeed', 'ATTITUDE.roll']
bad = [k for k, r in live.items() if k >= len(off) or any(float(r[f]) != float(off[k][f]) for f in fields)]
assert not bad, 'logged samples differ from the offline reading at k = %s' % bad[:5]
assert bridge['frames']['sequence_lost'] == vehicle['sequence_lost'], (bridge['frames'], vehicle)
assert bridge['frames']['bad_crc'] == 0 and bridge['frames']['cut'] == 0, bridge['frames']
assert bridge['published'] + bridge['grid']['gap_samples'] == grid, bridge
# Every grid sample is logged or counted lost: a gap the bridge did not send, or one the logger
# dropped (after a long gap the bus's leap guard holds one sample, docs/lcm.md §14: it is
# counted out of sequence on arrival and lost in the gap).
assert len(live) + lost == max(live) + 1 == grid, (len(live), lost, out_of_seq, grid)
assert grid >= len(off) - 2, (grid, len(off))
print('stamped: %d of %d grid samples logged, each equal to the offline reading; %d gaps counted, '
      '%d frames lost on the recorded link counted' % (len(live), grid, grid - len(live),
                                                       vehicle['sequence_lost']))
PYEOF
grep -q "ATTITUDE.pitchspeed" "$OUT/monitor_stamped.log" || fail "the monitor showed nothing: $(tail -5 "$OUT/monitor_stamped.log")"
[[ -s $OUT/stamped/model.json ]] || fail "the identifier saved no model"

# 2. Stamped, 5 % loss, a flood of junk, a rate request.
run lossy --udp 127.0.0.1:14562 --udp-stamped --request-rate ATTITUDE=50 -- \
  --udp 127.0.0.1:14562 --stamped --speed 4 --loss 0.05 --seed 7 --junk 10
"$PY" - "$OUT/lossy" <<'PYEOF' || fail "lossy run: see above"
import csv, json, re, sys
out = sys.argv[1]
bridge = json.load(open(out + '/bridge.json'))
vehicle = json.load(open(out + '/vehicle.json'))
f, junk = bridge['frames'], vehicle['junk']
assert vehicle['dropped'] > 0
assert f['sequence_lost'] == vehicle['sequence_lost'], ('lost on the link', f, vehicle)
assert f['bad_crc'] == junk['bad_crc'], ('bad checksums', f, junk)
assert f['other_sender'] == junk['other_sender'], ('another vehicle', f, junk)
assert f['cut'] == junk['cut'], ('cut frames', f, junk)
assert f['incompatible'] == junk['incompatible'], ('incompatible', f, junk)
assert f['unknown_ids'].get('178', 0) >= junk['unknown'], ('unknown', f, junk)
assert f['bytes_skipped'] > 0
live = list(csv.DictReader(open(out + '/live.csv')))
assert live and max(abs(float(r['ATTITUDE.pitchspeed'])) for r in live) < 100, 'junk reached the log'
export = open(out + '/export.log').read()
lost, out_of_seq = (int(x) for x in re.search(r'(\d+) lost, \d+ undecodable, (\d+) out of sequence', export).groups())
grid = bridge['grid']['samples']
assert bridge['published'] + bridge['grid']['gap_samples'] == grid, bridge
assert len(live) + lost == int(live[-1]['seq']) + 1 == grid, (len(live), lost, out_of_seq, grid)
commands = vehicle['commands']
assert commands, 'no command reached the vehicle'
c = commands[0]
assert (c['sysid'], c['compid'], c['command'], c['target'], c['param1'], c['param2']) == (
    255, 190, 511, [1, 1], 30.0, 20000.0), c
assert bridge['requests'][0]['result'] == 0, bridge['requests']
print('lossy: %d records dropped, %d frames lost counted as the sender counts them; junk %s all '
      'counted, none logged; %d of %d grid samples logged, the rest counted; ATTITUDE=50 asked '
      'and accepted' % (vehicle['dropped'], f['sequence_lost'], junk, len(live), grid))
PYEOF

# 3. A serial link: socat's pseudo-terminal pair, the vehicle on one end, the bridge on the other.
start socat socat pty,raw,echo=0,link="$OUT/vehicle-tty" pty,raw,echo=0,link="$OUT/radio-tty"
for _ in $(seq 100); do [[ -e $OUT/radio-tty && -e $OUT/vehicle-tty ]] && break; sleep 0.05; done
[[ -e $OUT/radio-tty ]] || fail "socat made no pty pair: $(cat "$OUT/socat.log")"
run serial --serial "$OUT/radio-tty" --baud 115200 --request-rate ATTITUDE=50 -- \
  --serial "$OUT/vehicle-tty" --speed 10
"$PY" - "$OUT/serial" <<'PYEOF' || fail "serial run: see above"
import json, sys
out = sys.argv[1]
bridge = json.load(open(out + '/bridge.json'))
vehicle = json.load(open(out + '/vehicle.json'))
f = bridge['frames']
assert f['ok'] > 0 and bridge['published'] > 0, bridge
assert f['bad_crc'] == 0, f
assert f['sequence_lost'] == vehicle['sequence_lost'], (f, vehicle)
assert vehicle['commands'] and vehicle['commands'][0]['command'] == 511, vehicle
assert bridge['requests'][0]['result'] == 0, bridge['requests']
print('serial: %d frames, %d samples published; the rate request written to the radio and '
      'accepted' % (f['ok'], bridge['published']))
PYEOF
pass "odonata-mavlink: a real .tlog over UDP equals odonata-log's reading; loss, junk and a serial link counted"
