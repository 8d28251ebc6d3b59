#!/bin/sh
# test_auto_keys.sh - the defaults "auto" of solver.formulation,
# analysis.flat_start and analysis.step_norm (src/cli/run_equilibrium.c,
# choose_keys; docs/reference/study-keys.md, "Large sheets"): up to
# solver.auto_unknowns unknowns in fold coordinates (default 300) the
# fold formulation's choices ("folds", "multipliers", "sum"), above it, with none of
# the three keys set, "poses", "sparse", "rms", said in one header line.
# On the 2x2 Miura-ori of bench/miura-study.sh (actuation, K = 1: 102
# unknowns in fold coordinates):
#  1: the default run is the explicit "folds"/"multipliers"/"sum" run, byte for
#     byte in branch.tsv (no header line), and DIR/study.cfg records the
#     three values;
#  2: with solver.auto_unknowns = 100 (a sheet just above the threshold) the
#     header states poses/sparse/rms and why, and branch.tsv is the
#     explicit poses/sparse/rms run's but for that line;
#  3: there, a key set keeps its value and the others the fold
#     formulation's ("limit" above the threshold: solver.formulation =
#     "folds" gives the explicit folds/limit/sum run), and the header says so;
#  4: the loop penalty (fold formulation only; 48 unknowns, no multipliers,
#     above a threshold of 40) keeps "folds";
#  5: flat_start = "sparse" alone is an input error (it needs poses), one
#     line naming the formulation in use, given before any point;
#  6: an unknown value of each key: one line naming the key and the
#     accepted values, "auto" among them;
#  7: the 4x4 sheet (518 unknowns) gets poses/sparse/rms at the default
#     threshold (first point only);
#  8: analysis.convergence: the K+1 run (126 unknowns, above a threshold
#     of 110 that the K run, 102, is not) keeps the K run's choices;
#  9: the 2x2 sheet under gravity and a tip load (bench/miura-study.sh 2
#     load 1): the fold formulation's flat start (the choice below the
#     threshold) reaches p = 1 (exit 0, no second run, folds/multipliers/sum
#     in study.cfg) and ends where the sparse pose start's run ends (tip uz
#     to 1e-7 m, fold angles to 5e-6 rad);
# 10: pattern miura --cells=3x2 --gravity --load=0.01, rest angles 0 (a
#     sheet whose limit start in fold coordinates found no first point):
#     the default run reaches the end of its path, p = 2 (exit 0, no
#     second run, folds/multipliers/sum), at the state of the explicit
#     sparse pose start's run (tip uz to 1e-9 m, energy to 1e-8 relative).
# 11: the 2x2 sheet under a 1 N tip load (pattern miura --load=1, rest
#     angles 0, to p = 0.2), whose start by the method of multipliers
#     leaves on a branch the path cannot follow (the fold along the straight
#     crease line): the run goes again with the limit start, says so in
#     its header, and is the explicit limit run but for that line.
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
. "$src/tests/tap.sh"
echo "1..11"
check() { if [ "$1" = 1 ]; then ok "$2"; else nok "$2"; fi; }
sh "$src/bench/miura-study.sh" 2 actuation 1 >"$tmp/m2.cfg"
run() {   # run NAME [SETTING...]: exit status
    name=$1; shift
    "$bin" run "$tmp/m2.cfg" -q -o "$tmp/$name" --set analysis.stability=false --set output.shapes=0 "$@" \
        >"$tmp/$name.out" 2>&1
    echo $?
}
last_diff() {   # last_diff A B: the last rows of two branch.tsv files: p of each,
    # |probe1_uz| difference, largest fold-angle difference, energy
    # difference relative to B's
    awk -F '\t' 'FNR == 1 {f++; h = 0} /^#/ {next} !h {for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next}
        {last[f] = $0}
        END {split(last[1], x, "\t"); split(last[2], y, "\t");
             du = x[c["probe1_uz"]] - y[c["probe1_uz"]]; du = du < 0 ? -du : du; dt = 0;
             for (j in c) if (j ~ /^theta/) { e = x[c[j]] - y[c[j]]; e = e < 0 ? -e : e; if (e > dt) dt = e }
             de = x[c["energy"]] - y[c["energy"]]; de = de < 0 ? -de : de; s = y[c["energy"]]; s = s < 0 ? -s : s
             printf "%s %s %.3g %.3g %.3g", x[c["p"]], y[c["p"]], du, dt, de / s}' "$1" "$2" 2>/dev/null
}
against_poses() {   # against_poses NAME CFG [SETTING...]: the default run (exit a, keys k)
    # and the explicit poses/sparse/rms run (exit b); d: last_diff of the two
    n=$1; c=$2; shift 2
    "$bin" run "$c" -q -o "$tmp/$n" "$@" >"$tmp/$n.out" 2>&1; a=$?
    "$bin" run "$c" -q -o "$tmp/${n}p" "$@" $poses >"$tmp/${n}p.out" 2>&1; b=$?
    k=$(keys "$tmp/$n"); d=$(last_diff "$tmp/$n/branch.tsv" "$tmp/${n}p/branch.tsv")
}
keys() {   # keys DIR: the three values recorded in DIR/study.cfg
    awk '/^ *(formulation|flat_start|step_norm) = / {gsub(/[";]/, ""); v[$1] = $3}
         END {print v["formulation"], v["flat_start"], v["step_norm"]}' "$1/study.cfg"
}
F='solver.formulation' S='analysis.flat_start' N='analysis.step_norm'
folds="--set $F=\"folds\" --set $S=\"multipliers\" --set $N=\"sum\""
poses="--set $F=\"poses\" --set $S=\"sparse\" --set $N=\"rms\""

# 1: below the threshold
a=$(run auto); e=$(run explicit $folds)
k=$(keys "$tmp/auto")
r=0
[ "$a" = 0 ] && [ "$e" = 0 ] && cmp -s "$tmp/auto/branch.tsv" "$tmp/explicit/branch.tsv" &&
    ! grep -q '^# auto' "$tmp/auto/branch.tsv" && [ "$k" = "folds multipliers sum" ] && r=1
check $r "2x2 (102 unknowns): the default run is the folds/multipliers/sum run (exit $a, $e; study.cfg: $k)"

# 2: just above a threshold of 100
a=$(run big --set solver.auto_unknowns=100); e=$(run bigx $poses)
k=$(keys "$tmp/big")
line=$(grep '^# auto' "$tmp/big/branch.tsv")
r=0
[ "$a" = 0 ] && [ "$e" = 0 ] && [ "$k" = "poses sparse rms" ] &&
    grep -v '^# auto' "$tmp/big/branch.tsv" | cmp -s - "$tmp/bigx/branch.tsv" &&
    [ "$line" = '# auto: 102 unknowns in fold coordinates, above solver.auto_unknowns = 100: solver.formulation = "poses", analysis.flat_start = "sparse", analysis.step_norm = "rms" (setting any of the three keys keeps "folds", "limit", "sum" for the others)' ] && r=1
check $r "above the threshold: poses/sparse/rms, the explicit run's branch.tsv (exit $a, $e; study.cfg: $k)"
[ $r = 1 ] || echo "# $line"

# 3: a key set wins, the others keep the fold formulation's choices
a=$(run set --set solver.auto_unknowns=100 --set "$F=\"folds\""); e=$(run explicitl --set $F=\"folds\" --set $S=\"limit\" --set $N=\"sum\")
k=$(keys "$tmp/set")
line=$(grep '^# auto' "$tmp/set/branch.tsv")
r=0
[ "$a" = 0 ] && [ "$k" = "folds limit sum" ] &&
    grep -v '^# auto' "$tmp/set/branch.tsv" | cmp -s - "$tmp/explicitl/branch.tsv" &&
    [ "$line" = '# auto: 102 unknowns in fold coordinates, above solver.auto_unknowns = 100, but solver.formulation is set: analysis.flat_start = "limit", analysis.step_norm = "sum" (the fold formulation'"'"'s)' ] && r=1
check $r "above the threshold, solver.formulation = \"folds\" set: folds/limit/sum, the explicit run (exit $a; study.cfg: $k)"
[ $r = 1 ] || echo "# $line"

# 4: the loop penalty exists in the fold formulation only
a=$(run pen --set solver.auto_unknowns=40 --set 'solver.constraints="penalty"' --set analysis.max_steps=3)
k=$(keys "$tmp/pen")
r=0
[ "$k" = "folds limit sum" ] && grep -q '^# auto: .*, but solver.constraints = "penalty" exists in the fold formulation only: solver.formulation = "folds"' "$tmp/pen/branch.tsv" && r=1
check $r "above the threshold with the loop penalty: folds (exit $a; study.cfg: $k)"

# 5: an explicit combination that does not work keeps its error
a=$(run sp --set "$S=\"sparse\"")
r=0
[ "$a" = 1 ] && grep -q 'analysis.flat_start = "sparse" needs solver.formulation = "poses" (it is "folds")' "$tmp/sp.out" &&
    [ "$(wc -l <"$tmp/sp.out")" = 1 ] && [ ! -e "$tmp/sp/branch.tsv" ] && r=1
check $r "flat_start = \"sparse\" alone: one line, before any point, naming the formulation in use (exit $a)"

# 6: unknown values
r=1
for c in "$F|x|must be \"auto\", \"folds\" or \"poses\" (got \"x\")" \
         "$S|x|must be \"auto\", \"limit\", \"direct\", \"sparse\" or \"multipliers\" (got \"x\")" \
         "$N|x|must be \"auto\", \"sum\" or \"rms\" (got \"x\")"; do
    key=${c%%|*}; rest=${c#*|}; val=${rest%%|*}; msg=${rest#*|}
    a=$(run bad --set "$key=\"$val\"")
    if [ "$a" = 0 ] || [ "$(wc -l <"$tmp/bad.out")" != 1 ] || ! grep -qF "$key: $msg" "$tmp/bad.out"; then
        r=0; sed 's/^/# /' "$tmp/bad.out"
    fi
done
check $r "an unknown value of each key: one line naming it and the accepted values, auto among them"

# 7: the default threshold, on the 4x4 sheet (first point only)
sh "$src/bench/miura-study.sh" 4 actuation 1 >"$tmp/m4.cfg"
"$bin" run "$tmp/m4.cfg" -q -o "$tmp/m4" --set analysis.stability=false --set output.shapes=0 \
    --set analysis.max_steps=1 >"$tmp/m4.out" 2>&1
k=$(keys "$tmp/m4")
r=0
[ "$k" = "poses sparse rms" ] && grep -q '^# auto: 518 unknowns in fold coordinates, above solver.auto_unknowns = 300: ' "$tmp/m4/branch.tsv" &&
    grep -q '^# formulation: poses, ' "$tmp/m4/branch.tsv" && r=1
check $r "4x4 (518 unknowns) at the default threshold 300: poses/sparse/rms (study.cfg: $k)"

# 8: the K+1 run of analysis.convergence keeps the choices of the K run
a=$(run conv --set solver.auto_unknowns=110 --set analysis.convergence=true)
k=$(keys "$tmp/conv/kplus1")
r=0
[ "$a" = 0 ] && [ "$k" = "folds multipliers sum" ] && [ -s "$tmp/conv/convergence.tsv" ] &&
    ! grep -q '^# auto' "$tmp/conv/kplus1/branch.tsv" && r=1
check $r "convergence: the K+1 run (126 unknowns, threshold 110) keeps folds/multipliers/sum (exit $a; study.cfg: $k)"

# 9: the 2x2 sheet under gravity and a tip load: the fold start follows
# the end of its path and ends at the pose run's state
sh "$src/bench/miura-study.sh" 2 load 1 >"$tmp/m2l.cfg"
against_poses m2l "$tmp/m2l.cfg" --set output.shapes=0
set -- $d
r=0
[ "$a" = 0 ] && [ "$b" = 0 ] && [ "$k" = "folds multipliers sum" ] && [ "$1" = 1 ] && [ "$2" = 1 ] &&
    ! grep -q '^# auto' "$tmp/m2l/branch.tsv" &&
    awk -v u="$3" -v t="$4" 'BEGIN {exit !(u <= 1e-7 && t <= 5e-6)}' && r=1
check $r "2x2 under gravity and a tip load: the fold start reaches p = $1 (exit $a; study.cfg: $k), the pose run p = $2 (exit $b); tip uz $3 m, fold angles $4 rad apart"

# 10: the fold start reaches the end of the path of a sheet that the limit
# start could not leave, at the sparse pose start's state
"$bin" pattern miura --cells=3x2 --gravity --load=0.01 -o "$tmp/m32.gen.cfg" >/dev/null 2>&1
sed 's/^\(  { name = "[a-z0-9]*"; rest_angle = \)-\{0,1\}[0-9.]*;/\10.0;/' "$tmp/m32.gen.cfg" >"$tmp/m32l.cfg"
against_poses m32l "$tmp/m32l.cfg" --set output.shapes=0 --set analysis.stability=false
set -- $d
r=0
[ "$a" = 0 ] && [ "$b" = 0 ] && [ "$k" = "folds multipliers sum" ] && [ "$1" = 2 ] && [ "$2" = 2 ] &&
    ! grep -q '^# auto' "$tmp/m32l/branch.tsv" &&
    awk -v u="$3" -v e="$5" 'BEGIN {exit !(u <= 1e-9 && e <= 1e-8)}' && r=1
check $r "3x2 under gravity and a tip load: the fold start reaches p = $1 (exit $a; study.cfg: $k), the sparse pose start p = $2 (exit $b); tip uz $3 m, energy $5 relative apart"

# 11: the start by the method of multipliers whose path stops at its first
# point: the same run again with the limit start
"$bin" pattern miura --load=1 -o "$tmp/ml1.gen.cfg" >/dev/null 2>&1
sed 's/^\(  { name = "[a-z0-9]*"; rest_angle = \)-\{0,1\}[0-9.]*;/\10.0;/' "$tmp/ml1.gen.cfg" >"$tmp/ml1.cfg"
"$bin" run "$tmp/ml1.cfg" -q -o "$tmp/ml1" --set output.shapes=0 --set analysis.end=0.2 >"$tmp/ml1.out" 2>&1
a=$?
"$bin" run "$tmp/ml1.cfg" -q -o "$tmp/ml1l" --set output.shapes=0 --set analysis.end=0.2 \
    --set "$S=\"limit\"" >"$tmp/ml1l.out" 2>&1
b=$?
k=$(keys "$tmp/ml1")
pend=$(grep -v '^#' "$tmp/ml1/branch.tsv" 2>/dev/null | tail -n 1 | cut -f 4)
r=0
[ "$a" = 0 ] && [ "$b" = 0 ] && [ "$pend" = 0.2 ] && [ "$k" = "folds limit sum" ] &&
    grep -q '^# auto: the .*start by the method of multipliers .*; run again with analysis.flat_start = "limit" (it said: ' "$tmp/ml1/branch.tsv" &&
    grep -v '^# auto' "$tmp/ml1/branch.tsv" | cmp -s - "$tmp/ml1l/branch.tsv" && r=1
check $r "2x2 under a 1 N tip load: run again with the limit start to p = $pend (exit $a; study.cfg: $k), the explicit limit run's branch.tsv"
