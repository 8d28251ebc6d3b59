#!/bin/sh
# test_run_exact.sh - `smoothfold run` with exact loop closure off the flat
# state: waterbomb2 and square4-corner reach the end of their paths with
# the loops closed to round-off; a locked sheet (tests/studies/deg4.cfg: a
# degree-4 vertex with K = 0 and finite widths) stops with exit status 5
# (SF_ELOCKED) and a one-line message naming the vertex; `check` reports
# the mobility.  Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..5"
n=1
for study in waterbomb2 square4-corner; do
    if "$bin" run "$src/studies/$study.cfg" --set solver.constraints=\"exact\" --set output.shapes=0 \
           -o "$tmp/$study" -q >"$tmp/log" 2>&1; then
        msg=$(grep -v '^#' "$tmp/$study/branch.tsv" | awk -F'\t' '
            NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "residual") r = i; if ($i == "type") t = i }; next }
            { if ($r > m) m = $r; last = $t; n++ }
            END { if (m < 1e-12 && last == "EP") printf "ok %d points, largest loop residual %g", n, m;
                  else printf "largest loop residual %g, last point %s", m, last }')
        case "$msg" in
            ok*) echo "ok $n - $study exact: ${msg#ok }" ;;
            *) echo "not ok $n - $study exact: $msg" ;;
        esac
    else
        echo "not ok $n - $study exact: $(cat "$tmp/log")"
    fi
    n=$((n + 1))
done

"$bin" run "$src/tests/studies/deg4.cfg" -o "$tmp/deg4" -q >"$tmp/out" 2>"$tmp/err"; rc=$?
lines=$(wc -l < "$tmp/err")
if [ $rc -eq 5 ] && [ "$lines" -eq 1 ] && grep -q "deg4.cfg: .*leave the sheet no motion .*vertex c (degree 4" "$tmp/err"; then
    echo "ok 3 - deg4 locked: exit status 5, names vertex c"
else
    echo "not ok 3 - deg4: exit status $rc, $lines lines: $(cat "$tmp/err")"
fi
if [ ! -e "$tmp/deg4/branch.tsv" ] && [ ! -e "$tmp/deg4/reactions.tsv" ]; then
    echo "ok 4 - deg4: no result files"
else
    echo "not ok 4 - deg4: result files written for a locked sheet"
fi

out=$("$bin" check "$src/tests/studies/deg4.cfg" 2>&1)
vout=$("$bin" check "$src/tests/studies/deg4.cfg" --verbose 2>&1)
# the summary: the verdict on one line, the locked vertex named in the
# count of locked vertices; --verbose: each vertex's own line
if printf '%s\n' "$out" | grep -q '^mobility (exact loop closure, about the flat sheet): locked' &&
   printf '%s\n' "$out" | grep -q '^  1 locked: c$' &&
   ! printf '%s\n' "$out" | grep -q 'alone:' &&
   printf '%s\n' "$vout" | grep -q '^  vertex c (degree 4, 4 coordinates) alone: locked'; then
    echo "ok 5 - check reports the locked vertex (summary; --verbose: the vertex's own line)"
else
    echo "not ok 5 - check output: $out; --verbose: $vout"
fi
