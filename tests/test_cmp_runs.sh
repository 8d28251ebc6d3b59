#!/bin/sh
# test_cmp_runs.sh - `smoothfold compare DIR_A DIR_B`: a run against itself
# differs by exactly 0 in every column; strip3 with K = 0 against K = 2
# (both end at p = 1): the largest difference of each fold angle is at
# least its difference at the common end point, computed here with awk
# from the two tables; --tol below it exits 8, above it 0; runs of
# different sheets are refused; analysis.convergence = true reruns at K+1
# into DIR/kplus1 and DIR/convergence.tsv equals `compare` of the run
# against a separate run with defaults.modes = 1; a later run without it
# removes both.  Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..7"
s3="$src/studies/strip3.cfg"
"$bin" run "$s3" -q --set output.shapes=0 -o "$tmp/k0" >/dev/null 2>&1
"$bin" run "$s3" -q --set output.shapes=0 --set defaults.modes=2 -o "$tmp/k2" >/dev/null 2>&1
"$bin" run "$src/studies/fold1.cfg" -q --set output.shapes=0 -o "$tmp/f1" >/dev/null 2>&1
# 1: itself
out=$("$bin" compare "$tmp/k0" "$tmp/k0" 2>&1); rc=$?
nz=$(printf '%s\n' "$out" | awk -F'\t' '!/^#/ && NR > 2 && $2 != 0' | wc -l)
ncol=$(printf '%s\n' "$out" | awk -F'\t' '!/^#/ && NR > 2' | wc -l)
[ $rc -eq 0 ] && [ "$nz" -eq 0 ] && [ "$ncol" -eq 6 ] \
    && echo "ok 1 - a run against itself: 0 in all $ncol columns" \
    || echo "not ok 1 - against itself: status $rc, $nz non-zero of $ncol: $out"
# 2: K = 0 against K = 2, fold angles, against the end rows
out=$("$bin" compare "$tmp/k0" "$tmp/k2" 2>&1); rc=$?
endd() { # column name -> |A - B| on the last rows (both at p = 1)
    for f in "$tmp/k0" "$tmp/k2"; do
        grep -v '^#' "$f/branch.tsv" | awk -F'\t' -v c="$1" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) k = i; next } NF > 2 { v = $k; p = $4 } END { printf "%s %s\n", p, v }'
    done | awk 'NR == 1 { p1 = $1; a = $2 } NR == 2 { p2 = $1; d = a - $2; if (d < 0) d = -d; if (p1 != 1 || p2 != 1) d = -1; printf "%.9g\n", d }'
}
bad=""
for c in theta1 theta2 theta3 probe1_uz; do
    e=$(endd $c)
    m=$(printf '%s\n' "$out" | awk -F'\t' -v c=$c '$1 == c { print $2 }')
    ok=$(awk -v e="$e" -v m="$m" 'BEGIN { print (e > 0 && m != "" && m >= e * (1 - 1e-6)) ? 1 : 0 }')
    [ "$ok" = 1 ] || bad="$bad $c(end $e, max $m)"
done
[ $rc -eq 0 ] && [ -z "$bad" ] && echo "ok 2 - K=0 vs K=2: max differences >= end-point differences ($(printf '%s\n' "$out" | grep 'largest fold angle'))" \
    || echo "not ok 2 - K=0 vs K=2: status $rc:$bad"
# 3, 4: --tol
t1=$(printf '%s\n' "$out" | awk -F'\t' '$1 == "theta1" { print $2 }')
"$bin" compare "$tmp/k0" "$tmp/k2" --tol=$(awk -v t="$t1" 'BEGIN { print t / 2 }') >/dev/null 2>"$tmp/err"; rc=$?
[ $rc -eq 8 ] && grep -q "differ by more than --tol" "$tmp/err" && echo "ok 3 - --tol below the difference: status 8" \
    || echo "not ok 3 - --tol below: status $rc $(cat "$tmp/err")"
"$bin" compare "$tmp/k0" "$tmp/k2" --tol=1 >/dev/null 2>"$tmp/err"; rc=$?
[ $rc -eq 0 ] && echo "ok 4 - --tol=1: status 0" || echo "not ok 4 - --tol=1: status $rc $(cat "$tmp/err")"
# 5: another sheet
"$bin" compare "$tmp/k0" "$tmp/f1" >/dev/null 2>"$tmp/err"; rc=$?
[ $rc -eq 1 ] && grep -q "not the same sheet" "$tmp/err" && echo "ok 5 - different sheets refused: $(cat "$tmp/err")" \
    || echo "not ok 5 - different sheets: status $rc $(cat "$tmp/err")"
# 6: analysis.convergence on strip3 (K = 0 everywhere)
"$bin" run "$s3" --set output.shapes=0 --set analysis.convergence=true -o "$tmp/conv" >"$tmp/out" 2>"$tmp/err"; rc=$?
"$bin" run "$s3" -q --set output.shapes=0 --set defaults.modes=1 -o "$tmp/k1" >/dev/null 2>&1
"$bin" compare "$tmp/conv" "$tmp/k1" | grep -v '^#' >"$tmp/want"
grep -v '^#' "$tmp/conv/convergence.tsv" >"$tmp/got" 2>/dev/null
line=$(grep '^convergence (K = 0 against K+1): largest probe difference' "$tmp/out")
if [ $rc -eq 0 ] && [ -s "$tmp/got" ] && cmp -s "$tmp/got" "$tmp/want" && [ -n "$line" ] && [ -s "$tmp/conv/kplus1/branch.tsv" ]; then
    echo "ok 6 - analysis.convergence: convergence.tsv = compare against a K=1 run; $line"
else
    echo "not ok 6 - convergence: status $rc, '$line', $(cat "$tmp/err" | tail -1)"; diff "$tmp/got" "$tmp/want" | head -5 | sed 's/^/#   /'
fi
# 7: the next run into the same directory without it leaves neither behind
"$bin" run "$s3" -q --set output.shapes=0 -o "$tmp/conv" >/dev/null 2>&1
[ ! -e "$tmp/conv/kplus1" ] && [ ! -e "$tmp/conv/convergence.tsv" ] && echo "ok 7 - a later run removes kplus1/ and convergence.tsv" \
    || echo "not ok 7 - left: $(ls "$tmp/conv")"
