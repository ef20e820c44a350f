#!/usr/bin/env bash
# Two boards: plant, generator and logger on board A; identifier and monitor on board B; each
# board its own network namespace, joined through a bridge in a third, ttl=1 on the named link.
source "$(dirname "$0")/lib.sh"
OUT=$(mktemp -d)
TAG=od$$
A=${TAG}A B=${TAG}B SW=${TAG}S
cleanup() {
  stop_all
  ip netns del "$A" 2>/dev/null || true
  ip netns del "$B" 2>/dev/null || true
  ip netns del "$SW" 2>/dev/null || true
  rm -rf "$OUT"
}
trap cleanup EXIT
ip netns add "$A" && ip netns add "$B" && ip netns add "$SW"
ip -n "$SW" link add br0 type bridge && ip -n "$SW" link set br0 up
i=1
for h in A B; do
  ns=${TAG}$h
  ip link add "veth$h$$" netns "$ns" type veth peer name "port$h" netns "$SW"
  ip -n "$SW" link set "port$h" master br0 && ip -n "$SW" link set "port$h" up
  ip -n "$ns" link set "veth$h$$" name eth1
  ip -n "$ns" addr add "10.77.0.$i/24" dev eth1
  ip -n "$ns" link set lo up && ip -n "$ns" link set eth1 up
  ip -n "$ns" route add 224.0.0.0/4 dev eth1
  i=$((i + 1))
done
URL='udpm://239.255.76.67:7684?ttl=1'
"$SRC/deploy/make-identifier-config" --preset yaw --duration 3 --build "$BUILD" --output "$OUT/id.json"
start logger ip netns exec "$A" "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
start plant ip netns exec "$A" "$PLANT" --mode lockstep --preset yaw --lcm-url "$URL"
start monitor ip netns exec "$B" "$MONITOR" --lcm-url "$URL" --summary-json "$OUT/monitor.json"
start ident ip netns exec "$B" "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0 --save-model "$OUT/model.json"
# Board B's services seen from board A, across the bridge.
wait_up_on() { local ns=$1; shift; ODONATA_NETNS=$ns wait_up "$@"; }
wait_up_on "$A" "$URL" logger odonata-plant identifier monitor
timeout 60 ip netns exec "$A" "$SIGNAL" --preset yaw --phase train --duration 3 --mode lockstep --lcm-url "$URL" \
  --wait-for identifier --wait-for logger \
  >"$OUT/signal.log" 2>&1 || { cat "$OUT/signal.log"; fail "the run across the bridge did not complete"; }
stop_clean "$PID_ident" "identifier on board B"
stop_clean "$PID_monitor" "monitor on board B"
stop_clean "$PID_plant" "plant on board A"
stop_clean "$PID_logger" "logger on board A"
"$LOGGER" export "$OUT"/log.* -o "$OUT/train.csv" --predictions "$OUT/pred.csv" >/dev/null 2>&1 || fail "export failed"
rows=$(($(wc -l <"$OUT/pred.csv") - 1))
((rows >= 290)) || fail "board A recorded only $rows predictions from board B"
offline_fit "$OUT/id.json" "$OUT/train.csv" "$OUT/offline.json"
same_model "$OUT/model.json" "$OUT/offline.json" || fail "board B's model differs from odonata-fit on board A's log"
pass "two boards over a bridge (ttl=1): $rows predictions crossed back; models equal"
