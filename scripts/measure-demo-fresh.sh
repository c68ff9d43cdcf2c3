#!/usr/bin/env bash
# Measures `scripts/demo.sh` on a fresh machine: a minimal Debian 12
# (debootstrap --variant=minbase, kept in BUILD/demo-fresh/base and copied for
# each run, so every run starts from a system that has never installed a
# package or built the project), the checkout's committed tree copied in
# (git archive HEAD), then `scripts/demo.sh` as a new user would run it,
# timed: installing its packages, building `lmcfg` and its database without
# any compiler cache, and the demo's steps. The debootstrap itself is not
# counted: a fresh machine has its system already. Needs root and the Debian
# mirror ($LMCFG_DEBIAN_MIRROR). Prints the demo's own split and the total;
# docs/ci.md records the figures.
#   scripts/measure-demo-fresh.sh
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="${LMCFG_BUILD_DIR:-$root/build}/demo-fresh"
mirror="${LMCFG_DEBIAN_MIRROR:-http://deb.debian.org/debian}"
base="$work/base"
run="$work/run"
mkdir -p "$work"
if [[ ! -x "$base/usr/bin/apt-get" ]]; then
  echo "measure-demo-fresh: debootstrap --variant=minbase bookworm (once; not counted)"
  rm -rf "$base"
  debootstrap --variant=minbase bookworm "$base" "$mirror" >"$work/debootstrap.log" 2>&1 ||
    { tail -20 "$work/debootstrap.log"; exit 1; }
fi
mounted=0
cleanup() { if ((mounted)); then umount "$run/proc" || true; fi; }
trap cleanup EXIT
rm -rf "$run"
cp -a "$base" "$run"
cp /etc/resolv.conf "$run/etc/resolv.conf"
mkdir -p "$run/src/lmcfg"
git -C "$root" archive HEAD | tar -x -C "$run/src/lmcfg"
mount -t proc proc "$run/proc" && mounted=1
echo "measure-demo-fresh: scripts/demo.sh in a fresh Debian 12 ($(nproc) cores)"
t0=$(date +%s)
chroot "$run" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root TERM=dumb CCACHE_DISABLE=1 \
  bash -c 'cd /src/lmcfg && ./scripts/demo.sh' >"$work/demo.log" 2>&1 || {
  tail -30 "$work/demo.log"
  echo "measure-demo-fresh: demo.sh failed after $(($(date +%s) - t0)) s"
  exit 1
}
t1=$(date +%s)
grep '^demo: dependencies' "$work/demo.log" || true
echo "measure-demo-fresh: total $((t1 - t0)) s (log: $work/demo.log)"
