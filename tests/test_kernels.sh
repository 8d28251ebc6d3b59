#!/bin/sh
# test_kernels.sh - results do not depend on rounding: the same studies
# under OpenBLAS's Haswell, SkylakeX and Prescott kernels
# (OPENBLAS_CORETYPE; those this CPU runs) give the same exit status, the
# same number of points on the same branches, the same stability verdict
# and Morse index on every row, and the same states (p, probes, energy,
# fold angles) to 1e-8 of each quantity's largest magnitude.  Where a
# study switches branches (square4-inplane), the points after a located
# branch point sit where the location's tolerance put them along the same
# curve: there the rows agree to 1e-6 and each branch's last point (p = the
# end of the range, or where the branch stops) to 1e-8.  Then the
# numerical tests of the start, stability and bifurcations run again under
# one kernel other than the environment's (Prescott, which every x86-64
# CPU runs; Haswell where the environment asks for Prescott).  Output is
# TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
build=${SF_BUILDDIR:-.}
. "$src/tests/tap.sh"
studies="square4 miura-2x2 yoshimura-2x2 waterbomb-2x2 twist square4-inplane"
again="test_start.sh test_stab_cert test_stability test_bifurcation test_multibp"
n1=0; for s in $studies; do n1=$((n1 + 1)); done
n2=0; for t in $again; do n2=$((n2 + 1)); done
echo "1..$((n1 + 1 + n2))"
# the kernels: the environment's and every other one the CPU has
flags=$(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null)
case "$(uname -m)" in
    x86_64) ;;
    *)  k=0; while [ $k -lt $((n1 + 1 + n2)) ]; do k=$((k + 1)); echo "ok $k # SKIP not x86-64: no OpenBLAS kernels to choose"; done; exit 0;;
esac
envk=${OPENBLAS_CORETYPE:-}
kernels=Prescott
case " $flags " in *" avx2 "*) kernels="$kernels Haswell";; esac
case " $flags " in *" avx512f "*) kernels="$kernels SkylakeX";; esac
others=
for k in $kernels; do [ "$k" != "$envk" ] && others="$others $k"; done

# cmp A B: "rows worst_rows worst_last mismatch" of two branch.tsv files:
# the largest difference over all rows and over each branch's last row,
# each relative to the largest magnitude of its quantity (probes together,
# fold angles together), and the first mismatch of a verdict column
cmp_runs() {
    awk -F'\t' '
    function grp(n) { if (n ~ /^probe/) return "probe"; if (n ~ /^theta/) return "theta"; return n }
    function num(x) { return x ~ /^[-+0-9.eE]+$/ }
    /^#/ { next }
    $1 == "point" { if (FNR == NR) for (k = 1; k <= NF; k++) name[k] = $k; next }
    $1 == "" { next }
    FNR == NR { na++; nf = NF; br[na] = $2
        for (k = 1; k <= NF; k++) { a[na, k] = $k; v = $k < 0 ? -$k : $k; g = grp(name[k]); if (num($k) && v > sc[g]) sc[g] = v }
        next }
    { nb++; if (nb > na) next
      last = (nb == na || br[nb + 1] != br[nb])
      for (k = 1; k <= NF; k++) {
          n = name[k]
          if (n == "branch" || n == "stable" || n == "morse" || n == "type") { if (a[nb, k] != $k && mis == "") mis = n " of point " $1 ": " a[nb, k] " / " $k; continue }
          if (n != "p" && n != "energy" && n !~ /^(probe|theta)/) continue
          s = sc[grp(n)]; if (!(s > 0)) s = 1
          d = a[nb, k] - $k; if (d < 0) d = -d; d /= s
          if (d > w) w = d
          if (last && d > wl) wl = d
      } }
    END { if (mis == "") mis = "-"; printf "%d/%d %.2g %.2g %s\n", na, nb, w, wl, mis }' "$1" "$2"
}

for s in $studies; do
    ref=
    for k in ${envk:-default} $others; do
        if [ "$k" = default ]; then
            env -u OPENBLAS_CORETYPE "$bin" run "$src/studies/$s.cfg" -q -o "$tmp/$s-$k" >/dev/null 2>&1
        else
            OPENBLAS_CORETYPE=$k "$bin" run "$src/studies/$s.cfg" -q -o "$tmp/$s-$k" >/dev/null 2>&1
        fi
        echo $? >"$tmp/$s-$k.rc"
        [ -z "$ref" ] && ref=$k
    done
    bad=; worst=0; worstl=0
    for k in $others; do
        [ "$(cat "$tmp/$s-$k.rc")" = "$(cat "$tmp/$s-$ref.rc")" ] || bad="$bad; exit $(cat "$tmp/$s-$ref.rc") under $ref, $(cat "$tmp/$s-$k.rc") under $k"
        if [ -f "$tmp/$s-$ref/branch.tsv" ] && [ -f "$tmp/$s-$k/branch.tsv" ]; then
            set -- $(cmp_runs "$tmp/$s-$ref/branch.tsv" "$tmp/$s-$k/branch.tsv")
            rows=$1; w=$2; wl=$3; shift 3; mis=$*
            case $rows in */*) [ "${rows%/*}" = "${rows#*/}" ] || bad="$bad; points $rows under $ref/$k";; esac
            [ "$mis" = "-" ] || bad="$bad; $mis under $ref/$k"
            worst=$(awk -v a="$worst" -v b="$w" 'BEGIN {print (b > a ? b : a)}')
            worstl=$(awk -v a="$worstl" -v b="$wl" 'BEGIN {print (b > a ? b : a)}')
        else
            bad="$bad; no branch.tsv under $ref or $k"
        fi
    done
    lim=1e-8; [ "$s" = square4-inplane ] && lim=1e-6
    if [ -z "$bad" ] && awk -v w="$worst" -v wl="$worstl" -v l="$lim" 'BEGIN {exit !(w <= l && wl <= 1e-8)}'; then
        ok "$s under ${envk:-default}$others: same exit and points, verdicts equal, states to $worst (every row) and $worstl (each branch's last point)"
    else
        nok "$s under ${envk:-default}$others:${bad:- states differ by $worst (every row), $worstl (last points)}"
    fi
done
# the issue's case: the 2x2 Miura actuation of bench/miura-study.sh, whose
# symmetric start has two mirror branches of equal energy
sh "$src/bench/miura-study.sh" 2 >"$tmp/m2.cfg"
bad=; worst=0; ref=
for k in ${envk:-default} $others; do
    if [ "$k" = default ]; then
        env -u OPENBLAS_CORETYPE "$bin" run "$tmp/m2.cfg" -q -o "$tmp/m2-$k" --set analysis.end=1 >/dev/null 2>&1
    else
        OPENBLAS_CORETYPE=$k "$bin" run "$tmp/m2.cfg" -q -o "$tmp/m2-$k" --set analysis.end=1 >/dev/null 2>&1
    fi
    echo $? >"$tmp/m2-$k.rc"
    [ -z "$ref" ] && ref=$k && continue
    [ "$(cat "$tmp/m2-$k.rc")" = "$(cat "$tmp/m2-$ref.rc")" ] || bad="$bad; exit differs under $k"
    set -- $(cmp_runs "$tmp/m2-$ref/branch.tsv" "$tmp/m2-$k/branch.tsv")
    [ "${1%/*}" = "${1#*/}" ] || bad="$bad; points $1 under $k"
    [ "$4" = "-" ] || bad="$bad; a verdict differs under $k"
    worst=$(awk -v a="$worst" -v b="$2" 'BEGIN {print (b > a ? b : a)}')
done
if [ -z "$bad" ] && awk -v w="$worst" 'BEGIN {exit !(w <= 1e-8)}'; then
    ok "miura 2x2 actuation (symmetric start) under ${envk:-default}$others: the same mirror branch, states to $worst"
else
    nok "miura 2x2 actuation under ${envk:-default}$others:${bad:- states differ by $worst}"
fi
# the numerical tests again, under one other kernel
second=Prescott
[ "$envk" = Prescott ] && second=Haswell
for t in $again; do
    res=
    for k in $second; do
        case $t in
            *.sh) out=$(OPENBLAS_CORETYPE=$k sh "$src/tests/$t" 2>&1); st=$?
                  echo "$out" | grep -q '^not ok' && st=1;;
            *)    out=$(OPENBLAS_CORETYPE=$k "$build/tests/$t" 2>&1); st=$?;;
        esac
        [ $st = 0 ] || res="$res $k"
    done
    if [ -z "$res" ]; then
        ok "$t passes under $second"
    else
        nok "$t fails under$res"
    fi
done
