#!/bin/sh
# test_vtk.sh - `smoothfold shape` writes files that VTK's own XML reader
# (the one ParaView uses, python3-vtk9) parses, with the documented arrays,
# the expected numbers of cells, finite coordinates, and faces that stay
# rigid (edge lengths of every face body preserved).  Output is TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
bin=${SF_BUILDDIR:-.}/src/smoothfold
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
py=/usr/bin/python3
echo "1..4"
if ! $py -c "import vtk" 2>/dev/null; then
    for i in 1 2 3 4; do echo "not ok $i - python3-vtk9 is not installed (apt-get install python3-vtk9)"; done
    exit 0
fi
check() { # n name study angles nfaces nfolds samples
    n=$1; name=$2; study=$3; angles=$4; nf=$5; nfo=$6; ns=$7
    out="$tmp/$name.vtp"
    if ! "$bin" shape "$src/studies/$study.cfg" --angles="$angles" --set output.samples=$ns -o "$out" >"$tmp/log" 2>&1; then
        echo "not ok $n - $name: shape failed: $(cat "$tmp/log")"; return
    fi
    "$bin" shape "$src/studies/$study.cfg" --set output.samples=$ns -o "$tmp/flat.vtp" >/dev/null 2>&1
    msg=$($py - "$out" "$tmp/flat.vtp" "$nf" "$nfo" "$ns" <<'PY'
import sys, math, vtk
path, flat, nf, nfo, ns = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
def read(p):
    r = vtk.vtkXMLPolyDataReader(); r.SetFileName(p); r.Update()
    if r.GetErrorCode() != 0: print("reader error code", r.GetErrorCode()); sys.exit(1)
    return r.GetOutput()
d, d0 = read(path), read(flat)
want = nf + nfo * ns
if d.GetNumberOfCells() != want: print("cells", d.GetNumberOfCells(), "expected", want); sys.exit(1)
cd = d.GetCellData()
for name in ("part", "index", "fold_angle", "curvature"):
    if cd.GetArray(name) is None: print("missing cell array", name); sys.exit(1)
if d.GetPointData().GetArray("displacement") is None: print("missing displacement"); sys.exit(1)
pts = d.GetPoints(); p0 = d0.GetPoints()
for i in range(d.GetNumberOfPoints()):
    if not all(math.isfinite(c) for c in pts.GetPoint(i)): print("non-finite point", i); sys.exit(1)
# faces are rigid: every edge of every face polygon keeps its length
part = cd.GetArray("part")
worst = 0.0
for c in range(d.GetNumberOfCells()):
    if part.GetValue(c) != 0: continue
    ids = d.GetCell(c).GetPointIds(); n = ids.GetNumberOfIds()
    for k in range(n):
        a, b = ids.GetId(k), ids.GetId((k + 1) % n)
        l1 = math.dist(pts.GetPoint(a), pts.GetPoint(b)); l0 = math.dist(p0.GetPoint(a), p0.GetPoint(b))
        worst = max(worst, abs(l1 - l0))
if worst > 1e-9: print("face edge length changed by", worst); sys.exit(1)
# the sheet is folded: something left the plane
zmax = max(abs(pts.GetPoint(i)[2]) for i in range(d.GetNumberOfPoints()))
print("ok cells=%d zmax=%.4g" % (d.GetNumberOfCells(), zmax))
PY
)
    case "$msg" in
        ok*) echo "ok $n - $name: $msg";;
        *) echo "not ok $n - $name: $msg";;
    esac
}
check 1 square4-folded square4 0.3 21 24 6
check 2 strip3-folded strip3 0.5,1.0,-1.5 4 3 8
check 3 waterbomb2-g2 waterbomb2 0.2 14 15 3
# bad --angles: one-line error, non-zero status, no file left behind
out=$("$bin" shape "$src/studies/strip3.cfg" --angles=0.1,nan,0.2 -o "$tmp/bad.vtp" 2>&1); rc=$?
if [ $rc -ne 0 ] && [ ! -e "$tmp/bad.vtp" ] && [ ! -e "$tmp/bad.vtp.tmp" ] && [ "$(printf '%s\n' "$out" | wc -l)" -eq 1 ]; then
    echo "ok 4 - bad --angles refused: $out"
else
    echo "not ok 4 - bad --angles: status $rc, output '$out'"
fi
