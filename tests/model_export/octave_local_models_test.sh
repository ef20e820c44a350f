#!/usr/bin/env bash
# octave_local_models_test.sh FIXTURE ODONATA_EXPORT (issue 49 point 3): each rule's local model,
# exported by `odonata-export --local-models` as a discrete state-space model, is loaded by
# Octave's control package as an ss object, whose pole, dcgain and step give odonata's own
# figures for the same rule to 1e-9 (poles: the rule's, plus one at 0 per delayed input sample
# the state holds).
set -euo pipefail
fixture=$1 exporter=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$fixture" "$dir" >/dev/null
"$exporter" "$dir/model.json" --local-models "$dir/local_models.m" >/dev/null
cat >"$dir/check.m" <<OCTAVE
run('$dir/local_models.m');
want = jsondecode(fileread('$dir/expected.json'));
if iscell(want), want = [want{:}]; end
assert(numel(local_models) == numel(want), 'rules: %d exported, %d expected', numel(local_models), numel(want));
worst = 0;
for k = 1:numel(local_models)
  m = local_models(k);
  p = pole(m.sys);
  mine = complex(want(k).poles(:, 1), want(k).poles(:, 2));
  for i = 1:numel(mine)  % each of odonata's poles is one of Octave's
    worst = max(worst, min(abs(p - mine(i))));
  end
  extra = sort(abs(p));  % the rest are the input shift register's, at 0
  extra = extra(1:numel(p) - numel(mine));
  worst = max([worst; extra(:)]);
  g = dcgain(m.sys);
  worst = max(worst, max(abs(g(:) - want(k).dcgain(:)) ./ max(1, abs(want(k).dcgain(:)))));
  for e = 1:numel(m.signals)
    y = step(m.sys(1, e), 39 * m.Ts);
    s = want(k).step(e, :);
    worst = max(worst, max(abs(y(:)' - s(:)') ./ max(1, max(abs(s)))));
  end
end
printf('octave-control: %d local models, max |octave - odonata| = %.3g (pole, dcgain, step)\n', numel(local_models), worst);
if !(worst <= 1e-9)
  exit(1);
end
OCTAVE
octave-cli --no-window-system -q "$dir/check.m"

# A model saved with its sample time (odonata-fit at 100 Hz writes "sample_time_s": 0.01): the
# export takes it without --sample-time, so Ts, the step's time axis and each rule's slowest time
# constant are in seconds, equal to odonata's τ in samples times 0.01 (1e-9).
python3 -c "
import json, sys
m = json.load(open('$dir/model.json')); m['sample_time_s'] = 0.01
json.dump(m, open('$dir/model_100hz.json', 'w'))"
"$exporter" "$dir/model_100hz.json" --local-models "$dir/local_100hz.m" >/dev/null
cat >"$dir/check_ts.m" <<OCTAVE
run('$dir/local_100hz.m');
want = jsondecode(fileread('$dir/expected.json'));
if iscell(want), want = [want{:}]; end
worst = 0;
for k = 1:numel(local_models)
  m = local_models(k);
  worst = max(worst, abs(m.Ts - 0.01) + abs(m.sys.Ts - 0.01));
  [y, t] = step(m.sys(1, 1), 39 * m.Ts);
  worst = max(worst, abs((t(2) - t(1)) - 0.01));
  mine = max(abs(complex(want(k).poles(:, 1), want(k).poles(:, 2))));
  if mine > 0 && mine < 1
    tau_s = -m.Ts / log(max(abs(pole(m.sys))));
    worst = max(worst, abs(tau_s - (-1 / log(mine)) * 0.01));
  end
end
printf('octave-control at Ts = 0.01 s: max error %.3g (Ts, step time axis, time constants)\n', worst);
if !(worst <= 1e-9)
  exit(1);
end
OCTAVE
octave-cli --no-window-system -q "$dir/check_ts.m"
# Each rule's parameter covariance (issue 60 point 2), as odonata-fit --save-model keeps it beside
# the model ("local_model_covariance"): Octave gets it to 1e-15, p × p in the order `parameters`
# names ("1" and the regressor); a rule the file holds none for gets [].
python3 -c "
import json
m = json.load(open('$dir/model.json'))
r = m['regressor']
p = 1 + len(r['outputs']) * r['output_lags'] + len(r['inputs']) * r['input_lags']
cov = [[(i + 1) * 0.1 + (0.01 / 3 if i != j else 0.0) for j in range(p)] for i in range(p)]
cov = [[cov[max(i, j)][min(i, j)] for j in range(p)] for i in range(p)]
m['local_model_covariance'] = {r['outputs'][0]: [cov]}
json.dump(m, open('$dir/model_cov.json', 'w'))
json.dump(cov, open('$dir/cov.json', 'w'))"
"$exporter" "$dir/model_cov.json" --local-models "$dir/local_cov.m" >"$dir/cov.out"
grep -q "with its parameter covariance" "$dir/cov.out" || { echo "FAIL: $(cat "$dir/cov.out")"; exit 1; }
cat >"$dir/check_cov.m" <<OCTAVE
run('$dir/local_cov.m');
want = jsondecode(fileread('$dir/cov.json'));
m = local_models(1);
assert(isequal(size(m.covariance), size(want)), 'covariance %dx%d', rows(m.covariance), columns(m.covariance));
% To the last bit or two: Octave's number literal and its jsondecode may round a 17-digit decimal
% apart by one unit in the last place.
assert(max(abs(m.covariance(:) - want(:))) <= 1e-15, 'the covariance differs: %.17g', max(abs(m.covariance(:) - want(:))));
assert(numel(m.parameters) == rows(want) && strcmp(m.parameters{1}, '1'), 'parameters');
if numel(local_models) > 1
  assert(isempty(local_models(2).covariance), 'rule 2 has no covariance in the file');
end
printf('octave: rule 1 covariance %dx%d to 1e-15, parameters %s ... %s\n', rows(want), columns(want), m.parameters{1}, m.parameters{end});
OCTAVE
octave-cli --no-window-system -q "$dir/check_cov.m"
"$exporter" "$dir/model.json" --local-models "$dir/local_samples.m" 2>"$dir/warn.txt" >/dev/null
grep -q "holds no sample time" "$dir/warn.txt" || { echo "FAIL: no warning for a model without a sample time"; exit 1; }
# The .fis says the sample time too (a comment before [System], as its first line already is).
"$exporter" "$dir/model_100hz.json" --fis "$dir/m.fis" >/dev/null
head -1 "$dir/m.fis" | grep -qE "^% Sample time Ts = 0\.010*[0-9]* s$" || { echo "FAIL: .fis: $(head -1 "$dir/m.fis")"; exit 1; }
