#!/usr/bin/env bash
# The man page and the bash completion cover every subcommand and option that
# `lmcfg --help` lists (registered with ctest: tests/CMakeLists.txt).
#   tests/cli-docs-test.sh LMCFG_BINARY MAN_PAGE COMPLETION
set -euo pipefail
lmcfg=$1 man_page=$2 completion=$3
fail=0
section() { awk -v s="$1" '$0 == s {on=1; next} /^[^ ]/ {on=0} on && /^  [^ ]/ {print $1}'; }
# Every option line of every option group ("Options:", "DeviceNet (...):").
options() { awk '/^  -/ {print $1}' | tr ',' '\n' | grep '^-' || true; }
page="$(MANWIDTH=200 man -l "$man_page" 2>/dev/null | col -b)"
[[ -n "$page" ]] || { echo "man -l $man_page rendered nothing"; exit 1; }
commands=()
for s in $("$lmcfg" --help | section "Subcommands:"); do
  commands+=("$s")
  for t in $("$lmcfg" "$s" --help | section "Subcommands:"); do commands+=("$s $t"); done
done
((${#commands[@]} >= 11)) || { echo "only ${#commands[@]} subcommands found in lmcfg --help"; exit 1; }
for c in "${commands[@]}"; do
  grep -qx "   lmcfg $c" <<<"$page" || { echo "man page: no section 'lmcfg $c'"; fail=1; }
  # shellcheck disable=SC2086
  for o in $("$lmcfg" $c --help | options); do
    grep -q -- "$o" <<<"$page" || { echo "man page: 'lmcfg $c' option $o missing"; fail=1; }
  done
done

# shellcheck disable=SC1090
source "$completion"
complete_words() {  # complete_words WORD...: COMPREPLY for the cursor on the last word
  COMP_WORDS=("$@")
  COMP_CWORD=$((${#COMP_WORDS[@]} - 1))
  COMPREPLY=()
  _lmcfg
  printf '%s\n' "${COMPREPLY[@]}" | sort
}
expect() {  # expect WHAT EXPECTED ACTUAL
  [[ "$2" == "$3" ]] || { printf '%s:\n expected: %s\n got:      %s\n' "$1" "$(echo $2)" "$(echo $3)"; fail=1; }
}
expect "lmcfg <TAB>" "$("$lmcfg" --help | section "Subcommands:" | sort)" "$(complete_words lmcfg '')"
expect "lmcfg db <TAB>" "$("$lmcfg" db --help | section "Subcommands:" | sort)" "$(complete_words lmcfg db '')"
expect "lmcfg d<TAB>" "$(printf 'db\ndefault\ndiff')" "$(complete_words lmcfg d)"
for c in "${commands[@]}"; do
  # shellcheck disable=SC2086
  expect "lmcfg $c -<TAB>" "$("$lmcfg" $c --help | options | sort)" "$(complete_words lmcfg $c -)"
done
expect "lmcfg backup --port /dev/ttyUSB0 --no-<TAB>" "$(printf -- '--no-ct\n--no-curves\n--no-describe\n--no-module-values')" \
  "$(complete_words lmcfg backup --port /dev/ttyUSB0 --no-)"
((fail == 0)) && echo "man page and completion cover ${#commands[@]} (sub)commands"
exit $fail
