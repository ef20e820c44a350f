#!/usr/bin/env bash
# Fleet benchmark (issue 13): N vehicles at 100 Hz each in real time, one odonata-identifier per
# vehicle (channel suffix V1 … VN), for N = 1, 4, 16, 64, in two layouts:
#   shared   — every vehicle on the default multicast group and port, as --channel-suffix alone
#              gives: every process receives every vehicle's packets and LCM drops the foreign
#              channels after reading them, so the load grows with N²;
#   per-port — vehicle i on its own UDP port (udpm://239.255.76.67:7700+i): each process reads
#              only its own vehicle's packets.
# Each vehicle is a bench_pipeline producer (commands and states paced at 100 Hz, predictions
# timed). Reports per layout and N: dropped predictions, latency p50/p99 (median over vehicles
# and worst vehicle) and the identifiers' CPU per vehicle (% of one core).
# One identifier serving several vehicles is not in the design: a process holds one model over
# one vehicle's channels (services/identifier/identifier_node.hpp).
# Runs inside a private network namespace. Usage: run_fleet_bench.sh [BUILD] [SECONDS]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${1:-$ROOT/build}
SECONDS_PER_RUN=${2:-10}
source "$ROOT/bench/lib.sh"
bench_enter_netns "$@"
B=$BUILD/bench/pipeline/bench_pipeline
ID=$BUILD/services/identifier/odonata-identifier
bench_scratch
TICK=$(getconf CLK_TCK)
cpu_ticks() { awk '{print $14 + $15}' "/proc/$1/stat" 2>/dev/null || echo 0; }
samples=$((SECONDS_PER_RUN * 100))

run() {  # layout N
  local layout=$1 n=$2 i url
  local -a ids=()
  for ((i = 1; i <= n; i++)); do
    url='udpm://239.255.76.67:7667?ttl=0'
    [[ $layout == per-port ]] && url="udpm://239.255.76.67:$((7700 + i))?ttl=0"
    cat >"$TMP/id$i.json" <<JSON
{"instance": "v$i", "outputs": ["roll_rad"], "inputs": ["u"], "ny": 1, "nu": 1, "delay": 1,
 "consequent": "singleton", "entropy_threshold": 0.05, "max_rules": 41,
 "ranges": {"roll_rad": [-1.5, 1.5], "u": [-1.5, 1.5]}, "snapshot_period_s": 0, "resume_wait_s": 0}
JSON
    "$ID" --config "$TMP/id$i.json" --lcm-url "$url" --channel-suffix "V$i" >"$TMP/id$i.log" 2>&1 &
    ids+=($!)
  done
  sleep $((1 + n / 16))
  local -a before=()
  for pid in "${ids[@]}"; do before+=($(cpu_ticks "$pid")); done
  local t0=$(date +%s.%N)
  for ((i = 1; i <= n; i++)); do
    url='udpm://239.255.76.67:7667?ttl=0'
    [[ $layout == per-port ]] && url="udpm://239.255.76.67:$((7700 + i))?ttl=0"
    "$B" --lcm-url "$url" --channel-suffix "V$i" --mode rate --rate-hz 100 --samples $samples \
      >"$TMP/veh$i.out" 2>&1 &
  done
  wait $(jobs -p | grep -v -F -x -f <(printf '%s\n' "${ids[@]}")) 2>/dev/null || true
  local t1=$(date +%s.%N)
  local ticks=0 k=0
  for pid in "${ids[@]}"; do ticks=$((ticks + $(cpu_ticks "$pid") - before[k])); k=$((k + 1)); done
  kill "${ids[@]}" 2>/dev/null || true
  wait "${ids[@]}" 2>/dev/null || true
  cat "$TMP"/veh*.out | "$ROOT/bench/pipeline/fleet_summary.py" "$layout" "$n" "$ticks" "$TICK" \
    "$(/usr/bin/python3 -c "print($t1 - $t0)")"
  rm -f "$TMP"/veh*.out
}

echo "fleet benchmark: N vehicles at 100 Hz, ${SECONDS_PER_RUN} s each, on $(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'))"
for layout in per-port shared; do
  for n in ${FLEET_SIZES:-1 4 16 64}; do run "$layout" "$n"; done
done
