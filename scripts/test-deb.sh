#!/usr/bin/env bash
# Builds the Debian package (cpack -G DEB in build/ or $LMCFG_BUILD_DIR), checks
# its contents (dpkg -c), and installs it with `apt-get install ./lmcfg_*.deb`
# into a fresh Debian 12 (debootstrap --variant=minbase into BUILD/deb-test/,
# chroot), where `lmcfg --version` and `lmcfg db show 13A2` must work. Needs
# root and network access to the Debian mirror ($LMCFG_DEBIAN_MIRROR).
# usage: test-deb.sh [--prepare]
#   --prepare: only the fresh Debian 12 (debootstrap, mostly waiting on the
#   mirror), so that CI runs it beside the build (.ci/run); a later run without
#   it finds the system there and goes on from the package.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${LMCFG_BUILD_DIR:-$root/build}"
mirror="${LMCFG_DEBIAN_MIRROR:-http://deb.debian.org/debian}"
start=$(date +%s)
step() { echo "test-deb: [$(($(date +%s) - start)) s] $*"; }

chroot_dir="$build/deb-test/root"
bootstrap() {  # a minimal Debian 12 in $chroot_dir, unless one is there
  if [[ ! -x "$chroot_dir/usr/bin/apt-get" ]]; then
    step "debootstrap --variant=minbase bookworm $chroot_dir"
    rm -rf "$chroot_dir"
    mkdir -p "$chroot_dir"
    debootstrap --variant=minbase bookworm "$chroot_dir" "$mirror" >"$build/deb-test/debootstrap.log" 2>&1 ||
      { tail -20 "$build/deb-test/debootstrap.log"; exit 1; }
  fi
}
if [[ ${1:-} == --prepare ]]; then
  bootstrap
  step "ok (prepared)"
  exit 0
fi

step "cpack -G DEB"
(cd "$build" && rm -f lmcfg_*.deb && cpack -G DEB >/dev/null)
deb="$(ls "$build"/lmcfg_*.deb)"
step "$deb: $(dpkg-deb -f "$deb" Depends)"
dpkg -c "$deb" >"$build/deb-contents.txt"
for f in ./usr/bin/lmcfg ./usr/share/lmcfg/lmcfg-upid.sqlite ./usr/share/lmcfg/schemas/lmcfg-config-v3.schema.json \
  ./usr/share/lmcfg/schemas/lmcfg-config-v3.xsd ./usr/share/man/man1/lmcfg.1 \
  ./usr/share/bash-completion/completions/lmcfg; do
  grep -q " $f\$" "$build/deb-contents.txt" || { echo "test-deb: $f not in $deb"; exit 1; }
done

mounted=0
cleanup() { if ((mounted)); then umount "$chroot_dir/proc" || true; fi; }
trap cleanup EXIT
bootstrap
# A fresh system each time: remove what an earlier run installed.
chroot "$chroot_dir" dpkg --purge lmcfg >/dev/null 2>&1 || true
cp "$deb" "$chroot_dir/tmp/"
cp /etc/resolv.conf "$chroot_dir/etc/resolv.conf"
mount -t proc proc "$chroot_dir/proc" && mounted=1  # the program finds its database via /proc/self/exe
step "apt-get install ./$(basename "$deb") in the chroot"
chroot "$chroot_dir" sh -c "apt-get update -qq && cd /tmp && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq ./$(basename "$deb")" \
  >"$build/deb-test/apt.log" 2>&1 || { tail -20 "$build/deb-test/apt.log"; exit 1; }
step "lmcfg --version; lmcfg db show 13A2 (in the chroot, from /)"
chroot "$chroot_dir" sh -c "cd / && lmcfg --version && lmcfg db show 13A2 | head -3"
step "ok"
