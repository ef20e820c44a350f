#!/usr/bin/env bash
# The README's "Your own vehicle" block, run as it is written (issue 23 point 1): extracted from
# README.md, with only the flights shortened (400 samples at 400 Hz instead of 3000 at 100 Hz),
# the build tree and the example folder pointed at this test's, and the bus a private one. Every
# step must work in that order: the services up before the vehicle flies, a freeze and a saved
# model, two flights exported as two runs, odonata-fit on them, a .fis written.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; rm -rf "$OUT"' EXIT
export LCM_DEFAULT_URL='udpm://239.255.76.67:7691?ttl=0'
block=$(readme_block "readme_own_vehicle_test.sh runs the next block")
grep -q 'own-vehicle --samples 3000' <<<"$block" || fail "the README block no longer flies 3000 samples"
block=${block//'$PWD/build/bin'/$BUILD/bin}
block=${block//'--samples 3000'/--samples 400 --rate 400}
block=${block//'../examples/'/$SRC/examples/}
printf '%s\n%s\n' "PS4='+ \${EPOCHREALTIME} '" "$block" >"$OUT/block.sh"
# Traced with times, so a failure shows which step waited.
(cd "$OUT" && timeout -k 5 200 bash -x "$OUT/block.sh") >"$OUT/block.log" 2>&1
F=$OUT/flight
show() { cat "$OUT/block.log"; }
grep -q "is not up" "$OUT/block.log" && { show; fail "a service did not answer get before the flight"; }
[[ $(grep -c "own-vehicle-id (odonata-identifier): accepted" "$OUT/block.log") -ge 2 ]] ||
  { show; fail "freeze and save-model were not both accepted"; }
[[ -s $F/model.json ]] || { show; fail "no model.json"; }
for csv in train validate; do
  [[ -s $F/$csv.csv ]] || { show; fail "no $csv.csv"; }
  rows=$(($(wc -l <"$F/$csv.csv") - 1))
  # Real time over UDP promises no delivery count; each flight is its own run, whole or not.
  ((rows >= 100 && rows <= 400)) || { show; fail "$csv.csv has $rows rows (a 400-sample flight)"; }
done
grep -q "validate" "$OUT/block.log" && grep -q "free_run" "$OUT/block.log" ||
  { show; fail "odonata-fit printed no validation scores"; }
grep -q "^\[System\]" "$F/vz.fis" || { show; fail "vz.fis is not a .fis"; }
pass "the README's own-vehicle block ran as written: frozen, saved, two flights exported, fitted, exported as .fis"
