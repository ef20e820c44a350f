#!/usr/bin/env bash
# odonata-fit's time and peak memory for 1k, 10k, 100k and 360k training rows (the defaults, one
# input, one output; the records are generated here). Usage:
#   bench/fit/run_fit_scaling.sh [--rows N ...] [--plot docs/fit_scaling.png] [--json FILE]
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
exec /usr/bin/python3 "$HERE/fit_scaling.py" "$@"
