#!/bin/sh
# bench/peers/merlin2.sh MERLIN2DIR [BUILDDIR] - smoothfold against MERLIN2
# (K. Liu, G. H. Paulino, bar-and-hinge model, MATLAB code run under GNU
# Octave) on the same Miura-ori sheets and load path.  Not part of make
# check; fetches nothing.
#
# MERLIN2 is not shipped with smoothfold (its licence is its authors'):
# get its MATLAB sources (MERLIN2 v1.1: PathAnalysis.m, PrepareData.m,
# GlobalK_fast_ver.m, ... in one folder) from its authors, or from a public
# copy such as the MERLIN2_v1.1/MERLIN2_v1.1 folder of the GitHub
# repository alejaboterob/origami, and give that folder as MERLIN2DIR.
# Octave: apt-get install octave.
#
# For each m in SIZES (default "2 4 8"): the study of `bench/miura-study.sh
# m load 1` (gravity and a tip load, p = load factor, exact loop closure,
# K = 1, stability on, the large-sheet defaults) run by smoothfold to the
# end of its path or where it stops (p reached); then the same sheet,
# supports and loads on MERLIN2's N4B5 model (bench/peers/merlin2_miura.m:
# the geometry, materials and load mapping are described there), loaded
# in as many equal increments of the load factor as smoothfold made
# points, to the p smoothfold reached, each solved by Newton on MERLIN2's
# internal forces and tangent stiffness (its GlobalK_fast_ver) to
# MERLIN2's tolerance.  So both follow the same load range in the same
# number of increments.
# Prints a markdown table: points (= increments), p reached, Newton
# iterations, the probe's (far corner's) uz at the end, CPU seconds
# (smoothfold: the whole process, user + system, and its path alone
# (stats.csv); MERLIN2: Octave's cputime of the increments alone, and the
# whole Octave process), and the ratios MERLIN2 / smoothfold per path
# (MERLIN2's increments against smoothfold's whole run) and per increment
# (MERLIN2's per increment against smoothfold's path per point: the
# points after its start).
# Environment: SIZES, TIMEOUT (per run, default 1200 s).
m2dir=${1:?usage: merlin2.sh MERLIN2DIR [BUILDDIR]}
src=$(cd "$(dirname "$0")/../.." && pwd)
build=${2:-$src}
bin=$build/src/smoothfold
sizes=${SIZES:-2 4 8}
tmo=${TIMEOUT:-1200}
[ -f "$m2dir/PathAnalysis.m" ] || { echo "merlin2.sh: no PathAnalysis.m in $m2dir (see the comment at the top)" >&2; exit 2; }
command -v octave-cli > /dev/null || { echo "merlin2.sh: octave-cli not found (apt-get install octave)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| m | code | increments | p reached | Newton | corner uz [m] | CPU path [s] | CPU process [s] | ratio per path | ratio per increment |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for m in $sizes; do
    t=$tmp/m$m
    sh "$src/bench/miura-study.sh" "$m" load 1 > "$t.cfg"
    /usr/bin/time -f "%U %S" -o "$t.time" timeout "$tmo" "$bin" run "$t.cfg" -q -o "$t.out" > "$t.log" 2>&1
    rc=$?
    cpu=$(tail -1 "$t.time" | awk "{ printf \"%.2f\", \$1 + \$2 }")
    rows=$(grep -v '^#' "$t.out/branch.tsv" | awk -F'\t' 'NR == 1 { for (k = 1; k <= NF; k++) h[$k] = k; next }
           { n++; p = $h["p"]; u = $h["probe1_uz"]; it += $h["newton"] } END { printf "%d %s %s %d", n - 1, p, u, it }')
    set -- $rows
    pts=$1 pend=$2 uz=$3 newt=$4
    tpath=$(sed -n 's/^# CPU time: .*, path \([0-9.]*\) s.*/\1/p' "$t.out/stats.csv")
    [ $rc -ne 0 ] && pend="$pend (exit $rc)"
    echo "| $m | smoothfold | $pts | $pend | $newt | $uz | $tpath | $cpu | | |"
    p=${2%% *}
    /usr/bin/time -f "%U %S" -o "$t.otime" timeout "$tmo" octave-cli --no-gui -q --eval \
        "M = $m; NINC = $pts; PEND = $p; MERLIN2DIR = '$m2dir'; source('$src/bench/peers/merlin2_miura.m');" \
        > "$t.olog" 2>&1
    ocpu=$(tail -1 "$t.otime" | awk "{ printf \"%.2f\", \$1 + \$2 }")
    set -- $(grep '^MERLIN2 ' "$t.olog")
    if [ $# -lt 7 ]; then
        echo "| $m | MERLIN2 | failed: $(tail -1 "$t.olog") | | | | | $ocpu | | |"
        continue
    fi
    echo "$3 $4 $5 $6 $7 $cpu $tpath $pts" | awk -v ocpu="$ocpu" -v m="$m" '{
        printf "| %s | MERLIN2 | %d | %.4g | %d | %.4g | %.2f | %s | %.2f | %.2f |\n", m, $1, $3, $2, $4, $5, ocpu,
               $5 / $6, ($5 / $1) / ($7 / $8) }'
done
