#!/usr/bin/env bash
# The main job: sets up, builds, and runs the paper's six identifications through the
# multi-process LCM pipeline (lockstep), then writes the report.
# Usage: deploy/run-main.sh [RESULTS_DIR] [extra deploy/run-experiments options, e.g. --mode realtime]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${1:-"$ROOT/results/$(date +%Y%m%d-%H%M%S)"}
shift || true
"$ROOT/deploy/setup.sh"
"$ROOT/deploy/build.sh" release
"$ROOT/deploy/run-experiments" --out "$OUT" "$@"
echo "report: $OUT/index.html (summary: $OUT/summary.md, $OUT/summary.json)"
