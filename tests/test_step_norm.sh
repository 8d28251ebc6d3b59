#!/bin/sh
# test_step_norm.sh - analysis.step_norm = "rms" (continuation/README.md,
# "Larger steps on large sheets"): steps measured by the RMS change of the
# fold coordinates, so that the Miura actuation path (bench/miura-study.sh
# M actuation 1, poses, sparse flat start) takes about the same number of
# points on every sheet, with the anchored reusing corrector from the
# first step and the second-order predictor.  The default "sum" counts
# every fold coordinate with weight 1, so its points grow with the sheet
# (41 at 3x3, 108 at 8x8).  Checked on the 3x3 and 8x8 sheets:
#  1-2: exit 0, p = 1, every written point's constraint residual <= 1e-10;
#  3: at p = 1 the 8x8 sheet is in the uniform Miura motion, every fold at
#     +-theta with theta the 3x3 sheet's (default norm, plain corrector) to
#     1e-9 rad;
#  4: the point counts of the two sheets differ by at most 2, and the 8x8
#     path takes at most 15 points and 1.8 factorisations per point (12 and
#     17 measured; without the anchored corrector 20 points and 44
#     factorisations: its plain Newton converges only linearly from the
#     long steps there);
#  5: the arclength s of the first point off the flat state (the chord
#     from the flat state, run_point.c) is measured in the path's norm:
#     the 3x3 sheet's first point is the same with both norms, and
#     (s1^2 - p1^2) of "sum" over that of "rms" is the number of fold
#     coordinates, 2 per fold with K = 1 (the angle and one mode);
#  6: the 8x8 path with the Newton tolerance 2e-11 instead of 1e-10: the
#     first level's anchored point of the step at p = 0.31 misses it (plain
#     residual about 3e-11, the anchor's bias) and its proximal iterations
#     meet it, so the path keeps the first level, the second-order predictor
#     and its steps: exit 0, p = 1, at most 15 points, no retry and at most
#     1.8 factorisations per point (12 points, 17 factorisations measured;
#     when the miss sent the corrector to the smaller weights of the next
#     level for the rest of the run: 16 points, a retry, 83 factorisations,
#     as the 24x24 sheet at 1e-10 did).
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
. "$src/tests/tap.sh"
echo "1..6"
run() {   # run M NORM [SETTING...]
    m=$1 norm=$2; shift 2
    "$bin" run "$tmp/m$m.cfg" -q -o "$tmp/o$m$norm" --set 'solver.formulation="poses"' \
        --set 'analysis.flat_start="sparse"' --set analysis.stability=false \
        --set "analysis.step_norm=\"$norm\"" "$@" >"$tmp/o$m$norm.out" 2>&1
    echo $?
}
# p of the last row, the largest residual column, points, min and max fold angle at p = 1
summary() {
    awk -F'\t' '/^#/ {next} !h {for (k = 1; k <= NF; k++) {if ($k == "residual") rc = k; if ($k == "p") pc = k
                                if ($k ~ /^theta/) {if (!f) f = k; l = k}}; h = 1; next}
                {n++; if ($rc + 0 > rmax) rmax = $rc + 0; p = $pc; lo = 1e9; hi = -1e9
                 for (k = f; k <= l; k++) {if ($k + 0 < lo) lo = $k + 0; if ($k + 0 > hi) hi = $k + 0}}
                END {printf "%s %.3g %d %.15g %.15g\n", p, rmax, n, lo, hi}' "$1"
}
for m in 3 8; do sh "$src/bench/miura-study.sh" $m actuation 1 >"$tmp/m$m.cfg"; done
s3=$(run 3 sum); r3=$(run 3 rms); r8=$(run 8 rms)
set -- $(summary "$tmp/o3sum/branch.tsv"); p3s=$1; n3s=$3; th=$5
set -- $(summary "$tmp/o3rms/branch.tsv"); p3=$1; res3=$2; n3=$3
set -- $(summary "$tmp/o8rms/branch.tsv"); p8=$1; res8=$2; n8=$3; lo8=$4; hi8=$5
for c in "3 $s3 $p3s 0 $r3 $p3 $res3" "8 0 1 0 $r8 $p8 $res8"; do
    set -- $c
    if [ "$2" = 0 ] && [ "$3" = 1 ] && [ "$5" = 0 ] && [ "$6" = 1 ] && awk -v r="$7" 'BEGIN {exit !(r <= 1e-10)}'; then
        ok "${1}x$1: exit 0, p = 1, largest point residual $7"
    else
        nok "${1}x$1: exit $5 (default norm $2), p = $6, largest residual $7"; sed 's/^/#   /' "$tmp/o$1rms.out" | head -3
    fi
done
if awk -v t="$th" -v lo="$lo8" -v hi="$hi8" 'BEGIN {d1 = hi - t; d2 = lo + t; if (d1 < 0) d1 = -d1; if (d2 < 0) d2 = -d2
                                                   exit !(t > 0.5 && d1 <= 1e-9 && d2 <= 1e-9)}'; then
    ok "8x8 at p = 1: fold angles in [$lo8, $hi8], the uniform Miura motion +-$th of the 3x3 sheet"
else
    nok "8x8 at p = 1: fold angles in [$lo8, $hi8] against +-$th (3x3)"
fi
fac=$(awk -F, '/^#/ || $1 == "point" {next} {f += $11} END {print f + 0}' "$tmp/o8rms/stats.csv")
if awk -v a="$n3" -v b="$n8" -v f="$fac" 'BEGIN {d = a - b; if (d < 0) d = -d; exit !(d <= 2 && b <= 15 && f <= 1.8 * b)}'; then
    ok "points: 3x3 $n3, 8x8 $n8 (default norm: 3x3 $n3s); 8x8 factorisations $fac"
else
    nok "points: 3x3 $n3, 8x8 $n8, 8x8 factorisations $fac"
fi
# s and p of the first point off the flat state (row 1)
first() { awk -F'\t' '/^#/ {next} !h {h = 1; next} $1 == 1 {print $3, $4}' "$1"; }
set -- $(first "$tmp/o3sum/branch.tsv") $(first "$tmp/o3rms/branch.tsv")
nf=$(grep -c 'from = ' "$tmp/m3.cfg")
if awk -v ss="$1" -v ps="$2" -v sr="$3" -v pr="$4" -v nq=$((2 * nf)) 'BEGIN {
        dp = ps - pr; if (dp < 0) dp = -dp; r = (ss * ss - ps * ps) / (sr * sr - pr * pr)
        d = r / nq - 1; if (d < 0) d = -d; exit !(ps > 0 && dp <= 1e-9 * ps && d <= 1e-6)}'; then
    ok "first point: s = $1 (sum), $3 (rms) at p = $2, $4: the ratio of the fold parts is $((2 * nf)) fold coordinates"
else
    nok "first point: s = $1 (sum), $3 (rms) at p = $2, $4: fold parts not in the ratio $((2 * nf))"
fi
# the 8x8 path at the Newton tolerance 2e-11
rm -rf "$tmp/o8rms"
r8=$(run 8 rms --set solver.tolerance=2e-11)
set -- $(summary "$tmp/o8rms/branch.tsv"); p8=$1; n8=$3
set -- $(awk -F, '/^#/ || $1 == "point" {next} {f += $11; r += $8} END {print f + 0, r + 0}' "$tmp/o8rms/stats.csv")
if [ "$r8" = 0 ] && [ "$p8" = 1 ] && awk -v n="$n8" -v f="$1" -v r="$2" 'BEGIN {exit !(n <= 15 && r == 0 && f <= 1.8 * n)}'; then
    ok "8x8 at tolerance 2e-11: p = 1 in $n8 points, $1 factorisations, $2 retries"
else
    nok "8x8 at tolerance 2e-11: exit $r8, p = $p8, $n8 points, $1 factorisations, $2 retries"
fi
