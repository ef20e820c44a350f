#!/usr/bin/env bash
# Installs everything odonata needs from Debian bookworm's packages. Idempotent, non-interactive;
# run as root (or with sudo available).
set -euo pipefail
PACKAGES=(
  build-essential cmake pkg-config git
  libeigen3-dev libboost-dev libcli11-dev nlohmann-json3-dev libsodium-dev
  libgtest-dev libgmock-dev libbenchmark-dev libfuzzylite-dev
  liblcm-dev liblcm-bin liblcm-java default-jdk-headless default-jre fonts-dejavu-core
  libjchart2d-java xvfb
  python3 python3-matplotlib python3-numpy python3-sklearn iproute2 util-linux iptables
  octave octave-fuzzy-logic-toolkit octave-control file dpkg-dev help2man bash-completion mmdebstrap
  clang-format universal-ctags chromium man-db socat
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "setup: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
