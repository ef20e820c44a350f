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
# A build for this machine's AVX2 says so in its version; deploy/package.sh's does not need it.
if grep -q "^ODONATA_X86_64_V3" "$build/CMakeCache.txt" 2>/dev/null ||
  grep -q -- "-march=x86-64-v3" "$build/CMakeFiles/"*/flags.make 2>/dev/null ||
  grep -rqs -- "-march=x86-64-v3" "$build/common/io/CMakeFiles/"; then
  [[ $(dpkg-deb -f "$deb" Version) == *+x86-64-v3 ]] ||
    fail "built with -march=x86-64-v3 but labelled $(dpkg-deb -f "$deb" Version)"
fi
for f in ./usr/bin/odonata-identifier ./usr/bin/odonata-run ./usr/bin/odonata-lcm-spy \
  ./usr/lib/systemd/system/odonata-identifier.service ./usr/lib/systemd/system/odonata.target \
  ./usr/include/odonata/tsk_model.hpp ./usr/share/java/odonata_lcmtypes.jar \
  ./usr/share/odonata/board/identifier.ini; do
  grep -q " $f\$" "$work/files" || fail "$(basename "$deb") lacks $f"
done
depends=$(dpkg-deb -f "$deb" Depends)
grep -q "liblcm1" <<<"$depends" || fail "the package does not depend on liblcm1 (Depends: $depends)"
[[ $(grep -o "liblcm1" <<<"$depends" | wc -l) == 1 ]] || fail "liblcm1 is listed more than once: $depends"
for f in ./usr/share/doc/odonata/copyright ./usr/share/doc/odonata/README.md \
  ./usr/share/odonata/python/odonata_programs.py ./usr/share/man/man1/odonata-fit.1; do
  grep -q " $f\$" "$work/files" || fail "$(basename "$deb") lacks $f"
done
! grep -q " ./usr/bin/.*\.py\$" "$work/files" || fail "Python modules in /usr/bin"
# The units start /usr/bin's programs (cpack installs into /usr).
dpkg-deb -x "$deb" "$work/root"
grep -q "^ExecStart=/usr/bin/odonata-identifier " "$work/root/usr/lib/systemd/system/odonata-identifier.service" ||
  fail "the packaged identifier unit does not start /usr/bin/odonata-identifier"
echo "PASS: $(basename "$deb"): $(wc -l <"$work/files") entries, Depends: $depends"
