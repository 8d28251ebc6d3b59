# path.gp - load-displacement diagram of an equilibrium path.
# usage: gnuplot -c plots/path.gp DIR [PROBE] [COMPONENT]
#   DIR        a `smoothfold run` output directory (reads DIR/branch.tsv)
#   PROBE      probe number, from 1 (default 1)
#   COMPONENT  ux, uy or uz (default uz)
# writes DIR/path.png and DIR/path.pdf: the parameter p against the probe
# displacement (mm), one curve per branch block, special points marked.
dir = ARG1
probe = (ARGC >= 2) ? ARG2 : "1"
comp = (ARGC >= 3) ? ARG3 : "uz"
file = dir . "/branch.tsv"
col = "probe" . probe . "_" . comp
set datafile separator "\t"
set datafile commentschars "#"
set key autotitle columnhead
set grid
set xlabel sprintf("probe %s %s [mm]", probe, comp)
set ylabel "p (load factor)"
set title sprintf("%s: equilibrium path", dir) noenhanced
do for [t in "pngcairo pdfcairo"] {
    if (t eq "pngcairo") { set terminal pngcairo size 900,600 enhanced font ",11"; set output dir . "/path.png" }
    else { set terminal pdfcairo size 6in,4in enhanced font ",10"; set output dir . "/path.pdf" }
    plot file using (1000*column(col)):(column("p")) with linespoints lw 2 pt 7 ps 0.6 title "smoothfold", \
         file using (1000*column(col)):(strcol("type") ne "-" && strcol("type") ne "EP" ? column("p") : NaN):(strcol("type")) \
              with labels offset 1,1 point pt 6 ps 2 notitle
    unset output
}
