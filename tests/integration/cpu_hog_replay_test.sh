#!/usr/bin/env bash
# A real-time replay beside two CPU hogs (issue 61): the Flapper's training flight paced at its own
# rate into an identifier with the configuration odonata-fit --save-config writes (scheduled
# refits, which the hogs slow down), a logger beside it, two `yes` processes on the two cores.
# Asserted is only what the protocol guarantees, never a count that follows the scheduling:
#   - SIGTERM is obeyed within the documented bound even while a refit runs;
#   - no sample unaccounted: every sample up to the newest the identifier heard is learned, or
#     counted lost on the way, or counted not learned (the socket is drained at the stop);
#   - the logger's export and the identifier agree on what was lost: every sample the replay
#     sent is in the log or counted missing there.
# The counts themselves (how many were lost) are printed, not asserted.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
R=${ODONATA_REALDATA:?}
REPLAY=$BUILD/services/replay/odonata-replay
OUT=$(mktemp -d)
HOGS=()
trap 'kill "${HOGS[@]}" 2>/dev/null || true; stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
URL="udpm://239.255.76.69:7803?ttl=0"
SECONDS_SENT=${ODONATA_HOG_SECONDS:-25}
STOP_BOUND_S=30  # a refit gives up on SIGTERM within a training pass (docs/identifier.md §6.3)

"$FIT" --train "$R/flapper_level1.csv" --output pitch_deg --input m2 --input thrust --ny 2 \
  --nu 2 --no-select --save-config "$OUT/pitch.json" >"$OUT/fit.log" 2>&1 ||
  fail "--save-config: $(cat "$OUT/fit.log")"
"$PY" - "$OUT/pitch.json" <<'PYEOF' || fail "the configuration has no scheduled refits"
import json, sys
c = json.load(open(sys.argv[1]))
assert c.get('refit_first', 0) > 0, c
PYEOF
for _ in 1 2; do yes >/dev/null & HOGS+=($!); done

start ident "$IDENT" --config "$OUT/pitch.json" --lcm-url "$URL" --resume-wait 0 \
  --save-model "$OUT/model.json"
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL"
wait_up "$URL" identifier logger -- --state running
"$REPLAY" "$R/flapper_level1.csv" --to "$SECONDS_SENT" --lcm-url "$URL" \
  --summary-json "$OUT/replay.json" >"$OUT/replay.out" 2>"$OUT/replay.err" ||
  fail "the replay failed: $(cat "$OUT/replay.err")"
# Stopped at once, whatever it is doing (a refit under the hogs, a backlog of samples).
t0=$(date +%s.%N)
kill -TERM "$PID_ident"
for _ in $(seq $((STOP_BOUND_S * 20))); do kill -0 "$PID_ident" 2>/dev/null || break; sleep 0.05; done
kill -0 "$PID_ident" 2>/dev/null && fail "the identifier ignored SIGTERM for $STOP_BOUND_S s: $(tail -3 "$OUT/ident.log")"
rc=0
wait "$PID_ident" || rc=$?
((rc == 0)) || fail "the identifier exited $rc after SIGTERM: $(tail -5 "$OUT/ident.log")"
stop_s=$("$PY" -c "import sys, time; print('%.1f' % (time.time() - float(sys.argv[1])))" "$t0")
stop_clean "$PID_logger" logger
"$LOGGER" export "$OUT"/log.* --signals -o "$OUT/logged.csv" >"$OUT/export.log" 2>&1 ||
  fail "export: $(cat "$OUT/export.log")"
kill "${HOGS[@]}" 2>/dev/null || true

"$PY" - "$OUT" "$stop_s" <<'PYEOF' || fail "samples unaccounted: see above"
import json, re, sys
out, stop_s = sys.argv[1], sys.argv[2]
ident = open(out + '/ident.log').read()
m = re.search(r'samples: newest seq (-?\d+); resumed through seq (-?\d+); (\d+) taken \((\d+) learned[^)]*\), (\d+) lost on the way \(gaps\), (\d+) not learned', ident)
assert m, 'no accounting line in the identifier\'s log:\n' + ident[-2000:]
newest, resumed, taken, learned, lost, not_learned = (int(x) for x in m.groups())
replay = json.load(open(out + '/replay.json'))
sent = replay['samples_sent'] if 'samples_sent' in replay else replay['sent']
assert resumed + 1 + taken + lost + not_learned == newest + 1, (
    'identifier: %d taken + %d lost + %d not learned != newest seq %d + 1' % (taken, lost, not_learned, newest))
assert learned <= taken
assert newest + 1 <= sent, (newest, sent)
export = open(out + '/export.log').read()
rows = int(re.search(r'(\d+) signals samples', export).group(1))
logger_lost = int(re.search(r'(\d+) lost', export).group(1))
with open(out + '/logged.csv') as f:
    last_seq = max(int(line.split(',')[0]) for line in list(f)[1:])
assert rows + logger_lost == last_seq + 1, ('logger', rows, logger_lost, last_seq)
print('beside two hogs: %d sent; the identifier heard up to seq %d, took %d (learned %d), counted '
      '%d lost and %d not learned; the logger holds %d and counts %d lost; SIGTERM obeyed in %s s'
      % (sent, newest, taken, learned, lost, not_learned, rows, logger_lost, stop_s))
PYEOF
pass "a real-time replay beside two CPU hogs: every sample learned or counted, SIGTERM obeyed"
