#!/bin/sh
# test_run_dynamics.sh - `smoothfold run` on the two dynamics studies writes
# the documented files: trajectory.tsv with its columns in order and finite
# numbers only (the last, warning, empty or a documented word), a shapes.pvd whose .vtp files exist, study.cfg and (with
# gnuplot) the plot; `smoothfold plot` redraws it; bad dynamics input is a
# one-line error with nothing written.  Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..6"
have_gnuplot=0
command -v gnuplot >/dev/null 2>&1 && have_gnuplot=1

# check_run N NAME STUDY NFOLDS NPROBES: run, then check the outputs
check_run() {
    n=$1; name=$2; study=$3; nf=$4; np=$5
    out="$tmp/$name"
    if ! "$bin" run "$src/studies/$study.cfg" -q -o "$out" >"$tmp/log" 2>&1; then
        echo "not ok $n - $name: run failed: $(tr '\n' ' ' < "$tmp/log")"; return
    fi
    want="step	t	p	load"
    i=1; while [ $i -le "$np" ]; do want="$want	probe${i}_ux	probe${i}_uy	probe${i}_uz"; i=$((i + 1)); done
    want="$want	energy	kinetic	drift	speed"
    i=1; while [ $i -le "$nf" ]; do want="$want	theta$i"; i=$((i + 1)); done
    want="$want	warning"
    got=$(awk '!/^#/ { print; exit }' "$out/trajectory.tsv")
    if [ "$got" != "$want" ]; then echo "not ok $n - $name: columns: $got"; return; fi
    bad=$(awk -F'\t' '!/^#/ && NR > 0 { if (hdr) { for (i = 1; i < NF; i++) if ($i !~ /^-?[0-9.]+(e[-+]?[0-9]+)?$/) { print NR ": " $i; exit }; if ($NF !~ /^(beyond180|crossing|beyond180,crossing)?$/) { print NR ": warning " $NF; exit } } else hdr = 1 }' "$out/trajectory.tsv")
    if [ -n "$bad" ]; then echo "not ok $n - $name: not a finite number at line $bad"; return; fi
    rows=$(grep -v '^#' "$out/trajectory.tsv" | tail -n +2 | wc -l)
    for f in $(sed -n 's/.*file="\([^"]*\)".*/\1/p' "$out/shapes.pvd"); do
        if [ ! -s "$out/$f" ]; then echo "not ok $n - $name: shapes.pvd names missing $f"; return; fi
    done
    nshape=$(grep -c 'file=' "$out/shapes.pvd")
    if [ ! -s "$out/study.cfg" ] || [ ! -s "$out/stats.csv" ]; then echo "not ok $n - $name: study.cfg or stats.csv missing"; return; fi
    if [ $have_gnuplot = 1 ] && [ ! -s "$out/trajectory.png" ]; then echo "not ok $n - $name: no trajectory.png"; return; fi
    if ls "$out"/*.tmp >/dev/null 2>&1; then echo "not ok $n - $name: temporary files left"; return; fi
    echo "ok $n - $name: $rows rows, $nshape shapes"
}
check_run 1 snap1-dynamics snap1-dynamics 1 1
check_run 2 selffold3-dynamics selffold3-dynamics 3 2

# 3: the snap lands folded up (theta > 1.8 rad) and the self-folding strip
# settles before its final time with the outer folds near their rest angle
last() { awk -F'\t' -v c="$2" '!/^#/ { if (!h) { for (i = 1; i <= NF; i++) col[$i] = i; h = 1; next } v = $col[c] } END { print v }' "$1"; }
th=$(last "$tmp/snap1-dynamics/trajectory.tsv" theta1)
tend=$(last "$tmp/selffold3-dynamics/trajectory.tsv" t)
th1=$(last "$tmp/selffold3-dynamics/trajectory.tsv" theta1)
if awk -v a="$th" -v t="$tend" -v b="$th1" 'BEGIN { exit !(a > 1.8 && t < 6.0 && b > 0.95 && b < 1.05) }'; then
    echo "ok 3 - end states: snap theta1 = $th, self-folding settled at t = $tend with theta1 = $th1"
else
    echo "not ok 3 - end states: snap theta1 = $th, self-folding t = $tend, theta1 = $th1"
fi

# 4: smoothfold plot redraws a trajectory directory
if [ $have_gnuplot = 1 ]; then
    rm -f "$tmp/snap1-dynamics/trajectory.png"
    if "$bin" plot "$tmp/snap1-dynamics" >"$tmp/log" 2>&1 && [ -s "$tmp/snap1-dynamics/trajectory.png" ]; then
        echo "ok 4 - plot: $(cat "$tmp/log")"
    else
        echo "not ok 4 - plot: $(tr '\n' ' ' < "$tmp/log")"
    fi
else
    echo "ok 4 # SKIP gnuplot is not installed"
fi

# expect_fail N NAME MESSAGE ARGS...: exit status 1, one line naming the
# problem, nothing written (not even the directory)
expect_fail() {
    n=$1; name=$2; text=$3; shift 3
    err=$("$bin" run "$@" -q -o "$tmp/$name" 2>&1 >/dev/null); rc=$?
    lines=$(printf '%s\n' "$err" | wc -l)
    if [ $rc -ne 1 ]; then echo "not ok $n - $name: exit status $rc: $err"
    elif [ "$lines" -ne 1 ]; then echo "not ok $n - $name: $lines lines: $err"
    elif [ -e "$tmp/$name" ]; then echo "not ok $n - $name: output directory created"
    else case "$err" in *"$text"*) echo "ok $n - $name: $err";; *) echo "not ok $n - $name: $err";; esac
    fi
}
expect_fail 5 load-twice "analysis.load_schedule: the load is the parameter p here" \
    "$src/studies/strip3.cfg" --set 'analysis.type="dynamics"' --set analysis.duration=1.0 \
    --set 'analysis.load_schedule=({ t = 0.0; value = 1.0; })'
expect_fail 6 flat-loops "singular point of vertex loop closure" \
    "$src/studies/square4.cfg" --set 'analysis.type="dynamics"' --set analysis.duration=1.0
