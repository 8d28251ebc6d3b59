#!/bin/sh
# test_import_public.sh - crease patterns nobody here wrote (tests/public/,
# README.md there: repository, commit, path, licence) through `smoothfold
# import` and `check`, as tests/public/manifest.tsv expects: each file that
# should read imports in one command, says its size on its first line and
# checks; each that should not fails with one line naming the problem.
# Independent figures (tests/public_check.py reads the FOLD file with
# Python's json): the folds' total length, in units of the sheet's larger
# side, is the file's mountain, valley and unassigned edges' (joining
# collinear edges into one band keeps it), and every F edge is a facet.
# SVG: the round trip SVG -> FOLD -> study gives the same folds, with the
# same assignments, and the same facet edges as SVG -> study; FOLD: the
# study exported and imported again has them too.  TAP.
src=${SF_SRCDIR:-$(dirname "$0")/..}
. "$src/tests/tap.sh"
man="$src/tests/public/manifest.tsv"
py=$(command -v python3)
n=$(grep -vc '^#' "$man")
nsvg=$(grep -v '^#' "$man" | awk -F'\t' '$1 ~ /\.svg$/ && $3 == "ok"' | wc -l)
nfold=$(grep -v '^#' "$man" | awk -F'\t' '$1 ~ /\.fold(\.gz)?$/ && $3 == "ok" && $2 == "-"' | wc -l)
echo "1..$((n + nsvg + 2 * nfold + 11))"
grep -v '^#' "$man" > "$tmp/manifest"   # read below without a pipe: ok/nok count on
while IFS='	' read -r file opts want; do
    f="$src/tests/public/$file"
    case $file in *.gz) g="$tmp/$(basename "$file" .gz)"; gzip -dc "$f" > "$g"; f=$g;; esac
    [ "$opts" = "-" ] && opts=""
    b=$(basename "$f" | sed 's/\.[a-z]*$//')
    out=$("$bin" import "$f" $opts -o "$tmp/$b.cfg" 2>"$tmp/err"); rc=$?
    if [ "$want" != ok ]; then
        nl=$(wc -l < "$tmp/err")
        if [ $rc -ne 0 ] && [ $rc -lt 128 ] && [ "$nl" -eq 1 ] && [ ! -e "$tmp/$b.cfg" ] && grep -qF -- "$want" "$tmp/err"; then
            ok "$file ${opts:+$opts }refused: $want"
        else nok "$file ${opts:+$opts }refused (status $rc, $nl lines): expected '$want'"; sed 's/^/#   /' "$tmp/err"; fi
        continue
    fi
    first=$(printf '%s\n' "$out" | head -1)
    case "$first" in *"crease pattern, "*" x "*" mm ("*) ;; *) rc=99;; esac
    if [ $rc -eq 0 ] && timeout 300 "$bin" check "$tmp/$b.cfg" >/dev/null 2>>"$tmp/err"; then
        ok "$file ${opts:+$opts }imports and checks (${first#*crease pattern, })"
    else nok "$file ${opts:+$opts }imports and checks (status $rc; first line: $first)"; sed 's/^/#   /' "$tmp/err" | head -5; continue; fi
    if [ -z "$py" ]; then continue; fi
    case $file in
    *.svg)
        # the round trip: SVG -> FOLD -> study against SVG -> study
        if "$bin" import "$f" $opts -o "$tmp/$b.rt.fold" >/dev/null 2>"$tmp/err" &&
           "$bin" import "$tmp/$b.rt.fold" -o "$tmp/$b.rt.cfg" >/dev/null 2>>"$tmp/err" &&
           r=$("$py" "$src/tests/public_check.py" same "$tmp/$b.cfg" "$tmp/$b.rt.cfg" 2e-10 2>&1); then
            ok "$file: SVG -> FOLD -> study has the same $r"
        else nok "$file: SVG -> FOLD -> study: $r"; sed 's/^/#   /' "$tmp/err" | head -3; fi;;
    *)
        [ -n "$opts" ] && continue
        # independent figures: the file's fold length and F edges
        set -- $("$py" "$src/tests/public_check.py" fold "$f")
        flen=$1 nf=$2 fspan=$4
        set -- $("$py" "$src/tests/public_check.py" cfg "$tmp/$b.cfg")
        slen=$1 nfac=$2 side=$("$py" -c "import sys; print(max(float(sys.argv[1]), float(sys.argv[2])))" "$5" "$6")
        if "$py" -c "import sys; a=float(sys.argv[1])/float(sys.argv[2]); b=float(sys.argv[3])/float(sys.argv[4]); sys.exit(abs(a-b) > 1e-9*b)" \
                "$slen" "$side" "$flen" "$fspan" && [ "$nfac" -eq "$nf" ]; then
            ok "$file: fold length $slen m on a $side m sheet, as the file's ($flen on $fspan); $nfac facet edges = its F edges"
        else nok "$file: fold length $slen on $side (file: $flen on $fspan), facets $nfac (file F: $nf)"; fi
        # the study's crease pattern through export and import again:
        # the same folds and facet edges (folds split at the facets' ends
        # on them in FOLD, joined again)
        if "$bin" export "$tmp/$b.cfg" -o "$tmp/$b.ex.fold" 2>"$tmp/err" &&
           "$bin" import "$tmp/$b.ex.fold" -o "$tmp/$b.ex.cfg" >/dev/null 2>>"$tmp/err" &&
           r=$("$py" "$src/tests/public_check.py" same "$tmp/$b.cfg" "$tmp/$b.ex.cfg" 2e-10 2>&1); then
            ok "$file: study -> export -> import has the same $r"
        else nok "$file: study -> export -> import: $r"; sed 's/^/#   /' "$tmp/err" | head -3; fi;;
    esac
done < "$tmp/manifest"
# Rabbit Ear's backslash-07 draws backslash-10's sheet with CSS
# transforms in a style sheet (its own tests expect the same graph of
# both): the same valley fold, in the same place
"$bin" import "$src/tests/public/rabbit-ear/backslash-07.svg" -o "$tmp/b7.cfg" >/dev/null 2>&1
"$bin" import "$src/tests/public/rabbit-ear/backslash-10.svg" -o "$tmp/b10.cfg" >/dev/null 2>&1
if r=$("$py" "$src/tests/public_check.py" samefolds "$tmp/b7.cfg" "$tmp/b10.cfg" 1e-12 2>&1) && [ "${r%% *}" = 1 ]; then
    ok "backslash-07.svg (CSS transform: scale, matrix) has backslash-10.svg's fold: $r"
else nok "backslash-07.svg against backslash-10.svg: $r"; fi
# Rabbit Ear's own reading of its SVG test files (its
# tests/convert.svgToFold.test.js at b717948): fish.svg 11 vertices, 22
# edges, 12 faces, 8 boundary edges; each backslash-NN.svg 7 vertices, 10
# edges, 4 faces, 6 boundary, 2 valley and 2 flat (grey) edges.  Here from
# the planar graph import writes as FOLD (faces by Euler: E - V + 1)
rab=""
for f in fish:11:22:12:8:-:- backslash-07:7:10:4:6:2:2 backslash-10:7:10:4:6:2:2; do
    b=${f%%:*}
    "$bin" import "$src/tests/public/rabbit-ear/$b.svg" -o "$tmp/re-$b.fold" >/dev/null 2>&1
    got=$("$py" -c "
import json, sys
d = json.load(open(sys.argv[1])); a = d['edges_assignment']
nv, ne = len(d['vertices_coords']), len(d['edges_vertices'])
print('%s:%d:%d:%d:%d:%s:%s' % (sys.argv[2], nv, ne, ne - nv + 1, a.count('B'),
      a.count('V') if sys.argv[3] != '-' else '-', a.count('F') if sys.argv[3] != '-' else '-'))"         "$tmp/re-$b.fold" "$b" "${f##*:}" 2>&1)
    [ "$got" = "$f" ] || rab="$rab $b: got $got, Rabbit Ear $f;"
done
if [ -z "$rab" ]; then
    ok "fish.svg, backslash-07.svg, backslash-10.svg: the vertices, edges, faces, boundary, valley and flat edges Rabbit Ear's own tests expect"
else nok "against Rabbit Ear's counts:$rab"; fi
# folds that end inside a face are left out, and import says so
"$bin" import "$src/tests/public/rabbit-ear/separated-parallel-edges.fold" -o "$tmp/sp.cfg" > "$tmp/out" 2>&1
if grep -q "separated-parallel-edges.fold: 4 folds left out: they end inside a face, where rigid faces keep them flat" "$tmp/out" &&
   grep -q "^# 4 folds left out" "$tmp/sp.cfg"; then
    ok "separated-parallel-edges.fold: the 4 folds that end inside a face are named on stdout and in the study"
else nok "separated-parallel-edges.fold: note"; sed 's/^/#   /' "$tmp/out"; fi
# a file of two sheets (two bird bases, unit squares at (0, 0) and (2, 2)):
# each --piece is one of them, scaled to 200 mm across on its own, with
# half of the file's fold length and M and V edges and half its F edges
set -- $("$py" "$src/tests/public_check.py" fold "$src/tests/public/rabbit-ear/two-bird-cp.fold" 0.2)
flen=$1 nf=$2 nmv=$3
pieces=""
for k in 1 2; do
    "$bin" import "$src/tests/public/rabbit-ear/two-bird-cp.fold" --piece=$k -o "$tmp/tb$k.cfg" >/dev/null 2>&1
    pieces="$pieces $("$py" "$src/tests/public_check.py" cfg "$tmp/tb$k.cfg" 2>&1)"
done
if printf '%s\n' "$pieces" | awk -v L="$flen" -v F="$nf" -v MV="$nmv" '{ l = $1 + $7; f = $2 + $8; mv = $4 + $10 }
        END { exit !(NF == 12 && $1 == $7 && $5 == 0.2 && $11 == 0.2 && l > 0 && (l - L) ^ 2 < 1e-20 && f == F && mv == MV) }'; then
    ok "two-bird-cp.fold --piece=1 and 2: one bird base each, 200 mm across, together the file's fold length $flen m, $nmv M/V and $nf F edges"
else nok "two-bird-cp.fold pieces: $pieces (file: length $flen, F $nf, M/V $nmv)"; fi
# units and the fold percent
"$bin" import "$src/tests/public/rabbit-ear/crane-cp.fold" --size=30cm --fold-percent=60 -o "$tmp/s.cfg" > "$tmp/out" 2>&1
if grep -q "crane-cp.fold: FOLD crease pattern, 300 x 300 mm (scaled to 300 mm across (--size))" "$tmp/out" &&
   grep -q '^  end = 0.6;' "$tmp/s.cfg" && grep -q 'rest_angle = 3.141592653589793;' "$tmp/s.cfg"; then
    ok "--size=30cm: 300 mm across; --fold-percent=60: analysis.end = 0.6 of the 180-degree target"
else nok "--size and --fold-percent"; sed 's/^/#   /' "$tmp/out"; fi
"$bin" import "$src/tests/public/rabbit-ear/crane-cp.fold" --unit=in -o "$tmp/u.cfg" > "$tmp/out" 2>&1
if grep -q "crane-cp.fold: FOLD crease pattern, 25.4 x 25.4 mm (coordinates in in (--unit))" "$tmp/out"; then
    ok "--unit=in: a unit square is 25.4 mm"
else nok "--unit=in"; sed 's/^/#   /' "$tmp/out"; fi
# bending faces on an imported triangulation: a facet edge that ends where
# import joined two folds is refused naming the fold and what to try; the
# automatic triangulation then gives every face its facets
"$bin" import "$src/tests/public/rabbit-ear/kraft-bird-base.fold" -o "$tmp/k.cfg" >/dev/null 2>&1
"$bin" check "$tmp/k.cfg" --set faces.bending=true -q > "$tmp/out" 2>&1; rc=$?
if [ $rc -eq 1 ] && grep -q "faces.facets\[0\]: v132-v77 ends at v132, which lies on fold [0-9]* (v[0-9]*->v[0-9]*) between its ends, not at a corner of a face; --set 'faces.facets=\[\]' triangulates the faces automatically" "$tmp/out" &&
   "$bin" check "$tmp/k.cfg" --set faces.bending=true --set 'faces.facets=[]' -q >/dev/null 2>&1; then
    ok "kraft-bird-base.fold, faces.bending: a facet edge ending on a joined fold refused with the way out, which checks"
else nok "kraft-bird-base.fold with faces.bending (status $rc)"; sed 's/^/#   /' "$tmp/out" | head -3; fi
# mobility at the flat state: every vertex of a flat-foldable crease
# pattern (Kawasaki's condition holds at each) moves under its own loops,
# so none is "undecided", and each of degree 4 has two folding modes (the
# counts of interior vertices, all and of degree 4, are the FOLD files':
# their vertices of degree 2 split straight folds); Rabbit Ear's
# windmill twist folds as a whole, and `run` folds it to p = 1 with the
# loops closed
for f in rabbit-ear/crane-cp:44:43 rabbit-ear/kraft-bird-base:103:87 \
         flat-folder/042_furutaoripa_katatsumuri_snail:97:96; do
    b=${f%%:*}; nv=${f#*:}; n4=${nv#*:}; nv=${nv%:*}
    "$bin" import "$src/tests/public/$b.fold" -o "$tmp/m-${b#*/}.cfg" >/dev/null 2>&1
    b=${b#*/}
    "$bin" check "$tmp/m-$b.cfg" > "$tmp/out" 2>&1
    if grep -q "^vertices under their own loops: $nv mobile, 0 locked, 0 undecided; all $n4 mobile of degree 4 with their two folding modes" "$tmp/out"; then
        ok "$b.fold: all $nv interior vertices mobile under their own loops, none undecided, the $n4 of degree 4 with two folding modes"
    else nok "$b.fold: vertices"; grep '^vertices\|undecided' "$tmp/out" | sed 's/^/#   /'; fi
done
"$bin" import "$src/tests/public/rabbit-ear/windmill.fold" -o "$tmp/w.cfg" >/dev/null 2>&1
"$bin" check "$tmp/w.cfg" > "$tmp/out" 2>&1
"$bin" run "$tmp/w.cfg" -o "$tmp/w" > "$tmp/run" 2>&1; rc=$?
last=$(grep '^point' "$tmp/run" | tail -1)
if grep -q '^mobility (exact loop closure, about the flat sheet): foldable' "$tmp/out" && [ $rc -eq 0 ] &&
   printf '%s\n' "$last" | awk '{ for (i = 1; i < NF; i++) { if ($i == "p") p = $(i + 1); if ($i == "|g|") g = $(i + 1) } }
       END { exit !(p == 1 && g + 0 < 1e-10) }'; then
    ok "windmill.fold: check says foldable; run folds it to p = 1, loops closed ($last)"
else nok "windmill.fold: check and run (status $rc)"; grep '^mobility' "$tmp/out" | sed 's/^/#   /'; tail -2 "$tmp/run" | sed 's/^/#   /'; fi
