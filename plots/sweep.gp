# sweep.gp - a map of one result column of a sweep over two varied keys.
# usage: gnuplot -c plots/sweep.gp DIR [COLUMN [XKEY [YKEY]]]
# reads DIR/sweep.tsv (smoothfold sweep); writes DIR/sweep.png and
# DIR/sweep.pdf.  Defaults: the "# map:" line of sweep.tsv (the first two
# varied keys and sweep.map, or lp_p / bp_p / end_probe1_uz).  Each variant
# is a square coloured by COLUMN; an open square is a variant without a
# value (e.g. no limit point on its path), a cross a variant whose run
# failed (status != 0).  With one varied key: COLUMN against it.  A key
# spanning more than a decade is drawn on a log scale.
dir = ARG1
file = dir . "/sweep.tsv"
set datafile separator "\t"
set datafile commentschars "#"
map = system(sprintf("awk '/^# map: / {print $3, $4, $5; exit}' '%s'", file))
col = (ARGC >= 2 && ARG2 ne "") ? ARG2 : word(map, 3)
xk = (ARGC >= 3 && ARG3 ne "") ? ARG3 : word(map, 1)
yk = (ARGC >= 4 && ARG4 ne "") ? ARG4 : word(map, 2)
header = system(sprintf("awk '!/^#/ {print; exit}' '%s'", file))
cn(name) = sum [i = 1:words(header)] (word(header, i) eq name ? i : 0)
cx = cn(xk); cy = cn(yk); cc = cn(col); cs = cn("status")
if (cx == 0 || cc == 0) {
    print sprintf("sweep.gp: %s: no column '%s' or '%s'", file, xk, col)
    exit status 1
}
distinct(c) = int(system(sprintf("awk -F'\t' '!/^#/ && n++ {v[$%d]} END {print length(v)}' '%s'", c, file)))
nx = distinct(cx)
ny = cy > 0 ? distinct(cy) : 1
failed(c) = strcol(cs) eq "0" ? NaN : column(c)
set grid
set xlabel xk noenhanced
study = system(sprintf("sed -n '1s/.*(study \\(.*\\))$/\\1/p' '%s'", file))
set title sprintf("%s sweep (%s): %s", study, dir, col) noenhanced
stats file using (column(cx)) nooutput
if (STATS_min > 0 && STATS_max > 50 * STATS_min) { set logscale x }
do for [t in "pngcairo pdfcairo"] {
    if (t eq "pngcairo") { set terminal pngcairo size 1000,700 enhanced font ",11"; set output dir . "/sweep.png" }
    else { set terminal pdfcairo size 6.5in,4.5in enhanced font ",10"; set output dir . "/sweep.pdf" }
    if (cy == 0) {
        set ylabel col noenhanced
        set key top left
        plot file using (column(cx)):(column(cc)) with linespoints pt 7 lw 1.5 title col noenhanced, \
             file using (column(cx)):(failed(cc)) with points pt 2 ps 2 lc rgb "red" title "run failed"
    } else {
        stats file using (column(cy)) nooutput
        if (STATS_min > 0 && STATS_max > 50 * STATS_min) { set logscale y }
        set ylabel yk noenhanced
        set cblabel col noenhanced
        set palette rgbformulae 33,13,10
        set offsets graph 0.04, graph 0.04, graph 0.04, graph 0.04
        set bmargin 6
        set key at screen 0.45, 0.03 center horizontal
        ps = 25.0 / (nx > ny ? nx : ny) + 0.8
        plot file using (column(cx)):(column(cy)) with points pt 4 ps ps lc rgb "gray50" title "no value", \
             file using (column(cx)):(column(cy)):(column(cc)) with points pt 5 ps ps lc palette notitle, \
             file using (column(cx)):(failed(cy)) with points pt 2 ps ps lw 2 lc rgb "black" title "run failed"
    }
    unset output
}
