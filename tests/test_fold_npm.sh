#!/bin/sh
# test_fold_npm.sh - the FOLD files smoothfold writes, read by the FOLD
# reference library (npm package `fold`, edemaine's; MIT licence), not by
# our own reader: tests/fold_check.js.  The package is installed with npm
# into the build tree on first use (CI: the registry is reachable); the
# whole test is skipped (TAP "1..0 # SKIP") only when node or npm is
# missing or the install fails, and says so.
#
# - the FOLD specification's crease-pattern example (examples/diagonal-cp.fold
#   of the package) imports, checks and runs: two commands;
# - its folded-form examples are refused with a clear message;
# - run's DIR/folded.fold of the generated studies: one foldedForm frame per
#   shape written (shapes.pvd), 3-D coordinates for every vertex, one fold
#   angle per edge, boundary edges at 0, the crease-pattern faces equal to
#   those the library finds from the edges, and at the end of the actuation
#   no mountain fold positive, no valley fold negative;
# - export of every study: the library's faces equal ours.
src=${SF_SRCDIR:-$(dirname "$0")/..}
build=${SF_BUILDDIR:-.}
bin=$build/src/smoothfold
mod=$build/tests/npm-fold
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
    echo "1..0 # SKIP node or npm is not installed: the FOLD reference library cannot be run"
    exit 0
fi
if [ ! -f "$mod/node_modules/fold/package.json" ]; then
    mkdir -p "$mod"
    if ! timeout 300 npm install --prefix "$mod" --no-audit --no-fund --loglevel=error fold@0.12.0 >"$mod/install.log" 2>&1; then
        echo "1..0 # SKIP npm install fold@0.12.0 failed (registry not reachable?): $(tail -1 "$mod/install.log")"
        exit 0
    fi
fi
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
i=0
ok() { i=$((i + 1)); echo "ok $i - $1"; }
nok() { i=$((i + 1)); echo "not ok $i - $1"; }
check() { node "$src/tests/fold_check.js" "$mod" "$1" 2>"$tmp/node.err"; }
field() { printf '%s\n' "$1" | sed -n "s/.*\"$2\":\([0-9]*\).*/\1/p"; }
echo "1..11"
ex="$mod/node_modules/fold/examples"
# 1-2: the specification's crease-pattern example, in two commands
if "$bin" import "$ex/diagonal-cp.fold" -o "$tmp/cp.cfg" 2>"$tmp/err" &&
   timeout 120 "$bin" run "$tmp/cp.cfg" -q -o "$tmp/cp" 2>>"$tmp/err"; then ok "FOLD spec example diagonal-cp.fold imports and runs"
else nok "FOLD spec example diagonal-cp.fold imports and runs"; sed 's/^/#   /' "$tmp/err"; fi
out=$(check "$tmp/cp/folded.fold")
if [ $? -eq 0 ] && [ "$(field "$out" V)" = 1 ] && [ "$(field "$out" frames)" = "$(grep -c '<DataSet' "$tmp/cp/shapes.pvd")" ]; then
    ok "its folded.fold in the reference library: $out"
else nok "its folded.fold in the reference library: $out"; sed 's/^/#   /' "$tmp/node.err"; fi
# 3: the folded-form examples are not crease patterns
n=0
for f in simple box squaretwist; do
    msg=$("$bin" import "$ex/$f.fold" -o "$tmp/x.cfg" 2>&1)
    case "$msg" in *"$f.fold: vertices_coords["*"off the plane that fits the vertices best: this frame is folded"*"no frame of the file lies flat"*)
        n=$((n + 1));; *) echo "#   $f: $msg";; esac
done
[ $n -eq 3 ] && ok "the spec's folded forms are refused (folded, no flat frame)" || nok "the spec's folded forms are refused"
# 4-9: folded.fold of the generated studies
for s in miura-2x2 yoshimura-2x2 waterbomb-2x2; do
    timeout 120 "$bin" run "$src/studies/$s.cfg" -q -o "$tmp/$s" 2>"$tmp/err"
    out=$(check "$tmp/$s/folded.fold"); rc=$?
    shapes=$(grep -c '<DataSet' "$tmp/$s/shapes.pvd" 2>/dev/null)
    if [ $rc -eq 0 ] && [ "$(field "$out" frames)" = "$shapes" ] && [ "$(field "$out" faces)" = "$(field "$out" faces_fold)" ]; then
        ok "$s: folded.fold has one frame per shape ($shapes), the library's faces: $out"
    else nok "$s: folded.fold: $out (shapes $shapes)"; sed 's/^/#   /' "$tmp/err" "$tmp/node.err"; fi
    if [ "$(field "$out" last_wrong_sign)" = 0 ]; then
        ok "$s: no fold ends with the sign opposite to its assignment ($(field "$out" last_flat) flat)"
    else nok "$s: $(field "$out" last_wrong_sign) folds end with the sign opposite to their assignment"; fi
done
# 10: export of every study
fails=0
for s in "$src"/studies/*.cfg; do
    b=$(basename "$s" .cfg)
    "$bin" export "$s" -o "$tmp/$b.fold" 2>"$tmp/err" && out=$(check "$tmp/$b.fold") &&
        [ "$(field "$out" faces)" = "$(field "$out" faces_fold)" ] || { fails=$((fails + 1)); echo "#   $b: $out"; }
done
[ $fails -eq 0 ] && ok "export: every study's faces are those the library finds" || nok "export: $fails studies differ"
# 11: a study with a load path and stability (square4): frames carry p and stability
timeout 120 "$bin" run "$src/studies/fold1.cfg" -q -o "$tmp/f1" 2>"$tmp/err"
out=$(check "$tmp/f1/folded.fold"); rc=$?
if [ $rc -eq 0 ] && [ "$(field "$out" frames)" = "$(grep -c '<DataSet' "$tmp/f1/shapes.pvd")" ]; then ok "fold1: folded.fold frames: $out"
else nok "fold1: folded.fold: $out"; sed 's/^/#   /' "$tmp/err" "$tmp/node.err"; fi
