#!/usr/bin/env bash
# `cmake --install` into a temporary prefix, then, from `/`: the installed
# program finds its database, prints its versions, its man page renders, and
# the consumer example (examples/backup-sim) builds against the prefix and
# backs up a simulated drive. Installs the build in build/ (or $LMCFG_BUILD_DIR);
# with LMCFG_INSTALL_PREFIX it checks that prefix instead, installed already
# (CI: the README's own install, scripts/test-readme-install.sh, so the Release
# build is not installed twice).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${LMCFG_BUILD_DIR:-$root/build}"
step() { echo "test-install: $*"; }

if [[ -n "${LMCFG_INSTALL_PREFIX:-}" ]]; then
  prefix="$(cd "$LMCFG_INSTALL_PREFIX" && pwd)"
  step "checking the install in $prefix"
else
  prefix="$(mktemp -d /tmp/lmcfg-prefix.XXXXXX)"
  trap 'rm -rf "$prefix"' EXIT
  cmake --install "$build" --prefix "$prefix" >/dev/null
fi
cd /
unset LMCFG_UPID_DB
for f in bin/lmcfg share/lmcfg/lmcfg-upid.sqlite share/lmcfg/schemas/lmcfg-config-v3.schema.json \
  share/lmcfg/schemas/lmcfg-config-v3.xsd share/man/man1/lmcfg.1 share/bash-completion/completions/lmcfg \
  lib/liblmcfg_ops.a lib/liblmcfg_sim.a include/lmcfg/ops/backup.hpp include/lmcfg/common/version.hpp lib/cmake/lmcfg/lmcfgConfig.cmake; do
  [[ -e "$prefix/$f" ]] || { echo "test-install: $f not installed"; exit 1; }
done
# Only the public API (lib/public-headers.txt): internals stay private.
for f in include/lmcfg/db/sqlite.hpp include/lmcfg/client/internal.hpp include/lmcfg/ops/restore_internal.hpp; do
  [[ ! -e "$prefix/$f" ]] || { echo "test-install: internal header $f installed"; exit 1; }
done
step "$(find "$prefix/include/lmcfg" -name '*.hpp' | wc -l) public headers installed"
step "PREFIX/bin/lmcfg db show 13A2"
"$prefix/bin/lmcfg" db show 13A2 | head -3
step "PREFIX/bin/lmcfg --version"
"$prefix/bin/lmcfg" --version | tee "$prefix/version.txt"
grep -q "^UPID database: $prefix/share/lmcfg/lmcfg-upid.sqlite\$" "$prefix/version.txt"
grep -q "^  fingerprint: fnv1a64:" "$prefix/version.txt"
step "man -l PREFIX/share/man/man1/lmcfg.1"
MANWIDTH=80 man -l "$prefix/share/man/man1/lmcfg.1" 2>/dev/null | col -b >"$prefix/man.txt"
grep -q "^   lmcfg restore\$" "$prefix/man.txt"
echo "rendered $(wc -l <"$prefix/man.txt") lines"

step "examples/backup-sim against the prefix"
cmake -S "$root/examples/backup-sim" -B "$prefix/example-build" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$prefix/example-build" -j"${LMCFG_JOBS:-2}" >/dev/null
cp "$prefix/share/lmcfg/sim/commissioned-axis.json" "$prefix/axis.sim.json"
"$prefix/example-build/backup-sim" "$prefix/axis.sim.json" "$prefix/example.json"
# The same drive backed up by the installed program: the same configuration.
"$prefix/bin/lmcfg" backup --port "sim:$prefix/axis.sim.json" -o "$prefix/tool.json" --quiet
"$prefix/bin/lmcfg" diff "$prefix/example.json" "$prefix/tool.json" --ignore-metadata
step "ok"
