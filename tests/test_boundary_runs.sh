#!/bin/sh
# test_boundary_runs.sh - two-parameter continuation (analysis.type = "boundary",
# docs/guides/stability.md) against closed forms.
#  - fold1-buckle-boundary: the branch point of the flat strip over the fold
#    width, p_cr(w) = D L / (w (0.03 - w/6)) / 1.5 (studies/
#    fold1-buckle-boundary.cfg), at every point, to 1e-8 relative.
#  - snap1-boundary: the limit point over the fold modulus E: from the fold
#    angle t of each point, the closed form k(E) + P f''(t) = 0 gives E and
#    theta0 = t + P f'(t) / k gives p (f(t) = w sin(t)/t + b cos t, k = D L / w,
#    studies/snap1-boundary.cfg), to 1e-8; the cusp where f'''(t) = 0:
#    t = 0, p = 0, k = P (b + w/3).
# Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "1..8"
# rows of a table as "name=value" per column, for awk -v
rows() { grep -v '^#' "$1"; }

# fold material of both studies: D / E = h^3 / (12 (1 - nu^2))
D1='h = 1.8e-3; nu = 0.45; D1 = h * h * h / (12 * (1 - nu * nu))'

# 1: fold1-buckle-boundary against the closed form
if "$bin" run "$src/studies/fold1-buckle-boundary.cfg" -o "$tmp/b1" -q >"$tmp/log1" 2>&1; then
    msg=$(rows "$tmp/b1/boundary.tsv" | awk -F'\t' "BEGIN { $D1 }"'
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        { w = $c["second"]; p = $c["p"]; want = 15.2e6 * D1 * 0.03 / (w * (0.03 - w / 6)) / 1.5
          d = (p - want) / want; if (d < 0) d = -d; if (d > worst) { worst = d; at = w }
          m = $c["mu"]; if (m < 0) m = -m; if (m > mumax) mumax = m
          if (NR == 2) w0 = w; w1 = w; n++ }
        END { if (n < 20) print n " points"
              else if (worst > 1e-8) printf "p off the closed form by %.3g (relative) at w = %g\n", worst, at
              else if (w0 != 0.004 || w1 != 0.03) printf "curve from w = %g to %g, expected 0.004 to 0.03\n", w0, w1
              else if (mumax > 1e-12) printf "mu up to %g, expected 0 (symmetric branch point)\n", mumax
              else printf "ok %d %.2g\n", n, worst }')
    case $msg in
    ok*) set -- $msg; echo "ok 1 - fold1-buckle-boundary: $2 points on p_cr(w) = k/(b + w/3)/P, w = 4 .. 30 mm, max rel. error $3 (< 1e-8)" ;;
    *) echo "not ok 1 - fold1-buckle-boundary: $msg" ;;
    esac
else
    echo "not ok 1 - fold1-buckle-boundary: run failed: $(cat "$tmp/log1")"
fi

# 2: the flat state is stable on the curve apart from the critical eigenvalue
msg=$(rows "$tmp/b1/boundary.tsv" 2>/dev/null | awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["morse"] != "0" { bad++ } { n++ } END { print (n > 0 && !bad) ? "ok" : bad + 0 " of " n + 0 " points" }')
[ "$msg" = ok ] && echo "ok 2 - fold1-buckle-boundary: Morse index 0 besides the critical eigenvalue along the curve" \
    || echo "not ok 2 - fold1-buckle-boundary: Morse index not 0 at $msg"

# 3-5: snap1-boundary
SNAP="$D1; P = 1.5; w = 0.01; b = 0.025; L = 0.03"
FUN='
function f1(t) { return (t < 1e-2 && t > -1e-2) ? w * (-t / 3 + t^3 / 30 - t^5 / 840) - b * sin(t) \
                       : w * (t * cos(t) - sin(t)) / (t * t) - b * sin(t) }
function f2(t) { return (t < 1e-2 && t > -1e-2) ? w * (-1 / 3 + t * t / 10 - t^4 / 168) - b * cos(t) \
                       : w * (2 * sin(t) - 2 * t * cos(t) - t * t * sin(t)) / (t * t * t) - b * cos(t) }
function abs(x) { return x < 0 ? -x : x }'
if "$bin" run "$src/studies/snap1-boundary.cfg" -o "$tmp/b2" -q >"$tmp/log2" 2>&1; then
    msg=$(rows "$tmp/b2/boundary.tsv" | awk -F'\t' "$FUN BEGIN { $SNAP }"'
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        { E = $c["second"]; p = $c["p"]; t = $c["theta1"]
          Ew = -P * f2(t) * w / (D1 * L); k = E * D1 * L / w; pw = t + P * f1(t) / k
          d = abs(E - Ew) / Ew; if (d > worstE) { worstE = d; atE = E }
          d = abs(p - pw); if (d > worstp) { worstp = d; atp = E }
          if (p > 0) np++; if (p < 0) nn++; n++ }
        END { if (n < 20) print n " points"
              else if (worstE > 1e-8) printf "E off the closed form by %.3g (relative) at E = %g\n", worstE, atE
              else if (worstp > 1e-8) printf "theta0 off the closed form by %.3g at E = %g\n", worstp, atp
              else if (np < 5 || nn < 5) printf "%d points with p > 0, %d with p < 0: the curve did not pass the cusp\n", np, nn
              else printf "ok %d %.2g %.2g\n", n, worstE, worstp }')
    case $msg in
    ok*) set -- $msg; echo "ok 3 - snap1-boundary: $2 limit points on the closed form over E (rel. error in E $3, in theta0 $4 rad)" ;;
    *) echo "not ok 3 - snap1-boundary: $msg" ;;
    esac
else
    echo "not ok 3 - snap1-boundary: run failed: $(cat "$tmp/log2")"
fi
msg=$(rows "$tmp/b2/boundary.tsv" 2>/dev/null | awk -F'\t' "$FUN BEGIN { $SNAP }"'
    NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["type"] == "CP" { ncp++; E = $c["second"]; p = $c["p"]; t = $c["theta1"] }
    END { Ec = P * (b + w / 3) * w / (D1 * L)
          if (ncp != 1) print ncp + 0 " cusps, expected 1"
          else if (abs(E - Ec) > 1e-8 * Ec || abs(p) > 1e-8 || abs(t) > 1e-8)
              printf "cusp at E = %.12g, p = %g, t = %g; expected E = %.12g, p = t = 0\n", E, p, t, Ec
          else printf "ok %.10g %.10g\n", E, Ec }')
case $msg in
ok*) set -- $msg; echo "ok 4 - snap1-boundary: cusp at E = $2 Pa, closed form P (b + w/3) w / (D/E L) = $3 Pa, p = t = 0" ;;
*) echo "not ok 4 - snap1-boundary: $msg" ;;
esac
# the two fold curves are mirror images: first and last points (E = 8e6)
msg=$(rows "$tmp/b2/boundary.tsv" 2>/dev/null | awk -F'\t' 'function abs(x) { return x < 0 ? -x : x }
    NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    NR == 2 { E0 = $c["second"]; p0 = $c["p"] } { E1 = $c["second"]; p1 = $c["p"] }
    END { if (E0 == 8e6 && E1 == 8e6 && abs(p0 + p1) < 1e-9 && abs(p0) > 0.1) print "ok " p0
          else printf "ends at E = %g, p = %g and E = %g, p = %g\n", E0, p0, E1, p1 }')
case $msg in
ok*) echo "ok 5 - snap1-boundary: the curve ends on both mirror fold curves at E = 8e6 Pa (p = +-${msg#ok })" ;;
*) echo "not ok 5 - snap1-boundary: $msg" ;;
esac

# 6: smoothfold plot draws the diagram
if ! command -v gnuplot >/dev/null 2>&1; then
    echo "ok 6 # SKIP gnuplot not installed"
elif SMOOTHFOLD_PLOTS="$src/plots" "$bin" plot "$tmp/b2" >"$tmp/log3" 2>&1 && [ -s "$tmp/b2/boundary.png" ] && [ -s "$tmp/b2/boundary.pdf" ]; then
    echo "ok 6 - smoothfold plot: boundary.png and boundary.pdf"
else
    echo "not ok 6 - smoothfold plot: $(cat "$tmp/log3")"
fi

# 7: a second parameter that is not a numeric key: one line naming it, no output
"$bin" run "$src/studies/snap1-boundary.cfg" -o "$tmp/b3" -q --set 'analysis.second="materials.fold.name"' >"$tmp/log4" 2>&1
rc=$?
if [ $rc -ne 0 ] && [ "$(wc -l <"$tmp/log4")" -eq 1 ] && grep -q 'analysis.second' "$tmp/log4" && [ ! -e "$tmp/b3" ]; then
    echo "ok 7 - bad analysis.second: exit $rc, $(cat "$tmp/log4")"
else
    echo "not ok 7 - bad analysis.second: exit $rc, output: $(cat "$tmp/log4")"
fi

# 8: the second parameter may be any numeric key: snap1's limit point over
# the load factor (analysis.load) has its cusp where the load is the
# buckling load of the flat strip, k / (b + w/3) / P (fold1-buckle's branch
# point), with t = 0 and theta0 = 0
if "$bin" run "$src/studies/snap1-boundary.cfg" -o "$tmp/b5" -q --set 'analysis.second="analysis.load"' \
        --set analysis.second_min=0.3 --set analysis.second_max=2.0 >"$tmp/log5" 2>&1; then
    msg=$(rows "$tmp/b5/boundary.tsv" | awk -F'\t' "$FUN BEGIN { $SNAP }"'
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        $c["type"] == "CP" { ncp++; q = $c["second"]; p = $c["p"]; t = $c["theta1"] }
        END { want = 15.2e6 * D1 * L / w / (b + w / 3) / P
              if (ncp != 1) print ncp + 0 " cusps, expected 1"
              else if (abs(q - want) > 1e-9 * want || abs(p) > 1e-8 || abs(t) > 1e-8)
                  printf "cusp at load %.12g, p = %g, t = %g; expected %.12g, 0, 0\n", q, p, t, want
              else printf "ok %.12g %.12g\n", q, want }')
    case $msg in
    ok*) set -- $msg; echo "ok 8 - snap1-boundary over analysis.load: cusp at load factor $2, closed form k/(b + w/3)/P = $3" ;;
    *) echo "not ok 8 - snap1-boundary over analysis.load: $msg" ;;
    esac
else
    echo "not ok 8 - snap1-boundary over analysis.load: run failed: $(cat "$tmp/log5")"
fi
