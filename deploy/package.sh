#!/usr/bin/env bash
# Builds the Debian package for any x86-64 board in build-package/ (no tests or benchmarks) and
# prints the .deb's path. The programs are built twice — for baseline x86-64 and for x86-64-v3
# (AVX2, FMA; build-package-v3/), which fits models about 1.5 times faster — and /usr/bin holds a
# launcher per program that runs the build the CPU supports (cmake/OdonataInstall.cmake).
# Usage: deploy/package.sh        then: apt-get install ./build-package/odonata_*.deb
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DIR="$ROOT/build-package"
V3="$ROOT/build-package-v3"
PROGRAMS=(odonata-plant odonata-signal odonata-identifier odonata-monitor odonata-logger
  odonata-control odonata-fit odonata-sim odonata-export odonata-replay odonata-ulog odonata-log
  odonata-mavlink)
common=(-DCMAKE_BUILD_TYPE=Release -DODONATA_NATIVE_ARCH=OFF -DODONATA_BUILD_TESTS=OFF
  -DODONATA_BUILD_BENCHMARKS=OFF)
cmake -S "$ROOT" -B "$V3" "${common[@]}" -DODONATA_FORCE_X86_64_V3=ON >/dev/null
cmake --build "$V3" -j "${JOBS:-$(nproc)}" --target "${PROGRAMS[@]}"
cmake -S "$ROOT" -B "$DIR" "${common[@]}" -DODONATA_V3_TREE="$V3" >/dev/null
cmake --build "$DIR" -j "${JOBS:-$(nproc)}"
(cd "$DIR" && cpack -G DEB >/dev/null)
ls "$DIR"/odonata_*.deb
