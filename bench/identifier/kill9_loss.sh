#!/usr/bin/env bash
# kill -9 of the identifier mid-flight, the configuration odonata-fit --save-config writes
# (snapshot every 100 samples): the Flapper's training flight replayed in real time, the monitor
# keeping the identifier's snapshots; at 30 s the identifier is killed and restarted at once, and
# resumes from the monitor's copy. Prints what the restarted identifier counts missed, and its
# accounting line. Usage: kill9_loss.sh [BUILD] [REALDATA]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${1:-$ROOT/build}
R=${2:-$ROOT/../shared/realdata}
source "$ROOT/bench/lib.sh"
bench_enter_netns "$@"
bench_scratch
URL="udpm://239.255.76.70:7840?ttl=0"
B=$BUILD/services
"$B/fit/odonata-fit" --train "$R/flapper_level1.csv" --output pitch_deg --input m2 --input thrust \
  --ny 2 --nu 2 --no-select --save-config "$TMP/pitch.json" >/dev/null 2>&1
"$B/monitor/odonata-monitor" --lcm-url "$URL" >"$TMP/monitor.log" 2>&1 &
"$B/identifier/odonata-identifier" --config "$TMP/pitch.json" --lcm-url "$URL" --resume-wait 0 \
  >"$TMP/ident1.log" 2>&1 &
id1=$!
sleep 2
"$B/replay/odonata-replay" "$R/flapper_level1.csv" --to 60 --lcm-url "$URL" >"$TMP/replay.log" 2>&1 &
replay=$!
sleep 30
kill -KILL $id1
"$B/identifier/odonata-identifier" --config "$TMP/pitch.json" --lcm-url "$URL" \
  >"$TMP/ident2.log" 2>&1 &
id2=$!
wait $replay
sleep 1
kill -TERM $id2
wait $id2 || true
echo "snapshot_every_samples: $(python3 -c "import json,sys; print(json.load(open(sys.argv[1])).get('snapshot_every_samples'))" "$TMP/pitch.json")"
grep -E "resum|missed on resume|samples: newest" "$TMP/ident2.log" || tail -5 "$TMP/ident2.log"
