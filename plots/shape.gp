# shape.gp - draw one folded shape (a .vtp of smoothfold run) as shaded
# polygons: faces blue-grey, fold bands orange.
#   gnuplot -e "vtp='DIR/shapes/shape_0040.vtp'; out='shape.png'; ttl='...'" plots/shape.gp
# (plots/vtp2gp.awk turns the polygons into gnuplot blocks)
if (!exists("vtp")) { print "shape.gp: give vtp='FILE.vtp'"; exit }
if (!exists("out")) out = 'shape.png'
if (!exists("ttl")) ttl = ''
if (!exists("awkdir")) awkdir = 'plots'
if (!exists("view_rot")) view_rot = 30
if (!exists("view_tilt")) view_tilt = 55
set terminal pngcairo size 560,360 font ",10"
set output out
set title ttl
set view view_tilt, view_rot, 1.5, 1.0
set view equal xyz
unset key
unset border
unset tics
set pm3d depthorder
set style fill solid 1.0 border lc rgb "#404040"
faces = sprintf("< awk -f %s/vtp2gp.awk '%s' | awk 'NF == 0 || $4 == 0'", awkdir, vtp)
bands = sprintf("< awk -f %s/vtp2gp.awk '%s' | awk 'NF == 0 || $4 == 1'", awkdir, vtp)
splot faces using 1:2:3 with polygons fc rgb "#9fb8d0", \
      bands using 1:2:3 with polygons fc rgb "#e89a48"
