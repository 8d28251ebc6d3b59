#!/bin/sh
# test_flatstart.sh - exact loop closure starting at the flat state
# (src/analysis/flatcone.c, docs/flatstart.md): the branch the driving
# selects on the tangent cone, for each generated pattern and square4;
# symmetric driving of a symmetric sheet gives a symmetric state; a start
# that finds no branch ends with a diagnosis, not a stall at ds_min.
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
i=0
ok() { i=$((i + 1)); echo "ok $i - $1"; }
nok() { i=$((i + 1)); echo "not ok $i - $1"; }
# last row of branch.tsv: value of column $2 of file $1
col() { awk -F'\t' -v c="$2" '/^#/ {next} !h {for (k = 1; k <= NF; k++) if ($k == c) n = k; h = 1; next} {v = $n} END {print v}' "$1"; }
# a generated load study with every actuation group's rest angle 0: the
# load alone folds the flat sheet
gen_flat() {   # output, pattern options...
    out=$1; shift
    "$bin" pattern "$@" -o "$out.gen.cfg" 2>/dev/null &&
        sed 's/^\(  { name = "[a-z0-9]*"; rest_angle = \)-\{0,1\}[0-9.]*;/\10.0;/' "$out.gen.cfg" >"$out"
}
echo "1..8"

# 1-4: each pattern folds from flat with exact closure to the end of its path
run_flat() {   # name, study, extra args
    name=$1; study=$2; shift 2
    "$bin" run "$study" "$@" -q -o "$tmp/$name" >"$tmp/$name.out" 2>&1
    st=$?
    b="$tmp/$name/branch.tsv"
    if [ $st = 0 ] && [ "$(col "$b" type)" = EP ] && grep -q '^# flat start: .*stable branch' "$b" &&
       awk -v u="$(col "$b" probe1_uz)" 'BEGIN {exit !(u != 0 && (u > 1e-6 || u < -1e-6))}'; then
        ok "$name folds from flat with exact closure to p = $(col "$b" p), tip uz $(col "$b" probe1_uz) m ($(sed -n 's/^# flat start: //p' "$b" | cut -c1-60)...)"
    else
        nok "$name from flat: exit $st"; sed 's/^/#   /' "$tmp/$name.out" | head -5
    fi
}
run_flat miura-2x2-actuation "$src/studies/miura-2x2.cfg"
gen_flat "$tmp/yl.cfg" yoshimura --load=0.01
run_flat yoshimura-2x2-tip-load "$tmp/yl.cfg"
gen_flat "$tmp/wl.cfg" waterbomb --cells=1x1 --load=0.01
run_flat waterbomb-base-tip-load "$tmp/wl.cfg"
run_flat square4-load "$src/studies/square4.cfg" --set output.shapes=0

# 5: a waterbomb base (degree 6) with all its folds driven: symmetric
# state, the four valleys equal and the two mountains equal (1e-9)
"$bin" pattern waterbomb --cells=1x1 --drive=all -o "$tmp/wa.cfg" 2>/dev/null
"$bin" run "$tmp/wa.cfg" -q -o "$tmp/wa" >"$tmp/wa.out" 2>&1
st=$?
b="$tmp/wa/branch.tsv"
if [ $st = 0 ] && awk -v a="$(col "$b" theta1)" -v b2="$(col "$b" theta2)" -v c="$(col "$b" theta3)" \
    -v d="$(col "$b" theta4)" -v e="$(col "$b" theta5)" -v f="$(col "$b" theta6)" '
    function rel(x, y) { return (x - y) / (x < 0 ? -x : x) }
    BEGIN { m = 0; split(b2 " " c " " d, v, " ");
            for (k in v) { r = rel(a, v[k]); if (r < 0) r = -r; if (r > m) m = r }
            r = rel(e, f); if (r < 0) r = -r; if (r > m) m = r;
            exit !(a > 0.3 && e < -0.3 && m < 1e-9) }'; then
    ok "waterbomb base, all folds driven: valleys $(col "$b" theta1), mountains $(col "$b" theta5) rad, symmetric to 1e-9"
else
    nok "waterbomb base symmetric: exit $st"; sed 's/^/#   /' "$tmp/wa.out" | head -5
fi

# 6: the same study, a branch that is not there: one line naming the key
"$bin" run "$tmp/wa.cfg" --set solver.flat_branch=4 -q -o "$tmp/wa4" >"$tmp/wa4.out" 2>&1
st=$?
if [ $st != 0 ] && [ "$(wc -l <"$tmp/wa4.out")" = 1 ] && grep -q 'solver.flat_branch = 4, but the flat state has 1 stable branch' "$tmp/wa4.out"; then
    ok "solver.flat_branch beyond the branches found: exit $st, one line"
else
    nok "solver.flat_branch = 4: exit $st"; sed 's/^/#   /' "$tmp/wa4.out" | head -5
fi

# 7: a 3x3 Miura sheet, which stalled at p = 1.2e-5 (ds_min) before: the
# flat state's residual (1.4e-14 of rounding) had been taken for a
# non-flat start
"$bin" pattern miura --cells=3x3 --set analysis.end=0.1 -o "$tmp/m3.cfg" 2>/dev/null
"$bin" run "$tmp/m3.cfg" -q -o "$tmp/m3" >"$tmp/m3.out" 2>&1
st=$?
b="$tmp/m3/branch.tsv"
if [ $st = 0 ] && [ "$(col "$b" type)" = EP ] && grep -q '^# flat start' "$b"; then
    ok "miura 3x3 starts at the flat state, reaches p = $(col "$b" p), tip uz $(col "$b" probe1_uz) m"
else
    nok "miura 3x3 start: exit $st"; sed 's/^/#   /' "$tmp/m3.out" | head -5
fi

# 8: no branch along the driving (2x2 Miura, K = 1, tip load): the
# message says what was found and what to try
gen_flat "$tmp/ml.cfg" miura --load=0.01
"$bin" run "$tmp/ml.cfg" -q -o "$tmp/ml" >"$tmp/ml.out" 2>&1
st=$?
if [ $st != 0 ] && grep -q 'no branch on the tangent cone along the driving' "$tmp/ml.out" &&
   grep -q 'defaults.modes' "$tmp/ml.out" && ! grep -q 'ds_min' "$tmp/ml.out"; then
    ok "miura 2x2 tip load: exit $st with the tangent-cone diagnosis"
else
    nok "miura 2x2 tip load: exit $st"; sed 's/^/#   /' "$tmp/ml.out" | head -5
fi
