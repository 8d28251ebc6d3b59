#!/bin/sh
# test_morse_unknown.sh - a Morse index the KKT inertia cannot decide is
# written as an EMPTY `morse` field, never as a number (docs/reference/output-files.md).
# The 4 x 4 Miura under load (bench/miura-study.sh 4 load 1, poses, sparse
# start) with the ARPACK method, whose index comes from the KKT matrix of
# the independent rows: its last points have nearly dependent constraint
# rows whose curvature that inertia cannot see ("inertia ambiguous: Morse
# index between lo and hi": rows 14-16, ranges [0, 1], [0, 3], [0, 3]).
#  1. every row with such a note has an empty morse field (and stable empty,
#     or 0 when lo > 0); every other row has an integer morse;
#  2. the dense method on the same study (same path: rows at the same p)
#     has its index inside the stated range at those rows;
#  3. the inertia method, which first tries the inertia of the corrector's
#     own matrix (every row kept, regularised: docs/design/linear-algebra.md, "Stable
#     by the corrector's matrix"), decides every row, those included, as
#     the dense method does (stable and morse equal at every row).
# When no row is ambiguous any more (a better inertia), tests 1 and 2 are
# skipped with that reason: the case then no longer tests the field.
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..3"
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
if ! run "$tmp/arpack" arpack || ! run "$tmp/dense" dense || ! run "$tmp/inertia" inertia; then
    echo "not ok 1 - run failed: $(cat "$tmp/arpack.log" "$tmp/dense.log" "$tmp/inertia.log")"
    echo "not ok 2 - run failed"
    echo "not ok 3 - run failed"
    exit 0
fi
ranges "$tmp/arpack" > "$tmp/ranges"
rows "$tmp/arpack" > "$tmp/rows"
rows "$tmp/dense" > "$tmp/dense.rows"
rows "$tmp/inertia" > "$tmp/inertia.rows"
# 3: the inertia method against the dense one, row by row (same p to 1e-9)
bad3=$(awk 'NR == FNR { dp[$1] = $2; dv[$1] = $3 " " $4; next }
    { if (!($1 in dp)) { print "row " $1 ": not in the dense run"; next }
      d = $2 - dp[$1]; if (d < 0) d = -d; if (d > 1e-9 * (1 + $2)) { print "row " $1 ": p " $2 " against " dp[$1]; next }
      if ($3 " " $4 != dv[$1]) print "row " $1 ": stable, morse " $3 " " $4 " against the dense " dv[$1] }' \
    "$tmp/dense.rows" "$tmp/inertia.rows")
nin=$(wc -l < "$tmp/inertia.rows")
namb=$(wc -l < "$tmp/ranges")
if [ -z "$bad3" ] && [ "$nin" -gt 10 ]; then
    line3="ok 3 - the inertia method decides all $nin rows as the dense method does (rows $(awk '{ printf "%s ", $1 }' "$tmp/ranges")undecided by the ARPACK method's)"
else
    line3="not ok 3 - ${bad3:-only $nin rows}"
fi
if [ "$namb" -eq 0 ]; then
    echo "ok 1 # SKIP no undecided Morse index on this path any more: the case no longer tests the empty field"
    echo "ok 2 # SKIP nothing to compare"
    echo "$line3"
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
echo "$line3"
