#!/bin/sh
# test_compare.sh - the reference-comparison feature of `smoothfold run`
# (study key `references`, src/analysis/compare/compare*.c) through the program:
#   - broken reference files and keys: exit status, one line naming the
#     file (or study key) and line, and no output written;
#   - a declared tolerance exceeded: exit 6, every file written, FAIL in
#     compare.tsv;
#   - a path that is not monotone in the abscissa (snap1, two limit
#     points): rows matched on the right piece, exactly when solved and to
#     the interpolation error when interpolated.
# (The closed-form and elastica comparisons are in test_accuracy.sh.)
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fold1=$src/studies/fold1.cfg
i=0
ok() { i=$((i + 1)); echo "ok $i - $*"; }
notok() { i=$((i + 1)); echo "not ok $i - $*"; }
echo "1..22"

# ref FILE [COLUMN] [QUANTITY]: a references value for --set
ref() {
    echo "references=( { name = \"r\"; file = \"$1\"; abscissa = { column = \"load_factor\"; }; columns = ( { column = \"${2:-probe1_uz}\"; quantity = \"${3:-${2:-probe1_uz}}\"; } ); } )"
}

# bad NAME STATUS WANT SETVALUE: the run must fail with STATUS, one line on
# stderr containing WANT, and create nothing (the output directory absent)
bad() {
    name=$1; want_rc=$2; want=$3; set=$4
    out=$("$bin" run "$fold1" -q -o "$tmp/out-$name" --set "$set" 2>&1 >/dev/null); rc=$?
    lines=$(printf '%s\n' "$out" | wc -l)
    if [ $rc -ne "$want_rc" ]; then notok "$name: exit status $rc, expected $want_rc ($out)"
    elif [ "$lines" -ne 1 ]; then notok "$name: $lines lines on stderr"; printf '%s\n' "$out" | sed 's/^/#   /'
    elif [ -e "$tmp/out-$name" ]; then notok "$name: the output directory was created"
    else
        case "$out" in
            *"$want"*) ok "$name: $out";;
            *) notok "$name"; echo "#   expected: ...$want..."; echo "#   got:      $out";;
        esac
    fi
}
d=$src/tests/compare
bad "no provenance header" 1 "$d/noprov.csv:1: no provenance header: '# source:'" "$(ref "$d/noprov.csv")"
bad "no kind line" 1 "$d/nokind.csv:4: no provenance header: '# kind:' (measured or simulated)" "$(ref "$d/nokind.csv")"
bad "kind neither measured nor simulated" 1 "$d/badkind.csv:4: '# kind:' must start with \"measured\" or \"simulated\"" "$(ref "$d/badkind.csv")"
bad "short row" 1 "$d/shortrow.csv:6: expected 3 values, got 2" "$(ref "$d/shortrow.csv")"
bad "long row" 1 "$d/longrow.csv:5: expected 3 values, got 4" "$(ref "$d/longrow.csv")"
bad "NaN" 1 "$d/nan.csv:6: column 2 (probe1_ux): not a finite number (nan)" "$(ref "$d/nan.csv")"
bad "not a number" 1 "$d/text.csv:6: column 3 (probe1_uz): '-0.025x' is not a number" "$(ref "$d/text.csv")"
bad "columns line against header" 1 "$d/colsline.csv:4: '# columns:' names column 2 'probe1_uz' but the header row (line 5) has 'probe1_ux'" "$(ref "$d/colsline.csv")"
bad "no data rows" 1 "$d/norows.csv:4: no data rows after the header row" "$(ref "$d/norows.csv")"
bad "missing file" 4 "references[0].file: cannot find 'no-such-file.csv'" "$(ref no-such-file.csv)"
bad "unknown column" 1 "references[0].columns[0].column: no column 'probe1_uzz' in $d/good.csv (did you mean 'probe1_uz'?)" "$(ref "$d/good.csv" probe1_uzz probe1_uz)"
bad "unknown quantity" 1 "references[0].columns[0].quantity: unknown quantity 'tip_uzz' (did you mean 'tip_uz'?)" "$(ref "$d/good.csv" probe1_uz tip_uzz)"
bad "bad measure" 1 "measure: must be \"scaled\", \"relative\" or \"absolute\"" "references=( { file = \"$d/good.csv\"; abscissa = { column = \"load_factor\"; }; columns = ( { column = \"probe1_uz\"; measure = \"relativ\"; } ); } )"

# `check` reads the reference files too
out=$("$bin" check "$fold1" --set "$(ref "$d/nan.csv")" 2>&1 >/dev/null); rc=$?
case "$rc:$out" in
    1:*"nan.csv:6: column 2 (probe1_ux): not a finite number"*) ok "check reports a bad reference file";;
    *) notok "check with a bad reference file: status $rc, '$out'";;
esac

# Finding a file: by $SMOOTHFOLD_DATA, and in shared/data above the
# study's directory (the project's data beside the repository)
mkdir -p "$tmp/data"
cp "$d/good.csv" "$tmp/data/mydata.csv"
out=$(SMOOTHFOLD_DATA="$tmp/nowhere:$tmp/data" "$bin" run "$fold1" -q -o "$tmp/env" --set output.shapes=0 --set "$(ref mydata.csv)" 2>&1); rc=$?
grep -q "^# reference r: $tmp/data/mydata.csv" "$tmp/env/compare.tsv" 2>/dev/null && [ $rc -eq 0 ] &&
    ok "a reference found through \$SMOOTHFOLD_DATA" || notok "SMOOTHFOLD_DATA: status $rc, $out"
if [ -f "$src/../shared/data/fold1_elastica.csv" ]; then
    want=$(cd "$src/../shared/data" && pwd -P)/fold1_elastica.csv
    out=$(env -u SMOOTHFOLD_DATA "$bin" run "$fold1" -q -o "$tmp/up" --set output.shapes=0 2>&1); rc=$?
    # compare resolved paths: shared/ may be reached through a symbolic link
    got=$(sed -n 's/^# reference elastica: \([^ ]*\).*/\1/p' "$tmp/up/compare.tsv" 2>/dev/null | head -1)
    [ -n "$got" ] && got=$(realpath "$got" 2>/dev/null)
    [ "$got" = "$want" ] && [ $rc -eq 0 ] &&
        ok "studies/fold1.cfg finds fold1_elastica.csv in ../shared/data above it" || notok "search in shared/data: status $rc, $out"
else
    ok "# SKIP no ../shared/data beside the source tree"
fi

# A tolerance exceeded: fold1 (K = 0, the circular arc) is 1.8% off the
# elastica at 4 N; a 1% tolerance on the relative error must fail the run
# (exit 6, one line naming the key) with every output written.
set_tol='references=( { name = "elastica"; file = "fold1_elastica.csv"; abscissa = { column = "load_factor"; }; columns = ( { column = "probe1_ux"; measure = "relative"; tolerance = 0.05; }, { column = "probe1_uz"; measure = "relative"; tolerance = 0.01; } ); } )'
out=$("$bin" run "$fold1" -q -o "$tmp/tol" --set "$set_tol" 2>&1 >/dev/null); rc=$?
if [ $rc -eq 6 ] && [ "$(printf '%s\n' "$out" | wc -l)" -eq 1 ]; then
    case "$out" in
        *"references[0].columns[1]: probe1_uz against elastica column probe1_uz: max relative error 0.0179"*"exceeds the tolerance 0.01"*) ok "tolerance exceeded: exit 6: $out";;
        *) notok "tolerance exceeded: message '$out'";;
    esac
else
    notok "tolerance exceeded: status $rc, '$out'"
fi
st=$(awk -F'\t' '/^#/ { next } $1 == "reference" { for (k = 1; k <= NF; k++) c[$k] = k; next } { printf "%s:%s ", $c["column"], $c["status"] }' "$tmp/tol/compare.tsv" 2>/dev/null)
if [ "$st" = "probe1_ux:ok probe1_uz:FAIL " ] && [ -s "$tmp/tol/branch.tsv" ] && [ -s "$tmp/tol/compare-points.tsv" ] && [ -s "$tmp/tol/study.cfg" ]; then
    ok "tolerance exceeded: all files written, compare.tsv status $st"
else
    notok "tolerance exceeded: compare.tsv status '$st' or files missing"; ls "$tmp/tol" | sed 's/^/#   /'
fi

# A tolerance declared in the study file: strip3 with its fold modulus
# halved deflects far more than the finite-element references; the message
# names the study file and the line of the first failing column.
out=$("$bin" run "$src/studies/strip3.cfg" -q -o "$tmp/strip3-soft" --set output.shapes=0 --set materials.fold.E=7.6e6 2>&1 >/dev/null); rc=$?
line=$(grep -n 'column = "probe1_uz"; measure = "relative"; tolerance = 0.015' "$src/studies/strip3.cfg" | cut -d: -f1)
case "$rc:$out" in
    6:*"strip3.cfg:$line: references[0].columns[0]: probe1_uz against plane_strain column probe1_uz: max relative error"*"exceeds the tolerance 0.015 (and "*" more)") ok "strip3, softer folds, against its declared tolerances: $out";;
    *) notok "strip3, softer folds: status $rc, '$out' (line $line)";;
esac

# snap1: the path turns back twice in p (limit points at p = +-0.3065), so
# p = 0 lies on three pieces with uz = -0.031, 0 and +0.031.  Reference: the
# stored regression samples of snap1 (solved at fixed p on all three
# pieces, rows in path order).  Solved at each p, the comparison must
# reproduce them to round-off (1e-9 of the largest |uz|: Newton tolerance
# 1e-10); interpolated between the computed points (solve = false) to the
# interpolation error (measured 5.5e-5; bound 1e-3 = the points' spacing
# cubed, ~0.1^3), far below the 0.3 (at least) that a wrong piece gives.
snap=$src/tests/regress/snap1.csv
for solve in true false; do
    tol=$([ $solve = true ] && echo 1e-9 || echo 1e-3)
    "$bin" run "$src/studies/snap1.cfg" -q -o "$tmp/snap-$solve" --set output.shapes=0 \
        --set "references=( { name = \"stored\"; file = \"$snap\"; solve = $solve; abscissa = { column = \"p\"; }; columns = ( { column = \"probe1_uz\"; tolerance = $tol; }, { column = \"theta1\"; tolerance = $tol; } ); } )" 2>"$tmp/err"
    rc=$?
    res=$(awk -F'\t' '/^#/ { next } $1 == "reference" { for (k = 1; k <= NF; k++) c[$k] = k; next } { printf "%s %s max %s outside %s; ", $c["column"], $c["status"], $c["max"], $c["outside"] }' "$tmp/snap-$solve/compare.tsv" 2>/dev/null)
    nrows=$(grep -vc '^#' "$snap")
    placed=$(awk -F'\t' '/^#/ || NF == 0 || $1 == "reference" { next } $2 == "probe1_uz" { n++ } END { print n + 0 }' "$tmp/snap-$solve/compare-points.tsv" 2>/dev/null)
    if [ $rc -eq 0 ] && [ "$placed" -eq $((nrows - 1)) ]; then ok "snap1 (limit points), solve = $solve: $placed rows placed; $res"
    else notok "snap1, solve = $solve: status $rc, $placed of $((nrows - 1)) rows placed; $res $(cat "$tmp/err")"; fi
done
# the three pieces at p = 0: the rows of the stored file near p = 0 are
# matched in path order (uz < 0, then ~0, then > 0)
order=$(awk -F'\t' '/^#/ || NF == 0 || $1 == "reference" { next } $2 == "probe1_uz" && ($5 < 0.1 && $5 > -0.1) { printf "%s ", ($7 < -0.01 ? "down" : $7 > 0.01 ? "up" : "mid") }' "$tmp/snap-false/compare-points.tsv")
case "$order" in
    "down "*"mid "*"up "*) ok "snap1: rows near p = 0 matched in path order: $order";;
    *) notok "snap1: rows near p = 0 matched as: $order";;
esac
