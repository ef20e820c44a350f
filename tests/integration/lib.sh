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

# wait_for_log FILE PATTERN: waits up to 5 s for a line matching PATTERN in FILE (a process's log).
wait_for_log() {
  for _ in $(seq 100); do grep -q "$2" "$1" 2>/dev/null && return 0; sleep 0.05; done
  return 1
}

# Stops a process with SIGTERM and fails unless it exits 0 within 5 s.
stop_clean() {
  local pid=$1 what=$2
  kill -TERM "$pid"
  for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
  kill -0 "$pid" 2>/dev/null && fail "$what did not exit within 5 s of SIGTERM"
  wait "$pid" || fail "$what exited with code $? after SIGTERM"
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

json_get() { "$PY" -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"; }

# Fails unless two model files hold the same model, compared as parsed JSON (doubles exactly).
same_model() {
  "$PY" -c "import json,sys; a=json.load(open(sys.argv[1])); b=json.load(open(sys.argv[2])); sys.exit(0 if a==b else 1)" "$1" "$2"
}

# offline_fit CONFIG TRAIN_CSV OUT_MODEL: odonata-fit with exactly the online learner's settings.
offline_fit() {
  local cfg=$1 csv=$2 model=$3
  "$PY" - "$cfg" "$csv" "$model" "$FIT" <<'PYEOF'
import json, subprocess, sys, tempfile, os
cfg, csv, model, fit = sys.argv[1:5]
c = json.load(open(cfg))
ranges = tempfile.NamedTemporaryFile("w", suffix=".json", delete=False)
json.dump(c["ranges"], ranges); ranges.close()
cmd = [fit, "--train", csv, "--output", c["outputs"][0], "--ny", str(c["ny"]), "--nu", str(c["nu"]),
       "--delay", str(c["delay"]), "--ranges", ranges.name, "--epochs", "1", "--no-least-squares",
       "--consequent", c["consequent"], "--kappa", str(c["kappa"]), "--sigma-min", str(c["sigma_min"]),
       "--max-rules", str(c["max_rules"]), "--entropy-threshold", str(c["entropy_threshold"]),
       "--forgetting", str(c.get("forgetting", 1.0)), "--prune-utility", str(c.get("prune_utility", 0.0)),
       "--save-model", model]
for i in c["inputs"]:
    cmd += ["--input", i]
subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
os.unlink(ranges.name)
PYEOF
}
