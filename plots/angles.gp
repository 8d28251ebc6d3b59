# angles.gp - fold angles against the parameter, for every branch of a run.
# usage: gnuplot -c plots/angles.gp DIR      (reads DIR/branch.tsv)
# writes DIR/angles.png and DIR/angles.pdf: one colour per fold; branch 1
# solid, further branches (branch switching) in other dash patterns;
# unstable states drawn thin.
dir = ARG1
file = dir . "/branch.tsv"
set datafile separator "\t"
set datafile commentschars "#"
set grid
set key outside right
set xlabel "p"
set ylabel "fold angle [rad]"
set title sprintf("%s: fold angles (thick: stable, thin: unstable)", dir) noenhanced
header = system(sprintf("awk '!/^#/ {print; exit}' '%s'", file))
cn(name) = sum [i = 1:words(header)] (word(header, i) eq name ? i : 0)
cp = cn("p"); cs = cn("stable"); ct1 = cn("theta1")
nf = 0
do for [i = 1:words(header)] { if (word(header, i)[1:5] eq "theta") { nf = nf + 1 } }
nb = int(system(sprintf("awk -F'\t' '!/^#/ && NF > 2 && $2 ~ /^[0-9]+$/ {b = $2} END {print b + 0}' '%s'", file)))
if (nb < 1) { nb = 1 }
stab(v) = (cs > 0 && strcol(cs) eq "0") ? NaN : v
do for [t in "pngcairo pdfcairo"] {
    if (t eq "pngcairo") { set terminal pngcairo size 1000,650 enhanced font ",11"; set output dir . "/angles.png" }
    else { set terminal pdfcairo size 6.5in,4.2in enhanced font ",10"; set output dir . "/angles.pdf" }
    plot for [b = 0:nb-1] for [j = 1:nf] file index b using (column(cp)):(column(ct1 + j - 1)) with lines lw 1 dt b%5+1 lc j \
             title (b == 0 ? sprintf("fold %d", j) : ""), \
         for [b = 0:nb-1] for [j = 1:nf] file index b using (column(cp)):(stab(column(ct1 + j - 1))) with lines lw 2.5 dt b%5+1 lc j notitle
    unset output
}
