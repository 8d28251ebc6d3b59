# boundary.gp - two-parameter stability diagram of a boundary run.
# usage: gnuplot -c plots/boundary.gp DIR
#   DIR  a `smoothfold run` output directory of an analysis.type = "boundary"
#        study (reads DIR/boundary.tsv)
# writes DIR/boundary.png and DIR/boundary.pdf: the second parameter (x)
# against the path parameter p (y), the curve of limit points (LP) or branch
# points (BP), the regions it separates shaded, cusps (CP) and the start
# point (SP, the special point of the path) labelled.
# Shading (docs/guides/stability.md):
#   BP curve, or LP curve without a cusp: the side of the curve where the
#     path started (header "start_side") is where the followed state is as
#     at the start (stable when "start_morse" is 0); the other side is
#     where it is unstable (BP) or gone (LP).
#   LP curve with a cusp: the region between the two fold curves that meet
#     in the cusp has three equilibria, two of them stable (bistable); the
#     rest of the plane has one.
dir = ARG1
file = dir . "/boundary.tsv"
set datafile separator "\t"
set datafile commentschars "#"
hdr(key) = system(sprintf("awk -F': ' '/^# %s: /{print $2; exit}' '%s'", key, file))
kind = hdr("kind"); second = hdr("second"); side = hdr("start_side"); pname = hdr("parameter")
morse0 = hdr("start_morse"); ncusp = int(hdr("cusps") . "0") / 10
header = system(sprintf("awk '!/^#/ {print; exit}' '%s'", file))
cn(name) = sum [i = 1:words(header)] (word(header, i) eq name ? i : 0)
cq = cn("second"); cp = cn("p"); ct = cn("type")
if (cq == 0 || cp == 0) { print sprintf("boundary.gp: %s has no columns second and p", file); exit status 1 }
stats file using cq:cp nooutput
xlo = STATS_min_x; xhi = STATS_max_x; ylo = STATS_min_y; yhi = STATS_max_y
dy = (yhi > ylo) ? 0.15 * (yhi - ylo) : 0.5
dx = (xhi > xlo) ? 0.03 * (xhi - xlo) : 0.5
ylo = ylo - dy; yhi = yhi + dy; xlo = xlo - dx; xhi = xhi + dx
set xrange [xlo:xhi]; set yrange [ylo:yhi]
set grid front
set key below
set xlabel second noenhanced
set ylabel sprintf("p: %s", pname) noenhanced
start_state = (morse0 eq "0") ? "stable" : sprintf("Morse index %s", morse0)
if (kind eq "LP" && ncusp > 0) {
    lab_in = (morse0 eq "0") ? "bistable: 3 equilibria, 2 stable" : "3 equilibria"
    lab_out = (morse0 eq "0") ? "one stable equilibrium" : "one equilibrium"
} else {
    lab_in = sprintf("followed state %s (as at the start)", start_state)
    lab_out = (kind eq "BP") ? "followed state unstable (it branches)" : "followed state gone (it snaps)"
}
set title sprintf("%s: %s curve over %s", dir, kind, second) noenhanced
spec(v) = (strcol(ct) eq "CP" || strcol(ct) eq "SP") ? v : NaN
lim_in = (side eq "below") ? ylo : yhi
lim_out = (side eq "below") ? yhi : ylo
do for [t in "pngcairo pdfcairo"] {
    if (t eq "pngcairo") { set terminal pngcairo size 1000,650 enhanced font ",11"; set output dir . "/boundary.png" }
    else { set terminal pdfcairo size 6.5in,4.2in enhanced font ",10"; set output dir . "/boundary.pdf" }
    if (kind eq "LP" && ncusp > 0) {
        set object 1 rectangle from graph 0, graph 0 to graph 1, graph 1 behind fillcolor rgb "#d8ecd8" fillstyle solid 1.0 noborder
        plot file using cq:cp with filledcurves closed fillcolor rgb "#bcd4ee" fillstyle solid 1.0 title lab_in, \
             NaN with filledcurves fillcolor rgb "#d8ecd8" fillstyle solid 1.0 title lab_out, \
             file using cq:cp with lines lw 2.5 lc rgb "black" title kind . " curve", \
             file using cq:(spec(column(cp))):(strcol(ct)) with labels offset 0,1.2 point pt 7 ps 1.3 lc rgb "black" notitle
        unset object 1
    } else {
        plot file using cq:cp:(lim_in) with filledcurves fillcolor rgb "#d8ecd8" fillstyle solid 1.0 title lab_in, \
             file using cq:cp:(lim_out) with filledcurves fillcolor rgb "#f3c9a8" fillstyle solid 1.0 title lab_out, \
             file using cq:cp with lines lw 2.5 lc rgb "black" title kind . " curve", \
             file using cq:(spec(column(cp))):(strcol(ct)) with labels offset 0,1.2 point pt 7 ps 1.3 lc rgb "black" notitle
    }
    unset output
}
