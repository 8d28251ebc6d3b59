# vtp2gp.awk - a shape written by smoothfold (VTK XML PolyData, ASCII:
# src/io/vtk.c) as gnuplot polygon blocks: "x y z part" per corner, the
# first corner repeated, a blank line after each polygon.  part 0: a face,
# 1: a fold band cell.  Used by plots/shape.gp.
#   awk -f plots/vtp2gp.awk DIR/shapes/shape_0040.vtp > shape.dat
/<DataArray/ {
    sec = ""
    if ($0 ~ /NumberOfComponents="3"/ && !havepts && !inpd) sec = "pts"
    else if ($0 ~ /Name="part"/) sec = "part"
    else if ($0 ~ /Name="connectivity"/) sec = "conn"
    next
}
/<PointData/ { inpd = 1 }
/<\/PointData>/ { inpd = 0 }
/<\/DataArray>/ { if (sec == "pts") havepts = 1; sec = ""; next }
sec == "pts" { np += 0; x[np] = $1; y[np] = $2; z[np] = $3; np++; next }
sec == "part" { part[nc + 0] = $1; nc++; next }
sec == "conn" {
    k += 0
    for (i = 1; i <= NF; i++) printf "%.9g %.9g %.9g %d\n", x[$i], y[$i], z[$i], part[k]
    printf "%.9g %.9g %.9g %d\n\n", x[$1], y[$1], z[$1], part[k]
    k++
    next
}
