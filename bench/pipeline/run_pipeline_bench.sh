#!/usr/bin/env bash
# Pipeline benchmark (issue 4): bare LCM round trip, identifier latency (p50/p99 over 10k
# samples), lockstep rate, and the highest paced rate held without a dropped sample.
# Runs inside a private network namespace. Usage: bench/pipeline/run_pipeline_bench.sh [BUILD]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${1:-$ROOT/build}
source "$ROOT/bench/lib.sh"
bench_enter_netns "$@"
URL='udpm://239.255.76.67:7690?ttl=0'
B=$BUILD/bench/pipeline/bench_pipeline
bench_scratch
cat >"$TMP/id.json" <<JSON
{"instance": "bench", "outputs": ["roll_rad"], "inputs": ["u"], "ny": 1, "nu": 1, "delay": 1,
 "consequent": "singleton", "entropy_threshold": 0.05, "max_rules": 41,
 "ranges": {"roll_rad": [-1.5, 1.5], "u": [-1.5, 1.5]}, "snapshot_period_s": 0, "resume_wait_s": 0}
JSON
"$B" --lcm-url "$URL" --mode echo &
sleep 0.3
"$B" --lcm-url "$URL" --mode rtt --samples 10000
kill %1
run_identifier() {
  "$BUILD/services/identifier/odonata-identifier" --config "$TMP/id.json" --lcm-url "$URL" >"$TMP/id.log" 2>&1 &
  IDPID=$!
  sleep 0.5
}
run_identifier
"$B" --lcm-url "$URL" --mode latency --samples 10011  # 10k measured after the regressor fill
kill $IDPID; wait $IDPID 2>/dev/null || true
best=0
for rate in 100 1000 2000 5000 10000 20000 40000; do
  run_identifier
  if "$B" --lcm-url "$URL" --mode rate --rate-hz $rate --samples $((rate < 2000 ? 2000 : rate * 2)); then best=$rate; fi
  kill $IDPID; wait $IDPID 2>/dev/null || true
done
echo "highest paced rate without a dropped sample: $best Hz"
