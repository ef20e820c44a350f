#!/usr/bin/env bash
# Starts lcm-spy with odonata's message types, on Debian's LCM 1.3.1 and any current Java.
# (Debian's own /usr/bin/lcm-spy passes -Xincgc, which Java 9+ rejects; see docs/lcm.md §12.)
set -euo pipefail

here=${BASH_SOURCE[0]%/*}
[[ $here == "${BASH_SOURCE[0]}" ]] && here=.
ROOT=$(cd "$here/.." && pwd)
BUILD_DIR=${ODONATA_BUILD_DIR:-$ROOT/build}
# As build/bin/odonata-lcm-spy (a link to this script): that build tree's jar, this source tree.
if [[ -f $here/../CMakeCache.txt ]]; then
  BUILD_DIR=${ODONATA_BUILD_DIR:-$ROOT}
  ROOT=$(cd "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/.." && pwd)
fi
DEFAULT_URL='udpm://239.255.76.67:7667?ttl=0'
# odonata's version: follows project() in CMakeLists.txt (tests/cli checks odonata-lcm-spy --version).
VERSION=0.1.0
LCM_JAR=${LCM_JAR:-/usr/share/java/lcm.jar}
JCHART2D_JAR=${JCHART2D_JAR:-/usr/share/java/jchart2d.jar}

usage() {
  cat <<EOF
Usage: deploy/lcm-spy.sh [--lcm-url URL] [TYPES.jar ...]

Opens lcm-spy (a window listing every channel on the bus, its type, rate and decoded fields)
with odonata's LCM types, so the project's channels decode instead of showing "??".

  TYPES.jar        jar(s) of lcm-gen Java classes. Default: the project's own,
                   $BUILD_DIR/lcmtypes/odonata_lcmtypes.jar
                   (built with 'cmake --build build --target odonata_lcmtypes_jar' if missing).
  -l, --lcm-url URL
                   bus to watch. Default: \$LCM_DEFAULT_URL, else $DEFAULT_URL
  -h, --help       this text.

Examples:
  deploy/lcm-spy.sh                                        # this machine's bus (ttl=0)
  deploy/lcm-spy.sh --lcm-url 'udpm://239.255.76.67:7667?ttl=1'
                                                           # a bus shared with another board
  xvfb-run -a deploy/lcm-spy.sh                            # no display (headless, for tests)

Needs: java (default-jre or default-jdk-headless), $LCM_JAR (liblcm-java),
$JCHART2D_JAR (libjchart2d-java), and an X display. deploy/setup.sh installs the packages.
Environment: LCM_JAR, JCHART2D_JAR, ODONATA_BUILD_DIR override the paths above.
EOF
}

die() {
  echo "lcm-spy.sh: $*" >&2
  exit 1
}

self=$0  # this command line, quoted for the hints below
for a in "$@"; do
  if [[ $a =~ ^[A-Za-z0-9_./:=@%+,-]+$ ]]; then self+=" $a"; else self+=" '${a//\'/\'\\\'\'}'"; fi
done
url=${LCM_DEFAULT_URL:-$DEFAULT_URL}
jars=()
while (($#)); do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --version) echo "odonata-lcm-spy (odonata) $VERSION"; exit 0 ;;
    -l | --lcm-url)
      (($# >= 2)) || die "$1 needs a URL (try --help)"
      url=$2; shift 2 ;;
    --lcm-url=*) url=${1#--lcm-url=}; shift ;;
    --) shift; jars+=("$@"); break ;;
    -*) echo "lcm-spy.sh: unknown option '$1' (try --help)" >&2; exit 2 ;;
    *) jars+=("$1"); shift ;;
  esac
done
[[ -n $url ]] || die "empty --lcm-url"

# --- dependencies -------------------------------------------------------------------------------
command -v java >/dev/null 2>&1 ||
  die "java not found: install a Java runtime (apt-get install default-jdk-headless, or run deploy/setup.sh)"
[[ -r $LCM_JAR ]] ||
  die "$LCM_JAR not found: install LCM's Java library (apt-get install liblcm-java, or run deploy/setup.sh)"
[[ -r $JCHART2D_JAR ]] ||
  die "$JCHART2D_JAR not found: lcm-spy needs it for its charts (apt-get install libjchart2d-java, or run deploy/setup.sh)"

# --- the types jar ------------------------------------------------------------------------------
# Installed (bin/odonata-lcm-spy): the package's jar in share/java beside bin/.
installed_jar=$ROOT/share/java/odonata_lcmtypes.jar
if ((${#jars[@]} == 0)) && [[ -z ${ODONATA_BUILD_DIR:-} && -f $installed_jar ]]; then
  jars=("$installed_jar")
fi
if ((${#jars[@]} == 0)); then
  jar=$BUILD_DIR/lcmtypes/odonata_lcmtypes.jar
  if [[ ! -f $jar ]]; then
    command -v cmake >/dev/null 2>&1 || die "$jar is missing and cmake is not installed to build it"
    if [[ ! -f $BUILD_DIR/CMakeCache.txt ]]; then
      echo "lcm-spy.sh: configuring $BUILD_DIR" >&2
      cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null ||
        die "could not configure $BUILD_DIR (run deploy/setup.sh, then deploy/build.sh)"
    fi
    echo "lcm-spy.sh: building the types jar" >&2
    cmake --build "$BUILD_DIR" --target odonata_lcmtypes_jar >&2 ||
      die "could not build the target odonata_lcmtypes_jar in $BUILD_DIR"
    [[ -f $jar ]] ||
      die "$jar was not built: CMake found no javac/jar (install default-jdk-headless and reconfigure)"
  fi
  jars=("$jar")
fi
types_cp=
for jar in "${jars[@]}"; do
  [[ -f $jar && -r $jar ]] || die "types jar '$jar' not found"
  case "$jar" in /*) ;; *) jar=$PWD/$jar ;; esac
  types_cp=${types_cp:+$types_cp:}$jar
done

# --- the display --------------------------------------------------------------------------------
if [[ -z ${DISPLAY:-} ]]; then
  die "no X display (DISPLAY is unset). lcm-spy is a window: run it from a desktop session,
  over 'ssh -X', or without a screen under a virtual one:
    xvfb-run -a $self   (package xvfb)"
fi
if [[ $DISPLAY =~ ^(unix)?:([0-9]+)(\.[0-9]+)?$ ]]; then
  # A local display: its socket must exist, or Java fails with a trace.
  [[ -S /tmp/.X11-unix/X${BASH_REMATCH[2]} ]] ||
    die "no X server on display '$DISPLAY' (no /tmp/.X11-unix/X${BASH_REMATCH[2]}).
  Start one, or run under a virtual one: xvfb-run -a $self"
fi

# --- the bus ------------------------------------------------------------------------------------
via=
if [[ $url =~ ^udpm://([0-9.]+) ]] && command -v ip >/dev/null 2>&1; then
  group=${BASH_REMATCH[1]}
  route=$(ip route get "$group" 2>/dev/null) ||
    die "no route to the multicast group $group, so LCM cannot join it ('No such device').
  On a machine without a network, route multicast over loopback (as root):
    ip route add 224.0.0.0/4 dev lo"
  # The interface the group is joined on: another board's traffic (ttl=1) arrives only there.
  [[ $route =~ \ dev\ ([^ ]+) ]] && via=" (multicast via ${BASH_REMATCH[1]})"
fi

echo "lcm-spy.sh: watching $url$via with $types_cp" >&2
# lcm-spy's class discoverer scans $CLASSPATH and the class path for lcm-gen classes.
export CLASSPATH=$types_cp${CLASSPATH:+:$CLASSPATH}
exec java -Djava.net.preferIPv4Stack=true -Xmx512m \
  -cp "$LCM_JAR:$JCHART2D_JAR" lcm.spy.Spy --lcm-url="$url"
