#!/bin/sh
# bench/studies.sh - whole-process wall time of `smoothfold run` for every
# study of CASES.md and the stability studies (median of N runs, shapes off
# so disk I/O is not timed; stability analysis on, as by default; reference
# comparisons off: they add solves at the reference loads), with points
# (all branches) and Newton iterations.  Prints a Markdown table.
# usage: bench/studies.sh [BUILDDIR] [N]      (not part of make check)
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src}
n=${2:-11}
bin=$build/src/smoothfold
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| study | constraints | unknowns | points | Newton iterations | wall time (median of $n) |"
echo "|---|---|---|---|---|---|"
for s in strip3 fold1 waterbomb2 square4 square4-stiff square4-narrow square4-corner square4-irregular \
         fold1-buckle snap1 square4-inplane; do
    cfg=$src/studies/$s.cfg
    times=""
    i=0
    while [ $i -lt $n ]; do
        t0=$(date +%s.%N)
        "$bin" run "$cfg" --set output.shapes=0 --set 'references=()' -o "$out/$s" -q >/dev/null 2>&1 || { echo "| $s | failed | | | | |"; continue 2; }
        t1=$(date +%s.%N)
        times="$times $(awk -v a="$t0" -v b="$t1" 'BEGIN{print b - a}')"
        i=$((i + 1))
    done
    med=$(echo $times | tr ' ' '\n' | sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}')
    pts=$(grep -v '^#' "$out/$s/branch.tsv" | awk -F'\t' 'NF > 3' | tail -n +2 | wc -l)
    newton=$(grep -v '^#' "$out/$s/branch.tsv" | awk -F'\t' 'NR==1{for(i=1;i<=NF;i++) if($i=="newton") c=i; next} {t+=$c} END{print t}')
    cons=$(sed -n 's/^ *constraints *= *"\([a-z]*\)".*/\1/p' "$out/$s/study.cfg" | head -1)
    unk=$("$bin" check "$cfg" | sed -n 's/.*; \([0-9]*\) generalised coordinates.*/\1/p')
    printf '| %s | %s | %s | %s | %s | %.1f ms |\n' "$s" "$cons" "$unk" "$pts" "$newton" "$(awk -v m="$med" 'BEGIN{print m * 1000}')"
done
