#!/bin/sh
# flatstart-cost.sh BUILDDIR [OTHER_BUILDDIR] [M ...] - the cost of the
# sparse flat start (analysis.flat_start = "sparse", docs/flatstart.md
# "Cost of the sparse start") on the M x M Miura sheets of
# bench/miura-study.sh (actuation, K = 1; default M = 8 12 16).
#
# Runs the start alone (analysis.max_steps = 1, stability off,
# OPENBLAS_NUM_THREADS=1) and prints per sheet: the limit problem's Newton
# iterations and MUMPS factorisations (all starts, from the note in
# branch.tsv), CPU time (user, /usr/bin/time), peak memory, and the limit
# energy followed.  With OTHER_BUILDDIR (e.g. a build of main) the same
# for it, and whether the first data rows of branch.tsv agree (largest
# absolute difference of their numbers).  16x16 takes 30 s CPU with the
# Gauss-Newton inertia correction, 80 s before; not part of make check.
src=$(cd "$(dirname "$0")/.." && pwd)
new=${1:?usage: flatstart-cost.sh BUILDDIR [OTHER_BUILDDIR] [M ...]}
shift
old=""
if [ $# -gt 0 ] && [ -d "$1" ]; then old=$1; shift; fi
sizes=${*:-8 12 16}
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
start() {   # BUILD M TAG
    OPENBLAS_NUM_THREADS=1 /usr/bin/time -f "%U %M" -o "$tmp/$3.time" "$1/src/smoothfold" run "$tmp/m$2.cfg" -q \
        -o "$tmp/$3" --set 'analysis.flat_start="sparse"' --set 'solver.formulation="poses"' \
        --set analysis.max_steps=1 --set analysis.stability=false >"$tmp/$3.out" 2>&1
    note=$(grep '^# flat start (sparse)' "$tmp/$3/branch.tsv")
    its=$(echo "$note" | sed -n 's/.* \([0-9][0-9]*\) Newton iterations, \([0-9][0-9]*\) MUMPS factorisations.*/\1 \2/p')
    en=$(echo "$note" | sed -n 's/.* \(-[0-9.e-]*\) (followed).*/\1/p')
    set -- $(tail -1 "$tmp/$3.time")
    printf '%s iterations/factorisations %s, CPU %s s, peak %.0f MB, followed limit energy %s\n' \
        "$tag" "${its:-?}" "$1" "$(echo "$2" | awk '{print $1 / 1024}')" "${en:-?}"
}
# the first data row off the flat sheet, one value a line, without the
# residual and Newton-count columns (solver accuracy, not the state)
first() {
    awk -F'\t' '/^#/ {next} $1 == "point" {for (k = 1; k <= NF; k++) skip[k] = $k ~ /^(residual|newton)/; next}
                $4 > 0 {for (k = 1; k <= NF; k++) if (!skip[k]) print $k; exit}' "$1"
}
for m in $sizes; do
    sh "$src/bench/miura-study.sh" "$m" actuation 1 >"$tmp/m$m.cfg"
    tag="${m}x$m this build:"
    start "$new" "$m" "n$m"
    if [ -n "$old" ]; then
        tag="${m}x$m other build:"
        start "$old" "$m" "o$m"
        first "$tmp/n$m/branch.tsv" >"$tmp/a"
        first "$tmp/o$m/branch.tsv" >"$tmp/b"
        paste "$tmp/a" "$tmp/b" | awk -v m="$m" '{d = $1 - $2; if (d < 0) d = -d; if (d > x) x = d}
            END {printf "%sx%s first data rows: largest difference %g\n", m, m, x}'
    fi
done
