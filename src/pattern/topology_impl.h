/* topology_impl.h - private to the topology files of src/pattern/
 * (topology.c, topology_geom.c, topology_check.c, topology_bodies.c): the
 * build state and the functions they share (prefix tp_).  The public face
 * is topology.h.
 *
 *   topology.c          labels, build state, the planar graph, faces, fold
 *                       geometry, interior-vertex cycles, the face tree,
 *                       locating points, sf_topology_build / _free
 *   topology_geom.c     2-D geometry: segments, polygons, containment
 *   topology_check.c    steps 1, 2 and 6 of sf_topology_build: the outline,
 *                       the folds and the bands checked
 *   topology_bodies.c   step 7: the rigid face bodies
 *   topology_grid.c     the pairs of nearby items the checks test (boxes
 *                       in a uniform grid, no loop over all pairs)
 */
#ifndef SF_TOPOLOGY_IMPL_H
#define SF_TOPOLOGY_IMPL_H

#include <math.h>
#include <stddef.h>

#include "topology.h"

#define TOPO_PI 3.14159265358979323846
#define TOPO_REL_TOL 1e-9     /* length tolerance relative to the sheet size */
#define TOPO_ANG_TOL 1e-9     /* angle tolerance [rad] */

static inline double dot2(const double a[2], const double b[2]) { return a[0] * b[0] + a[1] * b[1]; }
static inline double cross2(const double a[2], const double b[2]) { return a[0] * b[1] - a[1] * b[0]; }
static inline double dist2(const double a[2], const double b[2]) { return hypot(b[0] - a[0], b[1] - a[1]); }

typedef struct topo_build {
    const sf_study *s;
    sf_topology *t;
    sf_error *err;
    double tol;
    int *outline;      /* outline, ccw, as vertex indices */
    int noutline;
    char *used;        /* vertex is an end of some fold */
    int *bpos;         /* position in t->boundary, -1 if not on it */
    /* half-edges: edge e has half-edges 2e (forward) and 2e+1 (reverse);
     * edges 0..nb-1 are boundary edges, nb+i is fold i */
    int nh;
    int *hfrom, *hto, *hcycle, *hnext;
    double *hang;
    int *vfirst, *vdeg, *vout; /* outgoing half-edges per vertex, ccw */
    int ncycles;
    int *cface;        /* cycle -> face index, -1 for the outer face */
} topo_build;

static inline const double *VX(const topo_build *B, int v) { return B->s->vertices[v].x; }
static inline const char *VN(const topo_build *B, int v) { return B->s->vertices[v].name; }
static inline int VL(const topo_build *B, int v) { return B->s->vertices[v].line; }

typedef struct { char s[SF_NAME_MAX * 3 + 32]; } label_t;
typedef struct { char s[SF_NAME_MAX * 8 + 32]; } flabel_t;

/* topology.c: labels, build state */
flabel_t tp_FACEN(const topo_build *B, int f);
label_t tp_FN(const topo_build *B, int i);
int tp_fail_line(topo_build *B, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
int tp_nomem(topo_build *B);
void *tp_xcalloc(size_t n, size_t size);

/* topology_geom.c: 2-D geometry */
double tp_point_seg(const double p[2], const double q[2], const double r[2], double *s);
double tp_poly_area(int n, double (*p)[2]);
double tp_poly_centroid(int n, double (*p)[2], double c[2]);
int tp_poly_classify(int n, double (*p)[2], const double x[2], double tol, double *margin);
int tp_proper_cross(const double p[2], const double q[2], const double r[2],
                    const double s[2], double tol);
double tp_seg_seg(const double p[2], const double q[2], const double r[2], const double s[2]);
double tp_side(const double p[2], const double q[2], const double r[2]);
void tp_sub2(const double a[2], const double b[2], double r[2]);

/* topology_grid.c: pairs of nearby boxes */
typedef struct tp_box { double lo[2], hi[2]; } tp_box;
void tp_box_empty(tp_box *b);                      /* lo = +inf, hi = -inf */
void tp_box_add(tp_box *b, const double p[2]);     /* grow to contain p */
/* visit(ctx, a, b) for every pair of a box a of A (na) and a box b of Bx
 * (nb) that overlap when grown by tol (|gap| <= tol on both axes); with
 * Bx NULL the pairs within A, b < a.  Every such pair once, in no set
 * order (a check that reports the first failing pair of a loop takes the
 * least); empty boxes take no part.  0, or -1 when out of memory. */
int tp_box_pairs(int na, const tp_box *A, int nb, const tp_box *Bx, double tol,
                 void (*visit)(void *ctx, int a, int b), void *ctx);

/* topology_check.c: outline, folds and bands checked */
int tp_check_bands(topo_build *B);
int tp_check_folds_basic(topo_build *B);
int tp_check_folds_geometry(topo_build *B);
int tp_check_outline(topo_build *B);
int tp_insert_boundary(topo_build *B);

/* topology_bodies.c: face bodies */
int tp_build_bodies(topo_build *B);

#endif
