#!/usr/bin/env bash
# Builds the Debian package for any x86-64 board (no AVX2 or FMA assumed, unlike a build for
# this machine) in build-package/, without tests or benchmarks, and prints the .deb's path.
# Usage: deploy/package.sh        then: apt-get install ./build-package/odonata_*.deb
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DIR="$ROOT/build-package"
cmake -S "$ROOT" -B "$DIR" -DCMAKE_BUILD_TYPE=Release -DODONATA_NATIVE_ARCH=OFF \
  -DODONATA_BUILD_TESTS=OFF -DODONATA_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$DIR" -j "${JOBS:-$(nproc)}"
(cd "$DIR" && cpack -G DEB >/dev/null)
ls "$DIR"/odonata_*.deb
