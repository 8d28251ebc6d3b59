#!/bin/sh
# bench/penalty-limit.sh - the paper's loop penalty against exact loop
# closure: the end point of a study's path with the penalty weights
# (solver.penalty_rotation = 100 J, solver.penalty_translation = 1 J/m^2,
# the paper's) multiplied by 10^0 .. 10^8, against the exact path's
# (docs/design/start.md).  Not part of make check.
#
#   sh bench/penalty-limit.sh [BUILD_DIR] [STUDY ...]    (default: miura-2x2 square4)
#
# Prints one table per study: factor, where the penalty path ended (p;
# stiff penalties stall near the flat state: exit 3), the report probe's
# displacement there (uz) and |u - u_exact| / |u_exact| against the exact
# path interpolated linearly in p at that p, the largest loop residual
# along the penalty path (rotation [1], translation [m]), points, exit.
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-.}
[ $# -gt 0 ] && shift
bin=$build/src/smoothfold
[ -x "$bin" ] || { echo "bench/penalty-limit.sh: no $bin (give the build directory)" >&2; exit 1; }
studies=${*:-miura-2x2 square4}
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
# last row of branch.tsv: columns p, probe1_ux/uy/uz; max of residual_rot, residual_tra
last() {
    awk -F'\t' '/^#/ {next} !h {for (k = 1; k <= NF; k++) c[$k] = k; h = 1; next}
        {p = $c["p"]; x = $c["probe1_ux"]; y = $c["probe1_uy"]; z = $c["probe1_uz"]; n++
         if ($c["residual_rot"] + 0 > rr) rr = $c["residual_rot"] + 0
         if ($c["residual_tra"] + 0 > rt) rt = $c["residual_tra"] + 0}
        END {printf "%s %s %s %s %d %.3g %.3g\n", p, x, y, z, n, rr, rt}' "$1"
}
# the exact path's probe displacement at p (linear between its rows)
at_p() {
    awk -F'\t' -v p="$2" '/^#/ {next} !h {for (k = 1; k <= NF; k++) c[$k] = k; h = 1; next}
        {q = $c["p"]; x = $c["probe1_ux"]; y = $c["probe1_uy"]; z = $c["probe1_uz"]
         if (n && !done && (q - p) * (q0 - p) <= 0 && q != q0) {
             t = (p - q0) / (q - q0)
             printf "%.12g %.12g %.12g\n", x0 + t * (x - x0), y0 + t * (y - y0), z0 + t * (z - z0); done = 1 }
         q0 = q; x0 = x; y0 = y; z0 = z; n++}
        END {if (!done) printf "%.12g %.12g %.12g\n", x0, y0, z0}' "$1"
}
for s in $studies; do
    cfg=$src/studies/$s.cfg
    timeout 600 "$bin" run "$cfg" --set solver.constraints='"exact"' --set output.shapes=0 \
        --set analysis.stability=false -q -o "$tmp/exact" >/dev/null 2>"$tmp/err"
    st=$?
    set -- $(last "$tmp/exact/branch.tsv")
    pe=$1 xe=$2 ye=$3 ze=$4
    echo "## $s: exact closure: end p = $pe, probe u = ($xe, $ye, $ze) m, $5 points, exit $st"
    echo
    echo "| factor | lambda_R [J] | lambda_d [J/m^2] | end p | probe uz [m] | rel. diff. to exact at that p | max rot. residual | max transl. residual [m] | points | exit |"
    echo "|---|---|---|---|---|---|---|---|---|---|"
    for e in 0 1 2 3 4 5 6 7 8; do
        f=1e$e
        lr=$(awk -v f=$f 'BEGIN {printf "%.6g", 100 * f}')
        ld=$(awk -v f=$f 'BEGIN {printf "%.6g", 1 * f}')
        rm -rf "$tmp/pen"
        timeout 600 "$bin" run "$cfg" --set solver.constraints='"penalty"' --set solver.penalty_rotation=$lr \
            --set solver.penalty_translation=$ld --set output.shapes=0 --set analysis.stability=false \
            -q -o "$tmp/pen" >/dev/null 2>"$tmp/err"
        st=$?
        if [ -f "$tmp/pen/branch.tsv" ]; then
            set -- $(last "$tmp/pen/branch.tsv")
            d=$(at_p "$tmp/exact/branch.tsv" $1 | awk -v x=$2 -v y=$3 -v z=$4 '{a = $1; b = $2; c = $3;
                printf "%.3g", sqrt((x-a)^2 + (y-b)^2 + (z-c)^2) / sqrt(a^2 + b^2 + c^2)}')
            echo "| 1e$e | $lr | $ld | $1 | $4 | $d | $6 | $7 | $5 | $st |"
        else
            echo "| 1e$e | $lr | $ld | - | - | - | - | - | 0 | $st: $(head -c 120 "$tmp/err") |"
        fi
    done
    echo
done
