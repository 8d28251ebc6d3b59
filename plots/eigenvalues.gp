# eigenvalues.gp - the smallest eigenvalues of the constrained Hessian
# against the parameter, for every branch of a run.
# usage: gnuplot -c plots/eigenvalues.gp DIR      (reads DIR/branch.tsv)
# writes DIR/eigenvalues.png and DIR/eigenvalues.pdf: eig1..eigN against p,
# one colour per branch, one point type per eigenvalue; a zero crossing is
# a change of stability (limit or branch point).  The y axis is linear
# near zero and logarithmic far from it (asinh scale), so small
# eigenvalues stay readable next to large ones.
dir = ARG1
file = dir . "/branch.tsv"
set datafile separator "\t"
set datafile commentschars "#"
set grid
set key outside right
set xlabel "p"
header = system(sprintf("awk '!/^#/ {print; exit}' '%s'", file))
cn(name) = sum [i = 1:words(header)] (word(header, i) eq name ? i : 0)
cp = cn("p")
ne = 0
do for [i = 1:words(header)] { if (word(header, i)[1:3] eq "eig") { ne = ne + 1 } }
if (ne == 0) { print sprintf("eigenvalues.gp: %s has no eigenvalue columns (analysis.stability = false): no plot", file); exit }
ce1 = cn("eig1")
nb = int(system(sprintf("awk -F'\t' '!/^#/ && NF > 2 && $2 ~ /^[0-9]+$/ {b = $2} END {print b + 0}' '%s'", file)))
if (nb < 1) { nb = 1 }
# scale: the smallest nonzero |eig1| sets the linear zone of asinh
e0 = real(system(sprintf("awk -F'\t' -v c=%d '!/^#/ && $c != \"\" && $c+0 == $c {v = ($c < 0) ? -$c : $c; if (v > 0 && (m == 0 || v < m)) m = v; if (v > M) M = v} END {e = M * 1e-3; print (e > 0) ? e : 1}' '%s'", ce1, file)))
f(x) = asinh(x / e0)
set ylabel sprintf("asinh(eig / %.3g J)", e0)
set title sprintf("%s: smallest eigenvalues of the constrained Hessian", dir) noenhanced
set xzeroaxis lt -1 lw 1.5
ev(c) = (strcol(c) eq "") ? NaN : f(column(c))
do for [t in "pngcairo pdfcairo"] {
    if (t eq "pngcairo") { set terminal pngcairo size 1000,650 enhanced font ",11"; set output dir . "/eigenvalues.png" }
    else { set terminal pdfcairo size 6.5in,4.2in enhanced font ",10"; set output dir . "/eigenvalues.pdf" }
    plot for [b = 0:nb-1] for [j = 1:ne] file index b using (column(cp)):(ev(ce1 + j - 1)) with linespoints lw 1.5 pt j ps 0.6 lc b+1 \
         title (j == 1 ? sprintf("branch %d", b+1) : "")
    unset output
}
