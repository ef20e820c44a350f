#!/usr/bin/env bash
# octave_fis_test.sh WRITE_FIXTURE ODONATA_EXPORT: a model exported by odonata-export is read by
# Octave's fuzzy-logic-toolkit (readfis) and gives odonata's outputs (evalfis) on 1000 samples
# to within 1e-9.
set -euo pipefail
fixture=$1 exporter=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$fixture" "$dir"
"$exporter" "$dir/model.json" --fis "$dir/model.fis" --fll "$dir/model.fll"
cat >"$dir/check.m" <<OCTAVE
pkg load fuzzy-logic-toolkit
fis = readfis('$dir/model.fis');
x = dlmread('$dir/inputs.csv', ',');
want = dlmread('$dir/expected.csv');
got = evalfis(x, fis);
worst = max(abs(got(:) - want(:)));
printf('octave evalfis: %d samples, %d rules, max |octave - odonata| = %.3g\n', rows(x), numel(fis.rule), worst);
if !(worst <= 1e-9) || rows(x) != 1000
  exit(1);
end
OCTAVE
octave-cli --no-window-system -q "$dir/check.m"
