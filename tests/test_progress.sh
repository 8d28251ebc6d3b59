#!/bin/sh
# test_progress.sh - long work says what it is doing (src/cli/progress.h):
# `run` and `check` print a line on stderr at least every period (5 s;
# SMOOTHFOLD_PROGRESS_PERIOD = 0.3 s here, so that a short run shows it),
# during the sparse flat start of an 8 x 8 Miura sheet too, where no point
# is written for seconds (about 2 s here: long enough for two lines on a
# fast machine); nothing with --quiet; the result files are the
# same either way.  Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..4"
"$bin" pattern miura --cells=8x8 -o "$tmp/m8.cfg" >/dev/null 2>&1 || echo "# pattern failed"
# each stderr line with the time it came (seconds since the epoch, ms)
stamp() { while IFS= read -r l; do printf '%s %s\n' "$(date +%s.%N | cut -c1-14)" "$l"; done; }
# largest gap between consecutive lines, and from the start to the first
gaps() { awk -v t0="$1" '{ t = $1 + 0; if (NR == 1) g = t - t0; else if (t - p > g) g = t - p; p = t } END { printf "%.2f", g }' "$2"; }
t0=$(date +%s.%N | cut -c1-14)
{ SMOOTHFOLD_PROGRESS_PERIOD=0.3 "$bin" run "$tmp/m8.cfg" -o "$tmp/loud" --set analysis.max_steps=2 2>&1 >/dev/null; } | stamp > "$tmp/loud.err"
g=$(gaps "$t0" "$tmp/loud.err")
n=$(grep -c '^[0-9.]* smoothfold: run: ' "$tmp/loud.err")
# the reporter looks every 0.15 s here: a gap of at most 0.3 + 0.15 s,
# and up to 0.75 s more on a machine shared with other jobs
if [ "$n" -ge 2 ] && awk -v g="$g" 'BEGIN { exit !(g <= 1.3) }'; then
    echo "ok 1 - run: $n progress lines, none more than $g s after the one before"
else
    echo "not ok 1 - run: $n progress lines, largest gap $g s"; sed 's/^/#   /' "$tmp/loud.err" | cut -c1-200
fi
if grep -q 'run: following the path: point 1, from p = 0: [0-9]* evaluations of the equations' "$tmp/loud.err"; then
    echo "ok 2 - the line says what and how far: $(grep -m1 'evaluations' "$tmp/loud.err" | cut -d' ' -f2-)"
else
    echo "not ok 2 - no line with the evaluations so far"
fi
SMOOTHFOLD_PROGRESS_PERIOD=0.3 "$bin" run "$tmp/m8.cfg" -q -o "$tmp/quiet" --set analysis.max_steps=2 >/dev/null 2>"$tmp/quiet.err"
if ! grep -q 'smoothfold: run:' "$tmp/quiet.err" && cmp -s "$tmp/loud/branch.tsv" "$tmp/quiet/branch.tsv" &&
   cmp -s "$tmp/loud/special.tsv" "$tmp/quiet/special.tsv" && ! grep -q 'following the path' "$tmp/loud/branch.tsv"; then
    echo "ok 3 - --quiet: no progress lines; branch.tsv and special.tsv the same with and without them"
else
    echo "not ok 3 - --quiet: $(head -3 "$tmp/quiet.err"); files differ or hold progress"
fi
t0=$(date +%s.%N | cut -c1-14)
{ SMOOTHFOLD_PROGRESS_PERIOD=0.05 "$bin" check "$tmp/m8.cfg" 2>&1 >"$tmp/check.out"; } | stamp > "$tmp/check.err"
if grep -q 'smoothfold: check: ' "$tmp/check.err" && ! grep -q 'smoothfold: check:' "$tmp/check.out"; then
    echo "ok 4 - check: progress on stderr ($(grep -c 'check:' "$tmp/check.err") lines), none in its output"
else
    echo "not ok 4 - check: no progress lines on stderr, or some on stdout"
fi
