#!/usr/bin/env bash
# 14 MB unsigned snapshots flooding a signed real-time run (issue 51 point 4, docs/lcm.md §9):
# the identifier, which needs snapshots only to resume, has the kernel drop every fragment once
# it has started, so the flood never reaches its socket — its heartbeat counts no refused or
# broken message — while the monitor, which caches snapshots, hears and refuses them. The gaps
# of the real-time run during the flood are printed (a figure that depends on the machine, not an
# assertion).
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7713?ttl=0'
KEY=$OUT/bus.key
new_bus_key "$KEY"
K=(--lcm-url "$URL" --key "$KEY")
FLOOD=$BUILD/tests/integration/flood_publisher
[[ -x $FLOOD ]] || fail "$FLOOD is not built"
"$SRC/deploy/make-identifier-config" --preset roll --duration 6 --build "$BUILD" --output "$OUT/id.json"
start monitor "$MONITOR" "${K[@]}"
start plant "$PLANT" --mode realtime --preset roll "${K[@]}"
start ident "$IDENT" --config "$OUT/id.json" --resume-wait 0 "${K[@]}"
wait_up "$URL" monitor odonata-plant identifier -- --state running
start signal "$SIGNAL" --preset roll --phase train --duration 6 --mode realtime "${K[@]}"
# The run is under way: the identifier has learned from it.
wait_up "$URL" identifier -- --at-least messages_in=100
"$FLOOD" "$URL" "${FLOOD_S:-3}" snapshots >"$OUT/flood.log" 2>&1 || fail "the flood failed: $(cat "$OUT/flood.log")"
wait "$PID_signal" || fail "the run failed: $(cat "$OUT/signal.log")"
# A heartbeat published after the flood: the monitor refused snapshots, the identifier saw none.
((${FLOOD_S:-3} == 0)) || wait_up "$URL" monitor -- --at-least dropped=1 --fresh
"$HBWAIT" --lcm-url "$URL" --instance identifier --fresh --timeout 30 >"$OUT/ident_hb.txt" ||
  fail "no heartbeat from the identifier after the flood"
grep -q "dropped 0, decode_errors 0," "$OUT/ident_hb.txt" ||
  fail "the flood reached the identifier: $(cat "$OUT/ident_hb.txt")"
echo "$(cat "$OUT/flood.log"); identifier after it: $(cat "$OUT/ident_hb.txt")"
stop_clean "$PID_ident" identifier
stop_clean "$PID_plant" plant
stop_clean "$PID_monitor" monitor
pass "a 14 MB snapshot flood never reached the running identifier"
