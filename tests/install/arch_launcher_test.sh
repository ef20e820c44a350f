#!/usr/bin/env bash
# arch_launcher_test.sh BUILD: the launcher the dual-level package installs under every program's
# name (deploy/odonata-arch-launcher.in) runs the x86-64-v3 build exactly when the CPU has what
# x86-64-v3 needs (read here from /proc/cpuinfo, independently of the loader the launcher asks),
# the portable one otherwise or with ODONATA_ARCH=x86-64, with the arguments and exit code intact.
set -euo pipefail
build=$1
fail() { echo "FAIL: $*" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
levels=$(sed -nE 's|^levels="\$\(dirname "\$0"\)/(.*)"$|\1|p' "$build/odonata-arch-launcher")
[[ -n $levels ]] || fail "the configured launcher names no level directory"
mkdir -p "$work/bin"
for level in x86-64 x86-64-v3; do
  mkdir -p "$work/bin/$levels/$level"
  printf '#!/bin/sh\necho "%s" "$#" "$@"\nexit 7\n' "$level" >"$work/bin/$levels/$level/odonata-fit"
  chmod +x "$work/bin/$levels/$level/odonata-fit"
done
cp "$build/odonata-arch-launcher" "$work/bin/odonata-fit"
chmod +x "$work/bin/odonata-fit"
v3=x86-64
flags=$(grep -m1 '^flags' /proc/cpuinfo)
if [[ " $flags " == *" avx2 "* && " $flags " == *" fma "* && " $flags " == *" bmi2 "* &&
  " $flags " == *" movbe "* ]]; then
  v3=x86-64-v3
fi
set +e
out=$(PATH="$work/bin:$PATH" odonata-fit --train "a b.csv" -x)
rc=$?
forced=$(ODONATA_ARCH=x86-64 "$work/bin/odonata-fit" one)
set -e
[[ $out == "$v3 3 --train a b.csv -x" ]] || fail "ran '$out', expected the $v3 build with 3 arguments intact"
((rc == 7)) || fail "the launcher changed the exit code 7 to $rc"
[[ $forced == "x86-64 1 one" ]] || fail "ODONATA_ARCH=x86-64 ran '$forced'"
# A package without the v3 build (one level only) runs the portable one.
rm -rf "$work/bin/$levels/x86-64-v3"
[[ $("$work/bin/odonata-fit") == "x86-64 0" ]] || fail "without an x86-64-v3 build the launcher did not fall back"
echo "PASS: the launcher runs the $v3 build on this CPU, the portable one when told or when alone"
