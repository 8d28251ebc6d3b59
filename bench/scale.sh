#!/bin/sh
# scale.sh [BUILDDIR] - cost of the face-pose formulation on Miura-ori
# sheets of m x m cells (issue 12 item 5).  Not part of make check.
#
# For each driving and each m: the study of bench/miura-study.sh
#   load       m load K       gravity and a tip load, p = load factor 0..1
#   actuation  m actuation K  rest angles of both groups, p = 0..1 (rest
#                             angles up to 2.6 rad = 149 degrees)
# run with exact closure and the formulation FORMULATION, the flat start
# START and the step norm STEP_NORM (analysis.step_norm; "rms" takes steps
# of the same fold-angle change on every sheet size,
# continuation/README.md).  None of the three given: all three "auto"
# (docs/reference/study-keys.md, "Large sheets": poses, sparse, rms above 300
# unknowns in fold coordinates, folds, limit, sum below, so the 2x2 sheet
# runs in fold coordinates and its unknowns column is "-").  Any given:
# FORMULATION defaults to "poses", START to "direct" ("limit" with folds),
# STEP_NORM to "sum", as before "auto".  Stability on (STAB=1) or off (STAB=0), to the
# end of the path (analysis.max_steps = STEPS, default 100000) within
# TIMEOUT seconds (default 600).  Prints a markdown table: unknowns,
# Jacobian nonzeros, points, p reached, Newton iterations of the accepted
# corrector attempts (stats.csv "newton"), Jacobian evaluations (failed
# attempts included), factorisations of the corrector matrix (stats.csv
# "factorisations": the reusing corrector of the sparse solvers factorises
# about once per point and solves the rest with refinement), step
# retries (failed corrector attempts), wall time, CPU time (user + system,
# /usr/bin/time -v: on a shared machine the wall time also counts the
# waits for a core), its split into the start (reading, set-up and the
# start up to the path's first point: the flat start) and the path after
# it (corrector, stability, output), as the run writes them into
# stats.csv ("# CPU time"), the entries in the factors and the Mflop of
# the corrector's last factorisation (stats.csv, MUMPS's INFOG(29) and
# RINFOG(3)), peak memory (/usr/bin/time -v), exit status (0 = end of the
# path reached); then per driving the fitted exponents of the CPU time and
# of the path's CPU time against the unknowns over the sizes m >= FITFROM
# (default 8) that reached the end of the path.
# Environment: DRIVINGS (default "load actuation"), SIZES (default
# "2 4 8 16 31"), K (fold modes, default 1), STAB, STEPS, TIMEOUT, START,
# FITFROM, STEP_NORM, FORMULATION.
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src}
bin=$build/src/smoothfold
drivings=${DRIVINGS:-load actuation}
sizes=${SIZES:-2 4 8 16 31}
steps=${STEPS:-100000}
tmo=${TIMEOUT:-600}
if [ -n "$FORMULATION$START$STEP_NORM" ]; then
    form=${FORMULATION:-poses}
    start=${START:-direct}
    [ "$form" = folds ] && [ -z "$START" ] && start=limit
    norm=${STEP_NORM:-sum}
else
    form=auto start=auto norm=auto
fi
K=${K:-1}
fitfrom=${FITFROM:-8}
stab=true
[ "${STAB:-1}" = 0 ] && stab=false
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "K = $K, stability $stab, flat start $start, formulation $form, step norm $norm, timeout $tmo s"
echo
echo "| driving | m | folds | unknowns | nonzeros | points | p reached | Newton | Jacobians | factorisations | retries | wall [s] | CPU [s] | start CPU [s] | path CPU [s] | factor entries | Mflop per factorisation | peak MB | status |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for d in $drivings; do
    for m in $sizes; do
        t=$tmp/$d$m
        "$src/bench/miura-study.sh" "$m" "$d" "$K" > "$t.cfg"
        /usr/bin/time -v -o "$t.time" timeout "$tmo" "$bin" run "$t.cfg" -q \
            --set analysis.stability="$stab" --set analysis.max_steps="$steps" \
            --set analysis.flat_start=\""$start"\" --set solver.formulation=\""$form"\" \
            --set analysis.step_norm=\""$norm"\" \
            -o "$t.out" > "$t.log" 2>&1
        rc=$?
        wall=$(awk -F': ' '/Elapsed \(wall clock\)/ { n = split($2, a, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + a[i]; print s }' "$t.time")
        cpu=$(awk -F': ' '/User time/ { u = $2 } /System time/ { s = $2 } END { printf "%.2f", u + s }' "$t.time")
        mem=$(awk -F': ' '/Maximum resident/ { printf "%.0f", $2 / 1024 }' "$t.time")
        folds=$(grep -c 'from = ' "$t.cfg")
        unk=-; nnz=-; pts=0; pend=-; newt=0; jac=0; ret=0; fac=-; tst=-; tpa=-; fent=-; ffl=-
        if [ -f "$t.out/branch.tsv" ]; then
            unk=$(sed -n 's/^# formulation: [a-z]*, \([0-9]*\) unknowns.*/\1/p' "$t.out/branch.tsv")
            nnz=$(sed -n 's/.*multipliers), \([0-9]*\) Jacobian nonzeros.*/\1/p' "$t.out/branch.tsv")
            pts=$(grep -v '^#' "$t.out/branch.tsv" | awk 'NR > 1' | wc -l)
            pend=$(grep -v '^#' "$t.out/branch.tsv" | awk -F'\t' 'NR > 1 { p = $4 } END { printf "%.4g", p }')
            set -- $(grep -v '^#' "$t.out/stats.csv" | awk -F, 'NR == 1 { for (k = 1; k <= NF; k++) c[$k] = k; next }
                { n += $c["newton"]; j += $c["jacobian_evals"]; r += $c["retries"]; if (c["factorisations"]) f += $c["factorisations"] }
                END { print n + 0, j + 0, r + 0, (c["factorisations"] ? f + 0 : "-") }')
            newt=$1; jac=$2; ret=$3; fac=$4
            tst=$(sed -n 's/^# CPU time: start \([0-9.]*\) s.*/\1/p' "$t.out/stats.csv")
            tpa=$(sed -n 's/^# CPU time: .*, path \([0-9.]*\) s.*/\1/p' "$t.out/stats.csv")
            fent=$(sed -n 's/^# corrector.s last factorisation.*, \([0-9]*\) entries.*/\1/p' "$t.out/stats.csv")
            ffl=$(sed -n 's/^# corrector.s last factorisation.* entries in its factors, \([0-9.e+]*\) Mflop.*/\1/p' "$t.out/stats.csv")
        fi
        [ -z "$tst" ] && tst=-
        [ -z "$tpa" ] && tpa=-
        [ -z "$fent" ] && fent=-
        [ -z "$ffl" ] && ffl=-
        [ -z "$unk" ] && unk=-
        [ -z "$nnz" ] && nnz=-
        st=$rc; [ $rc -eq 124 ] && st="timeout ${tmo} s"
        echo "| $d | $m | $folds | $unk | $nnz | $pts | $pend | $newt | $jac | $fac | $ret | $wall | $cpu | $tst | $tpa | $fent | $ffl | $mem | $st |"
        [ $rc -eq 0 ] && [ "$m" -ge "$fitfrom" ] && [ "$unk" != - ] && echo "$d $unk $cpu $tpa" >> "$tmp/fit"
    done
done
echo
for d in $drivings; do
    touch "$tmp/fit"
    for col in 3 4; do
        awk -v d="$d" -v f="$fitfrom" -v c=$col '$1 == d && $c > 0 { x = log($2); y = log($c); n++; sx += x; sy += y; sxx += x * x; sxy += x * y }
             END { w = c == 3 ? "CPU time" : "path CPU time";
                   if (n >= 2) printf "fitted (%s): %s ~ unknowns^%.2f over %d sizes m >= %d\n", d, w, (n * sxy - sx * sy) / (n * sxx - sx * sx), n, f;
                   else printf "fitted (%s): fewer than two sizes m >= %d reached the end of the path\n", d, f }' "$tmp/fit"
    done
done
