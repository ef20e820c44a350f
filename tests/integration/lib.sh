# Shared helpers for the multi-process integration tests (sourced, not run).
# Every test runs its processes inside a private network namespace with multicast routed on
# that namespace's loopback, so no packet leaves the machine.
set -euo pipefail

BUILD=${ODONATA_BUILD:?ODONATA_BUILD must point at the build tree}
SRC=${ODONATA_SOURCE:?ODONATA_SOURCE must point at the source tree}
PLANT=$BUILD/services/plant/odonata-plant
SIGNAL=$BUILD/services/signal/odonata-signal
IDENT=$BUILD/services/identifier/odonata-identifier
MONITOR=$BUILD/services/monitor/odonata-monitor
LOGGER=$BUILD/services/logger/odonata-logger
CONTROL=$BUILD/services/control/odonata-control
FIT=$BUILD/services/fit/odonata-fit
HBWAIT=$BUILD/tests/integration/heartbeat_wait
PY=/usr/bin/python3

fail() { echo "FAIL: $*" >&2; exit 1; }
pass() { echo "PASS: $*"; }

# Re-executes the calling script inside a new network namespace (once).
enter_netns() {
  if [[ ${ODONATA_IN_NETNS:-0} != 1 ]]; then
    export ODONATA_IN_NETNS=1
    exec unshare -n sh -c 'ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec "$0" "$@"' \
      bash "$0" "$@"
  fi
}

PIDS=()
start() {  # start NAME CMD... : background process with its output in $OUT/NAME.log
  local name=$1
  shift
  "$@" >"$OUT/$name.log" 2>&1 &
  PIDS+=($!)
  eval "PID_${name//-/_}=$!"
}

stop_all() {
  for pid in "${PIDS[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${PIDS[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null || true
  done
}

# wait_for_log FILE PATTERN [SECONDS]: waits (5 s unless told) for a line matching PATTERN in
# FILE (a process's log); returns 1 at the timeout.
wait_for_log() {
  local polls=$(((${3:-5} * 20)))
  for _ in $(seq "$polls"); do grep -q "$2" "$1" 2>/dev/null && return 0; sleep 0.05; done
  return 1
}

# The tests wait for the system, not the clock: a sleep that stands for "the services are up" or
# "the run is halfway" breaks on a machine faster or slower than the one it was tuned on.
#
# wait_up URL NAME... [-- HEARTBEAT_WAIT_FLAGS...]: waits (up to 60 s) until every named instance
# (or service) has published a heartbeat meeting the flags after `--` (heartbeat_wait.cpp), e.g.
# `-- --state running --fresh`; fails naming them and what it last saw of each.
wait_up() {
  local url=$1 args=()
  shift
  while (($#)) && [[ $1 != -- ]]; do args+=(--instance "$1"); shift; done
  (($#)) && shift
  local netns=()  # ODONATA_NETNS: listen from inside that namespace (a test's board)
  [[ -n ${ODONATA_NETNS:-} ]] && netns=(ip netns exec "$ODONATA_NETNS")
  "${netns[@]}" "$HBWAIT" --lcm-url "$url" "${args[@]}" --timeout 60 "$@" >/dev/null 2>"$OUT/heartbeat_wait.err" ||
    fail "waited for $(cat "$OUT/heartbeat_wait.err")"
}

# wait_count URL NAME COUNTER N: waits (up to 60 s) until NAME's heartbeat reports COUNTER ≥ N
# (messages_in, messages_out, …): "the run is under way" read off the bus.
wait_count() {
  wait_up "$1" "$2" -- --at-least "$3=$4"
}

# wait_hold PID LOG K: waits until the generator (pid PID, stderr in LOG), started with
# --hold-at K, holds before command K with every state up to K confirmed; fails if it exits or
# takes more than 120 s. Whatever the test does next happens at sample K, at any speed.
wait_hold() {
  local pid=$1 log=$2 k=$3
  for _ in $(seq 2400); do
    grep -q "holding before command $k:" "$log" 2>/dev/null && return 0
    kill -0 "$pid" 2>/dev/null || fail "the generator exited before holding at command $k: $(cat "$log")"
    sleep 0.05
  done
  fail "the generator did not hold at command $k within 120 s: $(cat "$log")"
}

# Stops a process with SIGTERM and fails unless it exits 0 within 5 s.
stop_clean() {  # stop_clean PID WHAT [EXPECTED_CODE]: SIGTERM, exit within 5 s with the code
  local pid=$1 what=$2 expected=${3:-0} rc=0
  kill -TERM "$pid"
  for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
  kill -0 "$pid" 2>/dev/null && fail "$what did not exit within 5 s of SIGTERM"
  wait "$pid" || rc=$?
  ((rc == expected)) || fail "$what exited with code $rc after SIGTERM, not $expected"
}

# readme_block MARKER: the shell block of README.md after the comment line holding MARKER, as it is
# written (the README's blocks that tests run); fails when there is none.
readme_block() {
  "$PY" - "$SRC/README.md" "$1" <<'PYEOF' || fail "no block after '$1' in README.md"
import sys
lines = open(sys.argv[1]).read().split("\n")
start = next(i for i, l in enumerate(lines) if sys.argv[2] in l)
first = next(i for i in range(start, len(lines)) if lines[i].startswith("```"))
last = next(i for i in range(first + 1, len(lines)) if lines[i].startswith("```"))
print("\n".join(lines[first + 1:last]))
PYEOF
}

# json_get FILE EXPR: evaluates a Python expression on the parsed JSON `j`.
# odonata_run SECONDS ARGS...: deploy/odonata-run ARGS into $OUT/run, its output in $OUT/run.log,
# which a failure shows.
odonata_run() {
  local limit=$1
  shift
  timeout "$limit" "$SRC/deploy/odonata-run" "$@" --out "$OUT/run" --build "$BUILD" >"$OUT/run.log" 2>&1 ||
    { cat "$OUT/run.log"; fail "odonata-run failed"; }
}

# new_bus_key PATH: a fresh shared key for a signed bus (docs/lcm.md §15), readable by its owner
# only, as the services require.
new_bus_key() { (umask 077 && od -An -tx1 -N32 /dev/urandom | tr -d ' \n' >"$1"); }

json_get() { "$PY" -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"; }

# Fails unless two model files hold the same model, compared as parsed JSON (doubles exactly).
# same_model A B: the two model files hold the same model, bit for bit. Each rule's parameter
# covariance a file may keep beside it ("local_model_covariance", which the model never reads) is a
# statistic of the data its writer kept, not part of the model: odonata-fit estimates it on the
# training file, the identifier on the samples it kept for its refits.
same_model() {
  "$PY" -c "
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
for m in (a, b):
    m.pop('local_model_covariance', None)
sys.exit(0 if a == b else 1)" "$1" "$2"
}

# offline_fit CONFIG TRAIN_CSV OUT_MODEL [unfrozen]: odonata-fit with exactly the online learner's
# settings (keys the config leaves out take the identifier's defaults); "unfrozen" replays an
# identifier stopped without a freeze (no closing refit).
offline_fit() {
  local cfg=$1 csv=$2 model=$3 frozen=${4:-frozen}
  "$PY" - "$cfg" "$csv" "$model" "$FIT" "$IDENT" "$frozen" <<'PYEOF'
import json, subprocess, sys, tempfile, os
cfg, csv, model, fit, ident, frozen = sys.argv[1:7]
c = json.loads(subprocess.run([ident, "--print-config"], check=True, capture_output=True, text=True).stdout)
c.update(json.load(open(cfg)))
ranges = tempfile.NamedTemporaryFile("w", suffix=".json", delete=False)
json.dump(c["ranges"], ranges); ranges.close()
cmd = [fit, "--train", csv, "--output", c["outputs"][0], "--ny", str(c["ny"]), "--nu", str(c["nu"]),
       "--delay", str(c["delay"]), "--ranges", ranges.name, "--epochs", "1", "--no-least-squares",
       "--consequent", c["consequent"], "--kappa", str(c["kappa"]), "--sigma-min", str(c["sigma_min"]),
       "--max-rules", str(c["max_rules"]), "--entropy-threshold", str(c["entropy_threshold"]),
       "--forgetting", str(c.get("forgetting", 1.0)), "--prune-utility", str(c.get("prune_utility", 0.0)),
       "--refit-first", str(c["refit_first"]), "--refit-every", str(c["refit_every"]),
       "--refit-buffer", str(c["refit_buffer"]), "--refit-history", str(c.get("refit_history", 0.5)),
       "--refit-at-freeze", str(c["refit_at_freeze"]).lower(),
       "--save-model", model]
for i in c["inputs"]:
    cmd += ["--input", i]
if c.get("refit_horizon", 0) >= 2:
    cmd += ["--horizon", str(c["refit_horizon"])]
if frozen == "unfrozen":
    cmd += ["--replay-unfrozen"]
subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
os.unlink(ranges.name)
PYEOF
}

# vehicle_accounting URL INSTANCE N: asks a signals identifier (get) what it learned of a vehicle's
# N samples and sets LEARNED and GAPS. Real time over UDP guarantees no delivery; what the
# protocol guarantees is the accounting: a sample after the first (ny = nu = 1) is learned at
# most once and a lost one is counted (the last ones excepted: nothing after them shows the gap).
vehicle_accounting() {
  local url=$1 instance=$2 n=$3
  # BUS_KEY: the system's shared key, when its services sign (docs/lcm.md §15).
  "$CONTROL" get --target "$instance" --lcm-url "$url" ${BUS_KEY:+--key "$BUS_KEY"} >"$OUT/get.out" 2>&1 ||
    { cat "$OUT/get.out"; fail "the identifier did not answer get"; }
  LEARNED=$(sed -nE 's/.*samples_learned=([0-9]+).*/\1/p' "$OUT/get.out")
  GAPS=$(sed -nE 's/.* gaps=([0-9]+).*/\1/p' "$OUT/get.out")
  [[ -n $LEARNED && -n $GAPS ]] || { cat "$OUT/get.out"; fail "get did not report samples_learned and gaps"; }
  ((LEARNED >= 1 && LEARNED + GAPS <= n - 1)) ||
    { cat "$OUT/get.out"; fail "learned $LEARNED and lost $GAPS of $((n - 1)) samples"; }
}

# vehicle_offline_equal CONFIG CSV MODEL N: when nothing was lost live (GAPS) or in the log (CSV
# has N rows), odonata-fit on the exported CSV must give MODEL bit for bit (the logger and the
# identifier follow one sequence rule); sets SAME to what was found.
vehicle_offline_equal() {
  local cfg=$1 csv=$2 model=$3 n=$4 rows
  rows=$(($(wc -l <"$csv") - 1))
  if ((GAPS == 0 && rows == n)); then
    offline_fit "$cfg" "$csv" "$OUT/offline.json" unfrozen
    same_model "$model" "$OUT/offline.json" || fail "the online model differs from odonata-fit on the exported log"
    SAME="offline model identical"
  else
    SAME="$GAPS samples lost live, $((n - rows)) in the log: models not compared"
  fi
}
