# angles.gp - fold angles against the parameter along an equilibrium path.
# usage: gnuplot -c plots/angles.gp DIR      (reads DIR/branch.tsv)
# writes DIR/angles.png and DIR/angles.pdf, one curve per fold.
dir = ARG1
file = dir . "/branch.tsv"
set datafile separator "\t"
set datafile commentschars "#"
set grid
set key outside right
set xlabel "p"
set ylabel "fold angle [rad]"
set title sprintf("%s: fold angles", dir) noenhanced
# number of folds: columns named theta1, theta2, ... at the end of the header
header = system(sprintf("grep -v '^#' '%s/branch.tsv' | head -1", dir))
nf = 0
do for [i = 1:words(header)] { if (word(header, i)[1:5] eq "theta") { nf = nf + 1 } }
do for [t in "pngcairo pdfcairo"] {
    if (t eq "pngcairo") { set terminal pngcairo size 900,600 enhanced font ",11"; set output dir . "/angles.png" }
    else { set terminal pdfcairo size 6in,4in enhanced font ",10"; set output dir . "/angles.pdf" }
    plot for [j = 1:nf] file using (column("p")):(column(sprintf("theta%d", j))) every ::1 with lines lw 1.5 title sprintf("fold %d", j)
    unset output
}
