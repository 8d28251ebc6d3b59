#!/bin/sh
# test_man.sh - the man page (src/smoothfold.1, made by help2man from the
# program's --help texts at build time) renders with man -l without a
# formatter warning, and says what the binary says: every command and every
# option of `smoothfold --help`, and each command's own usage line.
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
. "$src/tests/tap.sh"
page=${SF_BUILDDIR:-.}/src/smoothfold.1
echo "1..5"
if [ ! -f "$page" ]; then
    nok "man page $page was built"
    for t in 2 3 4 5; do nok "man page (not built)"; done
    exit 0
fi
ok "man page $page was built"
LC_ALL=C.UTF-8 MANWIDTH=100 man --warnings -l "$page" >"$tmp/page" 2>"$tmp/warn"; rc=$?
if [ $rc -eq 0 ] && [ ! -s "$tmp/warn" ] && grep -q '^NAME' "$tmp/page" && grep -q '^SYNOPSIS' "$tmp/page" &&
   grep -q 'smoothfold - structural analysis of origami sheets' "$tmp/page"; then
    ok "man -l renders it (NAME, SYNOPSIS), no warnings"
else
    nok "man -l: status $rc; $(head -3 "$tmp/warn")"
fi
# the rendered text with hyphenation and line breaks undone, for grep
tr -s ' \n' '  ' <"$tmp/page" | sed 's/‐ //g; s/- //g' >"$tmp/flat"
cmds=$("$bin" --help | awk '/^Commands/ {on = 1; next} /^Options:/ {on = 0} on && /^  [a-z]/ {print $1}')
miss=""
for c in $cmds; do
    grep -q "$c" "$tmp/flat" || miss="$miss $c"
done
if [ -n "$cmds" ] && [ -z "$miss" ]; then ok "every command of --help is in the page: $(echo $cmds)"
else nok "commands missing from the page:$miss (of: $(echo $cmds))"; fi
opts=$("$bin" --help | grep -o -- '--[a-z][a-z-]*' | sort -u)
miss=""
for o in $opts; do
    grep -q -- "$o" "$tmp/flat" || miss="$miss $o"
done
if [ -n "$opts" ] && [ -z "$miss" ]; then ok "every option of --help is in the page ($(echo $opts | wc -w))"
else nok "options missing from the page:$miss"; fi
# each command's first usage line: the page is made from today's binary
miss=""
for c in check shape run plot compare pattern sweep keys; do
    u=$("$bin" "$c" --help | head -1 | tr -s ' ' | cut -c1-40)
    grep -qF -- "$u" "$tmp/flat" || miss="$miss $c"
done
if [ -z "$miss" ]; then ok "each command's usage line is in the page's COMMANDS section"
else nok "usage lines missing for:$miss"; fi
