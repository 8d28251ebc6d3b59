#!/bin/sh
# test_morse_unknown.sh - a Morse index the KKT inertia cannot decide is
# written as an EMPTY `morse` field, never as a number (docs/output-format.md).
# The 4 x 4 Miura under load (bench/miura-study.sh 4 load 1, poses, sparse
# start) with the inertia method: its last points have nearly dependent
# constraint rows whose curvature the inertia cannot see ("inertia
# ambiguous: Morse index between lo and hi", measured 2026-11-26: rows 14-16,
# ranges [0, 1], [0, 3], [0, 3]).
#  1. every row with such a note has an empty morse field (and stable empty,
#     or 0 when lo > 0); every other row has an integer morse;
#  2. the dense method on the same study (same path: rows at the same p)
#     has its index inside the stated range at those rows.
# When no row is ambiguous any more (a better inertia), test 1 is skipped
# with that reason: the case then no longer tests the field.  Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..2"
sh "$src/bench/miura-study.sh" 4 load 1 > "$tmp/m4l.cfg"
run() { # dir eigensolver
    "$bin" run "$tmp/m4l.cfg" -q -o "$1" --set analysis.flat_start='"sparse"' \
        --set solver.formulation='"poses"' --set analysis.eigensolver="\"$2\"" >"$1.log" 2>&1
}
# "row lo hi" of every note of an undecided index
ranges() { sed -n 's/^# stability at row \([0-9]*\) .*Morse index between \([0-9]*\) and \([0-9]*\).*/\1 \2 \3/p' "$1/branch.tsv"; }
# "row p stable morse" of the data rows
rows() { grep -v '^#' "$1/branch.tsv" | awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    { printf "%s %s [%s] [%s]\n", $c["point"], $c["p"], $c["stable"], $c["morse"] }'; }
if ! run "$tmp/inertia" inertia || ! run "$tmp/dense" dense; then
    echo "not ok 1 - run failed: $(cat "$tmp/inertia.log" "$tmp/dense.log")"
    echo "not ok 2 - run failed"
    exit 0
fi
ranges "$tmp/inertia" > "$tmp/ranges"
rows "$tmp/inertia" > "$tmp/rows"
rows "$tmp/dense" > "$tmp/dense.rows"
namb=$(wc -l < "$tmp/ranges")
if [ "$namb" -eq 0 ]; then
    echo "ok 1 # SKIP no undecided Morse index on this path any more: the case no longer tests the empty field"
    echo "ok 2 # SKIP nothing to compare"
    exit 0
fi
bad=$(awk 'NR == FNR { lo[$1] = $2; hi[$1] = $3; next }
    { r = $1; st = $3; mo = $4
      if (r in lo) { if (mo != "[]" || !(st == "[]" || (st == "[0]" && lo[r] > 0))) print "row " r ": stable " st ", morse " mo }
      else if (mo !~ /^\[[0-9]+\]$/) print "row " r ": morse " mo " without a note" }' "$tmp/ranges" "$tmp/rows")
if [ -z "$bad" ]; then
    echo "ok 1 - $namb rows with an undecided index ($(awk '{ printf "%s[%s,%s] ", $1, $2, $3 }' "$tmp/ranges")): empty morse, the others an integer"
else
    echo "not ok 1 - $bad"
fi
# same path (rows at the same p to 1e-9), dense index inside the range
bad=$(awk -v df="$tmp/dense.rows" 'NR == FNR { lo[$1] = $2; hi[$1] = $3; next }
    FILENAME == df { dp[$1] = $2; dm[$1] = $4; next }
    { if (!($1 in lo)) next
      if (!($1 in dp)) { print "row " $1 ": not in the dense run"; next }
      d = $2 - dp[$1]; if (d < 0) d = -d; if (d > 1e-9 * (1 + $2)) { print "row " $1 ": p " $2 " against " dp[$1]; next }
      m = dm[$1]; gsub(/[][]/, "", m)
      if (m == "" || m + 0 < lo[$1] || m + 0 > hi[$1]) print "row " $1 ": dense index " m " outside [" lo[$1] ", " hi[$1] "]" }' \
    "$tmp/ranges" "$tmp/dense.rows" "$tmp/rows")
if [ -z "$bad" ]; then
    echo "ok 2 - the dense index lies in the stated range at those rows ($(awk 'NR == FNR { a[$1] = 1; next } ($1 in a) { printf "%s%s ", $1, $4 }' "$tmp/ranges" "$tmp/dense.rows"))"
else
    echo "not ok 2 - $bad"
fi
