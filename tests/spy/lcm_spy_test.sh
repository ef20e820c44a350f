#!/usr/bin/env bash
# lcm-spy, started by deploy/lcm-spy.sh under Xvfb in a private network namespace, (a) starts
# and stays up, (b) lists the project's channels and (c) decodes their types.
#
# Usage: lcm_spy_test.sh LAUNCHER TYPES_JAR PUBLISHER PROBE_JAR WORK_DIR LCMTYPES_DIR
#
# How it observes: the launcher runs with JAVA_TOOL_OPTIONS=-javaagent:PROBE_JAR, a probe
# loaded into the very lcm-spy process, which rewrites WORK_DIR/probe.txt four times a second
# with the rows of lcm-spy's channel table as displayed (Channel, Type, Num Msgs, ...) and the
# last message lcm-spy decoded on each channel (see SpyProbe.java). The publisher sends marker
# values (e.g. source=spy-test); the test requires each channel's row to name its type and the
# decoded message to carry the markers, and a channel with a foreign fingerprint
# (SPY_TEST_UNKNOWN) to show as "?? <fingerprint>", so the check can tell the two apart.
# Leaves WORK_DIR/lcm-spy.png, a screenshot of the window, and the logs.
# Exit 0 pass, 1 fail, 77 skipped (no network namespace, Xvfb or java).
set -euo pipefail

(($# == 6)) || { echo "usage: $0 LAUNCHER TYPES_JAR PUBLISHER PROBE_JAR WORK_DIR LCMTYPES_DIR" >&2; exit 2; }
abs() { case $1 in /*) echo "$1" ;; *) echo "$PWD/$1" ;; esac; }
LAUNCHER=$(abs "$1") TYPES_JAR=$(abs "$2") PUBLISHER=$(abs "$3") PROBE_JAR=$(abs "$4")
WORK=$(abs "$5") LCMTYPES_DIR=$(abs "$6")
URL='udpm://239.255.76.67:7695?ttl=0'   # a port of its own (LCM fault #302: separate by port)
RATE_HZ=20

skip() { echo "SKIP: $*"; exit 77; }
fail() {
  echo "FAIL: $*"
  for f in spy.err spy.out publisher.err probe.txt; do
    [[ -s $WORK/$f ]] && { echo "--- $f"; tail -n 40 "$WORK/$f"; }
  done
  exit 1
}

# --- outside: enter a private network namespace, bounded in time -------------------------------
if [[ -z ${ODONATA_SPY_TEST_NETNS:-} ]]; then
  for tool in unshare ip Xvfb java timeout; do
    command -v "$tool" >/dev/null 2>&1 || skip "$tool not installed"
  done
  ns=(unshare -n)
  if ! unshare -n true 2>/dev/null; then
    unshare -rn true 2>/dev/null || skip "cannot create a network namespace (needs root or user namespaces)"
    ns=(unshare -rn)
  fi
  # Multicast over loopback inside the namespace only: nothing leaves the machine.
  # shellcheck disable=SC2016  # $0/$@ expand in the inner shell
  exec timeout -k 5 100 "${ns[@]}" sh -c \
    'ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec env ODONATA_SPY_TEST_NETNS=1 "$0" "$@"' \
    "$0" "$@"
fi

# --- inside -----------------------------------------------------------------------------------
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"
xvfb_pid='' spy_pid='' pub_pid=''
cleanup() {
  for pid in $pub_pid $spy_pid $xvfb_pid; do kill "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap cleanup EXIT
trap 'exit 1' INT TERM
t0=$SECONDS

# Every child has its own timeout too, so nothing outlives the test even if it is killed.
exec 3>display.txt
timeout 95 Xvfb -displayfd 3 -screen 0 1280x800x24 -nolisten tcp >xvfb.log 2>&1 &
xvfb_pid=$!
exec 3>&-
for _ in $(seq 100); do [[ -s display.txt ]] && break; sleep 0.1; done
[[ -s display.txt ]] || fail "Xvfb did not start"
DISPLAY=:$(head -n1 display.txt)
export DISPLAY
echo "Xvfb on $DISPLAY"

JAVA_TOOL_OPTIONS="-javaagent:$PROBE_JAR=out=$WORK/probe.txt,shot=$WORK/lcm-spy.png" \
  timeout 90 "$LAUNCHER" --lcm-url "$URL" "$TYPES_JAR" >spy.out 2>spy.err &
spy_pid=$!

alive() { kill -0 "$spy_pid" 2>/dev/null; }
# wait_for SECONDS DESCRIPTION COMMAND...: polls COMMAND every 0.25 s while lcm-spy is alive.
wait_for() {
  local deadline=$((SECONDS + $1)) what=$2
  shift 2
  until "$@"; do
    alive || fail "lcm-spy exited while waiting for $what"
    ((SECONDS < deadline)) || fail "timed out waiting for $what"
    sleep 0.25
  done
}

# (a) started: the window with the channel table is up.
window_up() { grep -q '^frame LCM Spy visible=1' probe.txt 2>/dev/null && grep -q '^column 1 Type' probe.txt; }
wait_for 30 "the lcm-spy window" window_up
echo "lcm-spy window up after $((SECONDS - t0)) s"

timeout 60 "$PUBLISHER" "$URL" 45 "$RATE_HZ" >publisher.out 2>publisher.err &
pub_pid=$!

# (b) + (c): each channel listed with its type, several messages counted, the decoded message
# carrying the publisher's markers; the foreign one listed as undecodable.
declare -A TYPE=(
  [DIMAV_COMMAND]=wing_command_t [DIMAV_STATE]=plant_state_t [DIMAV_BEAT_STATE]=beat_state_t
  [ODONATA_HEARTBEAT]=heartbeat_t [ODONATA_PREDICTION]=prediction_t
  [ODONATA_ACCURACY]=accuracy_t [ODONATA_CONTROL]=control_t [ODONATA_MODEL]=model_snapshot_t)
declare -A MARKERS=(
  [DIMAV_COMMAND]='source=spy-test excitation_names[0]=u_roll freq_hz[0]=30.0'
  [DIMAV_STATE]='fx_n[0]=0.25 status=0'
  [DIMAV_BEAT_STATE]='fz_total_n=0.375 u_roll_applied_rad=0.125 attitude_hold=1'
  [ODONATA_HEARTBEAT]='service=spy-test state=running'
  [ODONATA_PREDICTION]='names[0]=roll_rad max_entropy[0]=0.75 learning=1'
  [ODONATA_ACCURACY]='names[0]=roll_rad total_vaf_free_run[0]=95.5 rules[0]=3'
  [ODONATA_CONTROL]='target=spy-test command=6'
  [ODONATA_MODEL]='instance=spy-test outputs[0]=roll_rad inputs[0]=u_roll')
declare -A MISSING=()
channels_ok() {
  local snap ch row dec m
  snap=$(cat probe.txt 2>/dev/null) || return 1
  MISSING=()
  for ch in "${!TYPE[@]}"; do
    row=$(grep -P "^row $ch\t" <<<"$snap" || true)
    dec=$(grep -P "^decoded $ch\t" <<<"$snap" || true)
    # row: Channel, Type, Num Msgs, ...
    if ! awk -F'\t' -v t="${TYPE[$ch]}" '$2 == t && $3 + 0 >= 3 { ok = 1 } END { exit !ok }' <<<"$row"; then
      MISSING[$ch]="row '${row:-none}'"
      continue
    fi
    if ! grep -qP "\tclass=odonata\.${TYPE[$ch]}\t.*\terrors=0(\t|$)" <<<"$dec"; then
      MISSING[$ch]="decoded '${dec:-none}'"
      continue
    fi
    for m in ${MARKERS[$ch]}; do
      grep -qF "	$m" <<<"$dec" || { MISSING[$ch]="no $m in '$dec'"; break; }
    done
  done
  grep -qP '^row SPY_TEST_UNKNOWN\t\?\? deadbeef0dd00a7a\t' <<<"$snap" || MISSING[SPY_TEST_UNKNOWN]="not shown as ?? deadbeef0dd00a7a"
  ((${#MISSING[@]} == 0))
}
deadline=$((SECONDS + 30))
until channels_ok; do
  alive || fail "lcm-spy exited"
  kill -0 "$pub_pid" 2>/dev/null || fail "the publisher stopped early"
  if ((SECONDS >= deadline)); then
    for ch in "${!MISSING[@]}"; do echo "  $ch: ${MISSING[$ch]}"; done
    fail "lcm-spy did not list and decode every channel"
  fi
  sleep 0.25
done
echo "all channels listed and decoded after $((SECONDS - t0)) s:"
grep -P '^(column|row|decoded) ' probe.txt | cut -c1-160 | sed 's/^/  /'

# The class discoverer found exactly the project's types (one class per .lcm file).
ntypes=$(find "$LCMTYPES_DIR" -maxdepth 1 -name '*.lcm' | wc -l)
grep -q "^Found $ntypes LCM types" spy.out || fail "lcm-spy did not report 'Found $ntypes LCM types'"

# (a) stayed up: still running, still counting, still responsive afterwards (both counters move
# on within 30 s, however busy the machine).
count() { grep -P '^row DIMAV_STATE\t' probe.txt | cut -f3; }
tick() { sed -n 's/^tick //p' probe.txt; }
n1=$(count) k1=$(tick)
for _ in $(seq 120); do
  sleep 0.25
  alive || fail "lcm-spy exited"
  n2=$(count) k2=$(tick)
  ((n2 > n1 && k2 > k1)) && break
done
((n2 > n1)) || fail "lcm-spy stopped counting DIMAV_STATE ($n1 then $n2)"
((k2 > k1)) || fail "lcm-spy's window stopped responding"
if grep -E 'Exception|Error' spy.err spy.out | grep -v '^spy.err:Picked up JAVA_TOOL_OPTIONS'; then
  fail "lcm-spy reported errors"
fi

# The screenshot, with DIMAV_STATE's viewer open (for the README; a failure is only reported).
echo DIMAV_STATE >lcm-spy.png.request
for _ in $(seq 60); do [[ -s lcm-spy.png && ! -e lcm-spy.png.request ]] && break; sleep 0.25; done
if [[ -s lcm-spy.png ]]; then echo "screenshot: $WORK/lcm-spy.png"; else echo "warning: no screenshot"; fi

# Clean shutdown.
kill "$pub_pid" 2>/dev/null || true
kill "$spy_pid"
for _ in $(seq 40); do alive || break; sleep 0.25; done
alive && fail "lcm-spy did not exit on SIGTERM"
echo "PASS: lcm-spy listed and decoded ${#TYPE[@]} channels ($((SECONDS - t0)) s)"
