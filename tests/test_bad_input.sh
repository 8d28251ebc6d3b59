#!/bin/sh
# test_bad_input.sh - every broken study in tests/bad/ must make
# `smoothfold check` exit non-zero with a one-line error on stderr that
# names the file and line and contains the expected text.
#
# tests/bad/NAME.expect holds either two lines (the expected line number,
# 0 for a problem of the whole file, then a substring of the message) or one line (a substring of the message).
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
n=0
for cfg in "$src"/tests/bad/*.cfg; do n=$((n + 1)); done
echo "1..$((n + 1))"
i=0
for cfg in "$src"/tests/bad/*.cfg; do
    i=$((i + 1))
    name=$(basename "$cfg" .cfg)
    exp="${cfg%.cfg}.expect"
    if [ ! -f "$exp" ]; then echo "not ok $i - $name: no .expect file"; continue; fi
    nl=$(wc -l < "$exp")
    if [ "$nl" -ge 2 ]; then
        line=$(sed -n 1p "$exp"); text=$(sed -n 2p "$exp")
        if [ "$line" = 0 ]; then want="$cfg: "; else want="$cfg:$line: "; fi
    else
        line=""; text=$(sed -n 1p "$exp"); want="$cfg:"
    fi
    out=$("$bin" check "$cfg" 2>&1 >/dev/null); rc=$?
    lines=$(printf '%s\n' "$out" | wc -l)
    if [ $rc -eq 0 ]; then
        echo "not ok $i - $name: exit status 0, expected failure"
    elif [ $rc -ge 128 ]; then
        echo "not ok $i - $name: crashed (status $rc)"
    elif [ "$lines" -ne 1 ]; then
        echo "not ok $i - $name: expected one line, got $lines:"; printf '%s\n' "$out" | sed 's/^/#   /'
    else
        case "$out" in
            *"$want"*"$text"*) echo "ok $i - $name";;
            *) echo "not ok $i - $name"; echo "#   expected: ...$want...$text..."; echo "#   got:      $out";;
        esac
    fi
done
# a missing file is an error too, not a crash
i=$((i + 1))
out=$("$bin" check "$src/tests/bad/does-not-exist.cfg" 2>&1 >/dev/null); rc=$?
case "$rc:$out" in
    [1-9]:*does-not-exist.cfg*) echo "ok $i - missing file";;
    *) echo "not ok $i - missing file: status $rc, '$out'";;
esac
