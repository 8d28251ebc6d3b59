#!/bin/sh
# bench/stab-cost.sh BUILDDIR [M...] - CPU seconds per stability evaluation of
# Miura-ori M x M cells (bench/miura-study.sh M load: gravity and a tip
# load) in the face-pose formulation, dense LAPACK against the MUMPS
# inertia (analysis.eigensolver = "dense" / "inertia"), on the flat sheet
# at p = 0 and p = 1 (bench/stab_cost.c): the first evaluation and the
# mean of the 3 next ones.  The dense method is skipped
# above 3000 coordinates.  Builds bench/stab_cost against the build's
# libraries.  Not part of make check.
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:?usage: bench/stab-cost.sh BUILDDIR [M...]}
shift
export OPENBLAS_NUM_THREADS=1
sizes=${*:-"4 8 16"}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mk=$build/Makefile
val() { sed -n "s/^$1 = //p" "$mk" | head -1; }
inc="-I$src/src -I$src/src/pattern -I$src/src/model -I$src/src/io -I$src/src/cli -I$src/continuation"
for d in "$src"/src/analysis/*/; do inc="$inc -I$d"; done   # one folder per concern
# shellcheck disable=SC2046
cc -std=c11 -D_DEFAULT_SOURCE -O2 $inc $(val CPPFLAGS) $(val ARPACK_CFLAGS) -o "$out/stab_cost" \
    "$src/bench/stab_cost.c" "$build/src/libsmoothfold.a" "$build/continuation/libcont.a" \
    $(val ARPACK_LIBS) $(val LIBCONFIG_LIBS) $(val JANSSON_LIBS) $(val LIBS) || exit 1
for m in $sizes; do
    sh "$src/bench/miura-study.sh" "$m" load > "$out/m$m.cfg"
    meths="inertia,dense"
    [ "$m" -gt 12 ] && meths=inertia
    /usr/bin/time -f "  (process: %e s wall, %M KB peak RSS)" "$out/stab_cost" "$out/m$m.cfg" "$meths" 4
done
