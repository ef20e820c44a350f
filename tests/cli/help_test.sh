#!/usr/bin/env bash
# help_test.sh PROGRAM [ARGS…]: --help prints usage and options and exits 0; PROGRAM ARGS… with an
# unknown option exits 2 (bad arguments) with a message naming it.
set -uo pipefail
prog=$1
shift
name=$(basename "$prog")
out=$("$prog" --help 2>&1)
rc=$?
[[ $rc == 0 ]] || { echo "FAIL: $name --help exited $rc"; echo "$out"; exit 1; }
grep -qi "usage" <<<"$out" || { echo "FAIL: $name --help has no usage line"; echo "$out"; exit 1; }
grep -q -- "--help" <<<"$out" || { echo "FAIL: $name --help lists no options"; exit 1; }
out=$(timeout 10 "$prog" "$@" --no-such-option-xyz 2>&1)
rc=$?
[[ $rc == 2 ]] || { echo "FAIL: $name with --no-such-option-xyz exited $rc, not 2"; echo "$out"; exit 1; }
grep -q -- "no-such-option-xyz" <<<"$out" || { echo "FAIL: $name did not name the option"; echo "$out"; exit 1; }
echo "PASS: $name --help and an unknown option"
