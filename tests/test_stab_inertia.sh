#!/bin/sh
# test_stab_inertia.sh - stability from the inertia of the KKT matrix
# (analysis.eigensolver = "inertia": one MUMPS LDL^T per point, Morse
# index = negative pivots - rank of the constraint rows) against the
# dense method (explicit tangent basis, all eigenvalues, the Morse index
# counted from them), on the same paths: square4, snap1 and fold1-buckle
# (with unstable stretches) and Miura-ori 2x2 and 3x3 cells under
# actuation (3x3: poses only, for time), in both formulations, Miura 2x2
# with K = 2 in poses with the redundant rows dropped (solver.pose_rows =
# "independent"), and square4-inplane (Morse index up to
# several, fold formulation only: in-plane modes).  The step bound is off
# so that both methods follow the same steps; rows are matched by branch
# and p, located special points left out (their p comes from the
# eigenvalue with dense, from the index with inertia).  `stable` and
# `morse` must be equal at every matched row, except where the dense
# method finds an eigenvalue within 1e-6 (relative to the largest one
# printed) of zero, whose sign is round-off.  Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
sh "$src/bench/miura-study.sh" 2 actuation > "$tmp/miura2a.cfg"
sh "$src/bench/miura-study.sh" 3 actuation > "$tmp/miura3a.cfg"
# K = 2 with the identities among the fold rows dropped (solver.pose_rows =
# "independent", docs/design/model.md)
sh "$src/bench/miura-study.sh" 2 actuation 2 |
    sed 's/^solver = {/solver = { pose_rows = "independent";/' > "$tmp/miura2k2.cfg"
# study formulation max_steps least-rows least-unstable
cases="
$src/studies/square4.cfg folds 30 25 0
$src/studies/square4.cfg poses 30 25 0
$src/studies/snap1.cfg folds 60 25 5
$src/studies/snap1.cfg poses 60 25 5
$src/studies/fold1-buckle.cfg folds 60 25 1
$src/studies/fold1-buckle.cfg poses 60 25 1
$src/studies/square4-inplane.cfg folds 25 100 60
$tmp/miura2a.cfg folds 20 15 0
$tmp/miura2a.cfg poses 20 15 0
$tmp/miura3a.cfg poses 10 8 0
$tmp/miura2k2.cfg poses 20 15 0
"
echo "1..$(printf '%s\n' "$cases" | grep -c .)"
n=0
printf '%s\n' "$cases" | while read -r study form steps least unst; do
    [ -n "$study" ] || continue
    n=$((n + 1))
    name="$(basename "$study" .cfg) ($form)"
    ok=1
    for e in dense inertia; do
        if ! "$bin" run "$study" -o "$tmp/$e" -q --set solver.formulation=\"$form\" \
                --set analysis.eigensolver=\"$e\" --set analysis.step_bound=false \
                --set analysis.max_steps="$steps" --set output.shapes=0 >"$tmp/log" 2>&1 \
           && ! grep -q 'analysis.max_steps' "$tmp/log"; then
            echo "not ok $n - $name: run with $e failed: $(head -c 300 "$tmp/log")"
            ok=0
        fi
    done
    [ $ok = 1 ] || continue
    how=$(grep '^# stability:' "$tmp/inertia/branch.tsv")
    case "$how" in *", 0 by ARPACK, 0 by the MUMPS inertia"*|"") inertia=0 ;; *) inertia=1 ;; esac
    if [ $inertia = 0 ]; then
        echo "not ok $n - $name: the inertia run did not use the inertia method: $how"
        continue
    fi
    msg=$(awk -F'\t' -v least="$least" -v unst="$unst" '
        /^#/ { next }
        $1 == "point" { ne = 0; for (i = 1; i <= NF; i++) { col[$i] = i; if ($i ~ /^eig/) ne++ }; next }
        $col["type"] != "" { next }
        { key = $col["branch"] "|" sprintf("%.10g", $col["p"]) }
        FNR == NR { mo[key] = $col["morse"]; st[key] = $col["stable"]; big = 0; small = 1e300
                    for (k = 1; k <= ne; k++) { e = $col["eig" k]; if (e == "") continue
                        a = e < 0 ? -e : e; if (a > big) big = a; if (a < small) small = a }
                    amb[key] = small <= 1e-6 * big; next }
        !(key in mo) { next }
        amb[key] { skipped++; next }
        { c++; if (mo[key] > 0) u++
          if (mo[key] != $col["morse"] || st[key] != $col["stable"]) {
              nb++; if (nb <= 3) bad = bad sprintf(" [branch|p %s: dense stable %s morse %s, inertia %s %s]",
                                                    key, st[key], mo[key], $col["stable"], $col["morse"]) } }
        END { printf "%d rows compared (%d unstable, %d with an eigenvalue at zero left out)", c, u, skipped
              if (nb) printf ", %d differ:%s FAIL", nb, bad
              else if (c < least || u < unst) printf ", fewer than %d rows or %d unstable FAIL", least, unst }' \
        "$tmp/dense/branch.tsv" "$tmp/inertia/branch.tsv")
    case "$msg" in
        *FAIL) echo "not ok $n - $name: $msg" ;;
        *) echo "ok $n - $name: inertia and dense agree: $msg; ${how#\# }" ;;
    esac
done
