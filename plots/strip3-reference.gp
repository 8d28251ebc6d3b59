# strip3-reference.gp - the strip3 path against the reference data of
# ../shared/data: the paper's own code and 3-D shell / 2-D plane-strain
# finite elements.
# usage: gnuplot -c plots/strip3-reference.gp DIR DATADIR OUT.png
dir = ARG1; data = ARG2; out = ARG3
set terminal pngcairo size 900,600 enhanced font ",11"
set output out
set datafile commentschars "#"
set grid
set key bottom left
set xlabel "tip deflection -u_z [mm]"
set ylabel "tip load [N]"
set title "strip3: three smooth folds, tip load (CASES.md, fig. 15a)"
set datafile separator "\t"
set key autotitle columnhead
plot dir . "/branch.tsv" using (-1000*column("probe1_uz")):(0.2*column("p")) every ::1 \
        with linespoints lw 2 pt 7 ps 0.8 title "smoothfold (K = 0, exact arcs)", \
     "< tr , '\t' < " . data . "/strip3_paper_code.csv" using (-1000*column("probe1_uz")):(abs(column("load_N"))) \
        with points pt 6 ps 1.4 title "paper's MATLAB code" , \
     "< tr , '\t' < " . data . "/strip3_fe_shell.csv" using (-1000*column("probe1_uz")):(abs(column("load_N"))) \
        with lines dt 2 lw 2 title "3-D shell FE (CalculiX)"
