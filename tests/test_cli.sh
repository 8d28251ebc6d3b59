#!/bin/sh
# test_cli.sh - the command line as a new user meets it (issue 14): usage
# errors exit 2 with one line under the name "smoothfold:", each command has
# its own --help, `shape` writes only what its extension says, and a failed
# write gives its reason.  Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..25"
n=0
ok() { n=$((n + 1)); echo "ok $n - $1"; }
notok() { n=$((n + 1)); echo "not ok $n - $1"; }
# usage N NAME STATUS TEXT ARGS...: exit status, one line on stderr that
# starts with "smoothfold: " and holds TEXT, nothing on stdout
usage() {
    name=$1; want=$2; text=$3; shift 3
    "$bin" "$@" >"$tmp/out" 2>"$tmp/err"; rc=$?
    lines=$(wc -l <"$tmp/err")
    case "$rc:$lines:$(cat "$tmp/err")" in
        "$want:1:smoothfold: "*"$text"*) [ -s "$tmp/out" ] && notok "$name: wrote on stdout" || ok "$name: $(cat "$tmp/err")";;
        *) notok "$name: status $rc (want $want), $lines lines: $(cat "$tmp/err")";;
    esac
}
s3="$src/studies/strip3.cfg"
usage "no command" 2 "missing command"
usage "run without -o" 2 "give the output directory with -o" run "$s3"
usage "shape without -o" 2 "give the output file with -o" shape "$s3"
usage "plot without DIR" 2 "plot: expected DIR" plot
usage "compare with one DIR" 2 "compare: expected DIR_A DIR_B" compare "$tmp"
usage "check with two files" 2 "check: expected STUDY.cfg" check "$s3" "$s3"
usage "unknown command" 2 "unknown command 'chek'" chek "$s3"
usage "unknown long option" 2 "unknown option '--bogus'" check "$s3" --bogus
usage "unknown short option" 2 "unknown option '-x'" -x check "$s3"
usage "option without value" 2 "option '--set' needs a value" check "$s3" --set
# per-command help: its own usage line and options, status 0, on stdout
for c in check shape run plot compare; do
    out=$("$bin" "$c" --help 2>&1); rc=$?
    case "$rc:$out" in
        "0:Usage: smoothfold $c "*) ok "$c --help: $(printf '%s\n' "$out" | head -1)";;
        *) notok "$c --help: status $rc: $(printf '%s\n' "$out" | head -1)";;
    esac
done
if "$bin" run --help | grep -q -- "--force" && ! "$bin" check --help | grep -q -- "--angles" &&
   "$bin" --help | grep -q "^Commands"; then
    ok "run --help names --force, check --help does not name --angles, --help lists the commands"
else
    notok "help texts"
fi
# shape: only .vtp; another extension is refused, listing the supported one, no file
for ext in vtk vtu; do
    "$bin" shape "$s3" -o "$tmp/s.$ext" >"$tmp/out" 2>"$tmp/err"; rc=$?
    if [ $rc -eq 1 ] && grep -q "supported: .vtp" "$tmp/err" && [ ! -e "$tmp/s.$ext" ] &&
       [ ! -e "$tmp/s.$ext.tmp" ] && [ "$(wc -l <"$tmp/err")" -eq 1 ]; then
        ok "shape -o s.$ext refused: $(cat "$tmp/err")"
    else
        notok "shape -o s.$ext: status $rc, $(cat "$tmp/err"), files: $(ls "$tmp")"
    fi
done
if "$bin" shape "$s3" -q -o "$tmp/s.vtp" 2>"$tmp/err" && head -2 "$tmp/s.vtp" | grep -q 'type="PolyData"'; then
    ok "shape -o s.vtp writes XML PolyData"
else
    notok "shape -o s.vtp: $(cat "$tmp/err")"
fi
# a write that fails (file size limit: the kernel's EFBIG, as a full disk
# gives ENOSPC) names the file and the reason, leaves no file behind
(trap '' XFSZ; ulimit -f 1; exec "$bin" shape "$src/studies/square4.cfg" -q -o "$tmp/big.vtp") \
    >"$tmp/out" 2>"$tmp/err"; rc=$?
if [ $rc -eq 4 ] && grep -q "big.vtp: write failed: File too large" "$tmp/err" &&
   [ ! -e "$tmp/big.vtp" ] && [ ! -e "$tmp/big.vtp.tmp" ]; then
    ok "failed write gives strerror: $(cat "$tmp/err")"
else
    notok "failed write: status $rc, '$(cat "$tmp/err")', files: $(ls "$tmp")"
fi
# with -o the same run succeeds
"$bin" run "$s3" -q --set output.shapes=0 -o "$tmp/r" >/dev/null 2>"$tmp/err"; rc=$?
[ $rc -eq 0 ] && ok "run with -o: status 0" || notok "run: status $rc: $(cat "$tmp/err")"
# --plot draws an equilibrium run's plots; --no-plot keeps a dynamics run
# from drawing its own
"$bin" run "$s3" -q --plot --set output.shapes=0 -o "$tmp/rp" >/dev/null 2>"$tmp/err"; rc=$?
if [ $rc -eq 0 ] && [ -s "$tmp/rp/stability.png" ] && [ -s "$tmp/rp/angles.png" ]; then
    ok "run --plot: stability.png, angles.png drawn"
else
    notok "run --plot: status $rc: $(cat "$tmp/err")"
fi
"$bin" run "$src/studies/snap1-dynamics.cfg" -q --no-plot --set output.shapes=0 -o "$tmp/dn" >/dev/null 2>"$tmp/err"; rc=$?
if [ $rc -eq 0 ] && [ -s "$tmp/dn/trajectory.tsv" ] && [ ! -e "$tmp/dn/trajectory.png" ]; then
    ok "dynamics run --no-plot: no trajectory.png"
else
    notok "dynamics --no-plot: status $rc: $(cat "$tmp/err"), $(ls "$tmp/dn")"
fi
# values far outside physical sense: one warning line each, status 0
out=$("$bin" check "$s3" --set 'folds[0].rest_angle=90' --set 'folds[1].width=1e-12' 2>&1 >/dev/null); rc=$?
if [ $rc -eq 0 ] && [ "$(printf '%s\n' "$out" | grep -c '^smoothfold: warning: ')" -eq 2 ] &&
   printf '%s' "$out" | grep -q "fold 1: rest_angle 90 rad is beyond pi" && printf '%s' "$out" | grep -q "fold 2: width 1e-12 m is below"; then
    ok "warnings for rest_angle = 90 and width = 1e-12 m, status 0"
else
    notok "warnings: status $rc: $out"
fi
out=$("$bin" check "$s3" 2>&1 >/dev/null)
[ -z "$out" ] && ok "no warning for strip3 as it is" || notok "strip3 warns: $out"
