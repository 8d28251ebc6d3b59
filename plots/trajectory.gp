# trajectory.gp - a dynamics run against time.
# usage: gnuplot -c plots/trajectory.gp DIR     (reads DIR/trajectory.tsv)
# writes DIR/trajectory.png and DIR/trajectory.pdf, three panels sharing the
# time axis: the parameter p and the load factor; the displacement of every
# probe (ux, uy, uz in mm); every fold angle.
dir = ARG1
file = dir . "/trajectory.tsv"
set datafile separator "\t"
set datafile commentschars "#"
header = system(sprintf("awk '!/^#/ { print; exit }' '%s'", file))
nf = 0
np = 0
do for [i = 1:words(header)] {
    w = word(header, i)
    if (w[1:5] eq "theta") { nf = nf + 1 }
    if (w[1:5] eq "probe" && strstrt(w, "_uz") > 0) { np = np + 1 }
}
set grid
set key outside right
do for [term in "pngcairo pdfcairo"] {
    if (term eq "pngcairo") { set terminal pngcairo size 1000,900 enhanced font ",11"; set output dir . "/trajectory.png" }
    else { set terminal pdfcairo size 7in,6.3in enhanced font ",10"; set output dir . "/trajectory.pdf" }
    set multiplot layout 3,1 title sprintf("%s: trajectory", dir) noenhanced
    set lmargin 12
    set rmargin 22
    unset xlabel
    set ylabel "p, load"
    plot file using (column("t")):(column("p")) every ::1 with lines lw 2 title "p", \
         file using (column("t")):(column("load")) every ::1 with lines lw 1.5 dt 2 title "load"
    set ylabel "probe displacement [mm]"
    if (np > 0) {
        plot for [i = 1:np] for [c in "ux uy uz"] file using (column("t")):(1000*column(sprintf("probe%d_%s", i, c))) every ::1 \
             with lines lw 1.5 title sprintf("probe %d %s", i, c)
    } else {
        plot file using (column("t")):(column("energy")) every ::1 with lines lw 1.5 title "energy [J]"
    }
    set xlabel "t [s]"
    set ylabel "fold angle [rad]"
    plot for [j = 1:nf] file using (column("t")):(column(sprintf("theta%d", j))) every ::1 with lines lw 1.5 title sprintf("fold %d", j)
    unset multiplot
    unset output
}
