#!/usr/bin/env bash
# package_test.sh BUILD: cpack builds odonata's .deb; it installs the programs in /usr/bin, the
# units in /usr/lib/systemd/system, the header and the types jar, and declares its libraries.
set -euo pipefail
build=$1
fail() { echo "FAIL: $*" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(cd "$work" && cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work" >cpack.log 2>&1) ||
  { cat "$work/cpack.log"; fail "cpack failed"; }
deb=$(ls "$work"/odonata_*.deb 2>/dev/null | head -1)
[[ -n $deb ]] || fail "cpack wrote no odonata_*.deb"
dpkg-deb -c "$deb" >"$work/files"
for f in ./usr/bin/odonata-identifier ./usr/bin/odonata-run ./usr/bin/odonata-lcm-spy \
  ./usr/lib/systemd/system/odonata-identifier.service ./usr/lib/systemd/system/odonata.target \
  ./usr/include/odonata/tsk_model.hpp ./usr/share/java/odonata_lcmtypes.jar \
  ./usr/share/odonata/board/identifier.ini; do
  grep -q " $f\$" "$work/files" || fail "$(basename "$deb") lacks $f"
done
depends=$(dpkg-deb -f "$deb" Depends)
grep -q "liblcm1" <<<"$depends" || fail "the package does not depend on liblcm1 (Depends: $depends)"
echo "PASS: $(basename "$deb"): $(wc -l <"$work/files") entries, Depends: $depends"
