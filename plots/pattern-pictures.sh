#!/bin/sh
# pattern-pictures.sh - the pictures of docs/guides/patterns.md: each generated
# study of studies/ run to the end of its actuation path, its last shape
# drawn with plots/shape.gp.
#   plots/pattern-pictures.sh BUILDDIR        (from the source directory)
# writes docs/img/miura-2x2.png, yoshimura-2x2.png, waterbomb-2x2.png.
set -e
build=${1:-.}
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for s in miura-2x2 yoshimura-2x2 waterbomb-2x2; do
    "$build/src/smoothfold" run "$src/studies/$s.cfg" -q --no-plot -o "$tmp/$s"
    last=$(ls "$tmp/$s/shapes/" | tail -1)
    p=$(sed -n 's/.*timestep="\([^"]*\)".*'"$last"'.*/\1/p' "$tmp/$s/shapes.pvd")
    gnuplot -e "vtp='$tmp/$s/shapes/$last'; out='$src/docs/img/$s.png'; awkdir='$src/plots'; ttl='$s: actuation p = $p (faces blue, fold bands orange)'" \
        "$src/plots/shape.gp"
    echo "docs/img/$s.png"
done
