#!/usr/bin/env bash
# A replay into a freshly restarted identifier (issue 51 point 2, docs/lcm.md §15): on a signed
# bus, the identifier is killed (kill -9) mid-run and restarted at once, as odonata-run restarts
# it; while it waits for its snapshot, lcm-logplayer sends again everything lcm-logger captured
# of the run, signatures and all, up to the kill. The run ends with exit 0 and a model equal, bit
# for bit, to the one the same kill and restart give without the replay: nothing stamped before
# a receiver started is taken (stale), and a resumed identifier learns no sample its snapshot
# already held. The samples the kill cost are counted as gaps.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
KEY=$OUT/bus.key
new_bus_key "$KEY"
"$SRC/deploy/make-identifier-config" --preset roll --duration 20 --build "$BUILD" --output "$OUT/id.json"
HOLD=1000  # of 2000: the kill lands here, whatever the machine's speed

# run_case NAME PORT REPLAY: one signed lockstep run with a kill and restart at the hold, the
# capture replayed into the restarted identifier when REPLAY is 1.
run_case() {
  local name=$1 port=$2 replay=$3
  local url="udpm://239.255.76.67:$port?ttl=0"
  local K=(--lcm-url "$url" --key "$KEY")
  mkdir -p "$OUT/$name"
  start "${name}_capture" lcm-logger --lcm-url="$url" "$OUT/$name/capture.lcmlog"
  start "${name}_logger" "$LOGGER" record -o "$OUT/$name/log" "${K[@]}"
  start "${name}_monitor" "$MONITOR" "${K[@]}"
  start "${name}_plant" "$PLANT" --mode lockstep --preset roll "${K[@]}"
  start "${name}_ident1" "$IDENT" --config "$OUT/id.json" --resume-wait 0 "${K[@]}"
  wait_up "$url" logger monitor odonata-plant identifier -- --state running --state waiting
  start "${name}_signal" "$SIGNAL" --preset roll --phase train --duration 20 --mode lockstep \
    "${K[@]}" --timeout-ms 200 --max-resends 40 --hold-at $HOLD --wait-for identifier --wait-for logger
  local signal_pid_var="PID_${name}_signal" ident1_var="PID_${name}_ident1"
  wait_hold "${!signal_pid_var}" "$OUT/${name}_signal.log" $HOLD
  kill -KILL "${!ident1_var}"
  local capture_var="PID_${name}_capture"
  kill -INT "${!capture_var}"; wait "${!capture_var}" 2>/dev/null || true
  start "${name}_ident2" "$IDENT" --config "$OUT/id.json" --resume-wait 3 \
    --save-model "$OUT/$name/model.json" "${K[@]}"
  if ((replay)); then
    # Within its first second: before and while it resumes from the monitor's snapshot.
    start "${name}_replay" lcm-logplayer -l "$url" "$OUT/$name/capture.lcmlog"
  fi
  wait_up "$url" identifier -- --state running --fresh
  if ((replay)); then
    local replay_var="PID_${name}_replay"
    wait "${!replay_var}" || fail "lcm-logplayer failed: $(cat "$OUT/${name}_replay.log")"
  fi
  kill -USR1 "${!signal_pid_var}"
  wait "${!signal_pid_var}" || fail "run $name failed: $(cat "$OUT/${name}_signal.log")"
  # The samples the kill cost are gaps where a user looks: the heartbeat.
  wait_count "$url" identifier gaps 1
  local v
  for v in ident2 plant monitor logger; do
    local pid_var="PID_${name}_$v"
    stop_clean "${!pid_var}" "$name $v"
  done
  grep -q "from the bus snapshot after" "$OUT/${name}_ident2.log" ||
    fail "run $name did not resume: $(cat "$OUT/${name}_ident2.log")"
}

run_case clean 7711 0
run_case replayed 7712 1
[[ -s $OUT/replayed/capture.lcmlog ]] || fail "lcm-logger captured nothing"
grep -q "stale (stamped before this process started" "$OUT/replayed_ident2.log" ||
  fail "the restarted identifier did not refuse the replay as stale: $(cat "$OUT/replayed_ident2.log")"
same_model "$OUT/clean/model.json" "$OUT/replayed/model.json" ||
  fail "the replay changed the restarted identifier's model"
grep -q "samples missed on resume: [1-9][0-9]* samples before sample" "$OUT/replayed_ident2.log" ||
  fail "the restarted identifier did not say what the kill cost: $(cat "$OUT/replayed_ident2.log")"
pass "a capture replayed into a restarted identifier changed nothing it learned"
