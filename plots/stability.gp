# stability.gp - stability diagram of the equilibrium branches of a run.
# usage: gnuplot -c plots/stability.gp DIR [PROBE] [COMPONENT]
#   DIR        a `smoothfold run` output directory (reads DIR/branch.tsv)
#   PROBE      probe number, from 1 (default 1)
#   COMPONENT  ux, uy or uz (default uz)
# writes DIR/stability.png and DIR/stability.pdf: the parameter p against
# the probe displacement (mm), one colour per branch (branch.tsv blocks),
# stable states solid, unstable ones dashed (the `stable` column), limit
# and branch points (LP, BP) marked, one label per place (points shared by
# several branches, e.g. a BP where a new branch starts, are labelled once).
# `smoothfold plot` passes, from DIR/study.cfg: sf_title (study name),
# sf_plabel (what p is, per load stage), sf_probes (probe names).
dir = ARG1
probe = (ARGC >= 2) ? ARG2 : "1"
comp = (ARGC >= 3) ? ARG3 : "uz"
file = dir . "/branch.tsv"
col = "probe" . probe . "_" . comp
title0 = exists("sf_title") ? sf_title : dir
plabel = exists("sf_plabel") ? sf_plabel : "p"
pname = (exists("sf_probes") && words(sf_probes) >= int(probe)) ? word(sf_probes, int(probe)) : "probe " . probe
set datafile separator "\t"
set datafile commentschars "#"
set grid
set key outside right samplen 6
set xlabel sprintf("%s: %s [mm]", pname, comp) noenhanced
set ylabel plabel noenhanced
set title sprintf("%s: stability diagram", title0) noenhanced
# number of branches: the `branch` column of the last row
nb = int(system(sprintf("awk -F'\t' '!/^#/ && NF > 2 && $2 ~ /^[0-9]+$/ {b = $2} END {print b + 0}' '%s'", file)))
if (nb < 1) { nb = 1 }
# columns by name (gnuplot reads column headers only in the first block)
header = system(sprintf("awk '!/^#/ {print; exit}' '%s'", file))
cn(name) = sum [i = 1:words(header)] (word(header, i) eq name ? i : 0)
cx = cn(col); cp = cn("p"); cs = cn("stable"); ct = cn("type")
if (cx == 0) { print sprintf("stability.gp: %s has no column %s", file, col); exit status 1 }
stab(v) = (cs > 0 && strcol(cs) eq "0") ? NaN : v
spec(v) = (ct > 0 && (strcol(ct) eq "LP" || strcol(ct)[1:2] eq "BP")) ? v : NaN
# special points: each drawn; one label per cluster of points closer than
# a label's size (1/25 of the p range, 1/12 of the x range), with the
# distinct types joined ("BP/BP2") and the number of points when several
spec = system(sprintf("awk -F'\t' -v cx=%d -v cp=%d -v ct=%d '" . \
  "!/^#/ && NF > 2 && $1 ~ /^[0-9]+$/ { x = 1000 * $cx; y = $cp; " . \
  "  if (n == 0 || x < x0) x0 = x; if (n == 0 || x > x1) x1 = x; if (n == 0 || y < y0) y0 = y; if (n == 0 || y > y1) y1 = y; n++; " . \
  "  if ($ct == \"LP\" || substr($ct, 1, 2) == \"BP\") { m++; X[m] = x; Y[m] = y; T[m] = $ct } } " . \
  "END { dx = (x1 - x0) / 12; dy = (y1 - y0) / 25; " . \
  "  for (i = 1; i <= m; i++) { if (D[i]) continue; t = T[i]; k = 1; " . \
  "    for (j = i + 1; j <= m; j++) if (!D[j] && (X[j] - X[i])^2 <= dx^2 + 1e-30 && (Y[j] - Y[i])^2 <= dy^2 + 1e-30) { D[j] = 1; k++; if (index(\"/\" t \"/\", \"/\" T[j] \"/\") == 0) t = t \"/\" T[j] } " . \
  "    if (k > 1) t = t \"(x\" k \")\"; printf \"%%.10g %%.10g %%s\\n\", X[i], Y[i], t } }' '%s'", cx, cp, ct, file))
nl = words(spec) / 3
do for [t in "pngcairo pdfcairo"] {
    if (t eq "pngcairo") { set terminal pngcairo size 1100,650 enhanced font ",11" dashlength 1; set output dir . "/stability.png" }
    else { set terminal pdfcairo size 7in,4.2in enhanced font ",10" dashlength 1; set output dir . "/stability.pdf" }
    unset label
    do for [i = 1:nl] {
        set label i word(spec, 3*i) at real(word(spec, 3*i-2)), real(word(spec, 3*i-1)) \
            offset 0.8,0.8 front noenhanced
    }
    # each branch dashed along its whole length, then solid over its stable
    # stretches, so unstable stretches (and stable-unstable transitions) stay
    # dashed; the key shows one colour per branch and the two line styles
    plot for [b = 0:nb-1] file index b using (1000*column(cx)):(column(cp)) with lines lw 2 dt (6,4) lc b+1 notitle, \
         for [b = 0:nb-1] file index b using (1000*column(cx)):(stab(column(cp))) with lines lw 2.5 dt 1 lc b+1 notitle, \
         for [b = 0:nb-1] keyentry with lines lw 4 dt 1 lc b+1 title sprintf("branch %d", b+1), \
         keyentry with lines lw 2.5 dt 1 lc rgb "black" title "stable", \
         keyentry with lines lw 2 dt (6,4) lc rgb "black" title "unstable", \
         for [b = 0:nb-1] file index b using (1000*column(cx)):(spec(column(cp))) with points pt 7 ps 1.1 lc rgb "black" \
             title (b == 0 && nl > 0 ? "LP, BP" : "")
    unset output
}
