#!/bin/sh
# bench/start-cost.sh BUILDDIR - CPU time of the start (reading, set-up and
# the start up to the path's first point; stats.csv line 2) with the limit
# start and with the start by the method of multipliers
# (analysis.flat_start = "multipliers", docs/design/start.md) on the paper's
# studies, stability off.  Prints a tab-separated table.
b=${1:-.}/src/smoothfold
src=$(dirname "$0")/..
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cpu() { sed -n 2p "$1/stats.csv" | sed 's/.*start \([0-9.]*\) s.*/\1/'; }
printf 'study\tlimit start (s)\tmultipliers start (s)\n'
for st in square4 square4-irregular square4-corner square4-inplane miura-2x2 waterbomb-2x2 \
          waterbomb2 yoshimura-2x2 hard-near-pi hard-stiff-ratio hard-tiny-width; do
    "$b" run "$src/studies/$st.cfg" -q -o "$tmp/l" --set output.shapes=0 --set analysis.stability=false \
        --set 'analysis.flat_start="limit"' >/dev/null 2>&1
    "$b" run "$src/studies/$st.cfg" -q -o "$tmp/m" --set output.shapes=0 --set analysis.stability=false \
        --set 'analysis.flat_start="multipliers"' >/dev/null 2>&1
    printf '%s\t%s\t%s\n' "$st" "$(cpu "$tmp/l")" "$(cpu "$tmp/m")"
done
