// fold_check.js - check a FOLD file written by smoothfold with the FOLD
// reference library (npm package `fold`, edemaine's), not with our reader.
//   node fold_check.js MODULE_DIR FILE.fold
// Prints one JSON line: vertices, edges, faces (ours), faces_fold (found by
// the library from vertices_coords and edges_vertices, outer face
// excluded), assignment counts, frames, and per frame the numbers of
// vertices and fold angles with their checks.  Exits 1 when the library
// cannot read the file or a frame is inconsistent.
const path = require('path');
const fs = require('fs');
const FOLD = require(path.join(process.argv[2], 'node_modules', 'fold'));
const text = fs.readFileSync(process.argv[3], 'utf8');
const fold = JSON.parse(text);   // FOLD is JSON: the library's own .fold 'converter' is the identity
const out = {};
out.vertices = FOLD.filter.numVertices(fold);
out.edges = FOLD.filter.numEdges(fold);
out.faces = fold.faces_vertices ? fold.faces_vertices.length : 0;
out.B = FOLD.filter.boundaryEdges(fold).length;
out.M = FOLD.filter.mountainEdges(fold).length;
out.V = FOLD.filter.valleyEdges(fold).length;
out.U = FOLD.filter.unassignedEdges(fold).length;
// faces from the library (2-D crease pattern): drop the outer face (cw)
const cp = FOLD.convert.deepCopy(fold);
delete cp.faces_vertices;
delete cp.file_frames;
FOLD.convert.edges_vertices_to_faces_vertices(cp);
const area = (f) => {
  let a = 0;
  for (let i = 0; i < f.length; i++) {
    const p = cp.vertices_coords[f[i]], q = cp.vertices_coords[f[(i + 1) % f.length]];
    a += p[0] * q[1] - q[0] * p[1];
  }
  return a / 2;
};
out.faces_fold = cp.faces_vertices.filter((f) => area(f) > 0).length;
let bad = 0;
const frames = fold.file_frames || [];
out.frames = frames.length;
out.frame_checks = frames.map((fr, k) => {
  const c = {};
  c.folded = (fr.frame_classes || []).includes('foldedForm');
  c.inherits = fr.frame_inherit === true && fr.frame_parent === 0;
  c.vertices = fr.vertices_coords.length;
  c.dim3 = fr.vertices_coords.every((p) => p.length === 3 && p.every(Number.isFinite));
  c.angles = fr.edges_foldAngle.length;
  c.finite = fr.edges_foldAngle.every(Number.isFinite);
  // the boundary edges have angle 0
  c.boundary_flat = fold.edges_assignment.every((a, e) => a !== 'B' || fr.edges_foldAngle[e] === 0);
  c.p = fr['smoothfold:p'];
  c.branch = fr['smoothfold:branch'];
  if (!(c.folded && c.inherits && c.vertices === out.vertices && c.dim3 &&
        c.angles === out.edges && c.finite && c.boundary_flat && Number.isFinite(c.p) &&
        Number.isInteger(c.branch))) {
    bad = 1;
    console.error('frame ' + (k + 1) + ': ' + JSON.stringify(c));
  }
  return c;
});
// the signs of the last frame's angles against the assignment (reported,
// for the caller to judge): wrong sign, and flat (|angle| < 1e-9 degrees)
if (frames.length) {
  const last = frames[frames.length - 1].edges_foldAngle;
  out.last_wrong_sign = fold.edges_assignment.filter((a, e) =>
    (a === 'M' && last[e] > 1e-9) || (a === 'V' && last[e] < -1e-9)).length;
  out.last_flat = fold.edges_assignment.filter((a, e) =>
    (a === 'M' || a === 'V') && Math.abs(last[e]) <= 1e-9).length;
}
delete out.frame_checks;
console.log(JSON.stringify(out));
process.exit(bad);
