#!/usr/bin/env bash
# lcm-logger records a live run; lcm-logplayer replays it (standing in for plant and generator)
# into a fresh identifier, which must end with the live model. odonata-logger's own log must
# replay the same way. The recording is real time, so the replay at its own pace (100 Hz) sends
# no burst a UDP receive buffer could overflow on; a lost message would be a gap and fail.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7681?ttl=0'
start lcmlogger lcm-logger --lcm-url="$URL" -c 'DIMAV_.*' -f "$OUT/lcm-logger.log"
# lcm-logger has no heartbeat: a probe on a channel it records (nobody else listens to
# DIMAV_PROBE) shows in its file once everything published before it is written.
probes() { { grep -ao DIMAV_PROBE "$OUT/lcm-logger.log" 2>/dev/null || true; } | wc -l; }
probe_lcm_logger() {
  local before
  before=$(probes)
  for _ in $(seq 300); do
    "$CONTROL" get --channel control=DIMAV_PROBE --lcm-url "$URL" --timeout 0.1 >/dev/null 2>&1 || true
    (($(probes) > before)) && return 0
  done
  fail "lcm-logger recorded nothing"
}
probe_lcm_logger
# Real time (100 Hz) so lcm-logger, whose subscription queue LCM 1.3.1 caps at 30 messages,
# never sees a burst; the live and the replayed identifier see the same message sequence.
odonata_run 120 --host --lcm-url "$URL" --preset pitch --phases train --duration 3 --mode realtime
probe_lcm_logger
stop_clean "$PID_lcmlogger" lcm-logger
[[ -s $OUT/run/model.json ]] || fail "no live model"
for log in "$OUT/lcm-logger.log" "$OUT/run/odonata.lcmlog.00000"; do
  rm -f "$OUT/replayed.json"
  start replay-ident "$IDENT" --config "$OUT/run/identifier.json" --lcm-url "$URL" --resume-wait 0 \
    --instance replay --save-model "$OUT/replayed.json"
  wait_up "$URL" replay
  timeout 60 lcm-logplayer -s 1 -e 'DIMAV_.*' -l "$URL" "$log" >/dev/null 2>&1 || fail "lcm-logplayer failed on $log"
  wait_up "$URL" replay -- --fresh
  stop_clean "$PID_replay_ident" "replaying identifier"
  same_model "$OUT/run/model.json" "$OUT/replayed.json" || fail "replaying $(basename "$log") gave another model"
done
pass "lcm-logger and odonata-logger logs replayed by lcm-logplayer reproduce the live model"
