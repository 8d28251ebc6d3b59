#!/bin/sh
# sample.sh - the equilibrium path of a study at fixed parameter values, as
# a reference file (CSV with a provenance header, docs/reference/study-keys.md):
# probe displacements, fold angles and energy SOLVED at fixed p (Newton at
# that p, through the reference-comparison feature), not interpolated, so
# the values do not depend on where the continuation happened to step.
#
# usage: tests/regress/sample.sh SMOOTHFOLD STUDY.cfg OUT.csv [NOTE] [--set KEY=VALUE]...
#
# Sample points: each branch (block of branch.tsv) is cut into pieces
# monotone in p (limit points separate them); on each piece p at 1/8, 2/8,
# ... 7/8 of the way through its range (away from turning points, where a
# fixed-p solve is ill-conditioned), plus the first point of the path and
# the last point of every branch.  Rows follow the path, branch by branch.
# branch.tsv is read by column NAME (p, probe*_u*, theta*, energy; other
# columns ignored).
set -e
bin=$1; study=$2; out=$3; note=${4:-}
shift 3; [ $# -gt 0 ] && shift
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin" run "$study" -q -o "$tmp/run" --set output.shapes=0 --set 'references=()' "$@"
# 1. approximate template: linear interpolation of the computed points
awk -F'\t' -v OFS=',' '
    /^#/ { next }
    !hdr { for (i = 1; i <= NF; i++) if ($i == "p" || $i ~ /^probe[0-9]+_u[xyz]$/ || $i ~ /^theta[0-9]+$/ || $i == "energy") { c[++nc] = i; name[nc] = $i; if ($i == "p") cp = nc }
           hdr = 1; next }
    NF == 0 { if (n > bstart[nb]) { bend[nb] = n; nb++; bstart[nb] = n + 1 } ; next }
    { if (!nb) { nb = 1; bstart[1] = 1 } ; n++; for (k = 1; k <= nc; k++) v[n, k] = $c[k] }
    function emit(a, b, t,   k, line) {
        line = ""
        for (k = 1; k <= nc; k++) line = line (k > 1 ? "," : "") sprintf("%.15g", v[a, k] + t * (v[b, k] - v[a, k]))
        print line
    }
    function sample(a, b,   lo, hi, f, x, i, t) {   # piece from point a to point b
        lo = v[a, cp]; hi = v[b, cp]
        if (lo == hi) return
        for (f = 0.125; f < 0.9; f += 0.125) {
            x = lo + f * (hi - lo)
            for (i = a; i < b; i++)
                if ((x - v[i, cp]) * (x - v[i + 1, cp]) <= 0 && v[i + 1, cp] != v[i, cp]) {
                    t = (x - v[i, cp]) / (v[i + 1, cp] - v[i, cp]); emit(i, i + 1, t); break
                }
        }
    }
    END {
        if (n > bstart[nb] - 1) bend[nb] = n; else nb--
        line = ""; for (k = 1; k <= nc; k++) line = line (k > 1 ? "," : "") name[k]; print line
        for (bk = 1; bk <= nb; bk++) {
            f = bstart[bk]; l = bend[bk]
            if (bk == 1) emit(f, f, 0)        # later branches start at a point of an earlier one
            a = f; dir = 0
            for (i = f + 1; i <= l; i++) {
                d = v[i, cp] - v[i - 1, cp]; if (d == 0) continue
                s = d > 0 ? 1 : -1
                if (dir && s != dir) { sample(a, i - 1); a = i - 1 }
                dir = s
            }
            sample(a, l)
            emit(l, l, 0)
        }
    }' "$tmp/run/branch.tsv" > "$tmp/body.csv"
{ echo "# template"; echo "# source: linear interpolation"; echo "# kind: simulated"; echo "# units: as branch.tsv"; cat "$tmp/body.csv"; } > "$tmp/template.csv"
cols=$(head -1 "$tmp/body.csv" | tr ',' '\n' | grep -v '^p$' | awk '{printf "%s{ column = \"%s\"; measure = \"absolute\"; }", (NR > 1 ? ", " : ""), $1}')
# 2. the values solved at those p
"$bin" run "$study" -q -o "$tmp/run2" --set output.shapes=0 "$@" \
    --set "references=( { name = \"sample\"; file = \"$tmp/template.csv\"; abscissa = { column = \"p\"; }; columns = ( $cols ); } )"
awk -F'\t' '/^#/ || NF == 0 { next } $1 == "reference" { next } $10 == "interpolated" { bad++ } END { if (bad) { print "sample.sh: " bad " values could not be solved at fixed p (interpolated)" > "/dev/stderr"; exit 1 } }' "$tmp/run2/compare-points.tsv"
version=$("$bin" --version | head -1)
name=$(sed -n 's/^ *name *= *"\([^"]*\)".*/\1/p' "$tmp/run2/study.cfg" | head -1)
{
    echo "# $name: equilibrium path at fixed parameter values (stored results for regression tests)"
    echo "# source: $version, study $(basename "$study")${*:+ with $*}; values solved at each p by"
    echo "#   Newton at fixed p (reference-comparison feature), sampled by tests/regress/sample.sh${note:+; $note}"
    echo "# kind: simulated (results of the program itself: a regression baseline, not a validation)"
    echo "# units: p as analysis.parameter (load factor, actuation factor or m), probe displacements m,"
    echo "#   fold angles rad, energy J"
    echo "# columns: $(head -1 "$tmp/body.csv" | sed 's/,/, /g')"
    head -1 "$tmp/body.csv"
    # rows in template order, each column's solved value
    awk -F'\t' -v OFS=',' '
        FNR == NR { if (FNR > 1) { n++; split($0, f, ","); p[n] = f[1] } ; if (FNR == 1) nc = split($0, hn, ","); next }
        /^#/ || NF == 0 || $1 == "reference" { next }
        { key = $2; row[key]++; val[key, row[key]] = $7 }
        END {
            for (i = 1; i <= n; i++) {
                line = sprintf("%.15g", p[i])
                for (k = 2; k <= nc; k++) line = line "," sprintf("%.15g", val[hn[k], i])
                print line
            }
        }' "$tmp/body.csv" "$tmp/run2/compare-points.tsv"
} > "$out.tmp"
mv "$out.tmp" "$out"
