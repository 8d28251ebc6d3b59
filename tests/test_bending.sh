#!/bin/sh
# test_bending.sh - bending faces (faces.bending, docs/guides/bending-faces.md):
# as the faces grow stiff the path tends to the rigid-face path.  The
# 2x2 Miura under its actuation, the state at p = 1: the largest fold-angle
# difference from the rigid run, relative to the largest rigid fold angle,
# is below 1e-6 at a face modulus of 1e15 Pa and falls as 1/E (from 1e11
# to 1e15 Pa by 1e4 within 5 %); at 1e9 Pa the faces bend visibly (a
# difference above 1e-2, so that the comparison can fail).  A FOLD file's
# F edge (tests/fold/facet-square.fold) is imported as faces.facets and
# used as the facet of its face, the other face gets one of its own, and
# export writes both as F edges.  studies/hypar-4.cfg folds from the flat
# sheet into a saddle (one pair of opposite corners up, the other down,
# every point stable) and studies/twist.cfg (the square twist) to p = 1
# with exact closure, each with facet hinges folded; with rigid faces and
# K = 0 the square twist is locked (it is not rigidly foldable).  Output
# is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..8"
st="$src/studies/miura-2x2.cfg"
# the EP row: probe1_uz and theta1..theta24
ep() {
    awk -F'\t' '/^#/ {next} $1 == "point" {for (i = 1; i <= NF; i++) c[$i] = i; next}
        $(c["type"]) == "EP" {printf "%s", $(c["probe1_uz"]); for (k = 1; k <= 24; k++) printf " %s", $(c["theta" k]); print ""}' "$1/branch.tsv"
}
fail=0
"$bin" run "$st" -o "$tmp/rigid" -q --set output.shapes=0 --set 'analysis.flat_start="multipliers"' >"$tmp/log" 2>&1 || { echo "# rigid run failed: $(cat "$tmp/log")"; fail=1; }
R=$(ep "$tmp/rigid")
for E in 1e9 1e11 1e15; do
    "$bin" run "$st" -o "$tmp/E$E" -q --set output.shapes=0 --set faces.bending=true --set 'analysis.flat_start="multipliers"' \
        --set materials.face.E=$E --set materials.face.nu=0.3 >"$tmp/log" 2>&1 || { echo "# run at E = $E failed: $(cat "$tmp/log")"; fail=1; }
    B=$(ep "$tmp/E$E")
    d=$(echo "$R|$B" | awk -F'|' '{n = split($1, r, " "); split($2, b, " "); if (n < 25 || length($2) == 0) {print "nan"; exit}
        m = 0; d = 0; for (k = 2; k <= n; k++) {a = r[k] < 0 ? -r[k] : r[k]; if (a > m) m = a; x = b[k] - r[k]; if (x < 0) x = -x; if (x > d) d = x}
        printf "%.6e", d / m}')
    eval "d_$(echo $E | tr -d +)=$d"
    echo "# E = $E Pa: max relative fold-angle difference from the rigid faces $d"
done
# FOLD F edges: import, check with bending on, export
if "$bin" import "$src/tests/fold/facet-square.fold" -o "$tmp/fs.cfg" >/dev/null 2>"$tmp/log" &&
   grep -q 'facets = \["v1 v5"\];' "$tmp/fs.cfg" &&
   "$bin" check "$tmp/fs.cfg" --set faces.bending=true >"$tmp/out" 2>>"$tmp/log" &&
   grep -q "^bending faces: 2 facet hinges" "$tmp/out" && grep -q "^faces: 4" "$tmp/out"; then
    echo "ok 1 - the F edge of a FOLD file becomes faces.facets, and a facet with bending on"
else
    echo "not ok 1 - import of F edges as facets"; sed 's/^/#   /' "$tmp/log" "$tmp/out" 2>/dev/null
fi
if "$bin" export "$tmp/fs.cfg" --set faces.bending=true -o "$tmp/fs.fold" 2>"$tmp/log" &&
   [ "$(grep -o '"edges_assignment"[^]]*]' "$tmp/fs.fold" | grep -o '"F"' | wc -l)" -eq 2 ]; then
    echo "ok 2 - export writes the facet hinges as F edges"
else
    echo "not ok 2 - export of facets as F edges"; sed 's/^/#   /' "$tmp/log"
fi
# EP row of DIR/branch.tsv: the named columns, or "" when there is no EP row
epcols() {
    f=$1; shift
    awk -F'\t' -v want="$*" '/^#/ {next} $1 == "point" {for (i = 1; i <= NF; i++) c[$i] = i; next}
        $(c["type"]) == "EP" {n = split(want, w, " "); for (k = 1; k <= n; k++) printf "%s%s", (k > 1 ? " " : ""), ((w[k] in c) ? $(c[w[k]]) : "nan"); print ""}' "$f/branch.tsv"
}
# the largest |theta| of folds FIRST..LAST at the EP row
maxtheta() {
    awk -F'\t' -v a=$2 -v b=$3 '/^#/ {next} $1 == "point" {for (i = 1; i <= NF; i++) c[$i] = i; next}
        $(c["type"]) == "EP" {m = 0; for (k = a; k <= b; k++) {x = $(c["theta" k]); if (x < 0) x = -x; if (x > m) m = x}; print m}' "$1/branch.tsv"
}
if "$bin" run "$src/studies/hypar-4.cfg" -o "$tmp/hypar" -q --set output.shapes=0 >"$tmp/log" 2>&1; then
    set -- $(epcols "$tmp/hypar" probe1_uz probe2_uz probe3_uz probe4_uz p)
    nunst=$(awk -F'\t' '/^#/ {next} $1 == "point" {for (i = 1; i <= NF; i++) c[$i] = i; next} $(c["stable"]) != 1 {n++} END {print n + 0}' "$tmp/hypar/branch.tsv")
    mt=$(maxtheta "$tmp/hypar" 25 37)
    if awk -v a="$1" -v b="$2" -v c="$3" -v d="$4" -v p="$5" -v t="$mt" -v u="$nunst" \
        'BEGIN {exit !(p == 1 && a * c > 0 && b * d > 0 && a * b < 0 && u == 0 && t > 1e-3)}'; then
        echo "ok 3 - hypar-4: a saddle at p = 1 (corner uz $1 $2 $3 $4 m), stable, facets folded up to $mt rad"
    else
        echo "not ok 3 - hypar-4: expected a stable saddle at p = 1, got corners uz '$1 $2 $3 $4' at p = '$5', $nunst unstable points, facets up to '$mt' rad"
    fi
else
    echo "not ok 3 - hypar-4 run failed: $(cat "$tmp/log")"
fi
if "$bin" run "$src/studies/twist.cfg" -o "$tmp/twist" -q --set output.shapes=0 >"$tmp/log" 2>&1; then
    set -- $(epcols "$tmp/twist" p residual)
    mt=$(maxtheta "$tmp/twist" 13 21)
    if awk -v p="$1" -v r="$2" -v t="$mt" 'BEGIN {exit !(p == 1 && r < 1e-9 && t > 1e-2)}'; then
        echo "ok 4 - square twist folds with bending faces to p = 1 (loop residual $2, facets up to $mt rad)"
    else
        echo "not ok 4 - square twist: p '$1', residual '$2', largest facet angle '$mt'"
    fi
else
    echo "not ok 4 - twist run failed: $(cat "$tmp/log")"
fi
"$bin" run "$src/studies/twist.cfg" -o "$tmp/twist-rigid" -q --set output.shapes=0 --set faces.bending=false \
    --set defaults.modes=0 >"$tmp/log" 2>&1; rc=$?
if [ $rc = 5 ] && grep -qE "locked|leave the sheet no motion" "$tmp/log"; then echo "ok 5 - the square twist with rigid faces and K = 0 is locked (status 5)"
else echo "not ok 5 - rigid K = 0 square twist: expected status 5 and 'locked', got $rc: $(cat "$tmp/log")"; fi
[ $fail = 0 ] || { echo "not ok 6 - runs failed"; echo "not ok 7 - runs failed"; echo "not ok 8 - runs failed"; exit 0; }
awk -v d="$d_1e15" 'BEGIN {exit !(d + 0 < 1e-6 && d != "nan")}' \
    && echo "ok 6 - stiffest faces within 1e-6 of the rigid path ($d_1e15)" \
    || echo "not ok 6 - stiffest faces: expected below 1e-6, got $d_1e15"
awk -v a="$d_1e11" -v b="$d_1e15" 'BEGIN {r = a / b; exit !(r > 0.95e4 && r < 1.05e4)}' \
    && echo "ok 7 - the difference falls as 1/E (1e11 to 1e15 Pa: $d_1e11 to $d_1e15)" \
    || echo "not ok 7 - expected a ratio 1e4 +- 5 % from 1e11 to 1e15 Pa, got $d_1e11 / $d_1e15"
awk -v d="$d_1e9" 'BEGIN {exit !(d + 0 > 1e-2)}' \
    && echo "ok 8 - soft faces bend (difference $d_1e9 at 1e9 Pa)" \
    || echo "not ok 8 - at 1e9 Pa expected a difference above 1e-2, got $d_1e9"
