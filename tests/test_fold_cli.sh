#!/bin/sh
# test_fold_cli.sh - `smoothfold import` and `export` through the program:
# the FOLD files of tests/fold/ import, check and run (two commands);
# every broken file in tests/bad/fold_*.fold and svg_*.svg fails with one
# line naming the file and the location (*.expect: the text after "FILE:" or
# "FILE: "), a non-zero status and nothing written; export writes FOLD for
# every study.  Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
. "$src/tests/tap.sh"
nbad=$(ls "$src"/tests/bad/fold_*.fold "$src"/tests/bad/svg_*.svg | wc -l)
ngood=$(ls "$src"/tests/fold/*.fold | wc -l)
echo "1..$((nbad + 2 * ngood + 5))"
for f in "$src"/tests/fold/*.fold; do
    b=$(basename "$f" .fold)
    if "$bin" import "$f" -o "$tmp/$b.cfg" >/dev/null 2>"$tmp/err" && "$bin" check "$tmp/$b.cfg" >/dev/null 2>>"$tmp/err"; then
        ok "import $b.fold and check"
    else nok "import $b.fold and check"; sed 's/^/#   /' "$tmp/err"; fi
    if timeout 120 "$bin" run "$tmp/$b.cfg" -q -o "$tmp/$b" 2>"$tmp/err" && [ -s "$tmp/$b/branch.tsv" ]; then
        ok "run the imported $b"
    else nok "run the imported $b"; sed 's/^/#   /' "$tmp/err"; fi
done
for f in "$src"/tests/bad/fold_*.fold "$src"/tests/bad/svg_*.svg; do
    b=$(basename "$f" | sed 's/\.[a-z]*$//')
    text=$(sed -n 1p "$src/tests/bad/$b.expect")
    out=$("$bin" import "$f" -o "$tmp/bad.cfg" 2>&1 >/dev/null); rc=$?
    n=$(printf '%s\n' "$out" | wc -l)
    if [ $rc -eq 0 ] || [ $rc -ge 128 ] || [ "$n" -ne 1 ] || [ -e "$tmp/bad.cfg" ] || [ -e "$tmp/bad.cfg.tmp" ]; then
        nok "$b: status $rc, $n lines, written: $(ls "$tmp" | grep -c bad.cfg)"; printf '%s\n' "$out" | sed 's/^/#   /'
        continue
    fi
    case "$out" in
        *"$f:$text"*|*"$f: $text"*) ok "$b";;
        *) nok "$b"; echo "#   expected: $f: $text"; echo "#   got:      $out";;
    esac
done
# names, units and frames reach the study
"$bin" import "$src/tests/fold/one-valley.fold" --set defaults.width=0.002 -o "$tmp/ov.cfg" >/dev/null 2>"$tmp/err"
if grep -q 'v6 = \[0.03, 0.03\];' "$tmp/ov.cfg" && grep -q 'width = 0.002;' "$tmp/ov.cfg" &&
   grep -q 'rest_angle = 1.5707963267948966;' "$tmp/ov.cfg"; then ok "mm to m, --set, foldAngle 90 to pi/2"
else nok "mm to m, --set, foldAngle 90 to pi/2"; sed 's/^/#   /' "$tmp/err"; fi
out=$("$bin" import "$src/tests/fold/frames-3d.fold" --frame=0 -o "$tmp/f0.cfg" 2>&1); rc=$?
case "$rc:$out" in 0:*"frames-3d.fold: FOLD crease pattern, 50.8 x 28.4 mm"*"lie in the plane with normal (0, -0.4472, 0.8944): turned into the x-y plane"*)
    ok "--frame 0, flat in a tilted plane: turned into x-y (50.8 mm by 1.25^0.5 in)";;
    *) nok "--frame 0, flat in a tilted plane ($rc: $out)";; esac
# export: every study
fails=0
for s in "$src"/studies/*.cfg; do
    b=$(basename "$s" .cfg)
    "$bin" export "$s" -o "$tmp/$b.fold" 2>"$tmp/err" || { fails=$((fails + 1)); sed 's/^/#   /' "$tmp/err"; }
done
[ $fails -eq 0 ] && ok "export every study" || nok "export every study ($fails failed)"
out=$("$bin" export "$src/studies/fold1.cfg" -o "$tmp/x.json" 2>&1); rc=$?
case "$rc:$out" in 2:*"the output must end in .fold"*) ok "export refuses a non-.fold output";; *) nok "export refuses a non-.fold output ($rc: $out)";; esac
out=$("$bin" import "$src/tests/fold/missing.fold" -o "$tmp/m.cfg" 2>&1); rc=$?
case "$rc:$out" in [1-9]:*"missing.fold: cannot read"*) ok "missing file";; *) nok "missing file ($rc: $out)";; esac
