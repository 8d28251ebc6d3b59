#!/bin/sh
# test_outdir.sh - the output directory of `smoothfold run` (issue 14):
# a non-empty directory not written by smoothfold is refused (its files
# untouched) unless --force; a second run removes the first run's outputs
# (shapes of other branches, comparisons, stale shapes, *.tmp) and keeps
# other files; a run killed by SIGTERM leaves no *.tmp behind.
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..6"
s3="$src/studies/strip3.cfg"
# 1: foreign, non-empty: refused with status 4, naming a foreign file; untouched
mkdir -p "$tmp/mine/shapes"; echo "my notes" >"$tmp/mine/notes.txt"; echo x >"$tmp/mine/shapes/keep.vtp"
"$bin" run "$s3" -q -o "$tmp/mine" >"$tmp/out" 2>"$tmp/err"; rc=$?
if [ $rc -eq 4 ] && grep -q "is not empty and holds no smoothfold results" "$tmp/err" &&
   grep -q -- "--force" "$tmp/err" && [ ! -e "$tmp/mine/branch.tsv" ] &&
   [ "$(cat "$tmp/mine/notes.txt")" = "my notes" ] && [ "$(wc -l <"$tmp/err")" -eq 1 ]; then
    echo "ok 1 - foreign directory refused: $(cat "$tmp/err")"
else
    echo "not ok 1 - foreign directory: status $rc: $(cat "$tmp/err")"
fi
# 2: --force writes into it and keeps the other files
if "$bin" run "$s3" -q --force -o "$tmp/mine" 2>"$tmp/err" && [ -s "$tmp/mine/branch.tsv" ] &&
   [ "$(cat "$tmp/mine/notes.txt")" = "my notes" ] && [ -e "$tmp/mine/shapes/keep.vtp" ]; then
    echo "ok 2 - --force: results written, other files kept"
else
    echo "not ok 2 - --force: $(cat "$tmp/err")"
fi
# 3: square4-inplane (5 branches, shapes_branch2..5.pvd) then strip3 into
# the same directory: nothing of the first run is left
d="$tmp/run"
"$bin" run "$src/studies/square4-inplane.cfg" -q -o "$d" >/dev/null 2>&1
echo "x" >"$d/shapes/shape_9999.vtp.tmp"; echo "x" >"$d/branch.tsv.tmp"; echo "x" >"$d/README.txt"
n1=$(ls "$d/shapes" | wc -l)
"$bin" run "$s3" -o "$d" >/dev/null 2>"$tmp/err"; rc=$?
left=$(cd "$d" && ls shapes_branch*.pvd *.tmp shapes/*.tmp 2>/dev/null)
# every shape the .pvd names exists, and every shape file is named by it
named=$(sed -n 's/.*file="\([^"]*\)".*/\1/p' "$d/shapes.pvd" | sort)
have=$(cd "$d" && ls shapes/*.vtp | sort)
if [ $rc -eq 0 ] && [ -z "$left" ] && [ "$named" = "$have" ] && [ -e "$d/README.txt" ] &&
   grep -q "removed [0-9]* files of an earlier run from $d" "$tmp/err"; then
    echo "ok 3 - rerun clears the earlier run ($n1 shapes before, $(echo "$have" | wc -l) after; README.txt kept): $(grep "removed" "$tmp/err")"
else
    echo "not ok 3 - rerun: status $rc, left: $left; pvd names $(echo "$named" | wc -l), files $(echo "$have" | wc -l); $(cat "$tmp/err")"
fi
# 4: a directory from before the marker (branch.tsv with smoothfold's header) counts as ours
rm -f "$d/.smoothfold"
if "$bin" run "$s3" -q -o "$d" 2>"$tmp/err"; then
    echo "ok 4 - results without the marker are recognised by their header"
else
    echo "not ok 4 - unmarked results: $(cat "$tmp/err")"
fi
# 5, 6: SIGTERM at different moments of a run that writes 150 shapes:
# never a *.tmp, and the signal still ends the run (status 143)
bad=0; statuses=""
for t in 0.05 0.15 0.25 0.35 0.45 0.55 0.65 0.75; do
    "$bin" run "$src/studies/square4-inplane.cfg" -q --set output.shapes=50 -o "$tmp/k" >/dev/null 2>&1 &
    pid=$!
    sleep $t
    kill -TERM $pid 2>/dev/null
    wait $pid; statuses="$statuses $?"
    left=$(find "$tmp/k" -name '*.tmp' 2>/dev/null)
    [ -n "$left" ] && { bad=$((bad + 1)); echo "# after $t s: $left"; }
done
[ $bad -eq 0 ] && echo "ok 5 - 8 runs killed by SIGTERM: no *.tmp left (statuses:$statuses)" \
               || echo "not ok 5 - $bad of 8 killed runs left *.tmp files"
case "$statuses" in
    *143*) echo "ok 6 - SIGTERM still ends the run (status 143 seen)";;
    *) echo "not ok 6 - no run ended by the signal (statuses:$statuses)";;
esac
