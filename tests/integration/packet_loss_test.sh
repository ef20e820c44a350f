#!/usr/bin/env bash
# Packet loss on the bus (iptables' statistic match drops that share of the UDP datagrams on the
# port, inside this test's network namespace). Lockstep under 5 % loss with the default window of
# commands in flight gives the same model, bit for bit, as one command at a time without loss
# (the generator resends until every consumer has every sample, and the plant applies commands in
# seq order whatever order they arrive in). Real
# time under 1 % and 5 % loss still identifies the loop (validation one-step FIT ≥ 90 %, the
# paper's bar), and the identifier counts the samples it lost. How close that FIT comes to the
# clean run's is printed, not asserted: it follows the samples learned, which a CPU-starved run
# loses more of (96.8 against 98.6 % at 5 % loss under two hogs on one core).
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
command -v iptables >/dev/null || fail "iptables is missing (deploy/setup.sh installs it)"
OUT=$(mktemp -d)
trap 'stop_all; [[ -n ${KEEP:-} ]] || rm -rf "$OUT"' EXIT
PORT=7691
URL="udpm://239.255.76.67:$PORT?ttl=0"
loss() {  # loss PERCENT: drop that share of the datagrams on the port (0: none)
  iptables -F INPUT
  [[ $1 == 0 ]] && return
  iptables -A INPUT -p udp --dport $PORT -m statistic --mode random \
    --probability "$("$PY" -c "print($1 / 100)")" -j DROP
}
dropped() { iptables -L INPUT -v -n -x | awk '/DROP/ {print $1}'; }

# Lockstep: clean one command at a time, then 5 % loss with the default window, same seed: the
# same model. The consumers are named (--wait-for): discovery alone could miss both heartbeats
# under the loss and leave them out of the run (it did once, under four CPU hogs).
lockstep() {  # lockstep NAME [SIGNAL_FLAGS...]
  local name=$1
  shift
  start "logger_$name" "$LOGGER" record -o "$OUT/$name/log" --lcm-url "$URL"
  start "plant_$name" "$PLANT" --mode lockstep --preset roll --lcm-url "$URL"
  start "ident_$name" "$IDENT" --config "$OUT/id.json" --lcm-url "$URL" --resume-wait 0 \
    --save-model "$OUT/$name/model.json"
  wait_up "$URL" logger odonata-plant identifier -- --fresh
  timeout 120 "$SIGNAL" --preset roll --phase train --duration 5 --mode lockstep --lcm-url "$URL" \
    --timeout-ms 20 --max-resends 50 --wait-for identifier --wait-for logger "$@" \
    >"$OUT/$name/signal.log" 2>&1 ||
    fail "lockstep run ($name) failed: $(cat "$OUT/$name/signal.log")"
  eval "stop_clean \$PID_ident_$name identifier; stop_clean \$PID_plant_$name plant; stop_clean \$PID_logger_$name logger"
}
mkdir -p "$OUT/clean" "$OUT/lossy"
"$SRC/deploy/make-identifier-config" --preset roll --duration 5 --build "$BUILD" --output "$OUT/id.json"
loss 0
lockstep clean --window 1
loss 5
lockstep lossy
lost=$(dropped)
loss 0
((lost > 0)) || fail "iptables dropped nothing"
same_model "$OUT/clean/model.json" "$OUT/lossy/model.json" ||
  fail "5 % loss with a window of commands in flight changed the lockstep model"
# The logger acknowledged only what it had written: both logs export the same 500 samples.
for name in clean lossy; do
  "$LOGGER" export "$OUT/$name"/log.* -o "$OUT/$name/train.csv" >"$OUT/$name/export.log" 2>&1 ||
    { cat "$OUT/$name/export.log"; fail "export of the $name log failed"; }
done
rows=$(($(wc -l <"$OUT/lossy/train.csv") - 1))
((rows == 500)) || fail "the lossy run's log holds $rows of 500 samples"
cmp -s "$OUT/clean/train.csv" "$OUT/lossy/train.csv" ||
  fail "the lossy run's log exports other samples than the clean run's"
resends=$(grep -o "sent [0-9]* commands.*" "$OUT/lossy/signal.log")
echo "lockstep, 5 % loss: $lost datagrams dropped; $resends; model and logged samples identical to the clean run's"

# Real time: clean, 1 %, 5 %.
realtime() {  # realtime NAME PERCENT
  loss "$2"
  timeout 120 "$SRC/deploy/odonata-run" --host --lcm-url "$URL" --preset roll --mode realtime \
    --duration 8 --out "$OUT/rt-$1" --build "$BUILD" >"$OUT/rt-$1.log" 2>&1 ||
    fail "real-time run ($1) failed: $(tail -5 "$OUT/rt-$1.log")"
  echo "$(dropped)" >"$OUT/rt-$1/dropped"
  loss 0
}
realtime clean 0
realtime one 1
realtime five 5
"$PY" - "$OUT" <<'PYEOF'
import json, sys
out = sys.argv[1]
def get(name):
    j = json.load(open(f"{out}/rt-{name}/monitor-summary.json"))
    fit = j["outputs"]["roll_rad"]["one_step"]["fit"]  # the last run: validation, frozen model
    gaps = j["services"]["identifier"]["gaps"]
    dropped = int(open(f"{out}/rt-{name}/dropped").read().strip() or 0)
    return fit, gaps, dropped
def learned(name):
    # The identifier's own count in its last snapshot: the training phase's samples it learned.
    snaps = json.load(open(f"{out}/rt-{name}/snapshots.json"))
    snaps = snaps.get("snapshots", snaps) if isinstance(snaps, dict) else snaps
    return max(int(s.get("samples_learned", 0)) for s in snaps)
clean, _, _ = get("clean")
if not clean >= 90.0:
    print(f"FAIL: the clean real-time run reached only {clean:.2f} %"); sys.exit(1)
clean_learned = learned("clean")
for name, pct in (("one", 1), ("five", 5)):
    fit, gaps, dropped = get(name)
    n = learned(name)
    print(f"real time, {pct} % loss: {dropped} datagrams dropped, identifier counted {gaps} lost "
          f"samples and learned {n} (clean run {clean_learned}); validation one-step FIT "
          f"{fit:.2f} % (clean {clean:.2f} %)")
    if dropped == 0 or gaps == 0:
        print("FAIL: no loss happened or none was counted"); sys.exit(1)
    if not fit >= 90.0:
        print(f"FAIL: FIT {fit:.2f} % under {pct} % loss is below 90 % (clean run {clean:.2f} %)"); sys.exit(1)
    # How many are learned depends on the machine's load as well as the loss (a starved process
    # loses more in real time): a figure, not an assertion. That short gaps are bridged is what
    # tests/sysid and tests/identifier assert (quiet: 828/829 at 1 %, 758/829 at 5 %).
PYEOF
pass "packet loss: lockstep (window 16 against 1) bit-identical at 5 % (model and log), real time ≥ 90 % FIT at 1 % and 5 %, losses counted"
