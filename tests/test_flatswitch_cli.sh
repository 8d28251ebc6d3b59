#!/bin/sh
# test_flatswitch_cli.sh - every branch at the flat state with exact closure
# (src/analysis/start/flatswitch.c, docs/guides/stability.md) on a waterbomb base
# (degree 6) with all folds driven: analysis.branch_depth = 1 follows the
# isolated solutions of the reduced second-order equations besides the path;
# every row of every branch is an equilibrium (residual <= 1e-9) whose Morse
# index is the number of negative eigenvalues listed, and the classes of
# symmetric images have sizes dividing 4 (the base's reflections x -> -x,
# y -> -y).  Output is TAP.
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
echo "1..3"
"$bin" pattern waterbomb --cells=1x1 --drive=all -o "$tmp/wa.cfg" 2>/dev/null
"$bin" run "$tmp/wa.cfg" --set analysis.branch_depth=1 --set output.shapes=0 -o "$tmp/wa" >"$tmp/out" 2>&1
st=$?
b="$tmp/wa/branch.tsv"
nb=$(grep -c '^# branch [0-9]*: flat state, cone solution' "$b" 2>/dev/null)
if [ $st = 0 ] && [ "${nb:-0}" -ge 6 ]; then
    echo "ok 1 - waterbomb base: $nb branches from the flat state besides the path"
else
    echo "not ok 1 - waterbomb base: exit $st, $nb flat-state branches"; sed 's/^/#   /' "$tmp/out" | head -5
fi
bad=$(awk -F'\t' '/^#/ || NF < 5 {next} $1 == "point" {for (k = 1; k <= NF; k++) c[$k] = k; next}
    { neg = 0; ne = 0; for (j = 1; j <= 4; j++) { e = $c["eig" j]; if (e != "") { ne++; if (e < 0) neg++ } }
      if ($c["residual"] > 1e-9 || ($c["morse"] < ne && neg != $c["morse"])) n++ }
    END {print n + 0}' "$b")
rows=$(awk -F'\t' '/^#/ || NF < 5 || $1 == "point" {next} {n++} END {print n + 0}' "$b")
if [ $st = 0 ] && [ "$bad" = 0 ] && [ "$rows" -gt 50 ]; then
    echo "ok 2 - $rows rows: equilibria, Morse index = negative eigenvalues"
else
    echo "not ok 2 - $bad of $rows rows with a residual above 1e-9 or a Morse index unlike the eigenvalues"
fi
# class sizes from the notes "cone solution J: ..., class C, ..." (isolated ones)
sizes=$(sed -n 's/^#   cone solution [0-9]*: .*class \([0-9]*\),.*isolation \([0-9.e+-]*\)$/\1 \2/p' "$b" |
    awk '$2 >= 1e-6 {n[$1]++} END {for (c in n) printf "%d ", n[c]}')
okc=1
for s in $sizes; do [ $((4 % s)) = 0 ] || okc=0; done
if [ -n "$sizes" ] && [ $okc = 1 ]; then
    echo "ok 3 - classes of symmetric images of sizes $sizes (divide 4)"
else
    echo "not ok 3 - class sizes '$sizes'"
fi
