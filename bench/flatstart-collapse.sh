#!/bin/sh
# flatstart-collapse.sh [BUILDDIR] [M] - the sparse flat start's rule that
# leaves an extra start of the limit problem falling back to the flat state
# (analysis.flat_collapse, docs/flatstart.md "Cost of the sparse start"),
# on the M x M Miura sheet of bench/miura-study.sh (actuation, K = 1;
# default M = 16, the only size of 2..16 where the rule acts: about 100 s
# CPU with the rule, 180 s without, so not part of make check).
#
# Runs the start alone (analysis.max_steps = 1, stability off) with the
# rule (default) and without it (analysis.flat_collapse = 0) and checks
# that the rule changes the cost only: the same followed limit state
# (energy), the same first point (the whole first data row of branch.tsv),
# and, with the rule, the rigid-vertex-mode start listed as left.  Prints
# the flat-start notes, the CPU time (user, /usr/bin/time) of each run and
# PASS or FAIL (exit 1).
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src}
m=${2:-16}
bin=$build/src/smoothfold
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
sh "$src/bench/miura-study.sh" "$m" actuation 1 >"$tmp/m.cfg"
for v in on off; do
    extra=""
    [ $v = off ] && extra="--set analysis.flat_collapse=0"
    # shellcheck disable=SC2086
    OPENBLAS_NUM_THREADS=1 /usr/bin/time -f %U -o "$tmp/$v.time" "$bin" run "$tmp/m.cfg" -q -o "$tmp/$v" \
        --set 'analysis.flat_start="sparse"' --set 'solver.formulation="poses"' \
        --set analysis.max_steps=1 --set analysis.stability=false $extra >"$tmp/$v.out" 2>&1
    echo "rule $v: $(tail -1 "$tmp/$v.time") s CPU"
    grep '^# flat start (sparse)' "$tmp/$v/branch.tsv"
done
row() { awk -F'\t' '/^#/ || $1 == "point" {next} $4 > 0 {print; exit}' "$1"; }
energy() { sed -n 's/^# flat start (sparse):.* \(equal\|limit\) energy \([-0-9.e]*\).*/\2/p' "$1"; }
e1=$(energy "$tmp/on/branch.tsv"); e2=$(energy "$tmp/off/branch.tsv")
if [ -n "$e1" ] && [ "$e1" = "$e2" ] && [ -n "$(row "$tmp/on/branch.tsv")" ] &&
   [ "$(row "$tmp/on/branch.tsv")" = "$(row "$tmp/off/branch.tsv")" ]; then
    if grep -q 'rigid vertex modes: left' "$tmp/on/branch.tsv"; then
        echo "PASS: the rule acts (rigid start left) and the followed state ($e1) and first point are unchanged"
    else
        echo "PASS: the same followed state ($e1) and first point; the rule did not act at ${m}x$m"
    fi
else
    echo "FAIL: followed energy '$e1' / '$e2' or first rows differ"
    exit 1
fi
