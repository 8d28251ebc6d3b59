#!/bin/sh
# test_flatstart_cost.sh - the cost of the sparse flat start's limit
# problem (src/analysis/start/flatlimit_sparse.c, docs/flatstart.md "Cost of
# the sparse start"): where the full KKT matrix is indefinite, Newton
# steps with the Gauss-Newton matrix of the penalty instead of a shifted
# one.  On the 4x4 Miura sheet under gravity and a tip load
# (bench/miura-study.sh 4 load) the limit problem then takes at most 80
# Newton iterations and 130 MUMPS factorisations for its three starts
# (main at 658612c, shifted steps: 115 and 233; now 64 and 82), the
# three starts end on one state (first-order response, rigid vertex
# modes and mirror: the same limit energy to 1e-9 relative, a check
# independent of the cost) and the path reaches p = 0.3.
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
echo "1..1"
sh "$src/bench/miura-study.sh" 4 load 1 >"$tmp/m4l.cfg"
"$bin" run "$tmp/m4l.cfg" -q -o "$tmp/o" --set 'solver.formulation="poses"' --set 'analysis.flat_start="sparse"' \
    --set analysis.stability=false --set analysis.end=0.3 >"$tmp/o.out" 2>&1
st=$?
hd=$(grep '^# flat start (sparse)' "$tmp/o/branch.tsv" 2>/dev/null)
lim=$(echo "$hd" | sed -n 's/.* \([0-9][0-9]*\) Newton iterations, \([0-9][0-9]*\) MUMPS factorisations.*/\1 \2/p')
# "limit states found: first-order response E1 (followed), rigid vertex modes E2, mirror in the modes: the same state"
en=$(echo "$hd" | sed -n 's/.*first-order response \(-[0-9.e-]*\).*rigid vertex modes \(-[0-9.e-]*\).*/\1 \2/p')
pend=$(awk -F'\t' '/^#/ || $1 == "point" {next} {p = $4} END {print p}' "$tmp/o/branch.tsv" 2>/dev/null)
if [ "$st" = 0 ] && echo "$lim" | awk '{exit !(NF == 2 && $1 <= 80 && $2 <= 130)}' &&
   echo "$en" | awk '{d = ($1 - $2) / $1; if (d < 0) d = -d; exit !(NF == 2 && $1 < 0 && d <= 1e-9)}' &&
   echo "$hd" | grep -q 'mirror in the modes: the same state' &&
   awk -v p="$pend" 'BEGIN {exit !(p != "" && p + 0 >= 0.3 - 1e-12)}'; then
    echo "ok 1 - miura 4x4 load: limit problem in $lim Newton iterations / factorisations, one state from the three starts ($en), p = $pend"
else
    echo "not ok 1 - miura 4x4 load: exit $st, limit problem '$lim', energies '$en', p '$pend'"
    echo "$hd" | cut -c1-400 | sed 's/^/#   /'
fi
