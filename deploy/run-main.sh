#!/usr/bin/env bash
# The main job: sets up, builds, and runs the identification experiments.
# Usage: deploy/run-main.sh [RESULTS_DIR]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${1:-"$ROOT/results/$(date +%Y%m%d-%H%M%S)"}
"$ROOT/deploy/setup.sh"
"$ROOT/deploy/build.sh" release
mkdir -p "$OUT"
FIT="$ROOT/build/services/fit/odonata-fit"

echo "== Narendra–Parthasarathy benchmark (bundled example), entropy sweep, both consequents"
for kind in singleton linear; do
  "$FIT" --train "$ROOT/examples/narendra/train.csv" --validate "$ROOT/examples/narendra/validate.csv" \
    --output y --input u --consequent "$kind" --epochs 10 --sweep --rules \
    --save-model "$OUT/narendra-$kind.json" | tee "$OUT/narendra-$kind.txt"
done
echo
echo "results: $OUT"
