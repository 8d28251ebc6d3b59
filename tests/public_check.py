#!/usr/bin/env python3
"""public_check.py - independent figures for tests/test_import_public.sh.

  public_check.py fold FILE.fold [SCALE]   what the FOLD file says: total length
        of its mountain, valley and unassigned edges (times SCALE), its number
        of F edges, of M and V edges, the larger side of its bounding box (read
        with Python's json, not smoothfold; the creasePattern frame); the edges
        with the same face on both sides (found by tracing the faces of the
        graph of B, M, V and U edges) are not counted: rigid faces keep them
        flat and import leaves them out
  public_check.py cfg FILE.cfg             the same figures of a study written by
        smoothfold import (folds, facets, their lengths), and its bounding box
  public_check.py same A.cfg B.cfg TOL     the two studies have the same folds
        (ends within TOL, assignments) and the same facet edges
  public_check.py samefolds A.cfg B.cfg TOL   the same folds, facets not compared

Prints one line of numbers, or exits non-zero with the difference."""
import json, math, re, sys


def same_face_edges(xy, ev, ea):
    """The edges of the B, M, V, U graph whose two sides trace one face:
    at each vertex the edges sorted by angle, a face walked by turning to
    the next edge clockwise (in the plane of the two widest axes)."""
    axes = sorted(range(len(xy[0])), key=lambda k: -(max(p[k] for p in xy) - min(p[k] for p in xy)))[:2]
    pt = [(p[axes[0]], p[axes[1]]) for p in xy]
    edges = [e for e, s in enumerate(ea) if s.upper() in 'BMVU']
    out = {}
    for e in edges:
        a, b = ev[e]
        out.setdefault(a, []).append((b, e))
        out.setdefault(b, []).append((a, e))
    for v in out:
        out[v].sort(key=lambda t: math.atan2(pt[t[0]][1] - pt[v][1], pt[t[0]][0] - pt[v][0]))
    face = {}
    nface = 0
    for e in edges:
        for h in ((ev[e][0], ev[e][1], e), (ev[e][1], ev[e][0], e)):
            if h in face:
                continue
            u, v, ee = h
            while (u, v, ee) not in face:
                face[(u, v, ee)] = nface
                ring = out[v]
                i = next(k for k, t in enumerate(ring) if t == (u, ee))
                w, f = ring[i - 1]   # the next edge clockwise from the way back
                u, v, ee = v, w, f
            nface += 1
    return {e for e in edges if face[(ev[e][0], ev[e][1], e)] == face[(ev[e][1], ev[e][0], e)]}


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
    hanging = same_face_edges(xy, ev, ea)
    length, nf, nmv = 0.0, 0, 0
    for e, ((a, b), s) in enumerate(zip(ev, ea)):
        s = s.upper()
        if s in 'MVU' and e not in hanging:
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


def same(pa, pb, tol, facets=True):
    _, fa, ca = read_cfg(pa)
    _, fb, cb = read_cfg(pb)
    sa = sorted((key(a, b, tol), s) for a, b, s in fa)
    sb = sorted((key(a, b, tol), s) for a, b, s in fb)
    if sa != sb:
        diff = set(sa) ^ set(sb)
        sys.exit('folds differ: %d in A, %d in B, e.g. %s' % (len(sa), len(sb), sorted(diff)[:2]))
    ka = sorted(key(a, b, tol) for a, b in ca) if facets else []
    kb = sorted(key(a, b, tol) for a, b in cb) if facets else []
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
    elif cmd == 'samefolds':
        same(sys.argv[2], sys.argv[3], float(sys.argv[4]), facets=False)
