#!/bin/sh
# bench/bending-limit.sh - bending faces against rigid faces: the end point
# (EP row) of a study's path with faces.bending on and the face modulus E
# over a range, against the same study with rigid faces
# (docs/guides/bending-faces.md, "Validation").  Not part of make check (the test
# tests/test_bending.sh checks three of these points).
#
#   sh bench/bending-limit.sh [BUILD_DIR] [STUDY] [E ...]
#       (default: studies/miura-2x2.cfg, E = 1e8 .. 1e16 Pa; nu = 0.3)
#
# Prints a markdown table: E, the largest fold-angle difference (folds of
# the study only) relative to the largest rigid fold angle, and the report
# probe's uz difference relative to the rigid uz.
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src}
study=${2:-$src/studies/miura-2x2.cfg}
[ $# -ge 2 ] && shift 2 || shift $#
Es=${*:-"1e8 1e9 1e10 1e11 1e12 1e13 1e14 1e15 1e16"}
bin=$build/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# EP row: probe1_uz, then theta1..thetaN of the study's own folds
nf=$("$bin" check "$study" --set faces.bending=false 2>/dev/null | sed -n 's/^folds: \([0-9]*\).*/\1/p')
ep() {
    awk -F'\t' -v nf="$nf" '/^#/ {next} $1 == "point" {for (i = 1; i <= NF; i++) c[$i] = i; next}
        $(c["type"]) == "EP" {printf "%s", $(c["probe1_uz"]); for (k = 1; k <= nf; k++) printf " %s", $(c["theta" k]); print ""}' "$1/branch.tsv"
}
"$bin" run "$study" -o "$tmp/rigid" -q --set output.shapes=0 --set faces.bending=false >/dev/null 2>&1 || { echo "rigid run failed" >&2; exit 1; }
R=$(ep "$tmp/rigid")
echo "| face E [Pa] | max relative fold-angle difference | relative tip uz difference |"
echo "|---|---|---|"
for E in $Es; do
    if ! "$bin" run "$study" -o "$tmp/E" -q --set output.shapes=0 --set faces.bending=true \
            --set materials.face.E=$E --set materials.face.nu=0.3 >/dev/null 2>&1; then
        echo "| $E | run failed | |"; continue
    fi
    B=$(ep "$tmp/E")
    echo "$R|$B" | awk -v E=$E -F'|' '{n = split($1, r, " "); split($2, b, " "); m = 0; d = 0
        for (k = 2; k <= n; k++) {a = r[k] < 0 ? -r[k] : r[k]; if (a > m) m = a; x = b[k] - r[k]; if (x < 0) x = -x; if (x > d) d = x}
        u = b[1] - r[1]; if (u < 0) u = -u; ru = r[1] < 0 ? -r[1] : r[1]
        printf "| %s | %.2e | %.2e |\n", E, d / m, u / ru}'
done
