#!/bin/sh
# bench/peers/merlin2_bending.sh MERLIN2DIR [BUILDDIR] - smoothfold's
# bending faces against MERLIN2 (K. Liu, G. H. Paulino, bar and hinge,
# MATLAB code run under GNU Octave) on the square twist and the 4-ring
# hypar folded by actuation.  Not part of make check; fetches nothing.
# How to get MERLIN2 and Octave: see bench/peers/merlin2.sh.
#
# For each pattern (`smoothfold pattern twist`, `smoothfold pattern hypar
# --modes=2`: the generators of studies/twist.cfg and studies/hypar-4.cfg,
# every crease actuated to +-1 rad, faces of E = 2 GPa that bend) and each
# fraction f in FRACTIONS (default "1 0.25 0.0625") of the generator's
# band width w0: the pattern with width f w0 and its setbacks, the fold
# material's E times f (so the creases' stiffness D L / w stays about the
# same), run by smoothfold to p = 1 (exact closure); then the same sheet on
# MERLIN2 (bench/peers/merlin2_actuation.m): smoothfold's triangles as
# MERLIN2's panels, each crease and facet hinge with smoothfold's total
# stiffness, the same fixed triangle, the rest angles raised in as many
# equal increments as smoothfold made points, each solved by Newton on
# MERLIN2's forces and tangent stiffness (GlobalK_fast_ver).
# Prints a markdown table of the final states (bench/peers/merlin2_sheet.py
# compare): the largest crease angle, the largest differences of crease
# angles, the creases that the codes fold in opposite senses, the largest
# difference of facet angles, the largest difference of vertex positions relative to
# the largest vertex displacement, each code's largest vertex |uz|, and
# MERLIN2's largest bar strain (its panels stretch, smoothfold's do not).
# Environment: BAR_EA (MERLIN2's bar stiffness EA, default 1e8 N), FRACTIONS, PATTERNS (default "twist hypar miura": miura is
# `pattern miura` (2x2 cells) with bending faces of E = 2 GPa, nu = 0.3, the
# sheet of studies/miura-2x2-bending.cfg).
m2dir=${1:?usage: merlin2_bending.sh MERLIN2DIR [BUILDDIR]}
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
build=${2:-$src}
bin=$build/src/smoothfold
fractions=${FRACTIONS:-1 0.25 0.0625}
patterns=${PATTERNS:-twist hypar miura}
[ -f "$m2dir/PathAnalysis.m" ] || { echo "merlin2_bending.sh: no PathAnalysis.m in $m2dir (see bench/peers/merlin2.sh)" >&2; exit 2; }
command -v octave-cli > /dev/null || { echo "merlin2_bending.sh: octave-cli not found (apt-get install octave)" >&2; exit 2; }
[ -x "$bin" ] || { echo "merlin2_bending.sh: no $bin (build first, or give BUILDDIR)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| pattern | width [mm] | smoothfold points (exit) | MERLIN2 increments (Newton) | largest crease angle [deg] | largest crease difference [deg] | creases folded in opposite senses | largest facet difference [deg] | position difference / displacement | max vertex abs(uz) smoothfold, MERLIN2 [mm] | MERLIN2 bar strain | CPU smoothfold, MERLIN2 [s] |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for pat in $patterns; do
    case $pat in
        twist) gen="twist" ;;
        hypar) gen="hypar --modes=2" ;;
        miura) gen="miura --set faces.bending=true --set materials.face.E=2e9 --set materials.face.nu=0.3" ;;
        *) echo "merlin2_bending.sh: unknown pattern $pat (twist, hypar, miura)" >&2; exit 2 ;;
    esac
    $bin pattern $gen -o "$tmp/$pat.cfg" > /dev/null || exit 1
    w0=$(sed -n 's/^ *width = \([0-9.e+-]*\);.*/\1/p' "$tmp/$pat.cfg" | head -1)
    e0=$(sed -n 's/^ *fold = {.* E = \([0-9.e+-]*\);.*/\1/p' "$tmp/$pat.cfg" | head -1)
    for f in $fractions; do
        t=$tmp/$pat-$f
        w=$(awk -v a="$w0" -v f="$f" 'BEGIN { printf "%.6g", a * f }')
        e=$(awk -v a="$e0" -v f="$f" 'BEGIN { printf "%.6g", a * f }')
        $bin pattern $gen --width="$w" -o "$t.cfg" > /dev/null || exit 1
        /usr/bin/time -f "%U %S" -o "$t.time" "$bin" run "$t.cfg" -q -o "$t.out" \
            --set materials.fold.E="$e" > "$t.log" 2>&1
        rc=$?
        cpu=$(tail -1 "$t.time" | awk '{ printf "%.2f", $1 + $2 }')
        pts=$(grep -v '^#' "$t.out/branch.tsv" | awk 'END { print NR - 2 }')
        pend=$(grep -v '^#' "$t.out/branch.tsv" | awk -F'\t' 'NR == 1 { for (k = 1; k <= NF; k++) if ($k == "p") c = k; next } { p = $c } END { print p }')
        mm=$(awk -v w="$w" 'BEGIN { printf "%.3g", w * 1e3 }')
        if [ ! -s "$t.out/folded.fold" ]; then
            echo "| $pat | $mm | failed (exit $rc): $(tail -1 "$t.log") | | | | | | | | | $cpu |"
            continue
        fi
        $bin export "$t.out/study.cfg" -o "$t.fold" > /dev/null &&
            python3 "$here/merlin2_sheet.py" data "$t.out/study.cfg" "$t.fold" > "$t.m" || exit 1
        /usr/bin/time -f "%U %S" -o "$t.otime" octave-cli --no-gui -q --eval \
            "EA = ${BAR_EA:-1e8}; MERLIN2DIR = '$m2dir'; DATA = '$t.m'; NINC = $pts; PEND = $pend; OUT = '$t.res'; source('$here/merlin2_actuation.m');" \
            > "$t.olog" 2>&1
        ocpu=$(tail -1 "$t.otime" | awk '{ printf "%.2f", $1 + $2 }')
        if ! grep -q '^MERLIN2 ' "$t.res" 2> /dev/null; then
            echo "| $pat | $mm | $pts ($rc) | failed: $(grep -v 'ignoring const' "$t.olog" | tail -1) | | | | | | | | $cpu, $ocpu |"
            continue
        fi
        set -- $(python3 "$here/merlin2_sheet.py" compare "$t.m" "$t.out/folded.fold" "$t.res")
        if [ $# -lt 12 ]; then
            echo "| $pat | $mm | $pts ($rc) | MERLIN2 stopped before p = $pend: $(tail -1 "$t.res") | | | | | | | | $cpu, $ocpu |"
            continue
        fi
        echo "| $pat | $mm | $pts ($rc) | $8 ($9) | $2 | $3 | ${12} | $4 | $5 | $(awk -v a="$6" -v b="$7" 'BEGIN { printf "%.4g, %.4g", a * 1e3, b * 1e3 }') | ${10} | $cpu, $ocpu |"
    done
done
