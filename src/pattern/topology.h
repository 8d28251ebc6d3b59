/* topology.h - faces, fold sides, vertex cycles and the face tree, computed
 * from the crease pattern of a study (MODEL.md section 1).  Never typed in
 * by hand.
 *
 * Conventions (MODEL.md section 1): fold i runs from vertex a to vertex b,
 * m = (b - a)/l, left normal n = (-m2, m1).  The *left* face of a fold is the
 * face on the +n side, the *right* face the one on the -n side.
 */
#ifndef SF_TOPOLOGY_H
#define SF_TOPOLOGY_H

#include "pattern.h"
#include "sf_error.h"

typedef struct sf_polygon {
    int n;
    double (*p)[2];    /* counter-clockwise, not closed (last != first) */
} sf_polygon;

typedef struct sf_face {
    int nverts;
    int *verts;          /* crease-pattern polygon, vertex indices, ccw
                            (includes vertices lying on its edges) */
    int *edge_fold;      /* edge_fold[i]: fold along the edge verts[i] ->
                            verts[i+1], or -1 for an outline edge */
    sf_polygon poly;     /* the same polygon as coordinates */
    sf_polygon body;     /* the rigid face, ccw: the crease-pattern polygon
                            less the half-bands of its folds (each band's
                            edge line continued up to the outline where the
                            band stops short of it, so the setback strip
                            joins no face) and less the small polygon at
                            each interior vertex (band corners joined); see
                            build_body() in topology.c */
    double area;         /* of body [m^2] */
    double centroid[2];  /* of body */
    /* spanning tree rooted at the fixed face */
    int parent;          /* parent face, -1 for the root */
    int parent_fold;     /* fold crossed from the parent, -1 for the root */
    int depth;           /* 0 for the root */
} sf_face;

typedef struct sf_fold_geom {
    double a[2], b[2];   /* end points */
    double l;            /* length */
    double m[2], n[2];   /* unit direction, left normal */
    double L;            /* band length l - d^a - d^b */
    double corner[4][2]; /* band corners p1..p4 (MODEL.md section 1) */
    int left, right;     /* face indices on the +n and -n sides */
} sf_fold_geom;

typedef struct sf_ivertex {
    int vertex;          /* index into study->vertices */
    int degree;
    int *folds;          /* incident folds, counter-clockwise by direction
                            out of the vertex, starting at the smallest angle
                            in [0, 2 pi) */
    int *sign;           /* +1 when the fold leaves this vertex (vertex == a),
                            -1 when it arrives (vertex == b); crossing fold k
                            counter-clockwise goes from its right face to its
                            left face when sign = +1, and back when -1 */
    int *faces;          /* faces[k] lies between folds[k] and folds[k+1]
                            (counter-clockwise from folds[k]) */
} sf_ivertex;

typedef struct sf_topology {
    int nfaces;
    sf_face *faces;
    int nfolds;
    sf_fold_geom *folds;
    int nivertices;
    sf_ivertex *ivertices;
    int root;            /* the fixed face */
    int *order;          /* faces in breadth-first order from the root (a
                            face always comes after its parent) */
    int nboundary;       /* outline after inserting vertices on its edges */
    int *boundary;       /* vertex indices, ccw */
    int nvertices;       /* = study->nvertices */
    int *ivertex_of;     /* study vertex -> interior-vertex index, or -1 */
    double size;         /* sheet size: larger side of the outline's bounding box */
    double tol;          /* length tolerance used throughout: 1e-9 * size */
    double sheet_area;   /* area enclosed by the outline */
} sf_topology;

/* Build the topology of a study's crease pattern.  Checks the pattern and
 * fails with a one-line message naming the file, line and problem for:
 * zero-length or duplicate folds, folds crossing without a shared vertex,
 * folds through a vertex that is not theirs, folds on or outside the
 * outline, dangling folds that do not separate two faces, an outline with
 * fewer than 3 vertices or crossing itself, a fixed point outside the sheet,
 * overlapping bands (naming both folds), bands wider than the faces they
 * cut.  On failure t is left empty (safe to free).  The outline may be given
 * in either orientation; fold ends on its edges are inserted.  Face bodies:
 * see the comment above build_body() in topology.c. */
int sf_topology_build(const sf_study *s, sf_topology *t, sf_error *err);
void sf_topology_free(sf_topology *t);

/* Which crease-pattern face contains point x; -1 when x is outside the
 * sheet (farther than t->tol from it).  Near an edge between faces, the one
 * x is deeper in; exactly on a fold, either one. */
int sf_topology_locate_face(const sf_topology *t, const double x[2]);

/* Which fold band contains x (within t->tol; the lowest-numbered when bands
 * touch), with its band coordinates t along m from a and u along n, or -1.
 * tpos and upos may be NULL. */
int sf_topology_locate_band(const sf_topology *t, const double x[2],
                            double *tpos, double *upos);

/* Is x inside (or on the boundary of) polygon poly?  Points within tol of
 * the boundary count as inside. */
int sf_polygon_contains(const sf_polygon *poly, const double x[2], double tol);

/* "fold 3 (v1->v2)" (1-based; with the fold's name when it has one):
 * how every message names a fold. */
void sf_topology_fold_name(const sf_study *s, int i, char *buf, size_t size);
/* "face 2 (c1 f1a f1b c4)": 1-based index and the crease-pattern corners. */
void sf_topology_face_name(const sf_study *s, const sf_topology *t, int f, char *buf,
                           size_t size);

#endif
