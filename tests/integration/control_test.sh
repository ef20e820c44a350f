#!/usr/bin/env bash
# odonata-control against the running services over udpm: every command gets an answer it
# prints, a rejection or silence is a non-zero exit, `get` reads the live parameters back, and
# `shutdown` stops every service, the logger included, its log flushed and readable.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7685?ttl=0'
"$SRC/deploy/make-identifier-config" --preset roll --duration 2 --build "$BUILD" --output "$OUT/id.json"
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
start plant "$PLANT" --mode lockstep --preset roll --lcm-url "$URL"
start monitor "$MONITOR" --lcm-url "$URL" --summary-json "$OUT/monitor.json"
start ident "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0 --instance roll-id
wait_up "$URL" logger odonata-plant monitor roll-id
ctl() { "$CONTROL" "$@" --lcm-url "$URL" >"$OUT/ctl.out" 2>&1; }

ctl set-entropy-threshold 0.3 --target roll-id || { cat "$OUT/ctl.out"; fail "set-entropy-threshold 0.3 (positional) exited $?"; }
grep -q "roll-id (odonata-identifier): accepted" "$OUT/ctl.out" || { cat "$OUT/ctl.out"; fail "no accepted answer printed"; }
grep -q "entropy_threshold=0.3\b" "$OUT/ctl.out" || { cat "$OUT/ctl.out"; fail "the answer does not carry the value in force"; }

ctl get --target odonata-identifier || fail "get exited $?"
grep -q "entropy_threshold=0.3\b" "$OUT/ctl.out" || { cat "$OUT/ctl.out"; fail "get does not read the threshold back"; }

rc=0; ctl set-entropy-threshold 5 --target roll-id || rc=$?
((rc == 1)) || { cat "$OUT/ctl.out"; fail "an out-of-range threshold exited $rc, not 1"; }
grep -q "REJECTED" "$OUT/ctl.out" || { cat "$OUT/ctl.out"; fail "the rejection is not printed"; }

rc=0; ctl freeze --target no-such-service --timeout 0.3 || rc=$?
((rc == 3)) || { cat "$OUT/ctl.out"; fail "a command nobody answers exited $rc, not 3"; }
grep -q "no answer" "$OUT/ctl.out" || { cat "$OUT/ctl.out"; fail "silence is not explained"; }

rc=0; ctl freeze --target odonata-plant || rc=$?
((rc == 1)) || { cat "$OUT/ctl.out"; fail "freeze named at the plant exited $rc, not 1"; }

for bad in "set-entropy-threshold" "set-entropy-threshold abc" "fly-away"; do
  rc=0
  # shellcheck disable=SC2086
  "$CONTROL" $bad --lcm-url "$URL" >"$OUT/ctl.out" 2>&1 || rc=$?
  ((rc == 2)) || { cat "$OUT/ctl.out"; fail "'odonata-control $bad' exited $rc, not 2"; }
done

# A broadcast waits out its timeout for every answer: long enough for a busy machine.
ctl get --timeout 3 || fail "get to every service exited $?"
for who in odonata-plant odonata-identifier odonata-monitor odonata-logger; do
  grep -q "($who): accepted" "$OUT/ctl.out" || { cat "$OUT/ctl.out"; fail "$who did not answer get"; }
done

ctl shutdown --timeout 3 || { cat "$OUT/ctl.out"; fail "shutdown exited $?"; }
for who in odonata-plant odonata-identifier odonata-monitor odonata-logger; do
  grep -q "($who): accepted" "$OUT/ctl.out" || { cat "$OUT/ctl.out"; fail "$who did not answer shutdown"; }
done
for name in logger plant monitor ident; do
  pid_var=PID_$name
  pid=${!pid_var}
  for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
  kill -0 "$pid" 2>/dev/null && fail "$name still runs 5 s after shutdown"
  wait "$pid" || fail "$name exited with code $? after shutdown"
done
# The logger flushed and closed its file on the way out: the answers to shutdown are in it.
grep -q "events" "$OUT/logger.log" || { cat "$OUT/logger.log"; fail "the logger did not report its file on shutdown"; }
grep -qa "ODONATA_CONTROL_REPLY" "$OUT"/log.* || fail "the log lacks the control answers"
pass "odonata-control: answers printed, rejection 1, silence 3, get reads back, shutdown stops all four"
