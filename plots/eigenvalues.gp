# eigenvalues.gp - the smallest eigenvalues of the constrained Hessian
# against the parameter, for every branch of a run.
# usage: gnuplot -c plots/eigenvalues.gp DIR      (reads DIR/branch.tsv)
# writes DIR/eigenvalues.png and DIR/eigenvalues.pdf: one panel per
# eigenvalue (eig1..eigN, at most 6), each on a linear axis in its real
# unit (J per unit of the coordinates: J/rad^2 for fold angles), one colour
# per branch, the zero line drawn: a zero crossing is a change of stability
# (limit or branch point).  `smoothfold plot` passes sf_title (study name)
# and sf_plabel (what p is) from DIR/study.cfg.
dir = ARG1
file = dir . "/branch.tsv"
title0 = exists("sf_title") ? sf_title : dir
plabel = exists("sf_plabel") ? sf_plabel : "p"
set datafile separator "\t"
set datafile commentschars "#"
header = system(sprintf("awk '!/^#/ {print; exit}' '%s'", file))
cn(name) = sum [i = 1:words(header)] (word(header, i) eq name ? i : 0)
cp = cn("p")
ne = 0
do for [i = 1:words(header)] { if (word(header, i)[1:3] eq "eig") { ne = ne + 1 } }
if (ne == 0) { print sprintf("eigenvalues.gp: %s has no eigenvalue columns (analysis.stability = false): no plot", file); exit }
ce1 = cn("eig1")
# columns with at least one value (a problem with fewer coordinates than
# analysis.eigenvalues leaves the last ones empty)
ne = int(system(sprintf("awk -F'\t' -v c=%d -v n=%d '!/^#/ && NF > 2 && $1 ~ /^[0-9]+$/ { for (j = n; j > m; j--) if ($(c + j - 1) != \"\") { m = j; break } } END { print m + 0 }' '%s'", ce1, ne, file)))
if (ne == 0) { print sprintf("eigenvalues.gp: %s has no eigenvalues: no plot", file); exit }
nshow = (ne > 6) ? 6 : ne
nb = int(system(sprintf("awk -F'\t' '!/^#/ && NF > 2 && $2 ~ /^[0-9]+$/ {b = $2} END {print b + 0}' '%s'", file)))
if (nb < 1) { nb = 1 }
ev(c) = (strcol(c) eq "") ? NaN : column(c)
ncol = (nshow <= 2) ? 1 : 2
nrow = (nshow + ncol - 1) / ncol
do for [t in "pngcairo pdfcairo"] {
    if (t eq "pngcairo") { set terminal pngcairo size 1100,300+260*nrow enhanced font ",10"; set output dir . "/eigenvalues.png" }
    else { set terminal pdfcairo size 7in,(1.2+1.9*nrow)*1in enhanced font ",8"; set output dir . "/eigenvalues.pdf" }
    set multiplot layout nrow,ncol title sprintf("%s: smallest eigenvalues of the constrained Hessian%s", \
        title0, ne > nshow ? sprintf(" (first %d of %d)", nshow, ne) : "") noenhanced
    set grid
    set xzeroaxis lt -1 lw 1.5
    set format y "%.3g"
    set xlabel plabel noenhanced
    do for [j = 1:nshow] {
        set ylabel sprintf("eig%d [J]", j)
        if (j == 1) { set key top left opaque box samplen 3 } else { unset key }
        # an eigenvalue constant along the path: a range of 1 % around it
        # (gnuplot's own autoscale warns about an empty range)
        set autoscale y
        lohi = system(sprintf("awk -F'\t' -v c=%d '!/^#/ && NF > 2 && $1 ~ /^[0-9]+$/ && $c != \"\" " . \
            "{ v = $c + 0; if (n++ == 0 || v < lo) lo = v; if (n == 1 || v > hi) hi = v } " . \
            "END { printf \"%%.17g %%.17g\", lo, hi }' '%s'", ce1 + j - 1, file))
        lo = real(word(lohi, 1)); hi = real(word(lohi, 2))
        if (lo == hi) {
            d = (lo != 0) ? 0.01 * abs(lo) : 1
            set yrange [lo - d:hi + d]
        }
        plot for [b = 0:nb-1] file index b using (column(cp)):(ev(ce1 + j - 1)) with linespoints lw 1.5 pt 7 ps 0.35 lc b+1 \
             title sprintf("branch %d", b+1)
    }
    unset multiplot
    unset output
}
