#!/usr/bin/env bash
# The man page, the bash completion and the reference docs/cli.md cover every
# subcommand and option that `lmcfg --help` lists (registered with ctest:
# tests/CMakeLists.txt). docs/cli.md has a heading naming each (sub)command
# ("## lmcfg backup", "### lmcfg db show, lmcfg db find"), and names each of its
# options in that section (up to the next "lmcfg" heading), its parent's, or
# one of the shared sections "## Link options" and "## DeviceNet controllers".
#   tests/cli-docs-test.sh LMCFG_BINARY MAN_PAGE COMPLETION CLI_MD
set -euo pipefail
lmcfg=$1 man_page=$2 completion=$3 cli_md=$4
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

# docs/cli.md: the section of a (sub)command, from its heading to the next "lmcfg" heading.
md_section() {
  awk -v c="lmcfg $1" '
    /^#+ / { h = $0; sub(/^#+ /, "", h); if (on && h ~ /^lmcfg /) on = 0
             n = split(h, names, ", "); for (i = 1; i <= n; ++i) if (names[i] == c) on = 1 }
    on' "$cli_md"
}
link_md="$(awk '/^## / {on = ($0 == "## Link options" || $0 == "## DeviceNet controllers")} on' "$cli_md")"
grep -q '^## DeviceNet controllers$' "$cli_md" && grep -q '^## Link options$' "$cli_md" ||
  { echo "$cli_md: no section '## Link options' or '## DeviceNet controllers'"; fail=1; }
for c in "${commands[@]}"; do
  text="$(md_section "$c")"
  [[ -n "$text" ]] || { echo "$cli_md: no heading naming 'lmcfg $c'"; fail=1; continue; }
  [[ "$c" == *" "* ]] && text+=$'\n'"$(md_section "${c% *}")"  # the parent's section
  text+=$'\n'"$link_md"
  # shellcheck disable=SC2086
  for o in $("$lmcfg" $c --help | options); do
    [[ "$o" == --help || "$o" == -h ]] && continue
    grep -qE -- "(^|[^a-z-])$o([^a-z-]|\$)" <<<"$text" || { echo "$cli_md: 'lmcfg $c' option $o missing"; fail=1; }
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
((fail == 0)) && echo "man page, completion and $cli_md cover ${#commands[@]} (sub)commands"
exit $fail
