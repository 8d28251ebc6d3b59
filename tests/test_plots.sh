#!/bin/sh
# test_plots.sh - `smoothfold plot` (issue 14): the diagrams say what they
# show.  The real scripts of plots/ are run through wrappers (SMOOTHFOLD_PLOTS)
# that print gnuplot's settings afterwards: the title is the study name, the
# p axis says what p is per load stage (waterbomb2: two stages), the probe
# axis the probe's name; special points of square4-inplane get one label per
# place (no two labels overlapping, no type twice in a label); fold names in
# angles.png; --folds selects by name/group/number and refuses unknown names.
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..8"
if ! command -v gnuplot >/dev/null 2>&1; then
    for i in 1 2 3 4 5 6 7 8; do echo "ok $i # SKIP gnuplot is not installed"; done; exit 0
fi
mkdir -p "$tmp/wrap"
for g in stability eigenvalues angles; do
    cat >"$tmp/wrap/$g.gp" <<EOG
call '$src/plots/$g.gp' ARG1
EOG
done
# gnuplot prints `show` output on stderr; keep it per script
show='show title; show xlabel; show ylabel; show label'
for g in stability eigenvalues angles; do
    printf '%s\n' "$show" >>"$tmp/wrap/$g.gp"
done
plot() { SMOOTHFOLD_PLOTS="$tmp/wrap" "$bin" plot "$@" >"$tmp/out" 2>"$tmp/show"; }
"$bin" run "$src/studies/waterbomb2.cfg" -q --set output.shapes=0 -o "$tmp/wb" >/dev/null 2>&1
"$bin" run "$src/studies/square4-inplane.cfg" -q --set output.shapes=0 -o "$tmp/ip" >/dev/null 2>&1
# 1: real scripts, real files
if "$bin" plot "$tmp/wb" >/dev/null 2>"$tmp/err"; then
    bad=""
    for f in stability eigenvalues angles; do
        for e in png pdf; do [ -s "$tmp/wb/$f.$e" ] || bad="$bad $f.$e"; done
        head -c 8 "$tmp/wb/$f.png" | od -c | grep -q "P   N   G" || bad="$bad $f.png(not PNG)"
    done
    [ -z "$bad" ] && echo "ok 1 - plot writes stability, eigenvalues, angles as PNG and PDF" || echo "not ok 1 - missing:$bad"
else
    echo "not ok 1 - plot failed: $(cat "$tmp/err")"
fi
# 2: waterbomb2: title = study name, p axis per stage
plot "$tmp/wb"
if grep -q 'title is "waterbomb2: stability diagram"' "$tmp/show" &&
   grep -q 'ylabel is "load factor p (stage 1, p in \[0, 1\]: [^;]*; stage 2, p in \[1, 2\]: [^)]* N)"' "$tmp/show"; then
    echo "ok 2 - waterbomb2: title is the study name, p axis per stage: $(grep -m1 'ylabel is' "$tmp/show")"
else
    echo "not ok 2 - waterbomb2 labels:"; grep -E "title is|ylabel is" "$tmp/show" | sed 's/^/#   /'
fi
# 3: probe name on the displacement axis
probe=$(awk '/probes/ {p = 1} p && /name/ { match($0, /name *= *"[^"]*"/); s = substr($0, RSTART, RLENGTH); sub(/name *= *"/, "", s); sub(/"/, "", s); print s; exit }' "$src/studies/waterbomb2.cfg")
if [ -n "$probe" ] && grep -q "xlabel is \"$probe: uz \[mm\]\"" "$tmp/show"; then
    echo "ok 3 - probe axis named after the study's probe '$probe'"
else
    echo "not ok 3 - probe axis (probe '$probe'): $(grep 'xlabel is' "$tmp/show" | head -1)"
fi
# 4, 5: square4-inplane: labels of the special points
plot "$tmp/ip"
labels=$(grep -E '^[[:space:]]*label [0-9]+ "' "$tmp/show" | sort -u)
nlab=$(printf '%s\n' "$labels" | grep -c label)
nspec=$(grep -v '^#' "$tmp/ip/branch.tsv" | awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "type") t = i; next } $t ~ /^(LP|BP)/' | wc -l)
# positions: "at x, y" (first coordinates)
over=$(printf '%s\n' "$labels" | sed -n 's/.*"\([^"]*\)".* at \([-0-9.e+]*\), \([-0-9.e+]*\).*/\2 \3 \1/p' | awk '
    { x[NR] = $1; y[NR] = $2; t[NR] = $3; n = NR }
    END { for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) { dx = x[i] - x[j]; dy = y[i] - y[j]; if (dx < 0) dx = -dx; if (dy < 0) dy = -dy; if (dx < 20 && dy < 0.04) print t[i] "~" t[j] } }')
twice=$(printf '%s\n' "$labels" | sed -n 's/.*"\([^"]*\)".*/\1/p' | awk -F'[/(]' '{ delete s; for (i = 1; i <= NF; i++) if ($i != "" && $i !~ /^x/) { if ($i in s) print $0; s[$i] = 1 } }')
if [ "$nlab" -ge 3 ] && [ "$nlab" -lt "$nspec" ] && [ -z "$over" ]; then
    echo "ok 4 - square4-inplane: $nspec special rows, $nlab labels, none within 20 mm and 0.04 in p of another"
else
    echo "not ok 4 - labels: $nlab for $nspec special rows, overlapping: $over"; printf '%s\n' "$labels" | sed 's/^/#   /'
fi
[ -z "$twice" ] && echo "ok 5 - no label repeats a type (was BP2BP2BP)" || echo "not ok 5 - repeated: $twice"
# 6: --folds selects the folds drawn
names=$(SMOOTHFOLD_PLOTS="$tmp/wrap" "$bin" plot "$tmp/wb" --folds=1,2 2>&1 >/dev/null | grep -c 'title is ".*2 of 15 folds"')
if [ "$names" -ge 1 ]; then
    echo "ok 6 - --folds=1,2 draws 2 of 15 folds"
else
    echo "not ok 6 - --folds=1,2: $(SMOOTHFOLD_PLOTS="$tmp/wrap" "$bin" plot "$tmp/wb" --folds=1,2 2>&1 | grep 'title is' | tail -1)"
fi
# 7: an unknown name is refused, one line, status 1
"$bin" plot "$tmp/wb" --folds=nosuchfold >/dev/null 2>"$tmp/err"; rc=$?
if [ $rc -eq 1 ] && grep -q "'nosuchfold' is no fold name, group name or fold number" "$tmp/err" && [ "$(wc -l <"$tmp/err")" -eq 1 ]; then
    echo "ok 7 - --folds=nosuchfold refused: $(cat "$tmp/err")"
else
    echo "not ok 7 - --folds=nosuchfold: status $rc: $(cat "$tmp/err")"
fi
# 8: eigenvalues: one panel per eigenvalue, axis in J (not asinh); `show` sees the last panel
if grep -q 'ylabel is "eig[0-9]* \[J\]"' "$tmp/show" && ! grep -q asinh "$tmp/show"; then
    echo "ok 8 - eigenvalues on real axes in J, one panel each: $(grep 'ylabel is "eig' "$tmp/show" | cut -d'"' -f2)"
else
    echo "not ok 8 - eigenvalue axes: $(grep 'ylabel is "eig' "$tmp/show" | head -2)"
fi
