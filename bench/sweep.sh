#!/bin/sh
# bench/sweep.sh - 200 variants of square4 (fold width 20 values x fold
# modulus 10 values, shapes off), serially and under `mpirun -n 2`: wall
# time of the whole sweep (start-up of mpirun included), variants per
# second, speed-up, and whether the two sweep.tsv agree apart from wall_s.
# Prints a Markdown table.  The machine should be otherwise quiet: the
# speed-up is bounded by the cores actually free.
# usage: bench/sweep.sh [BUILDDIR] [REPEATS]      (not part of make check)
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src}
n=${2:-3}
bin=$build/src/smoothfold
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
if [ "$(id -u)" = 0 ]; then
    OMPI_ALLOW_RUN_AS_ROOT=1; OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    export OMPI_ALLOW_RUN_AS_ROOT OMPI_ALLOW_RUN_AS_ROOT_CONFIRM
fi
vary="--vary defaults.width=0.004:0.008:20 --vary materials.fold.E=1e6:4e6:10 --set output.shapes=0"
untimed() { awk -F'\t' 'BEGIN { OFS = "\t" } /^#/ { print; next } { NF--; print }' "$1"; }
# median wall time of n sweeps with launcher $1 into $out/$2
timed() {
    times=""
    i=0
    while [ $i -lt $n ]; do
        rm -rf "$out/$2"
        t0=$(date +%s.%N)
        $1 "$bin" sweep "$src/studies/square4.cfg" $vary -q -o "$out/$2" >/dev/null 2>"$out/$2.err" \
            || { echo "sweep failed: $(cat "$out/$2.err")" >&2; exit 1; }
        t1=$(date +%s.%N)
        times="$times $(awk -v a="$t0" -v b="$t1" 'BEGIN{print b - a}')"
        i=$((i + 1))
    done
    echo $times | tr ' ' '\n' | sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}'
}
ts=$(timed "" serial)
tm=$(timed "mpirun -n 2" mpi)
untimed "$out/serial/sweep.tsv" >"$out/a"; untimed "$out/mpi/sweep.tsv" >"$out/b"
same=$(cmp -s "$out/a" "$out/b" && echo yes || echo NO)
cpu=$(grep -v '^#' "$out/serial/sweep.tsv" | awk -F'\t' 'NR==1{for(i=1;i<=NF;i++) if($i=="wall_s") c=i; next} {t+=$c} END{printf "%.2f", t}')
failed=$(grep -v '^#' "$out/serial/sweep.tsv" | awk -F'\t' 'NR > 1 && $4 != 0' | wc -l)
echo "| run | variants | failed | wall time (median of $n) | variants/s | speed-up | sweep.tsv as serial |"
echo "|---|---|---|---|---|---|---|"
awk -v t="$ts" -v c="$cpu" -v f="$failed" 'BEGIN{printf "| serial (sum of variant wall times %.2f s) | 200 | %d | %.2f s | %.1f | 1 | - |\n", c, f, t, 200 / t}'
awk -v t="$tm" -v s="$ts" -v f="$failed" -v same="$same" 'BEGIN{printf "| mpirun -n 2 | 200 | %d | %.2f s | %.1f | %.2f | %s |\n", f, t, 200 / t, s / t, same}'
