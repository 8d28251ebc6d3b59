#!/bin/sh
# test_poses_run.sh - `smoothfold run` with solver.formulation = "poses":
# strip3 (a tree) and square4 (exact closure, flat start), solved to
# 1e-12, write the same probes and fold angles as with "folds", row by row;
# every file the fold run writes is written; the pose formulation with the
# paper's penalty, and with a trajectory, stops with a one-line error that
# names the study (or the --set that chose the formulation); the 2x2
# Miura under gravity and a tip load starts at the flat state directly
# (analysis.flat_start = "direct") and follows 20 steps with every fold's
# six rows closed to the Newton tolerance (1e-10) and the corner moving
# down; square4 with the sparse stability analysis (ARPACK on MUMPS, the
# pose blocks handed over as CSC) gives the stability and Morse index of
# the fold formulation at every point.  Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..6"
n=1
for study in strip3 square4; do
    ok=1
    for f in folds poses; do
        if ! "$bin" run "$src/studies/$study.cfg" --set solver.formulation=\"$f\" --set output.shapes=2 --set solver.tolerance=1e-12 \
                -o "$tmp/$study-$f" -q >"$tmp/log" 2>&1; then
            echo "not ok $n - $study: run with $f failed: $(cat "$tmp/log")"; ok=0
        fi
    done
    if [ $ok = 1 ]; then
        a=$(cd "$tmp/$study-folds" && find . -type f | sort | tr '\n' ' ')
        b=$(cd "$tmp/$study-poses" && find . -type f | sort | tr '\n' ' ')
        # row by row (the two starts' first points, and so the steps after
        # them, agree to round-off, not digit for digit): the same p to 1e-9,
        # and the probes and fold angles to 1e-9 relative once the fold
        # run's values are carried to the pose run's p along the fold run's
        # chord from its previous row
        msg=$(awk -F'\t' '
            /^#/ { next }
            $1 == "point" { for (i = 1; i <= NF; i++) { if ($i ~ /^probe/ || $i ~ /^theta/) c[i] = 1; if ($i == "p") pc = i }; next }
            FNR == NR { v[++na] = $0; next }
            { nb++; if (!(nb in v)) next; split(v[nb], o, "\t"); dp = $pc - o[pc]; adp = dp < 0 ? -dp : dp
              if (adp > 1e-9) { bad++; next }
              k++; np = split(v[nb > 1 ? nb - 1 : nb], q, "\t"); h = o[pc] - q[pc]
              for (i in c) { a = o[i]; if (h != 0) a += (o[i] - q[i]) / h * dp
                             d = a - $i; if (d < 0) d = -d; s = o[i] < 0 ? -o[i] : o[i]; if (s < 1e-6) s = 1e-6
                             if (d / s > w) w = d / s } }
            END { printf "%d common points, largest relative difference %.2g", k, w
                  if (na != nb) printf ", %d and %d rows", na, nb
                  if (bad) printf ", %d rows at another p", bad
                  if (k < 3 || w > 1e-9 || na != nb || bad) print " FAIL" }' \
            "$tmp/$study-folds/branch.tsv" "$tmp/$study-poses/branch.tsv")
        if [ "$a" != "$b" ]; then echo "not ok $n - $study: files differ: [$a] vs [$b]"
        else case "$msg" in
            *FAIL) echo "not ok $n - $study: $msg" ;;
            *) echo "ok $n - $study: folds and poses: $msg" ;;
        esac; fi
    fi
    n=$((n + 1))
done
refused() {
    name=$1; cfg=$2; shift 2
    out=$("$bin" run "$cfg" --set solver.formulation=\"poses\" "$@" -o "$tmp/$name" -q 2>&1); rc=$?
    lines=$(printf '%s\n' "$out" | wc -l)
    case "$out" in
        *"$cfg"*"formulation"*|*"--set solver.formulation"*"formulation"*) good=1 ;;
        *) good=0 ;;
    esac
    if [ $rc -ne 0 ] && [ $rc -lt 128 ] && [ "$lines" -eq 1 ] && [ $good = 1 ] && [ ! -e "$tmp/$name/branch.tsv" ]; then
        echo "ok $n - poses with $name: refused: $out"
    else
        echo "not ok $n - poses with $name: status $rc, output: $out"
    fi
    n=$((n + 1))
}
refused penalty "$src/studies/waterbomb2.cfg" --set solver.constraints=\"penalty\"
refused dynamics "$src/studies/snap1-dynamics.cfg"
out=$("$bin" run "$src/tests/studies/miura2.cfg" --set solver.formulation=\"poses\" \
      --set analysis.flat_start=\"direct\" --set analysis.stability=false --set analysis.max_steps=20 \
      -o "$tmp/miura2" -q 2>&1); rc=$?
# max_steps = 20 ends the path inside its range: status 7 and a
# "# STOPPED EARLY" line (docs/reference/output-files.md), the rows are complete
if [ $rc -ne 7 ] || ! grep -q "^# STOPPED EARLY: analysis.max_steps = 20" "$tmp/miura2/branch.tsv"; then
    echo "not ok $n - miura2 poses, direct flat start: status $rc: $out"
else
    msg=$(grep -v '^#' "$tmp/miura2/branch.tsv" | awk -F'\t' '
        NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "residual") r = i; if ($i == "probe1_uz") u = i; if ($i == "p") pc = i }; next }
        { k++; if ($r > m) m = $r; if (k > 1 && $u >= prev) bad++; prev = $u; p = $pc }
        END { printf "%d points to p = %.3g, largest residual %.2g, uz %.3g m", k, p, m, prev
              if (k < 20 || m > 1e-10 || bad || prev >= 0) print " FAIL" }')
    case "$msg" in
        *FAIL) echo "not ok $n - miura2 poses, direct flat start: $msg" ;;
        *) echo "ok $n - miura2 poses, direct flat start: $msg" ;;
    esac
fi
n=$((n + 1))
for f in folds poses; do
    "$bin" run "$src/studies/square4.cfg" --set solver.formulation=\"$f\" --set analysis.eigensolver=\"arpack\" \
        --set output.shapes=0 -o "$tmp/s4a-$f" -q >"$tmp/log" 2>&1 || echo "run $f: $(cat "$tmp/log")" >> "$tmp/s4a-err"
done
if [ -f "$tmp/s4a-err" ]; then
    echo "not ok $n - square4 sparse stability: $(cat "$tmp/s4a-err")"
else
    col() { grep -v '^#' "$1" | awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "stable") a = i; if ($i == "morse") b = i }; next } { print $a "/" $b }' | sort | uniq -c | tr -s ' \n' '  '; }
    a=$(col "$tmp/s4a-folds/branch.tsv"); b=$(col "$tmp/s4a-poses/branch.tsv")
    arp=$(grep -c '^# stability: 0 points by the dense LAPACK method' "$tmp/s4a-poses/branch.tsv")
    if [ "$a" = "$b" ] && [ "$arp" = 1 ]; then echo "ok $n - square4 sparse stability: stable/morse counts $b in both"
    else echo "not ok $n - square4 sparse stability: folds [$a] poses [$b] (ARPACK only: $arp)"; fi
fi
