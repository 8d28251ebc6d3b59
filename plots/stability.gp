# stability.gp - stability diagram of the equilibrium branches of a run.
# usage: gnuplot -c plots/stability.gp DIR [PROBE] [COMPONENT]
#   DIR        a `smoothfold run` output directory (reads DIR/branch.tsv)
#   PROBE      probe number, from 1 (default 1)
#   COMPONENT  ux, uy or uz (default uz)
# writes DIR/stability.png and DIR/stability.pdf: the parameter p against
# the probe displacement (mm), one colour per branch (branch.tsv blocks),
# stable states solid, unstable ones dashed (the `stable` column), limit
# and branch points (LP, BP) marked and labelled.
dir = ARG1
probe = (ARGC >= 2) ? ARG2 : "1"
comp = (ARGC >= 3) ? ARG3 : "uz"
file = dir . "/branch.tsv"
col = "probe" . probe . "_" . comp
set datafile separator "\t"
set datafile commentschars "#"
set grid
set key outside right
set xlabel sprintf("probe %s %s [mm]", probe, comp)
set ylabel "p"
set title sprintf("%s: stability diagram (solid: stable, dashed: unstable)", dir) noenhanced
# number of branches: the `branch` column of the last row
nb = int(system(sprintf("awk -F'\t' '!/^#/ && NF > 2 && $2 ~ /^[0-9]+$/ {b = $2} END {print b + 0}' '%s'", file)))
if (nb < 1) { nb = 1 }
# columns by name (gnuplot reads column headers only in the first block)
header = system(sprintf("awk '!/^#/ {print; exit}' '%s'", file))
cn(name) = sum [i = 1:words(header)] (word(header, i) eq name ? i : 0)
cx = cn(col); cp = cn("p"); cs = cn("stable"); ct = cn("type")
if (cx == 0) { print sprintf("stability.gp: %s has no column %s", file, col); exit status 1 }
stab(v) = (cs > 0 && strcol(cs) eq "0") ? NaN : v
spec(v) = (strcol(ct) eq "LP" || strcol(ct)[1:2] eq "BP") ? v : NaN
do for [t in "pngcairo pdfcairo"] {
    if (t eq "pngcairo") { set terminal pngcairo size 1000,650 enhanced font ",11" dashlength 2; set output dir . "/stability.png" }
    else { set terminal pdfcairo size 6.5in,4.2in enhanced font ",10" dashlength 2; set output dir . "/stability.pdf" }
    # each branch dashed along its whole length, then solid over its stable
    # stretches, so unstable stretches (and stable-unstable transitions) stay dashed
    plot for [b = 0:nb-1] file index b using (1000*column(cx)):(column(cp)) with lines lw 2 dt 2 lc b+1 title sprintf("branch %d", b+1), \
         for [b = 0:nb-1] file index b using (1000*column(cx)):(stab(column(cp))) with lines lw 2.5 dt 1 lc b+1 notitle, \
         for [b = 0:nb-1] file index b using (1000*column(cx)):(spec(column(cp))):(strcol(ct)) with labels offset 1.2,0.8 point pt 7 ps 1.2 lc rgb "black" notitle
    unset output
}
