#!/usr/bin/env bash
# odonata-compare (issue 23 point 3): a figure of measured against the fuzzy model and ARX for any
# CSV — one-step, k-step and free run, FIT % in each legend, training beside validation, each with
# its fastest stretch — and "diverges" where a FIT says nothing any more.
set -euo pipefail
fit=$1 src=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
ex=$src/examples/narendra
"$src/deploy/odonata-compare" --fit "$fit" --plot "$out/cmp.png" --train "$ex/train.csv" \
  --validate "$ex/validate.csv" --output y --input u --horizon 5 --no-select --epochs 3 \
  >"$out/stdout" 2>"$out/stderr" || { cat "$out/stderr"; fail "odonata-compare failed"; }
[[ $(head -c 8 "$out/cmp.png" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "cmp.png is not a PNG"
(($(stat -c %s "$out/cmp.png") > 20000)) || fail "cmp.png is too small to hold the panels"
# 3 modes x (training, its fastest stretch, validation, its fastest stretch) = 12 panels.
[[ $(grep -c "fuzzy (FIT [-0-9.]* %) | ARX (FIT [-0-9.]* %) | measured" "$out/stdout") == 12 ]] ||
  { cat "$out/stdout"; fail "not 12 panels with fuzzy and ARX FIT % in their legends"; }
for what in "training file, one step" "training file (fastest stretch), 5 steps ahead" \
  "validation file, free run" "validation file (fastest stretch), one step"; do
  grep -qF "$what" "$out/stdout" || { cat "$out/stdout"; fail "no panel '$what'"; }
done
# With a selection, odonata-fit calibrates prediction intervals: each panel draws the band, the
# validation's with the coverage odonata-fit reports (issue 60).
"$src/deploy/odonata-compare" --fit "$fit" --plot "$out/band.png" --train "$ex/train.csv" \
  --validate "$ex/validate.csv" --output y --input u --consequent linear --select-kappas 1 \
  --select-thresholds 0.45 --max-epochs 3 >"$out/band.out" 2>"$out/band.err" ||
  { cat "$out/band.err"; fail "odonata-compare with a selection failed"; }
grep -q "validation file, one step:.*| measured | 90 % interval (covers [0-9.]* %)" "$out/band.out" ||
  { cat "$out/band.out"; fail "no interval band with its coverage on the validation panels"; }
# Bad input ends in odonata-fit's own message and exit code; no --train is refused.
if "$src/deploy/odonata-compare" --fit "$fit" --plot "$out/x.png" --train "$ex/train.csv" \
  --output nosuch --input u >"$out/bad" 2>&1; then fail "a missing column was accepted"; fi
grep -q "nosuch" "$out/bad" || { cat "$out/bad"; fail "the missing column is not named"; }
if "$src/deploy/odonata-compare" --fit "$fit" --plot "$out/x.png" >"$out/none" 2>&1; then
  fail "no --train was accepted"; fi
[[ ! -e $out/x.png ]] || fail "a failed comparison left a figure"
# The labels: a free run of −3·10²⁴ % diverges, and so does one that leaves the data's range.
PYTHONPATH=$src/deploy /usr/bin/python3 - <<'PYEOF' || fail "the labels are wrong"
import odonata_compare as c
assert c.fit_label(-3438118371931235404480512.0) == "diverges"
assert c.fit_label(float("nan")) == "diverges" and c.fit_label(None) == "diverges"
assert c.fit_label(97.234) == "FIT 97.2 %" and c.fit_label(-99.0) == "FIT -99.0 %"
w = c.y_window([0.0, 1.0])
assert c.leaves([0.5, 5.0], w) and not c.leaves([0.5, 1.1], w) and c.leaves([float("inf")], w)
y = [0.0] * 100 + [(-1.0) ** k for k in range(20)] + [0.0] * 100
assert 90 <= c.fastest_window(y, 20) <= 101, c.fastest_window(y, 20)
PYEOF
echo "PASS: odonata-compare draws 12 panels with FIT % legends, refuses bad input, says diverges"
