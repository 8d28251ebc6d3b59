#!/bin/sh
# test_run_honest.sh - what a run says about itself (issue 14): a branch
# stopped by analysis.max_steps inside its range is no end point (exit
# status 7, a "# STOPPED EARLY" line, no EP row); a complete run ends in EP
# with status 0; shapes.pvd has a monotone time (the row number) also where
# p turns back (snap1), a shape at every special point and at both branch
# ends, p as field data of each shape; output.shape_every adds shapes every
# N points; output.plots draws the plots of an equilibrium run.
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..7"
# type column and p of the last data row of branch.tsv
lastrow() {
    grep -v '^#' "$1/branch.tsv" | awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "type") t = i; if ($i == "p") c = i }; next }
        NF > 2 { ty = $t; p = $c; if ($t == "EP") nep++ } END { printf "%s %s %d\n", (ty == "" ? "-" : ty), p, nep }'
}
# 1: max_steps = 1 on square4 (the issue's case: stops at p = 0.0147 of 1)
"$bin" run "$src/studies/square4.cfg" -q --set output.shapes=0 --set analysis.max_steps=1 -o "$tmp/ms" >/dev/null 2>"$tmp/err"; rc=$?
set -- $(lastrow "$tmp/ms")
if [ $rc -eq 7 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "stopped early: analysis.max_steps = 1 reached" "$tmp/err" &&
   grep -q "^# STOPPED EARLY: analysis.max_steps = 1 reached on branch 1 at p = " "$tmp/ms/branch.tsv" &&
   [ "$3" -eq 0 ] && awk -v p="$2" 'BEGIN { exit !(p > 0 && p < 0.5) }'; then
    echo "ok 1 - max_steps=1: status 7, STOPPED EARLY, last row at p = $2 untyped, no EP: $(cat "$tmp/err")"
else
    echo "not ok 1 - max_steps=1: status $rc, last row '$*', $(cat "$tmp/err")"
fi
# 2: the same study run to the end
"$bin" run "$src/studies/square4.cfg" -q --set output.shapes=0 -o "$tmp/full" >/dev/null 2>"$tmp/err"; rc=$?
set -- $(lastrow "$tmp/full")
if [ $rc -eq 0 ] && [ "$1" = EP ] && [ "$2" = 1 ] && ! grep -q "STOPPED EARLY" "$tmp/full/branch.tsv"; then
    echo "ok 2 - complete run: status 0, last row EP at p = 1"
else
    echo "not ok 2 - complete run: status $rc, last row '$*'"
fi
# 3-5: snap1 (p goes up to the limit point, back through the snap, and on)
"$bin" run "$src/studies/snap1.cfg" -q -o "$tmp/snap" >/dev/null 2>"$tmp/err"
pvd="$tmp/snap/shapes.pvd"
times=$(sed -n 's/.*timestep="\([^"]*\)".*file="shapes\/shape_\([0-9]*\).vtp".*/\1 \2/p' "$pvd")
mono=$(printf '%s\n' "$times" | awk 'NR > 1 && $1 <= prev { bad++ } { prev = $1; if ($1 != $2 + 0) bad++ } END { print bad + 0 }')
# p turns back somewhere along branch 1 of snap1
turns=$(grep -v '^#' "$tmp/snap/branch.tsv" | awk -F'\t' 'NR > 1 && NF > 2 { if (NR > 3 && ($4 - q) * (q - qq) < 0) t++; qq = q; q = $4 } END { print t + 0 }')
if [ -n "$times" ] && [ "$mono" -eq 0 ] && [ "$turns" -ge 1 ]; then
    echo "ok 3 - snap1: shapes.pvd time = row number, strictly increasing over $(printf '%s\n' "$times" | wc -l) shapes while p turns back $turns times"
else
    echo "not ok 3 - snap1 times: $mono bad, p turns $turns"
fi
# every special point and the last row have a shape
missing=""
for row in $(grep -v '^#' "$tmp/snap/special.tsv" | awk -F'\t' 'NR > 1 { print $1 }') \
           $(grep -v '^#' "$tmp/snap/branch.tsv" | awk -F'\t' 'NR > 1 && NF > 2 { r = $1 } END { print r }'); do
    f=$(printf 'shape_%04d.vtp' "$row")
    [ -s "$tmp/snap/shapes/$f" ] && grep -q "file=\"shapes/$f\"" "$pvd" || missing="$missing $row"
done
nsp=$(grep -v '^#' "$tmp/snap/special.tsv" | awk 'NR > 1' | wc -l)
[ "$nsp" -ge 2 ] && [ -z "$missing" ] && echo "ok 4 - snap1: a shape at each of the $nsp special points (LP) and at the end" \
    || echo "not ok 4 - snap1: rows without a shape:$missing ($nsp special)"
# p in each shape's field data is p of its row in branch.tsv
bad=$(for f in "$tmp"/snap/shapes/shape_*.vtp; do
        row=$(basename "$f" .vtp | sed 's/shape_0*//'); row=${row:-0}
        fp=$(sed -n 's/.*Name="p" NumberOfTuples="1" format="ascii">\([^<]*\)<.*/\1/p' "$f")
        tp=$(grep -v '^#' "$tmp/snap/branch.tsv" | awk -F'\t' -v r="$row" 'NR > 1 && $1 == r { print $4; exit }')
        awk -v a="$fp" -v b="$tp" -v f="$f" 'BEGIN { d = a - b; if (a == "" || d > 1e-9 || d < -1e-9) print f }'
      done)
[ -z "$bad" ] && echo "ok 5 - each shape carries p (field data) equal to its row's p" || echo "not ok 5 - field p differs: $bad"
# 6: output.shape_every = 1: a shape for every point (strip3: 9 points)
"$bin" run "$src/studies/strip3.cfg" -q --set output.shape_every=1 -o "$tmp/every" >/dev/null 2>&1
nrow=$(grep -v '^#' "$tmp/every/branch.tsv" | awk 'NR > 1 && NF > 2' | wc -l)
nsh=$(ls "$tmp/every/shapes" | wc -l)
[ "$nrow" -gt 2 ] && [ "$nsh" -eq "$nrow" ] && echo "ok 6 - output.shape_every=1: $nsh shapes for $nrow points" \
    || echo "not ok 6 - shape_every=1: $nsh shapes for $nrow points"
# 7: output.plots = true draws an equilibrium run's plots (gnuplot present)
if command -v gnuplot >/dev/null 2>&1; then
    "$bin" run "$src/studies/strip3.cfg" -q --set output.shapes=0 --set output.plots=true -o "$tmp/pl" >/dev/null 2>"$tmp/err"; rc=$?
    [ $rc -eq 0 ] && [ -s "$tmp/pl/stability.png" ] && [ -s "$tmp/pl/angles.pdf" ] \
        && echo "ok 7 - output.plots=true: plots drawn after the run" || echo "not ok 7 - output.plots: status $rc $(cat "$tmp/err")"
else
    echo "ok 7 # SKIP gnuplot is not installed"
fi
