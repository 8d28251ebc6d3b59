#!/bin/sh
# test_set_types.sh - study settings as a new user types them (issue 14):
# --set values read as the schema types the key (bare word for a string,
# integers for numbers), gravity.enabled=false on a study without gravity,
# one range for solver.quadrature, one-line messages for values holding a
# newline, analysis.eigenvalues bounded by the problem.  The merged study
# the run writes (DIR/study.cfg) shows what was understood.  Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..13"
n=0
ok() { n=$((n + 1)); printf 'ok %d - %s\n' $n "$1"; }
notok() { n=$((n + 1)); printf 'not ok %d - %s\n' $n "$1"; }
s3="$src/studies/strip3.cfg"
# 1-4: typed values reach the merged study
if "$bin" run "$src/studies/square4.cfg" -q --set output.shapes=0 --set solver.constraints=penalty \
      --set analysis.eigensolver=arpack --set 'defaults.setback=[0, 0.01]' \
      --set materials.fold.E=30400000 --set analysis.max_step=1 --set 'gravity.g=[0, 0, -9.81]' \
      --set gravity.enabled=false -o "$tmp/r" >/dev/null 2>"$tmp/err"; then
    c="$tmp/r/study.cfg"
    grep -q 'constraints = "penalty";' "$c" && ok "bare word for a string key: constraints = \"penalty\"" || notok "constraints: $(grep constraints "$c")"
    grep -q 'eigensolver = "arpack";' "$c" && ok "analysis.eigensolver=arpack" || notok "eigensolver: $(grep eigensolver "$c")"
    grep -q 'setback = \[0.0, 0.01\];' "$c" && ok "integers in a number list: setback = [0.0, 0.01]" || notok "setback: $(grep setback "$c")"
    grep -q 'E = 3.04e7;' "$c" && grep -q 'max_step = 1.0;' "$c" && grep -q 'g = \[0.0, 0.0, -9.81\]' "$c" \
        && ok "an integer for a number key: E = 3.04e7, max_step = 1.0, g = [0.0, 0.0, -9.81]" \
        || notok "numbers: $(grep -E ' E = |max_step|g = ' "$c" | tr '\n' ' ')"
else
    for i in 1 2 3 4; do notok "typed --set run failed: $(cat "$tmp/err")"; done
fi
# 5: integer keys still want integers; a quoted string still works
out=$("$bin" check "$s3" --set defaults.modes=2.0 2>&1 >/dev/null); rc=$?
out2=$("$bin" check "$s3" --set 'solver.constraints="penalty"' 2>&1 >/dev/null); rc2=$?
case "$rc:$rc2:$out" in
    1:0:*"expected an integer, got 2.0"*) ok "defaults.modes=2.0 refused, \"penalty\" with quotes accepted";;
    *) notok "modes=2.0: $rc $out; quoted: $rc2 $out2";;
esac
# 6: gravity.enabled=false on a study without gravity; with gravity.g given too, it is off
out=$("$bin" check "$s3" --set gravity.enabled=false 2>&1); rc=$?
out2=$("$bin" check "$s3" --set 'gravity.g=[0, 0, -9.81]' --set gravity.enabled=false 2>&1); rc2=$?
out3=$("$bin" check "$s3" --set 'gravity.g=[0, 0, -9.81]' 2>&1)
if [ $rc -eq 0 ] && [ $rc2 -eq 0 ] && ! printf '%s' "$out2" | grep -q "gravity (" && printf '%s' "$out3" | grep -q "gravity ("; then
    ok "gravity.enabled=false: accepted without gravity.g, and switches gravity off"
else
    notok "gravity.enabled=false: $rc $(printf '%s' "$out" | tail -1); $rc2 $(printf '%s' "$out2" | tail -1)"
fi
# 7: one range for the quadrature, refused by the schema under its own key
out=$("$bin" check "$s3" --set solver.quadrature=1 2>&1 >/dev/null); rc=$?
"$bin" check "$s3" --set solver.quadrature=64 >/dev/null 2>&1; rc64=$?
out65=$("$bin" check "$s3" --set solver.quadrature=65 2>&1 >/dev/null)
case "$rc:$rc64:$out:$out65" in
    1:0:*"solver.quadrature: must be between 2 and 64 (got 1)":*"between 2 and 64 (got 65)") ok "solver.quadrature: 1 and 65 refused by the key's range 2..64, 64 accepted";;
    *) notok "quadrature: $rc $out / $rc64 / $out65";;
esac
grep -q '`solver.quadrature` | integer 2..64' "$src/docs/reference/study-keys.md" && ok "docs give the same range 2..64" || notok "docs range"
# 9: a newline inside a value: still one line
out=$("$bin" check "$s3" --set "analysis.eigensolver=ar
pack" 2>&1 >/dev/null); rc=$?
if [ $rc -eq 1 ] && [ "$(printf '%s\n' "$out" | wc -l)" -eq 1 ] && printf '%s' "$out" | grep -q 'got "ar\\npack"'; then
    ok "newline in a string value: one line: $out"
else
    notok "newline: status $rc: $out"
fi
# a newline inside a name in the study file (a vertex of the outline)
sed 's/outline = \["v1"/outline = ["v\\n1"/' "$src/studies/square4.cfg" >"$tmp/nl.cfg"
out=$("$bin" check "$tmp/nl.cfg" 2>&1 >/dev/null); rc=$?
if [ $rc -eq 1 ] && [ "$(printf '%s\n' "$out" | wc -l)" -eq 1 ] && printf '%s' "$out" | grep -q 'v\\n1'; then
    ok "newline in a study string: one line: $out"
else
    notok "newline in a study string: status $rc: $out"
fi
# 11, 12: analysis.eigenvalues bounded by the problem (square4: 48 coordinates)
for ev in 2147483647 2000; do
    if timeout 60 "$bin" run "$src/studies/square4.cfg" -q --set output.shapes=0 --set analysis.eigenvalues=$ev \
            -o "$tmp/ev" >/dev/null 2>"$tmp/err"; then
        ncol=$(grep -v '^#' "$tmp/ev/branch.tsv" | head -1 | tr '\t' '\n' | grep -c '^eig')
        if [ "$ncol" -eq 48 ] && grep -q "# note: analysis.eigenvalues = $ev, but the sheet has 48 generalised coordinates" "$tmp/ev/branch.tsv"; then
            ok "analysis.eigenvalues=$ev: 48 columns (the coordinates), with a note"
        else
            notok "eigenvalues=$ev: $ncol columns"
        fi
    else
        notok "eigenvalues=$ev: status $?: $(cat "$tmp/err")"
    fi
done
# 13: the merged study with the new keys reads back
if "$bin" check "$tmp/r/study.cfg" >/dev/null 2>"$tmp/err"; then ok "merged study.cfg reads back"; else notok "study.cfg: $(cat "$tmp/err")"; fi
