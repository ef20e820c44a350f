#!/usr/bin/env bash
# deploy/lcm-spy.sh's checks, without a display or a bus: --help, bad arguments, a missing jar or
# dependency, and no DISPLAY all end with a clear message and no Java stack trace.
# Usage: lcm_spy_launcher_test.sh LAUNCHER TYPES_JAR
set -uo pipefail
LAUNCHER=$1 TYPES_JAR=$2
failures=0

# expect NAME STATUS PATTERN COMMAND...: COMMAND exits with STATUS and prints PATTERN (ERE).
expect() {
  local name=$1 status=$2 pattern=$3 out rc
  shift 3
  out=$(timeout 20 "$@" 2>&1)
  rc=$?
  if ((rc != status)) || ! grep -qE -e "$pattern" <<<"$out" || grep -qE 'Exception|^\s+at ' <<<"$out"; then
    echo "FAIL $name: exit $rc (want $status), output:"
    sed 's/^/  | /' <<<"$out"
    failures=$((failures + 1))
  else
    echo "ok   $name"
  fi
}

expect help 0 'Usage: deploy/lcm-spy.sh .*--lcm-url' "$LAUNCHER" --help
# A usage error exits 2, as every odonata program's does (tests/cli/help_test.sh).
expect unknown-option 2 "unknown option '--bogus'" "$LAUNCHER" --bogus
expect url-without-value 1 '--lcm-url needs a URL' "$LAUNCHER" --lcm-url
expect missing-jar 1 "types jar '/nonexistent/types.jar' not found" "$LAUNCHER" /nonexistent/types.jar
expect no-display 1 'no X display \(DISPLAY is unset\)' \
  env -u DISPLAY "$LAUNCHER" --lcm-url 'udpm://239.255.76.67:7695?ttl=0' "$TYPES_JAR"
expect no-display-hint 1 "xvfb-run -a .*lcm-spy.sh --lcm-url 'udpm://239.255.76.67:7695\?ttl=0'" \
  env -u DISPLAY "$LAUNCHER" --lcm-url 'udpm://239.255.76.67:7695?ttl=0' "$TYPES_JAR"
expect no-x-server 1 "no X server on display ':987'" env DISPLAY=:987 "$LAUNCHER" "$TYPES_JAR"
expect no-lcm-jar 1 '/nonexistent/lcm.jar not found: .*liblcm-java' \
  env LCM_JAR=/nonexistent/lcm.jar "$LAUNCHER" "$TYPES_JAR"
expect no-jchart2d 1 '/nonexistent/jchart2d.jar not found: .*libjchart2d-java' \
  env JCHART2D_JAR=/nonexistent/jchart2d.jar "$LAUNCHER" "$TYPES_JAR"
expect no-java 1 'java not found' env PATH=/nonexistent /bin/bash "$LAUNCHER" "$TYPES_JAR"

((failures == 0)) && echo "PASS" || echo "FAIL: $failures case(s)"
((failures == 0))
