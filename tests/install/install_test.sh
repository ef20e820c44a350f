#!/usr/bin/env bash
# install_test.sh BUILD: `cmake --install` into a staging prefix holds what a board needs, and
# odonata runs from the installed files only: a lockstep roll run through the installed
# odonata-run, and the services started the way the systemd units start them (their example
# settings files, the bus from odonata.env) in real time. Root: private network namespaces.
set -euo pipefail
build=$1
fail() { echo "FAIL: $*" >&2; exit 1; }
if [[ ${ODONATA_IN_NETNS:-0} != 1 ]]; then
  export ODONATA_IN_NETNS=1
  exec unshare -n sh -c 'ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec "$0" "$@"' \
    bash "$0" "$@"
fi
work=$(mktemp -d)
PIDS=()
cleanup() {
  for p in "${PIDS[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
stage=$work/prefix
cmake --install "$build" --prefix "$stage" >"$work/install.log" || fail "cmake --install failed"

for f in bin/odonata-{plant,signal,identifier,monitor,logger,control,fit,sim,export} \
  bin/odonata-{run,make-identifier-config,lcm-spy} include/odonata/tsk_model.hpp \
  share/java/odonata_lcmtypes.jar share/odonata/lcmtypes/odonata_plant_state_t.lcm \
  share/odonata/examples/narendra/train.csv share/odonata/board/odonata.env \
  share/odonata/python/odonata_signals.py share/odonata/examples/own_vehicle/vehicle.py \
  lib/systemd/system/odonata.target; do
  [[ -e $stage/$f ]] || fail "$f is not installed"
done
# Every unit starts a program where this installation put it (the prefix, not /usr/bin), with
# settings that are installed as examples.
for unit in "$stage"/lib/systemd/system/odonata-*.service; do
  exec_line=$(grep '^ExecStart=' "$unit") || fail "$unit has no ExecStart"
  [[ $exec_line == "ExecStart=$stage/bin/"* ]] || fail "$(basename "$unit"): $exec_line is not in $stage/bin"
  prog=$(sed -E "s|^ExecStart=$stage/bin/([^ ]+).*|\\1|" <<<"$exec_line")
  [[ -x $stage/bin/$prog ]] || fail "$(basename "$unit") starts $prog, which is not installed"
  settings=$(sed -E 's|.*--settings /etc/odonata/([^ ]+).*|\1|' <<<"$exec_line")
  [[ -f $stage/share/odonata/board/$settings ]] || fail "$(basename "$unit"): no example $settings"
done
echo "PASS: the staging prefix holds the programs, scripts, jar, header, units and settings"
# bin/ holds programs only; the scripts' modules are in share/odonata/python; the docs have the
# README and a copyright file.
[[ -z $(ls "$stage"/bin/*.py 2>/dev/null) ]] || fail "Python modules in bin/: $(ls "$stage"/bin/*.py)"
for f in share/odonata/python/odonata_programs.py share/odonata/python/odonata_compare.py \
  share/doc/odonata/README.md share/doc/odonata/copyright; do
  [[ -s $stage/$f ]] || fail "$f is not installed"
done
"$stage/bin/odonata-compare" --version >/dev/null || fail "the installed odonata-compare does not find its modules"

# Man pages made from --help, and bash completion of options and odonata-control's commands.
for p in odonata-{plant,signal,identifier,monitor,logger,control,fit,sim,export,replay,ulog,run,compare}; do
  page=$stage/share/man/man1/$p.1
  [[ -s $page ]] || fail "no man page $p.1"
  MANWIDTH=100 man -l "$page" 2>/dev/null | grep -q "^NAME" || fail "$p.1 does not render"
done
MANWIDTH=100 man -l "$stage/share/man/man1/odonata-logger.1" 2>/dev/null | grep -q -- "--strict" ||
  fail "odonata-logger.1 lacks its export subcommand's options"
completion=$(PATH=$stage/bin:$PATH bash -c '
  source /usr/share/bash-completion/bash_completion
  source "$1/share/bash-completion/completions/odonata-control"
  c() { COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); COMP_LINE="$*"; COMP_POINT=${#COMP_LINE}; COMPREPLY=()
        f=$(complete -p "$1" | sed -E "s/.*-F ([^ ]+).*/\1/"); "$f" "$1" "${COMP_WORDS[COMP_CWORD]}" ""
        echo "${COMPREPLY[*]}"; }
  c odonata-fit --inp; c odonata-control fr; c odonata-logger export --str; c odonata-fit --hori
  c odonata-replay --lock' bash "$stage")
# --horizon once, though a description mentions it too.
[[ $completion == $'--input\nfreeze\n--strict\n--horizon\n--lockstep' ]] || fail "bash completion gave: $completion"
echo "PASS: man pages for every program, bash completion of options and commands"

# The installed own-vehicle example builds on its own, as a vehicle's project would: lcm-gen on
# the installed signals_t.lcm, no odonata source or build tree.
cmake -S "$stage/share/odonata/examples/own_vehicle" -B "$work/own_vehicle" >"$work/ov.log" 2>&1 &&
  cmake --build "$work/own_vehicle" >>"$work/ov.log" 2>&1 ||
  { cat "$work/ov.log"; fail "the installed own_vehicle example does not build"; }
"$work/own_vehicle/own-vehicle" --help >/dev/null || fail "the installed example's own-vehicle does not run"
echo "PASS: the installed own_vehicle example builds alone"

# Nothing from the source or build tree: run from an empty directory, with a PATH that has only
# the system's folders, so the installed odonata-run can find nothing but the installed files.
mkdir "$work/cwd"
cd "$work/cwd"
export PATH=/usr/sbin:/usr/bin:/sbin:/bin
export ODONATA_NETNS=1  # already inside a namespace with multicast on lo
"$stage/bin/odonata-run" --preset roll --duration 4 --out "$work/run" >"$work/run.log" 2>&1 ||
  { cat "$work/run.log"; fail "the installed odonata-run failed"; }
[[ -s $work/run/model.json ]] || fail "the installed run left no model"
# odonata-run reports the validation run's live one-step FIT (roll: about 98.5 % clean).
fit=$(sed -nE 's/.*validate: .* one-step FIT ([0-9.]+) %.*/\1/p' "$work/run.log" | head -1)
[[ -n $fit ]] || { cat "$work/run.log"; fail "the installed run printed no validation FIT"; }
python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) >= 90 else 1)" "$fit" ||
  fail "the installed roll run's validation one-step FIT is $fit %, below 90 %"
echo "PASS: a lockstep roll run from the installed files (validation one-step FIT $fit %)"

# The board as systemd starts it: the example settings (state paths moved into the test's
# folder), the bus from odonata.env, each program from bin/.
board=$work/etc
mkdir -p "$board" "$work/state"
for f in "$stage"/share/odonata/board/*.ini; do
  sed "s|/var/lib/odonata|$work/state|g; s|/etc/odonata|$board|g" "$f" >"$board/$(basename "$f")"
done
set -a
# shellcheck disable=SC1091
. "$stage/share/odonata/board/odonata.env"
set +a
export LCM_DEFAULT_URL=${LCM_DEFAULT_URL/ttl=1/ttl=0}
"$stage/bin/odonata-make-identifier-config" --preset roll --duration 4 --output "$board/identifier.json"
# The settings name the system's key (signed messages, docs/lcm.md §15), as a board makes it.
(umask 077 && od -An -tx1 -N32 /dev/urandom | tr -d ' \n' >"$board/bus.key")
for svc in plant identifier monitor logger; do
  args=$(grep '^ExecStart=' "$stage/lib/systemd/system/odonata-$svc.service" | sed -E 's|^ExecStart=||')
  args=${args//\/etc\/odonata/$board}
  # shellcheck disable=SC2086
  $args >"$work/$svc.log" 2>&1 &
  PIDS+=($!)
done
# Up means answering on the bus (a get from each of the four), not a second gone by.
up=0
for _ in $(seq 60); do
  for p in "${PIDS[@]}"; do kill -0 "$p" 2>/dev/null || { cat "$work"/*.log; fail "a service exited at start"; }; done
  "$stage/bin/odonata-control" get --timeout 1 --key "$board/bus.key" >"$work/get.out" 2>&1 || true
  n=$(grep -c ": accepted" "$work/get.out") || true
  ((${n:-0} >= 4)) && { up=1; break; }
done
((up)) || { cat "$work/get.out"; fail "the four services did not all answer get within a minute"; }
# Without the key nobody answers: an unsigned command is refused by every service.
"$stage/bin/odonata-control" get --timeout 1 >"$work/get-unsigned.out" 2>&1 || true
! grep -q ": accepted" "$work/get-unsigned.out" || fail "a service obeyed an unsigned get: $(cat "$work/get-unsigned.out")"
args=$(grep '^ExecStart=' "$stage/lib/systemd/system/odonata-signal.service" | sed -E 's|^ExecStart=||')
args=${args//\/etc\/odonata/$board}
# shellcheck disable=SC2086
$args --duration 2 >"$work/signal.log" 2>&1 || { cat "$work/signal.log"; fail "signal failed"; }
for p in "${PIDS[@]}"; do
  kill -TERM "$p"
  wait "$p" || fail "a service did not stop cleanly on SIGTERM (as systemctl stop sends)"
done
PIDS=()
[[ -s $work/state/model.json ]] || { cat "$work"/identifier.log; fail "the identifier saved no model where identifier.ini says"; }
[[ -s $work/state/monitor-summary.json ]] || fail "the monitor wrote no summary where monitor.ini says"
ls "$work"/state/odonata* >/dev/null 2>&1 || fail "the logger wrote no log where logger.ini says"
learned=$(python3 -c "import json,sys; m=json.load(open(sys.argv[1])); print(sum(len(x.get('rules', [])) for x in m['models']))" "$work/state/model.json")
((learned >= 1)) || fail "the board's identifier learned no rule"
echo "PASS: the services started as the units start them learn in real time ($learned rules)"
