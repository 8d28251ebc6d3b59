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
again="test_start.sh test_flatstart.sh test_flatstart_sparse.sh test_run_exact.sh test_paths
       test_stab_cert test_stability test_stab_inertia.sh test_sstab test_bifurcation test_multibp"
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

# across NAME LIMIT CFG [--set ...]: CFG run under the environment's
# kernel and each other one, compared with the first run; one TAP line.
# LIMIT bounds the states on every row, 1e-8 bounds each branch's last row.
across() {
    name=$1; lim=$2; cfg=$3; shift 3
    ref=; bad=; worst=0; worstl=0
    for k in ${envk:-default} $others; do
        if [ "$k" = default ]; then
            env -u OPENBLAS_CORETYPE "$bin" run "$cfg" -q -o "$tmp/$name-$k" "$@" >/dev/null 2>&1
        else
            OPENBLAS_CORETYPE=$k "$bin" run "$cfg" -q -o "$tmp/$name-$k" "$@" >/dev/null 2>&1
        fi
        rc=$?
        if [ -z "$ref" ]; then ref=$k; rc0=$rc; continue; fi
        [ $rc = $rc0 ] || bad="$bad; exit $rc0 under $ref, $rc under $k"
        if [ -f "$tmp/$name-$ref/branch.tsv" ] && [ -f "$tmp/$name-$k/branch.tsv" ]; then
            read -r rows w wl mis <<CMP
$(cmp_runs "$tmp/$name-$ref/branch.tsv" "$tmp/$name-$k/branch.tsv")
CMP
            [ "${rows%/*}" = "${rows#*/}" ] || bad="$bad; points $rows under $ref/$k"
            [ "$mis" = "-" ] || bad="$bad; $mis under $ref/$k"
            worst=$(awk -v a="$worst" -v b="$w" 'BEGIN {print (b > a ? b : a)}')
            worstl=$(awk -v a="$worstl" -v b="$wl" 'BEGIN {print (b > a ? b : a)}')
        else
            bad="$bad; no branch.tsv under $ref or $k"
        fi
    done
    if [ -z "$bad" ] && awk -v w="$worst" -v wl="$worstl" -v l="$lim" 'BEGIN {exit !(w <= l && wl <= 1e-8)}'; then
        ok "$name under ${envk:-default}$others: same exit and points, verdicts equal, states to $worst (every row) and $worstl (each branch's last point)"
    else
        nok "$name under ${envk:-default}$others:${bad:- states differ by $worst (every row), $worstl (last points)}"
    fi
}

for s in $studies; do
    lim=1e-8; [ "$s" = square4-inplane ] && lim=1e-6
    across "$s" $lim "$src/studies/$s.cfg"
done
# the issue's case: the 2x2 Miura actuation of bench/miura-study.sh, whose
# symmetric start has two mirror branches of equal energy
sh "$src/bench/miura-study.sh" 2 >"$tmp/m2.cfg"
across "miura-2x2-actuation" 1e-8 "$tmp/m2.cfg" --set analysis.end=1
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
