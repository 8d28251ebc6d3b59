# angles.gp - fold angles against the parameter, for every branch of a run.
# usage: gnuplot -c plots/angles.gp DIR      (reads DIR/branch.tsv)
# writes DIR/angles.png and DIR/angles.pdf.  Branch 1 solid, further
# branches (branch switching) in other dash patterns; unstable states thin.
# Up to 8 folds drawn: one colour each, named in the key.  More: coloured
# by actuation group (grey: in no group), or, without groups, by the sign
# of the angle in the most folded state of the run (the two families of a
# folding pattern, mountain and valley); the key lists the groups.
# `smoothfold plot` passes from DIR/study.cfg: sf_title, sf_plabel, sf_folds
# (fold names), sf_fgroup (group of each fold, from 1; 0 none), sf_groups
# (group names) and, with --folds, sf_select (fold numbers to draw).
dir = ARG1
file = dir . "/branch.tsv"
title0 = exists("sf_title") ? sf_title : dir
plabel = exists("sf_plabel") ? sf_plabel : "p"
set datafile separator "\t"
set datafile commentschars "#"
set grid
set key outside right samplen 4 noenhanced
set xlabel plabel noenhanced
set ylabel "fold angle [rad]"
header = system(sprintf("awk '!/^#/ {print; exit}' '%s'", file))
cn(name) = sum [i = 1:words(header)] (word(header, i) eq name ? i : 0)
cp = cn("p"); cs = cn("stable"); ct1 = cn("theta1")
nf = 0
do for [i = 1:words(header)] { if (word(header, i)[1:5] eq "theta") { nf = nf + 1 } }
nb = int(system(sprintf("awk -F'\t' '!/^#/ && NF > 2 && $2 ~ /^[0-9]+$/ {b = $2} END {print b + 0}' '%s'", file)))
if (nb < 1) { nb = 1 }
# the folds drawn
sel = ""
if (exists("sf_select")) { sel = sf_select } else { do for [j = 1:nf] { sel = sel . sprintf(" %d", j) } }
ns = words(sel)
fnum(k) = int(word(sel, k))
fname(j) = (exists("sf_folds") && words(sf_folds) >= j) ? word(sf_folds, j) : sprintf("fold %d", j)
ngr = exists("sf_groups") ? words(sf_groups) : 0
fgrp(j) = (ngr > 0 && words(sf_fgroup) >= j) ? int(word(sf_fgroup, j)) : 0
# sign of every fold angle in the most folded state of the run (largest
# sum of |angles|): the two families when there are many folds and no groups
signs = system(sprintf("awk -F'\t' -v c=%d -v n=%d '!/^#/ && NF > 2 && $1 ~ /^[0-9]+$/ { a = 0; for (j = 0; j < n; j++) a += ($(c + j) < 0) ? -$(c + j) : $(c + j); if (a > best) { best = a; for (j = 0; j < n; j++) v[j] = $(c + j) } } END { for (j = 0; j < n; j++) printf \"%%s \", (v[j] < 0) ? 2 : 1 }' '%s'", ct1, nf, file))
family(j) = int(word(signs, j))
many = (ns > 8)
colour(j) = !many ? 0 : (ngr > 0 ? (fgrp(j) > 0 ? fgrp(j) : 0) : family(j))
pal(i) = int(word("9699539 40563 5682409 15113984 15787074 29362 15015440 0", (i - 1) % 8 + 1))
lcol(k) = many ? (colour(fnum(k)) == 0 ? 10066329 : pal(colour(fnum(k)))) : pal(k)
stab(v) = (cs > 0 && strcol(cs) eq "0") ? NaN : v
set title sprintf("%s: fold angles (thick: stable, thin: unstable)%s", title0, \
    ns < nf ? sprintf(", %d of %d folds", ns, nf) : "") noenhanced
do for [t in "pngcairo pdfcairo"] {
    if (t eq "pngcairo") { set terminal pngcairo size 1100,650 enhanced font ",11"; set output dir . "/angles.png" }
    else { set terminal pdfcairo size 7in,4.2in enhanced font ",10"; set output dir . "/angles.pdf" }
    if (!many) {
        plot for [b = 0:nb-1] for [k = 1:ns] file index b using (column(cp)):(column(ct1 + fnum(k) - 1)) with lines lw 1 dt b%5+1 lc rgb lcol(k) \
                 title (b == 0 ? fname(fnum(k)) : ""), \
             for [b = 0:nb-1] for [k = 1:ns] file index b using (column(cp)):(stab(column(ct1 + fnum(k) - 1))) with lines lw 2.5 dt b%5+1 lc rgb lcol(k) notitle, \
             for [b = 0:(nb > 1 ? nb-1 : -1)] keyentry with lines lw 2 dt b%5+1 lc rgb "black" title sprintf("branch %d", b+1)
    } else {
        plot for [b = 0:nb-1] for [k = 1:ns] file index b using (column(cp)):(column(ct1 + fnum(k) - 1)) with lines lw 0.8 dt b%5+1 lc rgb lcol(k) notitle, \
             for [b = 0:nb-1] for [k = 1:ns] file index b using (column(cp)):(stab(column(ct1 + fnum(k) - 1))) with lines lw 1.8 dt b%5+1 lc rgb lcol(k) notitle, \
             for [g = 1:(ngr > 0 ? ngr : 2)] keyentry with lines lw 3 lc rgb pal(g) \
                 title (ngr > 0 ? "group " . word(sf_groups, g) : (g == 1 ? "angle > 0 when most folded" : "angle < 0 when most folded")), \
             for [g = 1:(ngr > 0 ? 1 : 0)] keyentry with lines lw 3 lc rgb 10066329 title "no group", \
             for [b = 0:(nb > 1 ? nb-1 : -1)] keyentry with lines lw 2 dt b%5+1 lc rgb "black" title sprintf("branch %d", b+1)
    }
    unset output
}
