#!/usr/bin/env python3
"""public_check.py - independent figures for tests/test_import_public.sh.

  public_check.py fold FILE.fold [SCALE]   what the FOLD file says: total length
        of its mountain, valley and unassigned edges (times SCALE), its number
        of F edges, of M and V edges, the larger side of its bounding box (read
        with Python's json, not smoothfold; the creasePattern frame)
  public_check.py cfg FILE.cfg             the same figures of a study written by
        smoothfold import (folds, facets, their lengths), and its bounding box
  public_check.py same A.cfg B.cfg TOL     the two studies have the same folds
        (ends within TOL, assignments) and the same facet edges

Prints one line of numbers, or exits non-zero with the difference."""
import json, math, re, sys


def fold_figures(path, scale):
    d = json.load(open(path))
    frame = d
    if 'creasePattern' not in d.get('frame_classes', []):
        for f in d.get('file_frames', []):
            if 'creasePattern' in f.get('frame_classes', []):
                frame = f
    xy = frame.get('vertices_coords', d.get('vertices_coords'))
    ev = frame.get('edges_vertices', d.get('edges_vertices'))
    ea = frame.get('edges_assignment', d.get('edges_assignment'))
    if ea is None:   # FOLD makes it optional: the angles' signs say M or V
        fa = frame.get('edges_foldAngle', d.get('edges_foldAngle'))
        ea = ['V' if a and a > 0 else 'M' if a and a < 0 else 'B' for a in fa]
    length, nf, nmv = 0.0, 0, 0
    for (a, b), s in zip(ev, ea):
        s = s.upper()
        if s in 'MVU':
            length += math.dist(xy[a], xy[b])
            nmv += s in 'MV'
        nf += s == 'F'
    span = max(max(p[k] for p in xy) - min(p[k] for p in xy) for k in range(len(xy[0])))
    print('%.12g %d %d %.12g' % (length * scale, nf, nmv, span))


def read_cfg(path):
    text = open(path).read()
    verts = {m.group(1): (float(m.group(2)), float(m.group(3)))
             for m in re.finditer(r'^\s+(\w+) = \[([-0-9.eE+]+), ([-0-9.eE+]+)\];', text, re.M)}
    folds = []
    section = text.split('\nfolds = (')[1].split('\n);')[0]
    for m in re.finditer(r'\{ (?:name = "[^"]*"; )?from = "(\w+)"; to = "(\w+)";( assignment = "([MV])";)?', section):
        folds.append((verts[m.group(1)], verts[m.group(2)], m.group(4) or 'U'))
    m = re.search(r'^\s+facets = \[(.*?)\];', text, re.M | re.S)   # faces.facets
    facets = [(verts[a], verts[b]) for a, b in re.findall(r'"(\w+) (\w+)"', m.group(1))] if m else []
    return verts, folds, facets


def cfg_figures(path):
    verts, folds, facets = read_cfg(path)
    length = sum(math.dist(a, b) for a, b, _ in folds)
    xs = [p[0] for p in verts.values()]
    ys = [p[1] for p in verts.values()]
    print('%.12g %d %d %d %.12g %.12g' % (length, len(facets), len(folds),
                                         sum(s in 'MV' for _, _, s in folds),
                                         max(xs) - min(xs), max(ys) - min(ys)))


def key(a, b, tol):
    r = lambda p: (round(p[0] / tol), round(p[1] / tol))
    return tuple(sorted((r(a), r(b))))


def same(pa, pb, tol):
    _, fa, ca = read_cfg(pa)
    _, fb, cb = read_cfg(pb)
    sa = sorted((key(a, b, tol), s) for a, b, s in fa)
    sb = sorted((key(a, b, tol), s) for a, b, s in fb)
    if sa != sb:
        diff = set(sa) ^ set(sb)
        sys.exit('folds differ: %d in A, %d in B, e.g. %s' % (len(sa), len(sb), sorted(diff)[:2]))
    ka = sorted(key(a, b, tol) for a, b in ca)
    kb = sorted(key(a, b, tol) for a, b in cb)
    if ka != kb:
        sys.exit('facet edges differ: %d in A, %d in B' % (len(ka), len(kb)))
    print('%d folds %d facets' % (len(sa), len(ka)))


if __name__ == '__main__':
    cmd = sys.argv[1]
    if cmd == 'fold':
        fold_figures(sys.argv[2], float(sys.argv[3]) if len(sys.argv) > 3 else 1.0)
    elif cmd == 'cfg':
        cfg_figures(sys.argv[2])
    elif cmd == 'same':
        same(sys.argv[2], sys.argv[3], float(sys.argv[4]))
