#!/usr/bin/env bash
# Signed messages (issue 24 point 1, docs/lcm.md §15): with a shared key, a lockstep run under
# attack by everything a forger without the key can send — the well-formed forged kinds of the
# issue's probe (a lone state 0, far, negative and duplicate seqs, receipts far ahead in the
# consumers' names, freeze, shutdown, save-model and reset commands, answers to every control
# command it hears, a snapshot,
# a heartbeat of a consumer that does not exist), each unsigned and signed with a wrong key, the
# right key's signature a minute old, every genuine message captured and sent again, and
# lcm-logplayer replaying an lcm-logger recording of an earlier run of the same system — ends
# with exit 0, every forged message refused and counted, the log complete and the model, bit
# for bit, the one the clean samples give.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7693?ttl=0'
KEY=$OUT/bus.key
new_bus_key "$KEY"
K=(--lcm-url "$URL" --key "$KEY")
"$SRC/deploy/make-identifier-config" --preset roll --duration 10 --build "$BUILD" --output "$OUT/id.json"

# Run A: the signed system, recorded with its signatures by LCM's own lcm-logger.
start rec lcm-logger --lcm-url="$URL" "$OUT/a.lcmlog"
start plant_a "$PLANT" --mode lockstep --preset roll "${K[@]}"
start ident_a "$IDENT" --config "$OUT/id.json" --resume-wait 0 --instance identifier "${K[@]}"
# A logger started without the key (a board set-up error, issue 51 point 3): it says at once that
# the bus is signed, and the generator names it and stops at once with code 7 (not lossless for
# it).
start bare "$LOGGER" record -o "$OUT/bare" --lcm-url "$URL" --instance bare-logger
wait_up "$URL" odonata-plant identifier bare-logger
rc=0
# A 10-minute run: it must stop within seconds, naming the logger, not at its end.
SECONDS=0
timeout 120 "$SIGNAL" --preset roll --phase train --duration 600 --mode lockstep "${K[@]}" \
  >"$OUT/signal_a.log" 2>&1 || rc=$?
((rc == 7)) || { cat "$OUT/signal_a.log"; fail "signed run A beside a keyless logger exited $rc, not 7"; }
((SECONDS < 60)) || fail "the run went on for $SECONDS s beside a keyless logger"
grep -q "error: 'bare-logger' (odonata-logger) is heard but its messages are refused" "$OUT/signal_a.log" ||
  { cat "$OUT/signal_a.log"; fail "the generator did not name the keyless logger"; }
stop_clean "$PID_bare" "keyless logger"
grep -q "no key on a signed bus" "$OUT/bare.log" || { cat "$OUT/bare.log"; fail "the keyless logger did not say the bus is signed"; }
stop_clean "$PID_ident_a" "identifier (run A)"
stop_clean "$PID_plant_a" "plant (run A)"
kill -INT "$PID_rec" 2>/dev/null; wait "$PID_rec" 2>/dev/null || true
[[ -s $OUT/a.lcmlog ]] || fail "lcm-logger recorded nothing of run A"
# Run B's services start after run A's last message: run A's recording is stamped before any
# of them started, and is refused whole (docs/lcm.md §15).

start logger "$LOGGER" record -o "$OUT/log" "${K[@]}"
start monitor "$MONITOR" --summary-json "$OUT/monitor.json" "${K[@]}"
start plant "$PLANT" --mode lockstep --preset roll "${K[@]}"
mkdir -p "$OUT/models"
start ident "$IDENT" --config "$OUT/id.json" --resume-wait 0 --save-model "$OUT/model.json" \
  --models-dir "$OUT/models" "${K[@]}"
wait_up "$URL" logger monitor odonata-plant identifier
start forger "$BUILD/tests/integration/forger" "$URL" 60 "$KEY"
start replay lcm-logplayer -l "$URL" "$OUT/a.lcmlog"
# The forger's traffic is on the bus before the run starts: the plant has refused some already.
wait_count "$URL" odonata-plant dropped 1
# Every command is sent and every authentic consumer waited for; the forged heartbeats of a
# "consumer" (a forger and a keyless service look alike) would stop the run at once: told to
# keep going, the generator names them and ends with code 7.
rc=0
timeout 180 "$SIGNAL" --preset roll --phase train --duration 10 --mode lockstep "${K[@]}" \
  --keep-going-without-refused \
  >"$OUT/signal.log" 2>&1 || rc=$?
((rc == 0 || rc == 7)) || { cat "$OUT/signal.log"; fail "the signed run failed under attack (exit $rc)"; }
wait_up "$URL" identifier odonata-plant logger monitor -- --fresh --at-least dropped=1
for p in "$PID_logger" "$PID_monitor" "$PID_plant" "$PID_ident"; do
  kill -0 "$p" 2>/dev/null || fail "a service stopped under attack (a forged shutdown obeyed?)"
done
# A command to a service that does not exist, while the forger answers every command it hears
# "accepted": odonata-control with the key takes no forged answer (without it, exit 0).
if "$CONTROL" freeze --target ghost-identifier --timeout 1 "${K[@]}" >"$OUT/control.log" 2>&1; then
  fail "odonata-control took a forged answer: $(cat "$OUT/control.log")"
fi
"$CONTROL" freeze --target ghost-identifier --timeout 1 --lcm-url "$URL" >"$OUT/control-unsigned.log" 2>&1 ||
  fail "the forger's answers did not reach a keyless odonata-control: the check above proves nothing"
# And it says that such answers prove nothing (issue 51 point 6).
grep -q "not authenticated" "$OUT/control-unsigned.log" || fail "a keyless odonata-control did not say its answers are unauthenticated"
kill -TERM "$PID_forger" 2>/dev/null || true
wait "$PID_forger" 2>/dev/null || true
stop_clean "$PID_ident" identifier
stop_clean "$PID_plant" plant
stop_clean "$PID_monitor" monitor
stop_clean "$PID_logger" logger
! grep -q "waits for receipts from:.*ghost-identifier" "$OUT/signal.log" || fail "the generator believed a forged heartbeat"
[[ ! -e $OUT/models/forged.json ]] || fail "a forged save-model was obeyed"
grep -q "refused message" "$OUT/ident.log" || fail "the identifier reported no refused message"
for s in identifier odonata-plant logger monitor; do
  n=$(json_get "$OUT/monitor.json" "j['services']['$s']['dropped']")
  ((n > 0)) || fail "$s counted no refused message"
done
"$LOGGER" export "$OUT"/log.* -o "$OUT/train.csv" >"$OUT/export.log" 2>&1 || { cat "$OUT/export.log"; fail "export failed"; }
rows=$(($(wc -l <"$OUT/train.csv") - 1))
((rows == 1000)) || fail "the log holds $rows of 1000 samples"
offline_fit "$OUT/id.json" "$OUT/train.csv" "$OUT/offline.json"
same_model "$OUT/model.json" "$OUT/offline.json" || fail "the forged traffic changed the model"
sent=$(grep "^forger:" "$OUT/forger.log" || true)
[[ -n $sent ]] || fail "the forger said nothing: $(cat "$OUT/forger.log")"
pass "signed run under attack ($sent; lcm-logplayer replaying run A): all refused, log complete ($rows samples), model == clean-sample model"
