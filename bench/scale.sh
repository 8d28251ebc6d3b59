#!/bin/sh
# scale.sh [BUILDDIR] - cost of the face-pose formulation on Miura-ori
# sheets of m x m cells (issue 12 item 5).  Not part of make check.
#
# For each m: bench/miura-study.sh m load (gravity and a tip load, K = 1,
# exact closure), run with solver.formulation = "poses", the direct flat
# start, stability off, at most STEPS continuation steps (default 10) and
# TIMEOUT seconds (default 600).  Prints a markdown table: unknowns,
# Jacobian nonzeros (and per fold), points, p reached, Newton iterations,
# wall time, wall time per Newton iteration, peak memory (/usr/bin/time -v),
# exit status; then the fitted exponent of the time per Newton iteration
# against the unknowns (least squares in log-log over the sizes that ran).
# Environment: K (fold modes, default 1), SIZES (default "2 4 8 16 31"), STEPS, TIMEOUT, FORMULATION
# (default poses; "folds" for the fold formulation, with the limit start).
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src}
bin=$build/src/smoothfold
sizes=${SIZES:-2 4 8 16 31}
steps=${STEPS:-10}
tmo=${TIMEOUT:-600}
form=${FORMULATION:-poses}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
start=direct
[ "$form" = folds ] && start=limit
echo "| m | folds | unknowns | nonzeros | nnz/fold | points | p reached | Newton | wall [s] | s/Newton | peak MB | status |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for m in $sizes; do
    "$src/bench/miura-study.sh" "$m" load "${K:-1}" > "$tmp/m$m.cfg"
    /usr/bin/time -v -o "$tmp/time$m" timeout "$tmo" "$bin" run "$tmp/m$m.cfg" -q \
        --set analysis.stability=false --set analysis.max_steps="$steps" \
        --set analysis.flat_start=\""$start"\" --set solver.formulation=\""$form"\" \
        -o "$tmp/out$m" > "$tmp/log$m" 2>&1
    rc=$?
    wall=$(awk -F': ' '/Elapsed \(wall clock\)/ { n = split($2, a, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + a[i]; print s }' "$tmp/time$m")
    mem=$(awk -F': ' '/Maximum resident/ { printf "%.0f", $2 / 1024 }' "$tmp/time$m")
    folds=$(grep -c 'from = ' "$tmp/m$m.cfg")
    if [ -f "$tmp/out$m/branch.tsv" ]; then
        unk=$(sed -n 's/^# formulation: poses, \([0-9]*\) unknowns.*/\1/p' "$tmp/out$m/branch.tsv")
        nnz=$(sed -n 's/.*multipliers), \([0-9]*\) Jacobian nonzeros.*/\1/p' "$tmp/out$m/branch.tsv")
        pts=$(grep -v '^#' "$tmp/out$m/branch.tsv" | awk 'NR > 1' | wc -l)
        pend=$(grep -v '^#' "$tmp/out$m/branch.tsv" | awk -F'\t' 'NR > 1 { p = $4 } END { printf "%.4g", p }')
        newt=$(grep -v '^#' "$tmp/out$m/stats.csv" | awk -F, 'NR > 1 { s += $5 } END { print s + 0 }')
    else
        unk=-; nnz=-; pts=0; pend=-; newt=0
    fi
    [ -z "$unk" ] && unk=-
    [ -z "$nnz" ] && nnz=-
    per=$(awk -v w="$wall" -v n="$newt" 'BEGIN { if (n > 0) printf "%.3g", w / n; else print "-" }')
    npf=$(awk -v z="$nnz" -v f="$folds" 'BEGIN { if (z != "-") printf "%.0f", z / f; else print "-" }')
    st=$rc; [ $rc -eq 124 ] && st="timeout ${tmo} s"
    echo "| $m | $folds | $unk | $nnz | $npf | $pts | $pend | $newt | $wall | $per | $mem | $st |"
    echo "$unk $per" >> "$tmp/fit"
done
awk '$1 != "-" && $2 != "-" && $2 > 0 { x = log($1); y = log($2); n++; sx += x; sy += y; sxx += x * x; sxy += x * y }
     END { if (n >= 2) printf "\nfitted: time per Newton iteration ~ unknowns^%.2f (%d sizes)\n", (n * sxy - sx * sy) / (n * sxx - sx * sx), n;
           else print "\nfitted: fewer than two sizes ran" }' "$tmp/fit"
