#!/usr/bin/env bash
# Sets up, builds, and runs every test through ctest: a Release build, then an ASan+UBSan build.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
"$ROOT/deploy/setup.sh"
"$ROOT/deploy/build.sh" release
(cd "$ROOT/build" && ctest --output-on-failure -j 2)
"$ROOT/deploy/build.sh" sanitize
(cd "$ROOT/build-sanitize" && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j 2 -LE slow)
