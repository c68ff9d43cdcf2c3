#!/usr/bin/env bash
# Runs README.md's "From source" install commands as they are written: the
# lines of the ```sh block between the markers
#   <!-- readme-install: begin (scripts/test-readme-install.sh runs it) -->
#   <!-- readme-install: end -->
# so the README and CI cannot drift apart. Each line runs from the checkout's
# root, as a user who cloned it runs it, with two changes that it prints:
#   - `sudo ` is dropped when running as root (CI; a minimal system may have
#     no sudo), and before `cmake --install`, which goes into a prefix of ours;
#   - `cmake --install DIR` gets `--prefix PREFIX` (the README's own "or
#     --prefix DIR"): $LMCFG_README_PREFIX, else a temporary folder removed at
#     exit. The system's /usr/local is left alone.
# The build folder the README names (`-B DIR`) is removed first: a fresh build,
# as on a user's first install. scripts/test-install.sh then checks the
# installed tree (LMCFG_INSTALL_PREFIX=PREFIX, .ci/run).
# usage: test-readme-install.sh [--print]   (--print: show the commands, run nothing)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
begin='<!-- readme-install: begin (scripts/test-readme-install.sh runs it) -->'
end='<!-- readme-install: end -->'

# The block's command lines, each with its leading indentation removed.
block="$(awk -v b="$begin" -v e="$end" '
  { line = $0; sub(/^[ \t]+/, "", line) }
  line == b { on = 1; next }
  line == e { on = 0 }
  on && line ~ /^```/ { fence = !fence; next }
  on && fence && line != "" { print line }' README.md)"
if [[ -z "$block" ]]; then
  echo "test-readme-install: README.md has no sh block between '$begin' and '$end'" >&2
  exit 1
fi
mapfile -t commands <<<"$block"

print_only=0
[[ ${1:-} == --print ]] && print_only=1
if [[ -n "${LMCFG_README_PREFIX:-}" ]]; then
  prefix="$LMCFG_README_PREFIX"
  mkdir -p "$prefix"
else
  prefix="$(mktemp -d /tmp/lmcfg-readme-prefix.XXXXXX)"
  trap 'rm -rf "$prefix"' EXIT
fi

for line in "${commands[@]}"; do
  cmd="$line"
  # A trailing comment is the README's explanation, not part of the command.
  cmd="$(sed -E 's/[[:space:]]+#[^"'"'"']*$//' <<<"$cmd")"
  if [[ $cmd == "sudo "* ]] && { [[ $(id -u) == 0 ]] || [[ $cmd == "sudo cmake --install "* ]]; }; then
    cmd="${cmd#sudo }"
  fi
  if [[ $cmd =~ ^cmake\ --install\  ]]; then
    cmd="$cmd --prefix $prefix"
  fi
  if [[ $cmd =~ \ -B\ ([^ ]+) ]]; then
    fresh="${BASH_REMATCH[1]}"
    echo "test-readme-install: rm -rf $fresh (a fresh build folder)"
    ((print_only)) || rm -rf -- "${fresh:?}"
  fi
  if [[ "$cmd" != "$line" ]]; then
    echo "test-readme-install: README: $line"
  fi
  echo "test-readme-install: \$ $cmd"
  ((print_only)) || bash -c "$cmd"
done
echo "test-readme-install: ok, installed into $prefix"
