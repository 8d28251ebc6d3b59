#!/bin/sh
# bench/stability-sparse.sh - cost of the stability analysis on Miura-ori
# sheets (smoothfold pattern miura, K = 1): the same first S points of the
# actuation path with stability off, with the dense LAPACK method and with
# MUMPS + ARPACK (analysis.eigensolver = "arpack").  Penalty loop closure,
# so that the whole coordinate space is free and the eigenvalue problem is
# as large as it gets (with exact closure these paths stay near the flat
# state, where the tangent space is tiny).  Whole-process wall time
# and peak resident memory (GNU time), points, and the stability notes
# (ARPACK retries / unknown points) of branch.tsv.  Prints a Markdown table.
# usage: bench/stability-sparse.sh [BUILDDIR] [S] [CELLS...]   (not part of make check)
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src}
steps=${2:-6}
shift 2 2>/dev/null
cells=${*:-"4x4 6x6"}
bin=$build/src/smoothfold
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| cells | coordinates | loop rows (penalised) | stability | points | wall time [s] | peak RSS [MB] | retried / unknown points |"
echo "|---|---|---|---|---|---|---|---|"
for c in $cells; do
    "$bin" pattern miura --cells="$c" -o "$out/m.cfg" >/dev/null 2>&1 || { echo "| $c | generator failed |"; continue; }
    for m in off dense arpack; do
        case $m in
            off) set -- --set analysis.stability=false ;;
            *) set -- --set "analysis.eigensolver=\"$m\"" ;;
        esac
        set -- "$@" --set 'solver.constraints="penalty"'
        rm -rf "$out/r"
        /usr/bin/time -f "%e %M" -o "$out/time" "$bin" run "$out/m.cfg" -o "$out/r" -q \
            --set analysis.max_steps="$steps" --set output.shapes=0 "$@" >/dev/null 2>"$out/err"
        read -r wall rss < "$out/time"
        pts=$(grep -v '^#' "$out/r/branch.tsv" | tail -n +2 | wc -l)
        nq=$(grep -v '^#' "$out/r/branch.tsv" | head -1 | tr '\t' '\n' | grep -c '^theta')
        # 6 loop rows per interior vertex; (2M - 1)(2N - 1) of them in M x N cells
        nc=$(echo "$c" | awk -Fx '{print 6 * (2 * $1 - 1) * (2 * $2 - 1)}')
        retr=$(grep -c '^# stability at row .*retried' "$out/r/branch.tsv")
        unk=$(grep -c '^# stability at row .*UNKNOWN' "$out/r/branch.tsv")
        echo "| $c | $((2 * nq)) | $nc | $m | $pts | $wall | $((rss / 1024)) | $retr / $unk |"
    done
done
