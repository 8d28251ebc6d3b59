#!/bin/sh
# test_validity_public.sh - the physical-validity warnings (issue 34 item 5,
# src/analysis/validity/, docs/reference/output-files.md "Physical
# validity") on a crease pattern nobody here wrote: Rabbit Ear's Resch
# tessellation (tests/public/rabbit-ear/resch-tess.fold), imported and run
# as a user would.  Its default path folds it past itself: at p = 1 a
# mountain fold stands at -211.6 degrees.  Asserted against the run's own
# fold angles, read independently from branch.tsv's theta columns: a row is
# flagged `beyond180` exactly when one of its fold angles exceeds pi in
# magnitude; no row whose folds all stay below 2.5 rad (143 degrees) is
# flagged at all (no false alarm in the ordinary range); the last row is
# flagged both ways (a fold past 180 degrees turns its faces through each
# other); the results are written and the exit status stays 0; stderr ends
# with one warning line naming both.  TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
. "$src/tests/tap.sh"
echo "1..3"

"$bin" import "$src/tests/public/rabbit-ear/resch-tess.fold" -o "$tmp/r.cfg" >/dev/null 2>"$tmp/imp.err"
"$bin" run "$tmp/r.cfg" -q -o "$tmp/o" >"$tmp/run.out" 2>"$tmp/run.err"
st=$?
b="$tmp/o/branch.tsv"
# per row: largest |theta| (rad) and the warning column
awk -F'\t' 'function abs(x) { return x < 0 ? -x : x }
    /^#/ {next}
    !h {for (k = 1; k <= NF; k++) {c[$k] = k; if ($k ~ /^theta[0-9]+$/) th[++nt] = k}; h = 1; next}
    {m = 0; for (j = 1; j <= nt; j++) if (abs($th[j]) > m) m = abs($th[j])
     w = $c["warning"]; if (w == "") w = "-"
     printf "%s %.10g %s\n", $c["point"], m, w}' "$b" >"$tmp/rows" 2>/dev/null
rows=$(wc -l <"$tmp/rows")
pi=3.14159265358979

mism=$(awk -v pi=$pi '{b = index($3, "beyond180") > 0; if ((($2 > pi) ? 1 : 0) != b) n++; if (b) nb++}
                      END {print n + 0, nb + 0}' "$tmp/rows")
if [ $st = 0 ] && [ "$rows" -gt 10 ] && [ "${mism% *}" = 0 ] && [ "${mism#* }" -gt 0 ]; then
    ok "resch-tess: beyond180 flags exactly the rows with a fold angle above pi (${mism#* } of $rows rows)"
else
    nok "resch-tess: exit $st, $rows rows, mismatches and flagged rows: '$mism'"; head -3 "$tmp/run.err" | sed 's/^/#   /'
fi

quiet=$(awk '$2 <= 2.5 {n++; if ($3 != "-") bad++} END {print n + 0, bad + 0}' "$tmp/rows")
if [ "${quiet% *}" -gt 10 ] && [ "${quiet#* }" = 0 ]; then
    ok "resch-tess: none of the ${quiet% *} rows with every fold below 2.5 rad is flagged"
else
    nok "resch-tess: rows below 2.5 rad and those flagged among them: '$quiet'"
fi

last=$(tail -1 "$tmp/rows" | cut -d' ' -f3)
nl=$(grep -c 'warning: physically invalid shapes' "$tmp/run.err")
if [ "$last" = "beyond180,crossing" ] && [ "$nl" = 1 ] &&
   tail -1 "$tmp/run.err" | grep -q 'folds beyond +-180 degrees.*passes through itself' &&
   grep -q '^# warning: ' "$b"; then
    ok "resch-tess: the last row is flagged both ways; one stderr line and branch.tsv's header say so"
else
    nok "resch-tess: last row '$last', $nl warning lines"; tail -2 "$tmp/run.err" | sed 's/^/#   /'
fi
