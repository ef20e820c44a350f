#!/usr/bin/env bash
# Coverage-guided fuzzing with libFuzzer (clang), beyond the short seeded runs ctest does:
# installs clang if needed, builds the harnesses with ASan+UBSan in build-fuzz/, and runs each
# for SECONDS (default 60) from a copy of its seed corpus. Crashes land in build-fuzz/crashes/.
# Usage: deploy/fuzz.sh [SECONDS] [HARNESS...]   (harnesses: csv_reader model_json
#        identifier_config udpm_datagrams bus_messages event_log message_signer ulog_reader)
#        FUZZ_RUNS=N deploy/fuzz.sh ...   also stops each harness after N executions
# Every library is instrumented for coverage (-fsanitize=fuzzer-no-link), not only the harness:
# libFuzzer is guided by the code under test, where the bugs are.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SECONDS_EACH=${1:-60}
shift || true
HARNESSES=("$@")
((${#HARNESSES[@]})) || HARNESSES=(csv_reader model_json identifier_config udpm_datagrams bus_messages event_log
  message_signer ulog_reader)
if ! command -v clang++ >/dev/null || ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
  SUDO=""
  [[ $(id -u) -ne 0 ]] && SUDO=sudo
  $SUDO apt-get install -y -qq --no-install-recommends clang libclang-rt-14-dev
fi
DIR="$ROOT/build-fuzz"
CC=clang CXX=clang++ cmake -S "$ROOT" -B "$DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DODONATA_FUZZ=ON \
  -DODONATA_BUILD_BENCHMARKS=OFF \
  "-DCMAKE_CXX_FLAGS=-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=undefined" >/dev/null
cmake --build "$DIR" -j "${JOBS:-$(nproc)}" --target "${HARNESSES[@]/#/fuzz_}"
mkdir -p "$DIR/crashes"
for h in "${HARNESSES[@]}"; do
  work="$DIR/corpus-$h"
  mkdir -p "$work"
  cp -n "$ROOT/tests/fuzz/corpus/$h/"* "$work/" 2>/dev/null || true
  echo "fuzz.sh: $h for ${SECONDS_EACH} s"
  "$DIR/tests/fuzz/fuzz_$h" -max_total_time="$SECONDS_EACH" ${FUZZ_RUNS:+-runs="$FUZZ_RUNS"} \
    -artifact_prefix="$DIR/crashes/$h-" \
    -print_final_stats=1 "$work" 2>&1 | grep -E "INITED|stat::number_of_executed_units|stat::peak_rss_mb|ERROR|SUMMARY|Done" || true
done
