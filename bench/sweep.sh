#!/bin/sh
# bench/sweep.sh - 200 variants of square4 (fold width 20 values x fold
# modulus 10 values, shapes off), serially and under `mpirun -n 2`: wall
# time of the whole sweep (start-up of mpirun included), CPU time of all
# its processes (user + sys: what the dispatching costs on top of the
# variants), variants per second, speed-up, and whether the two sweep.tsv
# agree apart from wall_s.  Serial and MPI sweeps alternate, so both see
# the same background; the load average is printed with the table.  The
# speed-up is bounded by the cores actually free.  Prints Markdown.
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
# one sweep with launcher $1 into $out/$2; appends "wall cpu" to $out/$2.t
# (cpu: user + sys of every process of the sweep, from /usr/bin/time)
one() {
    rm -rf "$out/$2"
    t0=$(date +%s.%N)
    /usr/bin/time -f "%U %S" -o "$out/$2.cpu" $1 "$bin" sweep "$src/studies/square4.cfg" $vary -q -o "$out/$2" \
        >/dev/null 2>"$out/$2.err" || { echo "sweep failed: $(cat "$out/$2.err")" >&2; exit 1; }
    t1=$(date +%s.%N)
    awk -v a="$t0" -v b="$t1" '{print b - a, $1 + $2}' "$out/$2.cpu" >>"$out/$2.t"
}
med() { sort -g -k"$2" "$1" | awk -v k="$2" '{a[NR]=$k} END{print a[int((NR+1)/2)]}'; }
load0=$(cut -d' ' -f1-3 /proc/loadavg)
i=0
while [ $i -lt $n ]; do   # alternating, so that both see the same background
    one "" serial
    one "mpirun -n 2" mpi
    i=$((i + 1))
done
load1=$(cut -d' ' -f1-3 /proc/loadavg)
ts=$(med "$out/serial.t" 1); cs=$(med "$out/serial.t" 2)
tm=$(med "$out/mpi.t" 1); cm=$(med "$out/mpi.t" 2)
untimed "$out/serial/sweep.tsv" >"$out/a"; untimed "$out/mpi/sweep.tsv" >"$out/b"
same=$(cmp -s "$out/a" "$out/b" && echo yes || echo NO)
failed=$(grep -v '^#' "$out/serial/sweep.tsv" | awk -F'\t' 'NR > 1 && $4 != 0' | wc -l)
echo "load average (1, 5, 15 min) before: $load0, after: $load1; $(nproc) cores"
echo
echo "| run | variants | failed | wall time (median of $n) | CPU time, all processes | variants/s | speed-up | sweep.tsv as serial |"
echo "|---|---|---|---|---|---|---|---|"
awk -v t="$ts" -v c="$cs" -v f="$failed" 'BEGIN{printf "| serial | 200 | %d | %.2f s | %.2f s | %.1f | 1 | - |\n", f, t, c, 200 / t}'
awk -v t="$tm" -v c="$cm" -v s="$ts" -v f="$failed" -v same="$same" 'BEGIN{printf "| mpirun -n 2 | 200 | %d | %.2f s | %.2f s | %.1f | %.2f | %s |\n", f, t, c, 200 / t, s / t, same}'
