#!/usr/bin/env bash
# fresh_root_test.sh BUILD [DEB]: the .deb (cpack's from BUILD, or DEB, e.g. deploy/package.sh's)
# installs on a machine that has nothing else. A fresh Debian bookworm root (mmdebstrap, minbase
# variant, packages from deb.debian.org) gets odonata's .deb and what it declares it depends on,
# nothing more; `odonata-run --preset roll` then runs from that root as the README has a user run
# it, and its model equals the build tree's bit for bit (same code, same machine, same seed).
# Needs root and Debian's archive, like deploy/setup.sh.
set -euo pipefail
build=$1
fail() { echo "FAIL: $*" >&2; exit 1; }
command -v mmdebstrap >/dev/null || fail "mmdebstrap is not installed (deploy/setup.sh installs it)"
# /var/tmp rather than /tmp: the root is a few hundred MB and some machines keep /tmp in memory.
work=$(mktemp -d /var/tmp/odonata-fresh-root.XXXXXX)
trap 'rm -rf --one-file-system "$work"' EXIT
chmod 755 "$work"

if [[ -n ${2:-} ]]; then
  cp "$2" "$work/" && deb=$work/$(basename "$2")
else
  (cd "$work" && cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work" >cpack.log 2>&1) ||
    { cat "$work/cpack.log"; fail "cpack failed"; }
  deb=$(ls "$work"/odonata_*.deb 2>/dev/null | head -1)
  [[ -n $deb ]] || fail "cpack wrote no odonata_*.deb"
fi
chmod 644 "$deb"

# The hook makes the .deb visible inside the root while apt installs it with its dependencies.
root=$work/root
if ! mmdebstrap --variant=minbase --include="$deb" \
  --hook-dir=/usr/share/mmdebstrap/hooks/file-mirror-automount bookworm "$root" \
  >"$work/mmdebstrap.log" 2>&1; then
  tail -30 "$work/mmdebstrap.log"
  fail "mmdebstrap could not make a bookworm root with $(basename "$deb") (is deb.debian.org reachable?)"
fi
chroot "$root" dpkg-query -W -f='${Status}\n' odonata | grep -q "install ok installed" ||
  fail "odonata is not installed in the fresh root"
echo "PASS: $(basename "$deb") installs into a fresh bookworm root with its dependencies" \
  "($(chroot "$root" dpkg-query -W -f='.\n' | wc -l) packages in all)"

# The run inside the root, in a mount namespace of its own so /dev and /proc vanish with it;
# odonata-run makes its private network namespace itself, as on a board.
run_in_root() {
  unshare -m sh -c 'mount --make-rprivate / && mount --rbind /dev "$1/dev" &&
    mount -t proc proc "$1/proc" && mount -t tmpfs tmpfs "$1/tmp" && shift &&
    exec chroot "$0" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root "$@"' "$root" "$root" "$@"
}
run_in_root sh -c 'cd /root && odonata-run --preset roll --duration 4 --out /root/run' \
  >"$work/root-run.log" 2>&1 || { cat "$work/root-run.log"; fail "odonata-run failed in the fresh root"; }
[[ -s $root/root/run/model.json ]] || { cat "$work/root-run.log"; fail "the fresh root's run left no model"; }
fit=$(sed -nE 's/.*validate: .* one-step FIT ([0-9.]+) %.*/\1/p' "$work/root-run.log" | head -1)
[[ -n $fit ]] || { cat "$work/root-run.log"; fail "the fresh root's run printed no validation FIT"; }
echo "PASS: odonata-run --preset roll in the fresh root (validation one-step FIT $fit %)"

# The same run from the build tree: the package holds the same programs, so the same model.
"$build/bin/odonata-run" --preset roll --duration 4 --out "$work/build-run" >"$work/build-run.log" 2>&1 ||
  { cat "$work/build-run.log"; fail "odonata-run failed from the build tree"; }
cmp -s "$root/root/run/model.json" "$work/build-run/model.json" ||
  fail "the packaged run's model differs from the build tree's ($(wc -c <"$root/root/run/model.json") vs $(wc -c <"$work/build-run/model.json") bytes)"
echo "PASS: the packaged run's model equals the build tree's bit for bit"
