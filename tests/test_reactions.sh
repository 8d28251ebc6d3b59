#!/bin/sh
# test_reactions.sh - reactions.tsv of `smoothfold run`: sign and units of
# support reactions against statics in closed form, and the force of a
# prescribed displacement against load control of the same sheet.
# Studies: tests/studies/lever.cfg and tip.cfg (their headers give the
# closed forms).  Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..5"
# column value of the last data row (or of row number $3 when given) of a
# smoothfold table, by column name
col() { # file name [point]
    grep -v '^#' "$1" | awk -F'\t' -v c="$2" -v pt="${3:-}" '
        NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) k = i; next }
        pt == "" || $1 == pt { v = $k } END { if (k) printf "%.15g\n", v; else print "missing" }'
}

# 1: a point support under the tip of fold1 carries R_z = -f_z (0.058 -
# 0.03) / (0.06 - 0.03) at every load factor (f_z = -4 N), upwards
if "$bin" run "$src/tests/studies/lever.cfg" -o "$tmp/lever" -q >"$tmp/log" 2>&1; then
    msg=$(grep -v '^#' "$tmp/lever/reactions.tsv" | awk -F'\t' '
        NR == 1 { for (i = 1; i <= NF; i++) if ($i == "support1_z") k = i; next }
        { want = 4.0 * 28.0 / 30.0 * $2; d = $k - want; if (d < 0) d = -d
          if (d > 1e-9 * (1 + want)) bad = bad sprintf(" point %s: %s, expected %.12g", $1, $k, want); n++ }
        END { if (!k) print "no column support1_z"; else if (bad != "") print bad; else if (n != 6) print n " rows, expected 6"; else print "ok" }')
    [ "$msg" = ok ] && echo "ok 1 - lever: support1_z = 3.7333 N * p (statics)" || echo "not ok 1 - lever:$msg"
else
    echo "not ok 1 - lever: run failed: $(cat "$tmp/log")"
fi

# 2: the support holds: tip displacement and fold angle stay 0
uz=$(col "$tmp/lever/branch.tsv" probe1_uz); th=$(col "$tmp/lever/branch.tsv" theta1)
if awk -v a="$uz" -v b="$th" 'BEGIN { exit !(a != "missing" && (a < 0 ? -a : a) < 1e-12 && (b < 0 ? -b : b) < 1e-12) }'; then
    echo "ok 2 - lever: the held tip does not move (uz $uz m, theta $th rad)"
else
    echo "not ok 2 - lever: held tip moved: uz $uz m, theta $th rad"
fi

# 3, 4: tip load P under load control gives displacement U(P); prescribing
# U under displacement control needs the force P: probe1_fz = -P (the load
# is (0, 0, -1 N) times the load factor)
"$bin" run "$src/tests/studies/tip.cfg" -o "$tmp/load1" -q >"$tmp/log1" 2>&1
"$bin" run "$src/tests/studies/tip.cfg" --set analysis.end=0.5 -o "$tmp/load05" -q >>"$tmp/log1" 2>&1
n=3
for case in "load1 1" "load05 0.5"; do
    set -- $case
    U=$(col "$tmp/$1/branch.tsv" probe1_uz)
    if "$bin" run "$src/tests/studies/tip.cfg" --set analysis.parameter=\"displacement\" \
           --set analysis.probe=\"tip\" --set analysis.component=\"z\" --set analysis.load=0 \
           --set analysis.end="$U" --set analysis.step=0.002 -o "$tmp/disp$n" -q >"$tmp/log" 2>&1 &&
       [ -f "$tmp/disp$n/reactions.tsv" ]; then
        f=$(col "$tmp/disp$n/reactions.tsv" probe1_fz)
        p=$(col "$tmp/disp$n/reactions.tsv" p)
        if awk -v f="$f" -v P="$2" -v p="$p" -v U="$U" 'BEGIN { d = f + P; e = p - U
               exit !(f != "missing" && (d < 0 ? -d : d) < 1e-8 && (e < 0 ? -e : e) < 1e-12) }'; then
            echo "ok $n - tip: uz = $U m prescribed needs probe1_fz = $f N (load control: -$2 N)"
        else
            echo "not ok $n - tip: uz = $U m: probe1_fz = $f N at p = $p, expected -$2 N"
        fi
    else
        echo "not ok $n - tip: displacement run failed (load run: $(cat "$tmp/log1")): $(cat "$tmp/log")"
    fi
    n=$((n + 1))
done

# 5: no supports, no displacement parameter: no reactions.tsv
if [ -f "$tmp/load1/branch.tsv" ] && [ ! -e "$tmp/load1/reactions.tsv" ]; then
    echo "ok 5 - no supports: no reactions.tsv"
else
    echo "not ok 5 - reactions.tsv written without supports (or the load run failed)"
fi
