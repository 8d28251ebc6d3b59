#!/bin/sh
# test_sweep.sh - `smoothfold sweep`, serially and under mpirun: the
# branch points of a two-key sweep of fold1-buckle against their closed
# form, a failing variant recorded with its status and reason, the MPI
# table identical to the serial one apart from wall_s, SIGTERM and resume
# (serial and MPI), the map, bad input.  Output is TAP.  The MPI tests run
# `mpirun -n 3 --oversubscribe` (skipped when smoothfold-sweep-mpi or
# mpirun is missing).
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..11"
# mpirun refuses root unless told (CI containers run as root)
if [ "$(id -u)" = 0 ]; then
    OMPI_ALLOW_RUN_AS_ROOT=1; OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    export OMPI_ALLOW_RUN_AS_ROOT OMPI_ALLOW_RUN_AS_ROOT_CONFIRM
fi
mpi=""
if [ -x "${bin}-sweep-mpi" ] && command -v mpirun >/dev/null 2>&1; then
    mpi="timeout 120 mpirun -n 3 --oversubscribe"
fi
study="$src/studies/fold1-buckle.cfg"
vary="--vary defaults.width=0.006,0.01,0.014,-0.01 --vary materials.fold.thickness=1.5e-3:2e-3:3"
# process ids of the variants running into directory $1 (their command
# line holds "$1/<index>"; the sweep's own holds "$1" only), from /proc
# in one grep: no procps needed
pids() {
    grep -l -a "$1/[0-9]" /proc/[0-9]*/cmdline 2>/dev/null | sed 's|^/proc/\([0-9]*\)/cmdline$|\1|'
}
# data rows of a sweep.tsv
rows() { grep -v '^#' "$1" | tail -n +2; }
# the table without its last column (wall_s), comments kept
untimed() { awk -F'\t' 'BEGIN { OFS = "\t" } /^#/ { print; next } { NF--; print }' "$1"; }

# 1: the first BP of every variant against the closed form of
# studies/fold1-buckle.cfg: P_cr = k / (b + w/3), k = D L / w,
# D = E h^3 / (12 (1 - nu^2)), L = 0.03 m, b = 0.03 - w/2 (band to load);
# bp_p = P_cr / 1.5 N, and no BP when that is beyond the path's end p = 1.
# Rows in product order (the last key fastest).
if "$bin" sweep "$study" $vary --set output.shapes=0 -o "$tmp/serial" >"$tmp/log1" 2>&1; then
    msg=$(grep -v '^#' "$tmp/serial/sweep.tsv" | awk -F'\t' '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        { n++; w = $c["defaults.width"]; h = $c["materials.fold.thickness"]
          ew = substr("0.006 0.01  0.014 -0.01 ", 6 * int((n - 1) / 3) + 1, 5) + 0
          eh = 1.5e-3 + 0.25e-3 * ((n - 1) % 3)
          if (w != ew || h != eh) bad = bad sprintf(" row %d: %s %s, expected %g %g", n, w, h, ew, eh)
          if (w < 0) next
          D = 15.2e6 * h^3 / (12 * (1 - 0.45^2)); k = D * 0.03 / w
          p = k / (0.03 - w / 2 + w / 3) / 1.5
          if ($c["status"] != 0) { bad = bad " row " n ": status " $c["status"]; next }
          if (p > 1) { if ($c["bp_p"] != "") bad = bad sprintf(" row %d: BP at %s beyond p = 1", n, $c["bp_p"]); next }
          nbp++; d = $c["bp_p"] / p - 1; if (d < 0) d = -d
          if ($c["bp_p"] == "" || d > 1e-8) bad = bad sprintf(" row %d: bp_p %s, expected %.12g", n, $c["bp_p"], p) }
        END { if (n != 12) print n " rows, expected 12"; else if (nbp < 5) print nbp " BPs compared, expected >= 5"; else if (bad != "") print bad; else print "ok" }')
    [ "$msg" = ok ] && echo "ok 1 - serial sweep: 12 variants, bp_p = P_cr/1.5 in closed form to 1e-8" \
        || echo "not ok 1 - serial sweep:$msg"
else
    echo "not ok 1 - serial sweep failed: $(cat "$tmp/log1")"
fi

# 2: the failing variants (width -0.01) are rows with status 1, the
# study's message, no results; the sweep itself succeeded
msg=$(rows "$tmp/serial/sweep.tsv" | awk -F'\t' '
    $2 == -0.01 { n++; if ($4 != 1 || $5 !~ /defaults.width: must be positive/ || $6 != 0 || $8 != "") bad = bad " [" $0 "]" }
    END { if (n != 3) print n " failing rows, expected 3"; else if (bad != "") print bad; else print "ok" }')
[ "$msg" = ok ] && grep -q "3 with a non-zero status" "$tmp/log1" \
    && echo "ok 2 - failing variant recorded: status 1 with its one-line reason" \
    || echo "not ok 2 - failing variant:$msg"

# 3: under mpirun -n 3 the same table apart from wall_s
if [ -z "$mpi" ]; then
    echo "ok 3 # SKIP smoothfold-sweep-mpi or mpirun missing"
elif $mpi "$bin" sweep "$study" $vary --set output.shapes=0 -o "$tmp/mpi" >"$tmp/log3" 2>&1 \
    && untimed "$tmp/serial/sweep.tsv" >"$tmp/a" && untimed "$tmp/mpi/sweep.tsv" >"$tmp/b" \
    && cmp -s "$tmp/a" "$tmp/b" && [ "$(rows "$tmp/mpi/sweep.tsv" | wc -l)" = 12 ]; then
    echo "ok 3 - mpirun -n 3: sweep.tsv identical to the serial one apart from wall_s"
else
    echo "not ok 3 - mpirun -n 3 sweep differs or failed: $(diff "$tmp/a" "$tmp/b" | head -5) $(tail -3 "$tmp/log3")"
fi

# 4: the map over the two keys (gnuplot)
if ! command -v gnuplot >/dev/null 2>&1; then
    echo "ok 4 # SKIP gnuplot missing"
elif SMOOTHFOLD_PLOTS="$src/plots" "$bin" plot "$tmp/serial" >"$tmp/log4" 2>&1 && [ -s "$tmp/serial/sweep.png" ] \
    && grep -q "^# map: defaults.width materials.fold.thickness bp_p$" "$tmp/serial/sweep.tsv"; then
    echo "ok 4 - smoothfold plot DIR draws the bp_p map over width and thickness"
else
    echo "not ok 4 - plot: $(cat "$tmp/log4")"
fi

# A sweep that takes a second or so: SIGTERM once a few variants are done.
# $1 = launcher ("" or mpirun ...), $2 = directory.  Prints the exit status.
long="--vary defaults.width=0.004:0.008:16 --vary materials.fold.E=1e6,2e6,4e6 --set output.shapes=0"
interrupt() {
    $1 "$bin" sweep "$src/studies/square4.cfg" $long -q -o "$2" >"$2.log" 2>&1 &
    pid=$!
    i=0
    while [ $i -lt 1500 ]; do   # up to 30 s: mpirun starts slowly on a loaded machine
        n=$(rows "$2/sweep.tsv" 2>/dev/null | wc -l)
        [ "$n" -ge 3 ] && break
        sleep 0.02; i=$((i + 1))
    done
    kill -TERM $pid
    wait $pid
    echo $?
}
# every row of a table has as many fields as its header, and the
# "finished" comment counts them; prints the count
complete() {
    grep -v '^#' "$1" | awk -F'\t' -v f="$(grep -c '^# finished: ' "$1")" '
        NR == 1 { nf = NF; next } { n++; if (NF != nf || $4 == "") bad = 1 }
        END { print (bad || f != 1) ? -1 : n + 0 }'
}

# 5: serial: SIGTERM leaves a complete table of the finished variants;
# the same command again runs only the others, and the whole table equals
# an uninterrupted sweep's apart from wall_s
st=$(interrupt "" "$tmp/kill")
k=$(complete "$tmp/kill/sweep.tsv")
grep -q "^# finished: $k of 48 " "$tmp/kill/sweep.tsv" && kk=ok || kk=bad
rows "$tmp/kill/sweep.tsv" >"$tmp/before"
"$bin" sweep "$src/studies/square4.cfg" $long -q -o "$tmp/kill" >"$tmp/log5" 2>&1
"$bin" sweep "$src/studies/square4.cfg" $long -q -o "$tmp/full" >/dev/null 2>&1
untimed "$tmp/kill/sweep.tsv" >"$tmp/a"; untimed "$tmp/full/sweep.tsv" >"$tmp/b"
if [ "$st" = 143 ] && [ "$kk" = ok ] && [ "$k" -ge 3 ] && [ "$k" -lt 48 ] \
    && grep -q "48 variants ($((48 - k)) run now, $k finished before)" "$tmp/log5" \
    && [ "$(rows "$tmp/kill/sweep.tsv" | grep -c -F -x -f "$tmp/before")" = "$k" ] && cmp -s "$tmp/a" "$tmp/b"; then
    echo "ok 5 - serial SIGTERM after $k of 48: complete table, exit 143; resumed to the uninterrupted table"
else
    echo "not ok 5 - serial kill/resume: exit $st, $k rows ($kk); $(cat "$tmp/log5") $(diff "$tmp/a" "$tmp/b" | head -3)"
fi

# 6: the same under mpirun -n 3: killed, then resumed under mpirun; no
# variant process is left behind
if [ -z "$mpi" ]; then
    echo "ok 6 # SKIP smoothfold-sweep-mpi or mpirun missing"
else
    st=$(interrupt "$mpi" "$tmp/mkill")
    k=$(complete "$tmp/mkill/sweep.tsv")
    # the ranks stop their variants on SIGTERM; on a loaded machine those
    # may take a moment to exit: wait up to 10 s for them to be gone
    i=0
    while [ $i -lt 100 ]; do
        left=$(pids "$tmp/mkill" | wc -l)
        [ "$left" = 0 ] && break
        sleep 0.1; i=$((i + 1))
    done
    k2=$(complete "$tmp/mkill/sweep.tsv")   # nothing recorded after the stop
    $mpi "$bin" sweep "$src/studies/square4.cfg" $long -q -o "$tmp/mkill" >"$tmp/log6" 2>&1
    untimed "$tmp/mkill/sweep.tsv" >"$tmp/a"
    if [ "$st" != 0 ] && [ "$k" -ge 3 ] && [ "$k" -lt 48 ] && [ "$left" = 0 ] && [ "$k2" = "$k" ] \
        && grep -q "48 variants ($((48 - k)) run now, $k finished before)" "$tmp/log6" && cmp -s "$tmp/a" "$tmp/b"; then
        echo "ok 6 - mpirun SIGTERM after $k of 48: complete table; resumed under mpirun to the serial table"
    else
        echo "not ok 6 - mpirun kill/resume: exit $st, $k rows ($k2 later), $left left running; $(tail -2 "$tmp/log6")"
    fi
fi

# 7: the study's sweep group gives the same variants as --vary (list mode:
# variant i takes the i-th value of every key)
grp='sweep = { vary = ["defaults.width=0.006,0.01", "materials.fold.thickness=1.5e-3,2e-3"]; mode = "list"; };'
"$bin" sweep "$study" --set "$grp" --set output.shapes=0 -q -o "$tmp/grp" >/dev/null 2>&1
"$bin" sweep "$study" --list --vary defaults.width=0.006,0.01 --vary materials.fold.thickness=1.5e-3,2e-3 \
    --set output.shapes=0 -q -o "$tmp/cli" >/dev/null 2>&1
a=$(rows "$tmp/grp/sweep.tsv" | cut -f1-3,6-20); b=$(rows "$tmp/cli/sweep.tsv" | cut -f1-3,6-20)
if [ -n "$a" ] && [ "$a" = "$b" ] && [ "$(echo "$a" | cut -f1-3 | tr '\t\n' ' ')" = "0 0.006 1.5e-3 1 0.01 2e-3 " ]; then
    echo "ok 7 - sweep group (list mode) = --list --vary"
else
    echo "not ok 7 - sweep group: [$a] vs [$b]"
fi

# 8: bad input: an unknown key, a malformed range, another sweep's directory
e1=$("$bin" sweep "$study" --vary defaults.widht=1,2 -o "$tmp/bad" 2>&1); s1=$?
e2=$("$bin" sweep "$study" --vary defaults.width=1:2 -o "$tmp/bad" 2>&1); s2=$?
e3=$("$bin" sweep "$study" --vary defaults.width=0.02 -o "$tmp/serial" 2>&1); s3=$?
if [ $s1 = 1 ] && [ $s2 = 1 ] && [ $s3 = 1 ] \
    && [ "$e1" = "smoothfold: --vary defaults.widht=1,2: unknown study key 'defaults.widht' (did you mean 'defaults.width'?)" ] \
    && [ "$e2" = "smoothfold: --vary defaults.width=1:2: expected KEY=START:STOP:N" ] \
    && echo "$e3" | grep -q "variants.tsv: $tmp/serial holds another sweep"; then
    echo "ok 8 - bad input: unknown key, bad range, another sweep's directory (status 1, one line)"
else
    echo "not ok 8 - bad input: [$s1 $e1] [$s2 $e2] [$s3 $e3]"
fi

# 9: START:STOP:N gives N values, ends exact, in the shortest exact text
"$bin" sweep "$study" --vary analysis.end=0.1:0.3:3 --set output.shapes=0 -q -o "$tmp/range" >/dev/null 2>&1
v=$(rows "$tmp/range/sweep.tsv" | cut -f2 | tr '\n' ' ')
[ "$v" = "0.1 0.2 0.3 " ] && echo "ok 9 - START:STOP:N values: $v" || echo "not ok 9 - range values: [$v]"

# 10: a variant that crashes (SIGSEGV sent to its process) is a row with
# status 139 and "killed by signal 11", and the sweep goes on
# (short steps make each variant live about a second, so the signal
# reaches a running process, not one already on its way out)
"$bin" sweep "$src/studies/square4.cfg" --vary defaults.width=0.004:0.008:6 --set output.shapes=0 -q \
    --set analysis.step=0.004 --set analysis.max_step=0.004 --set analysis.max_steps=100000 \
    -o "$tmp/crash" >"$tmp/log10" 2>&1 &
pid=$!
i=0
# poll without sleeping, and try again if the one found has just finished
while [ $i -lt 5000 ] && kill -0 $pid 2>/dev/null; do
    c=$(pids "$tmp/crash" | head -1)
    [ -n "$c" ] && kill -SEGV "$c" 2>/dev/null && break
    i=$((i + 1))
done
wait $pid; st=$?
msg=$(rows "$tmp/crash/sweep.tsv" | awk -F'\t' '$3 == 139 && $4 ~ /^killed by signal 11/ { k++ } $3 == 0 { ok++ }
    END { print k + 0, ok + 0 }')
[ $st = 0 ] && [ "$msg" = "1 5" ] && echo "ok 10 - crashed variant recorded (status 139, signal 11), the other 5 ran" \
    || echo "not ok 10 - crash: exit $st, [crashed ok] = [$msg] $(cat "$tmp/log10")"

# 11: a second sweep into a directory while the first still runs there is
# refused (DIR/sweep.lock), and the first is not disturbed
"$bin" sweep "$src/studies/square4.cfg" $long -q -o "$tmp/lock" >"$tmp/log11" 2>&1 &
pid=$!
i=0
while [ ! -f "$tmp/lock/sweep.tsv" ] && [ $i -lt 500 ]; do sleep 0.01; i=$((i + 1)); done
e=$("$bin" sweep "$src/studies/square4.cfg" $long -q -o "$tmp/lock" 2>&1); s2=$?
wait $pid; s1=$?
if [ $s1 = 0 ] && [ $s2 = 1 ] && echo "$e" | grep -q "sweep.lock: another sweep is running in $tmp/lock" \
    && [ "$(complete "$tmp/lock/sweep.tsv")" = 48 ]; then
    echo "ok 11 - a second sweep into a busy directory is refused (status 1); the first completes"
else
    echo "not ok 11 - lock: first exit $s1, second exit $s2: $e"
fi
