#!/usr/bin/env bash
# odonata-mavlink's latency (issue 58's target: the bridge adds at most 1 ms median from datagram
# to published sample): a bridge on UDP with one ATTITUDE field at a given rate, and
# bench_mavlink_latency sending it ATTITUDE frames at that rate for SECONDS, inside a private
# network namespace. Prints the percentiles. Usage: run_mavlink_bench.sh [BUILD] [SECONDS] [RATE_HZ]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${1:-$ROOT/build}
SECONDS_RUN=${2:-20}
RATE=${3:-100}
source "$ROOT/bench/lib.sh"
bench_enter_netns "$@"
bench_scratch
URL="udpm://239.255.76.67:7830?ttl=0"
"$BUILD/services/mavlink/odonata-mavlink" --udp 127.0.0.1:14570 --field ATTITUDE.pitchspeed \
  --rate "$RATE" --lcm-url "$URL" --summary-json "$TMP/bridge.json" >"$TMP/bridge.log" 2>&1 &
bridge=$!
for _ in $(seq 100); do grep -q "listening on UDP" "$TMP/bridge.log" && break; sleep 0.05; done
"$BUILD/bench/mavlink/bench_mavlink_latency" --lcm-url "$URL" --udp-port 14570 --rate-hz "$RATE" \
  --seconds "$SECONDS_RUN"
kill -TERM $bridge
wait $bridge || true
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print('bridge: %d frames, %d published, %d gap samples' % (j['frames']['ok'], j['published'], j['grid']['gap_samples']))" "$TMP/bridge.json"
