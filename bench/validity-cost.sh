#!/bin/sh
# bench/validity-cost.sh BUILDDIR [M...] - CPU seconds of one
# physical-validity check (src/analysis/validity/validity.h) on Miura-ori M x M
# cells (bench/miura-study.sh M actuation), every fold at 0.3 rad: the
# R*-tree's pairs, and every pair of parts up to 16 x 16 (brute force,
# the same answer); then the exponent of a least-squares fit of log time
# against log parts.  Builds bench/validity_cost against the build's
# libraries.  Not part of make check.
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:?usage: bench/validity-cost.sh BUILDDIR [M...]}
shift
export OPENBLAS_NUM_THREADS=1
sizes=${*:-"4 8 16 32 64"}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mk=$build/Makefile
val() { sed -n "s/^$1 = //p" "$mk" | head -1; }
inc="-I$src/src -I$src/src/pattern -I$src/src/model -I$src/src/io -I$src/continuation"
for d in "$src"/src/analysis/*/; do inc="$inc -I$d"; done   # one folder per concern
# shellcheck disable=SC2046
cc -std=c11 -D_DEFAULT_SOURCE -O2 $inc $(val CPPFLAGS) -o "$out/validity_cost" \
    "$src/bench/validity_cost.c" "$build/src/libsmoothfold.a" "$build/continuation/libcont.a" \
    $(val ARPACK_LIBS) $(val LIBCONFIG_LIBS) $(val JANSSON_LIBS) $(val LIBS) -lm || exit 1
echo "| cells | folds | parts | triangles | part pairs (tree) | triangle pairs tested | crossings | s per check (tree) | s per check (all pairs) |"
echo "|---|---|---|---|---|---|---|---|---|"
for m in $sizes; do
    sh "$src/bench/miura-study.sh" "$m" actuation > "$out/m$m.cfg"
    brute=0; [ "$m" -le 16 ] && brute=1
    reps=20; [ "$m" -ge 32 ] && reps=3
    "$out/validity_cost" "$out/m$m.cfg" $reps $brute | awk -F'\t' -v m="$m" '{ printf "| %d x %d | %s | %s | %s | %s | %s | %s | %s | %s |\n", m, m, $1, $2, $3, $4, $5, $6, $7, ($8 < 0 ? "-" : $8) }' | tee -a "$out/rows"
done
awk -F'|' '{ n++; x = log($4 + 0); y = log($9 + 0); sx += x; sy += y; sxx += x * x; sxy += x * y }
    END { if (n > 1) printf "\nfit: time ~ parts^%.2f (least squares over %d sizes)\n", (n * sxy - sx * sy) / (n * sxx - sx * sx), n }' "$out/rows"
