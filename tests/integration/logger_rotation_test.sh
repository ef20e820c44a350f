#!/usr/bin/env bash
# odonata-logger takes its options from a settings file, rotates its event log by size, and
# every rotated file is a standard LCM log that lcm-logplayer reads.
source "$(dirname "$0")/lib.sh"
enter_netns "$@"
OUT=$(mktemp -d)
trap 'stop_all; rm -rf "$OUT"' EXIT
URL='udpm://239.255.76.67:7685?ttl=0'
cat >"$OUT/logger.toml" <<TOML
[record]
output = "$OUT/rot"
split-mb = 0.05
lcm-url = "$URL"
TOML
start logger "$LOGGER" --settings "$OUT/logger.toml" record
wait_up "$URL" logger
"$BUILD/tests/integration/bad_input_publisher" "$URL" 150 2
wait_up "$URL" logger -- --fresh  # its loop has gone round since the last datagram
stop_clean "$PID_logger" logger
files=("$OUT"/rot.*)
((${#files[@]} >= 3)) || fail "expected several files at 50 kB each, got ${#files[@]}"
total=0
for f in "${files[@]}"; do
  size=$(stat -c %s "$f")
  ((size <= 50000 + 300)) || fail "$f is $size bytes, over the 50 kB split"
  n=$(timeout 30 lcm-logplayer -v -s 1000 -l 'udpm://239.255.76.67:7686?ttl=0' "$f" 2>/dev/null | grep -c "^") || true
  ((n > 0)) || fail "lcm-logplayer read nothing from $f"
  total=$((total + n))
done
pass "${#files[@]} rotated logs, all readable by lcm-logplayer ($total events)"
