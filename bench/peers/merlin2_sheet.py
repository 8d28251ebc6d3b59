#!/usr/bin/env python3
"""bench/peers/merlin2_sheet.py - a bending-face study for MERLIN2, and the
comparison of the two codes' final states.

  merlin2_sheet.py data STUDY.cfg EXPORT.fold > SHEET.m
      the sheet as MERLIN2 needs it (Octave assignments, read by
      merlin2_actuation.m): nodes, the triangles of smoothfold's split
      (EXPORT.fold is `smoothfold export STUDY.cfg`, whose faces are the
      rigid triangles and whose F edges are the facet hinges), every
      hinge with smoothfold's total rotational stiffness and its rest angle
      at p = 1, the nodes of the fixed face.
  merlin2_sheet.py compare SHEET.m FOLDED.fold MERLIN2.txt
      one markdown table row: smoothfold's last frame of FOLDED.fold (the
      run's folded.fold) against MERLIN2's final state (merlin2_actuation.m's
      output): the largest difference of crease angles and of facet angles
      (degrees), of vertex positions (relative to the largest
      displacement), each code's largest vertex |uz|, and how many creases
      the two codes fold in opposite senses.

Stiffness matched hinge by hinge (docs/design/peers.md "Bending faces"):
a crease is smoothfold's band of K = 0, U = (1/2) (D L / w) theta^2 with
L = l - setbacks (MODEL.md 5); a facet hinge has K_B = C_B (l / t)^(1/3) D
(docs/guides/bending-faces.md).  MERLIN2's spring of a hinge of length l
is l k (he - he0), so k = K / l.
"""
import json
import math
import re
import sys


def fail(msg):
    sys.stderr.write("merlin2_sheet.py: %s\n" % msg)
    sys.exit(2)


def parse_cfg(path):
    """The few keys of a generated study that the comparison needs."""
    text = open(path).read()
    body = re.sub(r"#[^\n]*", "", text)
    mats = {}
    group = re.search(r"materials\s*=\s*\{(.*?)\n\};", body, re.S)
    for m in re.finditer(r"(\w+)\s*=\s*\{([^}]*)\}", group.group(1) if group else ""):
        val = dict(re.findall(r"(\w+)\s*=\s*([^;]+);", m.group(2)))
        if all(k in val for k in ("E", "nu", "thickness")):
            mats[m.group(1)] = tuple(float(val[k]) for k in ("E", "nu", "thickness"))

    def key(pattern, conv=float, default=None):
        m = re.search(pattern, body)
        if not m:
            if default is None:
                fail("%s: no %s" % (path, pattern))
            return default
        return conv(m.group(1))

    defaults = re.search(r"defaults\s*=\s*\{([^}]*)\}", body)
    if not defaults:
        fail("%s: no defaults group" % path)
    dtext = defaults.group(1)
    width = float(re.search(r"width\s*=\s*([^;]+);", dtext).group(1))
    fold_mat = re.search(r'material\s*=\s*"(\w+)"', dtext).group(1)
    faces = re.search(r"faces\s*=\s*\{([^}]*)\}", body)
    if not faces or not re.search(r"bending\s*=\s*true", faces.group(1)):
        fail("%s: faces.bending is not on" % path)
    face_mat = re.search(r'material\s*=\s*"(\w+)"', faces.group(1)).group(1)
    cb = re.search(r"bending_coefficient\s*=\s*([^;]+);", faces.group(1))
    if re.search(r'parameter\s*=\s*"(\w+)"', body).group(1) != "actuation":
        fail("%s: analysis.parameter is not \"actuation\"" % path)
    folds = []
    for m in re.finditer(r"\{\s*from\s*=\s*\"(\w+)\";\s*to\s*=\s*\"(\w+)\";([^}]*)\}", body):
        rest = m.group(3)
        sb = re.search(r"setback\s*=\s*\[([^,\]]+),\s*([^\]]+)\]", rest)
        w = re.search(r"width\s*=\s*([^;]+);", rest)
        mat = re.search(r'material\s*=\s*"(\w+)"', rest)
        folds.append({"a": m.group(1), "b": m.group(2),
                      "setback": (float(sb.group(1)), float(sb.group(2))) if sb else (0.0, 0.0),
                      "width": float(w.group(1)) if w else width,
                      "material": mat.group(1) if mat else fold_mat})
    fixed = re.search(r"fixed_face\s*=\s*\[([^,\]]+),\s*([^\]]+)\]", body)
    if not fixed:
        fail("%s: no fixed_face point" % path)
    return {"materials": mats, "folds": folds, "face_material": face_mat,
            "cb": float(cb.group(1)) if cb else 0.55,
            "fixed": (float(fixed.group(1)), float(fixed.group(2)))}


def plate(mat):
    E, nu, t = mat
    return E * t ** 3 / (12.0 * (1.0 - nu * nu))


def inside(p, tri):
    (x, y), s = p, []
    for k in range(3):
        (x0, y0), (x1, y1) = tri[k], tri[(k + 1) % 3]
        s.append((x1 - x0) * (y - y0) - (y1 - y0) * (x - x0))
    return all(v >= 0 for v in s) or all(v <= 0 for v in s)


def sheet(cfg_path, fold_path):
    cfg = parse_cfg(cfg_path)
    fold = json.load(open(fold_path))
    xy = [c[:2] for c in fold["vertices_coords"]]
    names = fold["smoothfold:vertices_name"]
    index = {n: i for i, n in enumerate(names)}
    by_pair = {}
    for f in cfg["folds"]:
        by_pair[frozenset((index[f["a"]], index[f["b"]]))] = f
    face = cfg["materials"][cfg["face_material"]]
    hinges = []
    for e, (a, b) in enumerate(fold["edges_vertices"]):
        kind = fold["edges_assignment"][e]
        if kind in ("B", "C"):
            continue
        l = math.dist(xy[a], xy[b])
        if kind == "F":
            K = cfg["cb"] * (l / face[2]) ** (1.0 / 3.0) * plate(face)
            rest = 0.0
        else:
            f = by_pair.get(frozenset((a, b)))
            if f is None:
                fail("%s: edge %d-%d is no fold of %s" % (fold_path, a, b, cfg_path))
            L = l - f["setback"][0] - f["setback"][1]
            K = plate(cfg["materials"][f["material"]]) * L / f["width"]
            rest = math.radians(fold["edges_foldAngle"][e])
        hinges.append((a, b, 1 if kind == "F" else 0, K, l, rest))
    tris = fold["faces_vertices"]
    if any(len(t) != 3 for t in tris):
        fail("%s: a face is not a triangle (faces.bending splits every face)" % fold_path)
    fixed = [t for t in tris if inside(cfg["fixed"], [xy[v] for v in t])]
    if not fixed:
        fail("%s: the fixed_face point is in no triangle" % cfg_path)
    return xy, tris, hinges, fixed[0]


def cmd_data(cfg_path, fold_path):
    xy, tris, hinges, fixed = sheet(cfg_path, fold_path)
    size = max(max(c[0] for c in xy) - min(c[0] for c in xy),
               max(c[1] for c in xy) - min(c[1] for c in xy))
    out = sys.stdout
    out.write("%% %s, from %s by bench/peers/merlin2_sheet.py\n" % (cfg_path, fold_path))
    out.write("Ls = %.17g;\n" % size)
    out.write("XY = [%s];\n" % "; ".join("%.17g, %.17g" % tuple(c) for c in xy))
    out.write("Tri = [%s];\n" % "; ".join("%d, %d, %d" % tuple(v + 1 for v in t) for t in tris))
    out.write("% hinge: vertex a, vertex b (1-based), facet (1) or crease (0),\n"
              "% total stiffness [N m / rad], length [m], rest angle at p = 1 [rad]\n")
    out.write("H = [%s];\n" % "; ".join("%d, %d, %d, %.17g, %.17g, %.17g" % (a + 1, b + 1, f, K, l, r)
                                         for a, b, f, K, l, r in hinges))
    out.write("Fixed = [%s];\n" % ", ".join(str(v + 1) for v in fixed))


def cmd_compare(data_path, folded_path, merlin_path):
    text = open(data_path).read()
    rows = re.search(r"H = \[([^\]]*)\]", text).group(1).split(";")
    hinges = [tuple(float(x) for x in r.split(",")) for r in rows]
    folded = json.load(open(folded_path))
    frame = folded["file_frames"][-1]
    p = frame["smoothfold:p"]
    sf_xyz = frame["vertices_coords"]
    sf_angle = {}
    for e, (a, b) in enumerate(folded["edges_vertices"]):
        sf_angle[frozenset((a + 1, b + 1))] = frame["edges_foldAngle"][e]
    m_xyz, m_angle, info = [], {}, {}
    for line in open(merlin_path):
        w = line.split()
        if w[0] == "node":
            m_xyz.append([float(v) for v in w[1:4]])
        elif w[0] == "hinge":
            m_angle[frozenset((int(w[1]), int(w[2])))] = math.degrees(float(w[3]))
        elif w[0] == "MERLIN2":
            info = dict(zip(("increments", "newton", "p", "strain", "cpu"), w[1:]))
    if not info or float(info["p"]) != p:
        return None
    d_crease = max(abs(sf_angle[frozenset(h[:2])] - m_angle[frozenset(h[:2])])
                   for h in hinges if h[2] == 0)
    d_facet = max(abs(sf_angle[frozenset(h[:2])] - m_angle[frozenset(h[:2])])
                  for h in hinges if h[2] == 1)
    opposite = sum(1 for h in hinges if h[2] == 0 and
                   sf_angle[frozenset(h[:2])] * m_angle[frozenset(h[:2])] < 0)
    flat = folded["vertices_coords"]
    umax = max(math.dist(s, list(f) + [0.0]) for s, f in zip(sf_xyz, flat))
    dx = max(math.dist(s, m) for s, m in zip(sf_xyz, m_xyz))
    crease_max = max(abs(sf_angle[frozenset(h[:2])]) for h in hinges if h[2] == 0)
    return {"p": p, "crease": d_crease, "facet": d_facet, "crease_max": crease_max,
            "dx": dx / umax, "sf_uz": max(abs(s[2]) for s in sf_xyz),
            "m_uz": max(abs(m[2]) for m in m_xyz), "info": info,
            "opposite": opposite, "creases": sum(1 for h in hinges if h[2] == 0)}


def main(argv):
    if len(argv) == 4 and argv[1] == "data":
        cmd_data(argv[2], argv[3])
    elif len(argv) == 5 and argv[1] == "compare":
        r = cmd_compare(argv[2], argv[3], argv[4])
        if r is None:
            print("no MERLIN2 state at smoothfold's last p")
            return 1
        i = r["info"]
        print("%g %.3g %.3g %.3g %.3g %.5g %.5g %s %s %s %s %d/%d" % (
            r["p"], r["crease_max"], r["crease"], r["facet"], r["dx"], r["sf_uz"], r["m_uz"],
            i["increments"], i["newton"], i["strain"], i["cpu"], r["opposite"], r["creases"]))
    else:
        fail("usage: merlin2_sheet.py data STUDY.cfg EXPORT.fold | compare SHEET.m FOLDED.fold MERLIN2.txt")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
