#!/usr/bin/env bash
# kill -9 of the logger in lockstep: everything it acknowledged is in its file (it flushes before
# each receipt, so nothing the generator will not resend is lost with the process), and the log
# it leaves — possibly ending in a cut-off event — exports up to the kill. The logger flushes by
# its clock only once a minute here, so only the flush before each receipt can pass the test.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7689?ttl=0'
HOLD=600  # of 1000
start logger "$LOGGER" record -o "$OUT/log" --lcm-url "$URL" --flush-period 60
start plant "$PLANT" --mode lockstep --preset roll --lcm-url "$URL"
wait_up "$URL" logger odonata-plant
start signal "$SIGNAL" --preset roll --phase train --duration 10 --mode lockstep --lcm-url "$URL" \
  --hold-at $HOLD --timeout-ms 50 --max-resends 4
wait_hold "$PID_signal" "$OUT/signal.log" $HOLD
grep -q "waits for receipts from: logger" "$OUT/signal.log" ||
  fail "the generator did not find the logger: $(cat "$OUT/signal.log")"
kill -KILL "$PID_logger"
kill -USR1 "$PID_signal"
rc=0
wait "$PID_signal" || rc=$?
((rc == 4)) || fail "losing the logger gave exit code $rc, not 4: $(cat "$OUT/signal.log")"
stop_clean "$PID_plant" plant
"$LOGGER" export "$OUT"/log.* -o "$OUT/train.csv" >"$OUT/export.log" 2>&1 ||
  { cat "$OUT/export.log"; fail "the killed logger's log does not export"; }
rows=$(($(wc -l <"$OUT/train.csv") - 1))
# States 0 … HOLD were acknowledged, each with its command and beat state: HOLD samples at least.
((rows >= HOLD)) || fail "the log holds $rows samples; the logger had acknowledged $HOLD"
# The newest acknowledged state itself, HOLD, is in the file (the export's samples pair a state
# with the command applied at it, so they end one before): read the log's DIMAV_STATE seqs.
newest=$("$PY" - "$OUT"/log.* <<'PYEOF'
import struct, sys
newest = -1
for path in sys.argv[1:]:
    b = open(path, "rb").read()
    i = 0
    while i + 28 <= len(b) and b[i:i + 4] == b"\xed\xa1\xda\x01":
        clen, dlen = struct.unpack(">ii", b[i + 20:i + 28])
        if i + 28 + clen + dlen > len(b):
            break  # the cut-off end
        channel = b[i + 28:i + 28 + clen].decode(errors="replace")
        data = b[i + 28 + clen:i + 28 + clen + dlen]
        if channel == "DIMAV_STATE" and len(data) >= 24:
            newest = max(newest, struct.unpack(">q", data[16:24])[0])
        i += 28 + clen + dlen
print(newest)
PYEOF
)
((newest >= HOLD)) || fail "the newest state in the log is $newest; the logger had acknowledged $HOLD"
pass "logger killed at sample $HOLD: its log exports $rows samples and holds state $newest, all it acknowledged"
