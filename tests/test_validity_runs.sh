#!/bin/sh
# test_validity_runs.sh - the physical-validity warning column of
# trajectory.tsv (dynamics) and boundary.tsv (stability boundary), checked
# against what the fold angles in the same rows say:
#  - the three-fold strip folding itself (studies/selffold3-dynamics.cfg):
#    as it is, no row flagged and no warning;
#  - its rest angles raised to 3.0 rad: the strip curls through itself;
#    every row flagged `crossing` has a total fold turning above pi (a
#    strip that turns less than half a turn in all cannot meet itself),
#    none is `beyond180`, the flagged rows run from the first to the end
#    (the heating only rises), and the line at the end names t and the
#    table;
#  - its rest angles at 3.5 rad: `beyond180` on exactly the rows where some
#    |theta| > pi + 1e-9;
#  - a stability boundary (studies/snap1-boundary.cfg): the column there,
#    no row flagged.
# TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
. "$src/tests/tap.sh"
echo "1..4"
dyn="$src/studies/selffold3-dynamics.cfg"
# columns: the row's warning, its total |theta| and its largest |theta|
angles() {
    awk -F'\t' '/^#/ { next }
        !h { for (i = 1; i <= NF; i++) if ($i ~ /^theta[0-9]+$/) th[i] = 1; last = NF; h = 1; next }
        { s = 0; m = 0; for (i in th) { a = $i < 0 ? -$i : $i; s += a; if (a > m) m = a }
          printf "%s\t%.12g\t%.12g\n", $last == "" ? "-" : $last, s, m }' "$1"
}
"$bin" run "$dyn" -o "$tmp/d0" --no-plot -q > "$tmp/out" 2>&1; rc=$?
h=$(grep -v '^#' "$tmp/d0/trajectory.tsv" | head -1 | awk -F'\t' '{ print $NF }')
n=$(angles "$tmp/d0/trajectory.tsv" | awk -F'\t' '$1 != "-"' | wc -l)
if [ $rc -eq 0 ] && [ "$h" = warning ] && [ "$n" -eq 0 ] && ! grep -q 'physically invalid' "$tmp/out" "$tmp/d0/trajectory.tsv"; then
    ok "selffold3-dynamics: trajectory.tsv ends with a warning column, empty on all $(angles "$tmp/d0/trajectory.tsv" | wc -l) rows"
else nok "selffold3-dynamics as it is (status $rc, last column '$h', $n rows flagged)"; sed 's/^/#   /' "$tmp/out" | head -3; fi
"$bin" run "$dyn" -o "$tmp/d3" --no-plot -q --set 'actuation.[0].rest_angle=3.0' \
    --set 'actuation.[1].rest_angle=3.0' > "$tmp/out" 2>&1; rc=$?
angles "$tmp/d3/trajectory.tsv" > "$tmp/a3"
if [ $rc -eq 0 ] && awk -F'\t' -v pi=3.141592653589793 '
        $1 == "crossing" { n++; if ($2 <= pi) bad++; if (!first) first = NR }
        $1 != "crossing" && $1 != "-" { bad++ }
        $1 == "-" && first { bad++ }
        END { exit !(n > 0 && !bad) }' "$tmp/a3" &&
   grep -q '^smoothfold: warning: physically invalid shapes: [0-9]* rows where the sheet passes through itself (from row [0-9]*; deepest at row [0-9]*, t = .*(warning column of trajectory.tsv' "$tmp/out" &&
   grep -q '^# warning: physically invalid shapes:' "$tmp/d3/trajectory.tsv"; then
    ok "rest angles 3.0 rad: $(grep -c crossing "$tmp/a3") rows 'crossing' to the end, each turning more than pi in all; none beyond180; the line names t and trajectory.tsv"
else nok "rest angles 3.0 rad (status $rc)"; sed 's/^/#   /' "$tmp/out" | head -3; sort "$tmp/a3" | uniq -c -w 9 | head -5 | sed 's/^/#   /'; fi
"$bin" run "$dyn" -o "$tmp/d35" --no-plot -q --set 'actuation.[0].rest_angle=3.5' \
    --set 'actuation.[1].rest_angle=3.5' > "$tmp/out" 2>&1; rc=$?
angles "$tmp/d35/trajectory.tsv" > "$tmp/a35"
if [ $rc -eq 0 ] && awk -F'\t' -v pi=3.141592653589793 '
        { beyond = $1 ~ /beyond180/; over = $3 > pi + 1e-9; if (beyond != over) bad++; n += beyond }
        END { exit !(n > 0 && !bad) }' "$tmp/a35"; then
    ok "rest angles 3.5 rad: 'beyond180' on exactly the $(grep -c beyond180 "$tmp/a35") rows with some |theta| > pi"
else nok "rest angles 3.5 rad (status $rc)"; sed 's/^/#   /' "$tmp/out" | head -3; fi
"$bin" run "$src/studies/snap1-boundary.cfg" -o "$tmp/b" --no-plot -q > "$tmp/out" 2>&1; rc=$?
h=$(grep -v '^#' "$tmp/b/boundary.tsv" | head -1 | awk -F'\t' '{ print $NF }')
n=$(grep -v '^#' "$tmp/b/boundary.tsv" | awk -F'\t' 'NR > 1 && $NF != ""' | wc -l)
rows=$(grep -v '^#' "$tmp/b/boundary.tsv" | awk 'NR > 1' | wc -l)
if [ $rc -eq 0 ] && [ "$h" = warning ] && [ "$n" -eq 0 ] && [ "$rows" -gt 10 ] && ! grep -q 'physically invalid' "$tmp/out"; then
    ok "snap1-boundary: boundary.tsv ends with a warning column, empty on all $rows rows"
else nok "snap1-boundary (status $rc, last column '$h', $n of $rows rows flagged)"; sed 's/^/#   /' "$tmp/out" | head -3; fi
