#!/bin/sh
# Usage: make_types_jar.sh OUT_JAR WORK_DIR LCM_JAR TYPE.lcm...
# Generates Java classes for the types and packs them into a jar for lcm-spy.
set -eu
out=$1 work=$2 lcmjar=$3
shift 3
rm -rf "$work"
mkdir -p "$work/src" "$work/classes"
lcm-gen --java --jpath "$work/src" "$@"
# --release 8 keeps the jar loadable by any JVM that runs lcm-spy.
javac -nowarn --release 8 -cp "$lcmjar" -d "$work/classes" "$work"/src/odonata/*.java 2>/dev/null ||
  javac -nowarn -cp "$lcmjar" -d "$work/classes" "$work"/src/odonata/*.java
jar cf "$out" -C "$work/classes" .
