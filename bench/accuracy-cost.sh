#!/bin/sh
# bench/accuracy-cost.sh - what each digit of accuracy costs in time.
# For fold1, strip3 and square4 (CASES.md), vary one knob at a time from a
# base setting and measure the error against the best available reference
# and the wall time of `smoothfold run`:
#   K           shape modes per fold (defaults.modes)
#   quadrature  Gauss points across a fold (solver.quadrature)
#   step        continuation step length (analysis.step = analysis.max_step)
#   tolerance   Newton corrector tolerance (solver.tolerance)
#   linear      dense LU or sparse LU (KLU) (solver.linear_solver)
# References: fold1 the exact elastica (../shared/data); strip3 a converged
# run (K = 8, tolerance 1e-12) and the 3-D shell finite elements
# (../shared/data); square4 a converged run (K = 8, tolerance 1e-12).
# Error: the largest relative error over the reference loads of the
# reported displacement (fold1, strip3: tip uz; square4: uy and uz of the
# report point), with the equilibrium solved at each reference load; for the
# step knob the path is judged as computed instead (values interpolated
# between its points, references[].solve = false), since a solve at the
# reference load would hide the step.  Time: wall time of a whole
# `smoothfold run` process (start-up and output included; shapes, stability
# analysis and comparison off: they are not what the knobs trade), the best of N runs (the machine is shared: the minimum is
# the least disturbed); the table adds the path's own solver time (sum of
# stats.csv wall_s, also best of N).
# Writes docs/guides/accuracy-cost.md (tables) and docs/img/accuracy-cost.png
# (gnuplot, log-log).  Not part of make check; takes about two minutes.
# On a machine shared with other jobs, differences of a few ms between fold1
# or strip3 settings are noise.
# usage: bench/accuracy-cost.sh [BUILDDIR] [N]
set -e
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src}
n=${2:-5}
bin=$build/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$src/docs/img"
data=$tmp/data
mkdir -p "$data"

# converged references at fixed loads (tests/regress/sample.sh: solved at p)
"$src/tests/regress/sample.sh" "$bin" "$src/studies/strip3.cfg" "$tmp/strip3-K8.csv" "converged reference for bench/accuracy-cost.sh" \
    --set defaults.modes=8 --set solver.tolerance=1e-12
"$src/tests/regress/sample.sh" "$bin" "$src/studies/square4.cfg" "$tmp/square4-K8.csv" "converged reference for bench/accuracy-cost.sh" \
    --set defaults.modes=8 --set solver.tolerance=1e-12

refset() {  # case solve -> --set value of the references
    case $1 in
    fold1) echo "references=( { name = \"ref\"; file = \"fold1_elastica.csv\"; solve = $2; abscissa = { column = \"load_factor\"; }; columns = ( { column = \"probe1_uz\"; measure = \"relative\"; } ); } )";;
    strip3) echo "references=( { name = \"ref\"; file = \"$tmp/strip3-K8.csv\"; solve = $2; abscissa = { column = \"p\"; }; columns = ( { column = \"probe1_uz\"; measure = \"relative\"; } ); }, { name = \"shell\"; file = \"strip3_fe_shell.csv\"; solve = $2; abscissa = { column = \"load_factor\"; }; columns = ( { column = \"probe1_uz\"; measure = \"relative\"; } ); } )";;
    square4) echo "references=( { name = \"ref\"; file = \"$tmp/square4-K8.csv\"; solve = $2; abscissa = { column = \"p\"; }; columns = ( { column = \"probe1_uy\"; measure = \"relative\"; }, { column = \"probe1_uz\"; measure = \"relative\"; } ); } )";;
    esac
}
maxerr() {  # compare.tsv reference -> largest "max" of its columns
    awk -F'\t' -v r="$2" '/^#/ { next } $1 == "reference" { for (k = 1; k <= NF; k++) h[$k] = k; next }
        $h["reference"] == r { if ($h["max"] > m) m = $h["max"]; f = 1 } END { if (f) printf "%.3e", (m > 1e-16 ? m : 1e-16); else print "-" }' "$1/compare.tsv"
}

# measure CASE KNOB VALUE BASE-SETS... : one configuration
measure() {
    c=$1; knob=$2; val=$3; shift 3
    study=$src/studies/$c.cfg
    solve=true; [ "$knob" = step ] && solve=false
    times=""; ptimes=""; i=0
    while [ $i -lt $n ]; do
        t0=$(date +%s%N)
        if ! "$bin" run "$study" -q -o "$tmp/run" --set output.shapes=0 --set analysis.stability=false --set 'references=()' "$@" >/dev/null 2>"$tmp/err"; then
            echo "  $c $knob=$val: failed: $(cat "$tmp/err")" >&2
            printf '| %s | %s | failed: %s | | | | |%s\n' "$knob" "$val" "$(sed 's/.*: \(cannot start[^(]*\).*/\1/; s/|/ /g' "$tmp/err" | head -1)" "$([ "$c" = strip3 ] && echo " |")" >> "$tmp/$c.md"
            return 0
        fi
        t1=$(date +%s%N)
        times="$times $(( (t1 - t0) / 1000 ))"
        ptimes="$ptimes $(awk -F',' '/^#/ { next } !h { for (k = 1; k <= NF; k++) if ($k == "wall_s") c = k; h = 1; next } { t += $c } END { printf "%d", t * 1e6 }' "$tmp/run/stats.csv")"
        i=$((i + 1))
    done
    us=$(echo $times | tr ' ' '\n' | sort -n | head -1)     # best of n: least disturbed by other load
    pus=$(echo $ptimes | tr ' ' '\n' | sort -n | head -1)
    pts=$(awk -F'\t' '/^#/ || NF == 0 { next } !h { h = 1; next } { k++ } END { print k }' "$tmp/run/branch.tsv")
    newton=$(awk -F'\t' '/^#/ || NF == 0 { next } !h { for (k = 1; k <= NF; k++) if ($k == "newton") c = k; h = 1; next } { t += $c } END { print t }' "$tmp/run/branch.tsv")
    "$bin" run "$study" -q -o "$tmp/cmp" --set output.shapes=0 --set analysis.stability=false "$@" --set "$(refset "$c" $solve)" >/dev/null 2>&1 || true
    e=$(maxerr "$tmp/cmp" ref)
    es=""
    [ "$c" = strip3 ] && es=$(maxerr "$tmp/cmp" shell)
    s=$(awk -v u="$us" 'BEGIN { printf "%.6f", u / 1e6 }')
    ps=$(awk -v u="$pus" 'BEGIN { printf "%.6f", u / 1e6 }')
    echo "$val $e $s ${es:-0} $ps" >> "$data/$c-$knob.dat"
    printf '| %s | %s | %s | %.1f | %.1f | %s | %s |%s\n' "$knob" "$val" "$e" "$(awk -v u="$us" 'BEGIN { print u / 1000 }')" \
        "$(awk -v u="$pus" 'BEGIN { print u / 1000 }')" "$pts" "$newton" \
        "$([ "$c" = strip3 ] && echo " $es |")" >> "$tmp/$c.md"
    echo "  $c $knob=$val: error $e${es:+ (shell $es)}, $(awk -v u="$us" 'BEGIN { print u / 1000 }') ms, $pts points, $newton Newton" >&2
}

# knobs CASE BASE-K K-VALUES
knobs() {
    c=$1; kb=$2; kvals=$3
    for K in $kvals; do measure "$c" K "$K" --set defaults.modes=$K; done
    for Q in 2 3 4 6 8 12 24; do measure "$c" quadrature "$Q" --set defaults.modes=$kb --set solver.quadrature=$Q; done
    for h in 0.4 0.2 0.1 0.05 0.025 0.0125; do measure "$c" step "$h" --set defaults.modes=$kb --set analysis.step=$h --set analysis.max_step=$h; done
    for t in 1e-4 1e-6 1e-8 1e-10 1e-12; do measure "$c" tolerance "$t" --set defaults.modes=$kb --set solver.tolerance=$t; done
    for l in dense sparse; do measure "$c" linear "$l" --set defaults.modes=$kb --set "solver.linear_solver=\"$l\""; done
}
knobs fold1 6 "0 1 2 3 4 5 6 7 8"
knobs strip3 4 "0 1 2 3 4 5 6"
knobs square4 4 "1 2 3 4 5 6"

version=$("$bin" --version | head -1)
host=$(uname -srm)
cpu=$(awk -F': ' '/model name/ { print $2; exit }' /proc/cpuinfo 2>/dev/null)
out=$src/docs/guides/accuracy-cost.md
{
    echo "# Accuracy against cost"
    echo
    echo "Written by \`bench/accuracy-cost.sh\` ($version; $host${cpu:+, $cpu}; best of $n runs)."
    echo "Do not edit by hand: rerun the script. Conclusions: [accuracy.md](accuracy.md)."
    echo
    echo "![error against wall time, one curve per knob](../img/accuracy-cost.png)"
    echo
    echo "Each knob is varied alone from a base setting (fold1: K = 6; strip3: K = 4;"
    echo "square4: K = 4; otherwise the study's own settings: 24 Gauss points, its"
    echo "continuation step, Newton tolerance 1e-10, dense LU); the K rows vary K from"
    echo "the study's settings. **error**: largest relative error over the reference"
    echo "loads of the reported displacement (fold1, strip3: tip uz; square4: uy and uz"
    echo "of the report point), the equilibrium solved at each reference load; for the"
    echo "**step** rows the path as computed, interpolated between its points."
    echo "References: fold1 the exact elastica; strip3 and square4 a converged run"
    echo "(K = 8, Newton tolerance 1e-12, at 7 loads of the path and its end); strip3"
    echo "also the 3-D shell finite elements (column *vs shell FE*). **time**: wall"
    echo "time of the whole \`smoothfold run\` process (start-up, path, output; shapes"
    echo "and the stability analysis off), best of $n runs; **path**: the continuation's own time (stats.csv). For scale: the strip3 shell FE reference took 391 s, the 2-D plane-strain"
    echo "FE 220 s (one core, CalculiX; ../shared/data/README.md), the paper's MATLAB code"
    echo "7.2 s for the strip3 path (Octave)."
    for c in fold1 strip3 square4; do
        echo
        echo "## $c"
        echo
        if [ $c = strip3 ]; then
            echo "| knob | setting | error | time [ms] | path [ms] | points | Newton iterations | vs shell FE |"
            echo "|---|---|---|---|---|---|---|---|"
        else
            echo "| knob | setting | error | time [ms] | path [ms] | points | Newton iterations |"
            echo "|---|---|---|---|---|---|---|"
        fi
        cat "$tmp/$c.md"
    done
} > "$out.tmp"
mv "$out.tmp" "$out"

# the plot
cat > "$tmp/plot.gp" <<GP
set terminal pngcairo size 1500,1000 enhanced font ",10"
set output "$src/docs/img/accuracy-cost.png.tmp"
set multiplot layout 2,3 title "smoothfold: error against time, one knob varied at a time ($version)"
set logscale xy
set format y "10^{%L}"
set format x "10^{%L}"
set grid
set ylabel "max relative error"
set key top right font ",9" spacing 0.9
f(c, k) = "$data/" . c . "-" . k . ".dat"
do for [row = 1:2] {
  col = (row == 1 ? 3 : 5)
  if (row == 1) { set xrange [1e-3:2e3]; set xlabel "wall time of the whole smoothfold run [s]" }
  if (row == 2) { set xrange [1e-5:2e3]; set xlabel "time of the path alone (continuation, stats.csv) [s]" }
  do for [c in "fold1 strip3 square4"] {
    ttl = c . (c eq "fold1" ? " (vs exact elastica)" : " (vs converged K = 8 run)") . (row == 1 ? "" : ": path time")
    set title ttl
    unset arrow; unset label
    set arrow 1 from 391, graph 0 to 391, graph 1 nohead dt 2 lw 1.5 lc rgb "#555555"
    set label 1 "3-D shell FE\nof strip3\n391 s" at 391, graph 0.45 right offset -0.5,0 font ",8"
    if (c eq "strip3") {
      set arrow 2 from 220, graph 0 to 220, graph 1 nohead dt 3 lw 1.2 lc rgb "#555555"
      set label 2 "plane-strain\nFE 220 s" at 220, graph 0.25 right offset -0.5,0 font ",8"
      set arrow 3 from 7.2, graph 0 to 7.2, graph 1 nohead dt 3 lw 1.2 lc rgb "#999999"
      set label 3 "paper's code\n7.2 s" at 7.2, graph 0.45 right offset -0.5,0 font ",8"
      plot f(c, "K") u col:2 w lp lw 2 pt 7 t "K (shape modes)", \
           f(c, "K") u col:2:1 w labels offset 0.9,0.6 font ",8" notitle, \
           f(c, "quadrature") u col:2 w lp lw 1.5 pt 5 t "quadrature order", \
           f(c, "step") u col:2 w lp lw 1.5 pt 9 t "step length (path as sampled)", \
           f(c, "tolerance") u col:2 w lp lw 1.5 pt 11 t "Newton tolerance", \
           f(c, "linear") u col:2 w p pt 13 ps 1.5 t "dense / sparse LU", \
           f(c, "K") u col:4 w lp dt 2 lw 1.5 pt 6 t "K, error vs 3-D shell FE"
    } else {
      plot f(c, "K") u col:2 w lp lw 2 pt 7 t "K (shape modes)", \
           f(c, "K") u col:2:1 w labels offset 0.9,0.6 font ",8" notitle, \
           f(c, "quadrature") u col:2 w lp lw 1.5 pt 5 t "quadrature order", \
           f(c, "step") u col:2 w lp lw 1.5 pt 9 t "step length (path as sampled)", \
           f(c, "tolerance") u col:2 w lp lw 1.5 pt 11 t "Newton tolerance", \
           f(c, "linear") u col:2 w p pt 13 ps 1.5 t "dense / sparse LU"
    }
  }
}
unset multiplot
GP
gnuplot "$tmp/plot.gp"
mv "$src/docs/img/accuracy-cost.png.tmp" "$src/docs/img/accuracy-cost.png"
echo "docs/guides/accuracy-cost.md, docs/img/accuracy-cost.png written"
