#!/usr/bin/env bash
# odonata-fit's defaults beside ARX, polynomial NARX (FROLS, degree 2 and 3) and an MLP NARX on
# the measured records (default ../shared/realdata from the project's root; a missing record is
# skipped). Usage: bench/accuracy/run_real_records.sh [DIR] [--only NAME] [--json FILE]
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
exec /usr/bin/python3 "$HERE/real_records.py" "$@"
