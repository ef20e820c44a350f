#!/usr/bin/env bash
# help_test.sh VERSION PROGRAM [ARGS…]: --help prints usage and options and exits 0; --version
# prints "NAME (odonata) VERSION" and exits 0; PROGRAM ARGS… with an unknown option exits 2 (bad
# arguments) with a message naming it, and a mistyped one is answered with the option it meant
# (compiled programs; argparse's scripts name the unknown one).
set -uo pipefail
version=$1 prog=$2
shift 2
name=$(basename "$prog")
out=$("$prog" --help 2>&1)
rc=$?
[[ $rc == 0 ]] || { echo "FAIL: $name --help exited $rc"; echo "$out"; exit 1; }
grep -qi "usage" <<<"$out" || { echo "FAIL: $name --help has no usage line"; echo "$out"; exit 1; }
grep -q -- "--help" <<<"$out" || { echo "FAIL: $name --help lists no options"; exit 1; }
out=$("$prog" --version 2>&1)
rc=$?
[[ $rc == 0 && $out == "$name (odonata) $version" ]] ||
  { echo "FAIL: $name --version exited $rc with '$out', not '$name (odonata) $version'"; exit 1; }
out=$(timeout 10 "$prog" "$@" --no-such-option-xyz 2>&1)
rc=$?
[[ $rc == 2 ]] || { echo "FAIL: $name with --no-such-option-xyz exited $rc, not 2"; echo "$out"; exit 1; }
grep -q -- "no-such-option-xyz" <<<"$out" || { echo "FAIL: $name did not name the option"; echo "$out"; exit 1; }
if [[ $(head -c 2 "$prog") != "#!" ]]; then
  out=$(timeout 10 "$prog" "$@" --hlep 2>&1)
  grep -q -- "--hlep: did you mean --help?" <<<"$out" ||
    { echo "FAIL: $name did not suggest --help for --hlep"; echo "$out"; exit 1; }
fi
echo "PASS: $name --help, --version and an unknown option"
