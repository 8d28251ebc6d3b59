/* topology.c - from a study's crease pattern to faces, fold sides, interior
 * vertex cycles, the face tree and the rigid face bodies (MODEL.md section 1).
 *
 * Outline of sf_topology_build():
 *   1. outline: at least 3 distinct vertices, no zero-length edge, not
 *      self-intersecting, oriented counter-clockwise (reversed if given
 *      clockwise); every fold end lying on an outline edge is inserted into
 *      the boundary, sorted along the edge;
 *   2. folds: positive width, setbacks that leave a band, no zero length,
 *      no duplicates, no fold through a foreign vertex, no crossings, no
 *      fold on or outside the outline;
 *   3. the planar straight-line graph (boundary edges + folds) as half-edges
 *      sorted by angle around each vertex; faces are traced by always taking
 *      the next half-edge clockwise from the reversed arrival (so the face is
 *      on the left); the cycle of the reversed boundary is the outer face and
 *      is dropped;
 *   4. every fold must separate two different faces; every face must be a
 *      simple polygon hanging off the outline (no isolated fold clusters);
 *   5. interior-vertex cycles, the breadth-first face tree from the face of
 *      the fixed point;
 *   6. bands: corners, and a separating-axis test between every two bands;
 *   7. face bodies (see build_bodies() for the construction).
 *
 * All lengths are compared with tol = 1e-9 * (size of the sheet), so the
 * same pattern behaves alike in metres or millimetres.
 */
#include "topology.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TOPO_PI 3.14159265358979323846
#define TOPO_REL_TOL 1e-9     /* length tolerance relative to the sheet size */
#define TOPO_ANG_TOL 1e-9     /* angle tolerance [rad] */

/* ------------------------------------------------------------ 2-D helpers */

static double dot2(const double a[2], const double b[2]) { return a[0] * b[0] + a[1] * b[1]; }
static double cross2(const double a[2], const double b[2]) { return a[0] * b[1] - a[1] * b[0]; }
static double dist2(const double a[2], const double b[2]) { return hypot(b[0] - a[0], b[1] - a[1]); }

static void sub2(const double a[2], const double b[2], double r[2])
{
    r[0] = a[0] - b[0];
    r[1] = a[1] - b[1];
}

/* Signed distance of r from the line through p, q (positive on the left). */
static double side(const double p[2], const double q[2], const double r[2])
{
    double d[2], e[2];
    sub2(q, p, d);
    sub2(r, p, e);
    double len = hypot(d[0], d[1]);
    return len > 0.0 ? cross2(d, e) / len : hypot(e[0], e[1]);
}

/* Distance from r to segment pq; *s gets the parameter of the nearest point
 * (0 at p, 1 at q) when s is not NULL. */
static double point_seg(const double p[2], const double q[2], const double r[2], double *s)
{
    double d[2], e[2];
    sub2(q, p, d);
    sub2(r, p, e);
    double dd = dot2(d, d), u = dd > 0.0 ? dot2(e, d) / dd : 0.0;
    if (u < 0.0) u = 0.0;
    if (u > 1.0) u = 1.0;
    if (s) *s = u;
    double c[2] = {p[0] + u * d[0] - r[0], p[1] + u * d[1] - r[1]};
    return hypot(c[0], c[1]);
}

/* Do segments pq and rs cross properly: each one's ends strictly (beyond
 * tol) on opposite sides of the other's line? */
static int proper_cross(const double p[2], const double q[2], const double r[2],
                        const double s[2], double tol)
{
    double a = side(p, q, r), b = side(p, q, s), c = side(r, s, p), d = side(r, s, q);
    return ((a > tol && b < -tol) || (a < -tol && b > tol)) &&
           ((c > tol && d < -tol) || (c < -tol && d > tol));
}

/* Smallest distance between segments pq and rs (0 when they cross). */
static double seg_seg(const double p[2], const double q[2], const double r[2], const double s[2])
{
    if (proper_cross(p, q, r, s, 0.0)) return 0.0;
    double m = point_seg(p, q, r, NULL), v;
    if ((v = point_seg(p, q, s, NULL)) < m) m = v;
    if ((v = point_seg(r, s, p, NULL)) < m) m = v;
    if ((v = point_seg(r, s, q, NULL)) < m) m = v;
    return m;
}

static double poly_area(int n, double (*p)[2])
{
    double a = 0.0;
    for (int i = 0; i < n; i++) {
        const double *u = p[i], *v = p[(i + 1) % n];
        a += u[0] * v[1] - v[0] * u[1];
    }
    return 0.5 * a;
}

/* Area and centroid of a simple polygon (shoelace, relative to the first
 * vertex to keep the sums well conditioned). */
static double poly_centroid(int n, double (*p)[2], double c[2])
{
    double a = 0.0, cx = 0.0, cy = 0.0, o[2] = {p[0][0], p[0][1]};
    for (int i = 0; i < n; i++) {
        double u[2] = {p[i][0] - o[0], p[i][1] - o[1]};
        double v[2] = {p[(i + 1) % n][0] - o[0], p[(i + 1) % n][1] - o[1]};
        double w = u[0] * v[1] - v[0] * u[1];
        a += w;
        cx += (u[0] + v[0]) * w;
        cy += (u[1] + v[1]) * w;
    }
    a *= 0.5;
    if (a != 0.0) {
        c[0] = o[0] + cx / (6.0 * a);
        c[1] = o[1] + cy / (6.0 * a);
    } else {
        c[0] = o[0];
        c[1] = o[1];
    }
    return a;
}

/* 1 when x is strictly inside (farther than tol from the boundary), 0 when
 * within tol of the boundary, -1 outside.  *margin (if not NULL) gets the
 * distance to the boundary, signed positive inside. */
static int poly_classify(int n, double (*p)[2], const double x[2], double tol, double *margin)
{
    double dmin = INFINITY;
    int inside = 0;
    for (int i = 0, j = n - 1; i < n; j = i++) {
        double d = point_seg(p[j], p[i], x, NULL);
        if (d < dmin) dmin = d;
        /* even-odd ray casting towards +x */
        if ((p[i][1] > x[1]) != (p[j][1] > x[1])) {
            double xc = p[j][0] + (x[1] - p[j][1]) * (p[i][0] - p[j][0]) / (p[i][1] - p[j][1]);
            if (x[0] < xc) inside = !inside;
        }
    }
    if (margin) *margin = inside ? dmin : -dmin;
    if (dmin <= tol) return 0;
    return inside ? 1 : -1;
}

int sf_polygon_contains(const sf_polygon *poly, const double x[2], double tol)
{
    if (!poly || poly->n < 3 || !poly->p) return 0;
    return poly_classify(poly->n, poly->p, x, tol, NULL) >= 0;
}

/* ------------------------------------------------------------ labels */

void sf_topology_fold_name(const sf_study *s, int i, char *buf, size_t size)
{
    const sf_fold_def *f = &s->folds[i];
    const char *a = (f->a >= 0 && f->a < s->nvertices) ? s->vertices[f->a].name : "?";
    const char *b = (f->b >= 0 && f->b < s->nvertices) ? s->vertices[f->b].name : "?";
    if (f->name[0])
        snprintf(buf, size, "fold %d '%s' (%s->%s)", i + 1, f->name, a, b);
    else
        snprintf(buf, size, "fold %d (%s->%s)", i + 1, a, b);
}

void sf_topology_face_name(const sf_study *s, const sf_topology *t, int f, char *buf,
                           size_t size)
{
    const sf_face *F = &t->faces[f];
    size_t k = (size_t)snprintf(buf, size, "face %d (", f + 1);
    for (int i = 0; i < F->nverts && k < size; i++) {
        if (i == 6 && F->nverts > 7) {
            k += (size_t)snprintf(buf + k, size - k, " ...");
            break;
        }
        k += (size_t)snprintf(buf + k, size - k, "%s%s", i ? " " : "",
                              s->vertices[F->verts[i]].name);
    }
    if (k < size) snprintf(buf + k, size - k, ")");
}

/* ------------------------------------------------------------ build state */

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

static int fail_line(topo_build *B, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

static int fail_line(topo_build *B, int line, const char *fmt, ...)
{
    char msg[900];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (line > 0) return sf_fail(B->err, SF_EINPUT, "%s:%d: %s", B->s->path, line, msg);
    return sf_fail(B->err, SF_EINPUT, "%s: %s", B->s->path, msg);
}

static const double *VX(const topo_build *B, int v) { return B->s->vertices[v].x; }
static const char *VN(const topo_build *B, int v) { return B->s->vertices[v].name; }
static int VL(const topo_build *B, int v) { return B->s->vertices[v].line; }

typedef struct { char s[SF_NAME_MAX * 3 + 32]; } label_t;

static label_t FN(const topo_build *B, int i)
{
    label_t l;
    sf_topology_fold_name(B->s, i, l.s, sizeof l.s);
    return l;
}

typedef struct { char s[SF_NAME_MAX * 8 + 32]; } flabel_t;

static flabel_t FACEN(const topo_build *B, int f)
{
    flabel_t l;
    sf_topology_face_name(B->s, B->t, f, l.s, sizeof l.s);
    return l;
}

static void *xcalloc(size_t n, size_t size)
{
    return calloc(n ? n : 1, size);
}

static void build_free(topo_build *B)
{
    free(B->outline);
    free(B->used);
    free(B->bpos);
    free(B->hfrom);
    free(B->hto);
    free(B->hcycle);
    free(B->hnext);
    free(B->hang);
    free(B->vfirst);
    free(B->vdeg);
    free(B->vout);
    free(B->cface);
}

static int nomem(topo_build *B)
{
    return sf_fail(B->err, SF_ENOMEM, "%s: out of memory building the topology", B->s->path);
}

/* ------------------------------------------------------------ 1. outline */

static int check_outline(topo_build *B)
{
    const sf_study *s = B->s;
    int n = s->noutline;
    int line0 = (n > 0 && s->outline[0] >= 0 && s->outline[0] < s->nvertices)
                ? VL(B, s->outline[0]) : 0;
    if (n < 3)
        return fail_line(B, line0, "outline needs at least 3 vertices (got %d)", n);
    for (int i = 0; i < n; i++)
        if (s->outline[i] < 0 || s->outline[i] >= s->nvertices)
            return fail_line(B, line0, "outline vertex %d refers to no vertex", i + 1);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < i; j++)
            if (s->outline[i] == s->outline[j])
                return fail_line(B, VL(B, s->outline[i]),
                                 "outline lists vertex %s twice", VN(B, s->outline[i]));

    /* sheet size from the outline's bounding box sets the tolerance */
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 2; k++) {
            double c = VX(B, s->outline[i])[k];
            if (!isfinite(c))
                return fail_line(B, VL(B, s->outline[i]), "vertex %s has a non-finite coordinate",
                                 VN(B, s->outline[i]));
            if (c < lo[k]) lo[k] = c;
            if (c > hi[k]) hi[k] = c;
        }
    double size = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (!(size > 0.0)) return fail_line(B, line0, "outline has zero size");
    B->t->size = size;
    B->tol = B->t->tol = TOPO_REL_TOL * size;
    double tol = B->tol;

    for (int i = 0; i < n; i++) {
        int a = s->outline[i], b = s->outline[(i + 1) % n];
        if (dist2(VX(B, a), VX(B, b)) <= tol)
            return fail_line(B, VL(B, b), "outline edge %s-%s has zero length", VN(B, a), VN(B, b));
    }
    for (int i = 0; i < n; i++) {
        int a = s->outline[i], b = s->outline[(i + 1) % n];
        /* an edge folding straight back onto the previous one */
        int c = s->outline[(i + 2) % n];
        double d1[2], d2[2];
        sub2(VX(B, b), VX(B, a), d1);
        sub2(VX(B, c), VX(B, b), d2);
        if (fabs(side(VX(B, a), VX(B, b), VX(B, c))) <= tol && dot2(d1, d2) < 0.0)
            return fail_line(B, VL(B, b), "outline is self-intersecting: it doubles back at vertex %s",
                             VN(B, b));
        for (int j = i + 2; j < n; j++) {
            if (i == 0 && j == n - 1) continue;   /* adjacent through the closure */
            int p = s->outline[j], q = s->outline[(j + 1) % n];
            if (seg_seg(VX(B, a), VX(B, b), VX(B, p), VX(B, q)) <= tol)
                return fail_line(B, VL(B, p), "outline is self-intersecting: edges %s-%s and %s-%s meet",
                                 VN(B, a), VN(B, b), VN(B, p), VN(B, q));
        }
    }
    B->outline = malloc(sizeof(int) * (size_t)n);
    if (!B->outline) return nomem(B);
    B->noutline = n;
    double (*P)[2] = malloc(sizeof *P * (size_t)n);
    if (!P) return nomem(B);
    for (int i = 0; i < n; i++) {
        P[i][0] = VX(B, s->outline[i])[0];
        P[i][1] = VX(B, s->outline[i])[1];
    }
    double area = poly_area(n, P);
    free(P);
    if (fabs(area) <= tol * size) return fail_line(B, line0, "outline encloses no area");
    for (int i = 0; i < n; i++) B->outline[i] = area > 0.0 ? s->outline[i] : s->outline[n - 1 - i];
    B->t->sheet_area = fabs(area);
    return SF_OK;
}

/* ------------------------------------------------------------ 2. folds */

static int check_folds_basic(topo_build *B)
{
    const sf_study *s = B->s;
    for (int i = 0; i < s->nfolds; i++) {
        const sf_fold_def *f = &s->folds[i];
        if (f->a < 0 || f->a >= s->nvertices || f->b < 0 || f->b >= s->nvertices)
            return fail_line(B, f->line, "%s refers to an unknown vertex", FN(B, i).s);
        if (f->a == f->b || dist2(VX(B, f->a), VX(B, f->b)) <= B->tol)
            return fail_line(B, f->line, "%s has zero length", FN(B, i).s);
        if (!isfinite(VX(B, f->a)[0]) || !isfinite(VX(B, f->a)[1]) ||
            !isfinite(VX(B, f->b)[0]) || !isfinite(VX(B, f->b)[1]))
            return fail_line(B, f->line, "%s has an end with a non-finite coordinate", FN(B, i).s);
        if (!(f->width > 0.0) || !isfinite(f->width))
            return fail_line(B, f->line, "%s: width must be positive (got %g)", FN(B, i).s, f->width);
        if (!(f->setback[0] >= 0.0) || !(f->setback[1] >= 0.0) ||
            !isfinite(f->setback[0]) || !isfinite(f->setback[1]))
            return fail_line(B, f->line, "%s: setbacks must be non-negative (got %g, %g)",
                             FN(B, i).s, f->setback[0], f->setback[1]);
        double l = dist2(VX(B, f->a), VX(B, f->b));
        if (f->setback[0] + f->setback[1] >= l - B->tol)
            return fail_line(B, f->line, "%s: setbacks %g + %g leave no band (fold length %g)",
                             FN(B, i).s, f->setback[0], f->setback[1], l);
        B->used[f->a] = B->used[f->b] = 1;
    }
    return SF_OK;
}

/* Put every fold end that lies on an outline edge into the boundary. */
static int insert_boundary(topo_build *B)
{
    const sf_study *s = B->s;
    int n = B->noutline, nv = s->nvertices;
    sf_topology *t = B->t;
    t->boundary = malloc(sizeof(int) * (size_t)(n + nv));
    double *par = malloc(sizeof(double) * (size_t)nv);
    int *cand = malloc(sizeof(int) * (size_t)nv);
    if (!t->boundary || !par || !cand) {
        free(par);
        free(cand);
        return nomem(B);
    }
    char *listed = xcalloc((size_t)nv, 1);
    if (!listed) {
        free(par);
        free(cand);
        return nomem(B);
    }
    for (int i = 0; i < n; i++) listed[B->outline[i]] = 1;
    int nb = 0, rc = SF_OK;
    for (int i = 0; i < n && rc == SF_OK; i++) {
        int a = B->outline[i], b = B->outline[(i + 1) % n];
        t->boundary[nb++] = a;
        int nc = 0;
        for (int v = 0; v < nv; v++) {
            if (!B->used[v] || listed[v]) continue;
            double u, d = point_seg(VX(B, a), VX(B, b), VX(B, v), &u);
            if (d > B->tol) continue;
            if (dist2(VX(B, v), VX(B, a)) <= B->tol || dist2(VX(B, v), VX(B, b)) <= B->tol) {
                int o = dist2(VX(B, v), VX(B, a)) <= B->tol ? a : b;
                rc = fail_line(B, VL(B, v), "vertices %s and %s coincide at (%g, %g)",
                               VN(B, o), VN(B, v), VX(B, v)[0], VX(B, v)[1]);
                break;
            }
            /* insertion sort by position along the edge */
            int k = nc++;
            while (k > 0 && par[k - 1] > u) {
                par[k] = par[k - 1];
                cand[k] = cand[k - 1];
                k--;
            }
            par[k] = u;
            cand[k] = v;
        }
        for (int k = 0; k < nc && rc == SF_OK; k++) {
            if (listed[cand[k]] == 2) {
                /* cannot happen for a simple outline: a point on two edges is
                 * an outline vertex */
                rc = fail_line(B, VL(B, cand[k]), "vertex %s lies on two outline edges",
                               VN(B, cand[k]));
                break;
            }
            listed[cand[k]] = 2;
            t->boundary[nb++] = cand[k];
        }
    }
    t->nboundary = nb;
    for (int k = 0; k < nb; k++) B->bpos[t->boundary[k]] = k;
    free(par);
    free(cand);
    free(listed);
    return rc;
}

static int check_folds_geometry(topo_build *B)
{
    const sf_study *s = B->s;
    const sf_topology *t = B->t;
    int nv = s->nvertices, nf = s->nfolds, nb = t->nboundary;
    double tol = B->tol;

    /* distinct pattern vertices at distinct places */
    for (int v = 0; v < nv; v++) {
        if (!B->used[v] && B->bpos[v] < 0) continue;
        for (int u = 0; u < v; u++) {
            if (!B->used[u] && B->bpos[u] < 0) continue;
            if (dist2(VX(B, u), VX(B, v)) <= tol)
                return fail_line(B, VL(B, v), "vertices %s and %s coincide at (%g, %g)",
                                 VN(B, u), VN(B, v), VX(B, v)[0], VX(B, v)[1]);
        }
    }
    for (int j = 0; j < nf; j++)
        for (int i = 0; i < j; i++) {
            const sf_fold_def *fi = &s->folds[i], *fj = &s->folds[j];
            if ((fi->a == fj->a && fi->b == fj->b) || (fi->a == fj->b && fi->b == fj->a))
                return fail_line(B, fj->line, "%s duplicates %s", FN(B, j).s, FN(B, i).s);
        }
    for (int i = 0; i < nf; i++) {
        const sf_fold_def *f = &s->folds[i];
        for (int v = 0; v < nv; v++) {
            if (v == f->a || v == f->b || (!B->used[v] && B->bpos[v] < 0)) continue;
            if (point_seg(VX(B, f->a), VX(B, f->b), VX(B, v), NULL) <= tol)
                return fail_line(B, f->line, "%s passes through vertex %s, which is not one of its ends",
                                 FN(B, i).s, VN(B, v));
        }
    }
    for (int i = 0; i < nf; i++) {
        const sf_fold_def *f = &s->folds[i];
        int pa = B->bpos[f->a], pb = B->bpos[f->b];
        if (pa >= 0 && pb >= 0 && ((pa + 1) % nb == pb || (pb + 1) % nb == pa))
            return fail_line(B, f->line, "%s lies on the outline", FN(B, i).s);
        for (int k = 0; k < nb; k++) {
            int p = t->boundary[k], q = t->boundary[(k + 1) % nb];
            if (proper_cross(VX(B, f->a), VX(B, f->b), VX(B, p), VX(B, q), tol))
                return fail_line(B, f->line, "%s crosses the outline (edge %s-%s)", FN(B, i).s,
                                 VN(B, p), VN(B, q));
        }
    }
    for (int j = 0; j < nf; j++)
        for (int i = 0; i < j; i++) {
            const sf_fold_def *fi = &s->folds[i], *fj = &s->folds[j];
            const double *p = VX(B, fi->a), *q = VX(B, fi->b), *r = VX(B, fj->a), *w = VX(B, fj->b);
            if (!proper_cross(p, q, r, w, tol)) continue;
            double d[2], e[2], g[2];
            sub2(q, p, d);
            sub2(w, r, e);
            sub2(r, p, g);
            double u = cross2(g, e) / cross2(d, e);
            return fail_line(B, fj->line, "%s crosses %s at (%g, %g) without a common vertex",
                             FN(B, j).s, FN(B, i).s, p[0] + u * d[0], p[1] + u * d[1]);
        }
    /* with no crossing and no foreign vertex on it, a fold is wholly inside
     * or wholly outside: its midpoint tells which */
    double (*P)[2] = malloc(sizeof *P * (size_t)nb);
    if (!P) return nomem(B);
    for (int k = 0; k < nb; k++) {
        P[k][0] = VX(B, t->boundary[k])[0];
        P[k][1] = VX(B, t->boundary[k])[1];
    }
    int rc = SF_OK;
    for (int i = 0; i < nf && rc == SF_OK; i++) {
        const sf_fold_def *f = &s->folds[i];
        double mid[2] = {0.5 * (VX(B, f->a)[0] + VX(B, f->b)[0]),
                         0.5 * (VX(B, f->a)[1] + VX(B, f->b)[1])};
        if (poly_classify(nb, P, mid, tol, NULL) <= 0)
            rc = fail_line(B, f->line, "%s lies outside the outline", FN(B, i).s);
    }
    free(P);
    return rc;
}

/* ------------------------------------------------------------ 3. graph */

static int build_graph(topo_build *B)
{
    const sf_study *s = B->s;
    const sf_topology *t = B->t;
    int nb = t->nboundary, nf = s->nfolds, nv = s->nvertices;
    int ne = nb + nf, nh = 2 * ne;
    B->nh = nh;
    B->hfrom = malloc(sizeof(int) * (size_t)nh);
    B->hto = malloc(sizeof(int) * (size_t)nh);
    B->hcycle = malloc(sizeof(int) * (size_t)nh);
    B->hnext = malloc(sizeof(int) * (size_t)nh);
    B->hang = malloc(sizeof(double) * (size_t)nh);
    B->vfirst = xcalloc((size_t)nv + 1, sizeof(int));
    B->vdeg = xcalloc((size_t)nv, sizeof(int));
    B->vout = malloc(sizeof(int) * (size_t)nh);
    if (!B->hfrom || !B->hto || !B->hcycle || !B->hnext || !B->hang || !B->vfirst ||
        !B->vdeg || !B->vout)
        return nomem(B);
    for (int e = 0; e < ne; e++) {
        int a, b;
        if (e < nb) {
            a = t->boundary[e];
            b = t->boundary[(e + 1) % nb];
        } else {
            a = s->folds[e - nb].a;
            b = s->folds[e - nb].b;
        }
        B->hfrom[2 * e] = a;
        B->hto[2 * e] = b;
        B->hfrom[2 * e + 1] = b;
        B->hto[2 * e + 1] = a;
    }
    for (int h = 0; h < nh; h++) {
        double d[2];
        sub2(VX(B, B->hto[h]), VX(B, B->hfrom[h]), d);
        double ang = atan2(d[1], d[0]);
        if (ang < 0.0) ang += 2.0 * TOPO_PI;
        if (ang >= 2.0 * TOPO_PI) ang = 0.0;
        B->hang[h] = ang;
        B->vdeg[B->hfrom[h]]++;
    }
    for (int v = 0; v < nv; v++) B->vfirst[v + 1] = B->vfirst[v] + B->vdeg[v];
    int *fill = xcalloc((size_t)nv, sizeof(int));
    if (!fill) return nomem(B);
    for (int h = 0; h < nh; h++) {
        int v = B->hfrom[h];
        int *list = B->vout + B->vfirst[v];
        int k = fill[v]++;
        /* insertion sort by angle (degrees are small) */
        while (k > 0 && B->hang[list[k - 1]] > B->hang[h]) {
            list[k] = list[k - 1];
            k--;
        }
        list[k] = h;
    }
    free(fill);
    /* next half-edge around a face: at the arrival vertex, the outgoing
     * half-edge just clockwise of the way back */
    for (int h = 0; h < nh; h++) {
        int v = B->hto[h], tw = h ^ 1, deg = B->vdeg[v];
        const int *list = B->vout + B->vfirst[v];
        int k = 0;
        while (k < deg && list[k] != tw) k++;
        B->hnext[h] = list[(k - 1 + deg) % deg];
    }
    for (int h = 0; h < nh; h++) B->hcycle[h] = -1;
    int nc = 0;
    for (int h = 0; h < nh; h++) {
        if (B->hcycle[h] >= 0) continue;
        int g = h, guard = 0;
        do {
            B->hcycle[g] = nc;
            g = B->hnext[g];
            if (++guard > nh) return sf_fail(B->err, SF_EINTERNAL, "%s: face tracing did not close",
                                             s->path);
        } while (g != h);
        nc++;
    }
    B->ncycles = nc;
    return SF_OK;
}

static double cycle_area(const topo_build *B, int h0)
{
    double a = 0.0;
    int h = h0;
    const double *o = VX(B, B->hfrom[h0]);
    do {
        const double *p = VX(B, B->hfrom[h]), *q = VX(B, B->hto[h]);
        a += (p[0] - o[0]) * (q[1] - o[1]) - (q[0] - o[0]) * (p[1] - o[1]);
        h = B->hnext[h];
    } while (h != h0);
    return 0.5 * a;
}

/* ------------------------------------------------------------ 4. faces */

static int build_faces(topo_build *B)
{
    const sf_study *s = B->s;
    sf_topology *t = B->t;
    int nb = t->nboundary, nf = s->nfolds, nc = B->ncycles;
    int outer = B->hcycle[1];     /* reverse of the first boundary edge */
    for (int i = 0; i < nf; i++) {
        int h = 2 * (nb + i);
        if (B->hcycle[h] == B->hcycle[h + 1])
            return fail_line(B, s->folds[i].line, "%s does not separate two different faces "
                             "(a dangling fold: one of its ends is free)", FN(B, i).s);
        if (B->hcycle[h] == outer || B->hcycle[h + 1] == outer)
            return sf_fail(B->err, SF_EINTERNAL, "%s: %s borders the outside", s->path, FN(B, i).s);
    }
    /* a cluster of folds that touches nothing else leaves a second cycle of
     * negative area (a hole) around it */
    int *first = malloc(sizeof(int) * (size_t)nc);
    B->cface = malloc(sizeof(int) * (size_t)nc);
    if (!first || !B->cface) {
        free(first);
        return nomem(B);
    }
    for (int c = 0; c < nc; c++) first[c] = -1;
    for (int h = 0; h < B->nh; h++)
        if (first[B->hcycle[h]] < 0) first[B->hcycle[h]] = h;
    int nfaces = 0;
    for (int c = 0; c < nc; c++) {
        B->cface[c] = -1;
        if (c == outer) continue;
        if (cycle_area(B, first[c]) <= 0.0) {
            int h = first[c], guard = 0;
            while (h < 2 * nb && ++guard <= B->nh) h = B->hnext[h];
            free(first);
            if (h < 2 * nb)
                return sf_fail(B->err, SF_EINTERNAL, "%s: a face of the outline has no area",
                               s->path);
            int fi = h / 2 - nb;
            return fail_line(B, s->folds[fi].line, "%s is not connected to the outline through "
                             "other folds (a face would have a hole)", FN(B, fi).s);
        }
        B->cface[c] = nfaces++;
    }
    t->nfaces = nfaces;
    t->faces = xcalloc((size_t)nfaces, sizeof(sf_face));
    if (!t->faces) {
        free(first);
        return nomem(B);
    }
    for (int c = 0; c < nc; c++) {
        int f = B->cface[c];
        if (f < 0) continue;
        sf_face *F = &t->faces[f];
        int n = 0, h = first[c];
        do {
            n++;
            h = B->hnext[h];
        } while (h != first[c]);
        F->nverts = n;
        F->verts = malloc(sizeof(int) * (size_t)n);
        F->edge_fold = malloc(sizeof(int) * (size_t)n);
        F->poly.p = malloc(sizeof *F->poly.p * (size_t)n);
        if (!F->verts || !F->edge_fold || !F->poly.p) {
            free(first);
            return nomem(B);
        }
        F->poly.n = n;
        F->parent = F->parent_fold = F->depth = -1;
        int k = 0;
        h = first[c];
        do {
            F->verts[k] = B->hfrom[h];
            F->edge_fold[k] = h / 2 >= nb ? h / 2 - nb : -1;
            F->poly.p[k][0] = VX(B, B->hfrom[h])[0];
            F->poly.p[k][1] = VX(B, B->hfrom[h])[1];
            k++;
            h = B->hnext[h];
        } while (h != first[c]);
    }
    free(first);
    for (int f = 0; f < nfaces; f++) {
        const sf_face *F = &t->faces[f];
        for (int i = 0; i < F->nverts; i++)
            for (int j = 0; j < i; j++)
                if (F->verts[i] == F->verts[j])
                    return fail_line(B, VL(B, F->verts[i]), "%s touches itself at vertex %s; "
                                     "faces must be simple polygons", FACEN(B, f).s,
                                     VN(B, F->verts[i]));
    }
    return SF_OK;
}

/* ------------------------------------------------------------ 5. folds, vertices, tree */

static int build_fold_geom(topo_build *B)
{
    const sf_study *s = B->s;
    sf_topology *t = B->t;
    int nb = t->nboundary, nf = s->nfolds;
    t->nfolds = nf;
    t->folds = xcalloc((size_t)nf, sizeof(sf_fold_geom));
    if (!t->folds) return nomem(B);
    for (int i = 0; i < nf; i++) {
        const sf_fold_def *f = &s->folds[i];
        sf_fold_geom *g = &t->folds[i];
        const double *a = VX(B, f->a), *b = VX(B, f->b);
        g->a[0] = a[0];
        g->a[1] = a[1];
        g->b[0] = b[0];
        g->b[1] = b[1];
        g->l = dist2(a, b);
        g->m[0] = (b[0] - a[0]) / g->l;
        g->m[1] = (b[1] - a[1]) / g->l;
        g->n[0] = -g->m[1];
        g->n[1] = g->m[0];
        g->L = g->l - f->setback[0] - f->setback[1];
        double w2 = 0.5 * f->width, t0 = f->setback[0], t1 = g->l - f->setback[1];
        const double tt[4] = {t0, t1, t1, t0}, uu[4] = {-w2, -w2, w2, w2};
        for (int c = 0; c < 4; c++)
            for (int k = 0; k < 2; k++)
                g->corner[c][k] = a[k] + tt[c] * g->m[k] + uu[c] * g->n[k];
        int h = 2 * (nb + i);
        g->left = B->cface[B->hcycle[h]];
        g->right = B->cface[B->hcycle[h + 1]];
    }
    return SF_OK;
}

static int build_ivertices(topo_build *B)
{
    const sf_study *s = B->s;
    sf_topology *t = B->t;
    int nv = s->nvertices, nb = t->nboundary;
    t->nvertices = nv;
    t->ivertex_of = malloc(sizeof(int) * (size_t)(nv ? nv : 1));
    if (!t->ivertex_of) return nomem(B);
    int niv = 0;
    for (int v = 0; v < nv; v++) {
        t->ivertex_of[v] = -1;
        if (B->used[v] && B->bpos[v] < 0) t->ivertex_of[v] = niv++;
    }
    t->nivertices = niv;
    t->ivertices = xcalloc((size_t)niv, sizeof(sf_ivertex));
    if (!t->ivertices) return nomem(B);
    for (int v = 0; v < nv; v++) {
        int k = t->ivertex_of[v];
        if (k < 0) continue;
        sf_ivertex *iv = &t->ivertices[k];
        int deg = B->vdeg[v];
        const int *list = B->vout + B->vfirst[v];
        iv->vertex = v;
        iv->degree = deg;
        iv->folds = malloc(sizeof(int) * (size_t)deg);
        iv->sign = malloc(sizeof(int) * (size_t)deg);
        iv->faces = malloc(sizeof(int) * (size_t)deg);
        if (!iv->folds || !iv->sign || !iv->faces) return nomem(B);
        for (int j = 0; j < deg; j++) {
            int h = list[j];
            iv->folds[j] = h / 2 - nb;
            iv->sign[j] = (h & 1) ? -1 : +1;
            /* the face just counter-clockwise of an outgoing half-edge is the
             * one on its left */
            iv->faces[j] = B->cface[B->hcycle[h]];
        }
        /* consistency: faces[j] is the left face of fold j when it leaves
         * the vertex and its right face when it arrives, and it is also the
         * face on the clockwise side of fold j+1 */
        for (int j = 0; j < deg; j++) {
            const sf_fold_geom *g = &t->folds[iv->folds[j]];
            int want = iv->sign[j] > 0 ? g->left : g->right;
            const sf_fold_geom *g2 = &t->folds[iv->folds[(j + 1) % deg]];
            int want2 = iv->sign[(j + 1) % deg] > 0 ? g2->right : g2->left;
            if (iv->faces[j] != want || iv->faces[j] != want2)
                return sf_fail(B->err, SF_EINTERNAL, "%s: inconsistent face order at vertex %s",
                               s->path, VN(B, v));
        }
    }
    return SF_OK;
}

int sf_topology_locate_face(const sf_topology *t, const double x[2])
{
    if (!t || !t->faces) return -1;
    int best = -1;
    double bestm = -INFINITY;
    for (int f = 0; f < t->nfaces; f++) {
        double m;
        int c = poly_classify(t->faces[f].poly.n, t->faces[f].poly.p, x, t->tol, &m);
        if (c < 0) continue;
        if (m > bestm) {
            bestm = m;
            best = f;
        }
    }
    return best;
}

int sf_topology_locate_band(const sf_topology *t, const double x[2], double *tpos, double *upos)
{
    if (!t || !t->folds) return -1;
    for (int i = 0; i < t->nfolds; i++) {
        const sf_fold_geom *g = &t->folds[i];
        double d[2];
        sub2(x, g->a, d);
        double tt = dot2(d, g->m), uu = dot2(d, g->n);
        /* band extent from its corners: p1 is (t = d^a, u = -w/2) */
        double t0 = dot2((double[2]){g->corner[0][0] - g->a[0], g->corner[0][1] - g->a[1]}, g->m);
        double t1 = dot2((double[2]){g->corner[1][0] - g->a[0], g->corner[1][1] - g->a[1]}, g->m);
        double w2 = -dot2((double[2]){g->corner[0][0] - g->a[0], g->corner[0][1] - g->a[1]}, g->n);
        if (tt >= t0 - t->tol && tt <= t1 + t->tol && fabs(uu) <= w2 + t->tol) {
            if (tpos) *tpos = tt;
            if (upos) *upos = uu;
            return i;
        }
    }
    return -1;
}

static int build_tree(topo_build *B)
{
    const sf_study *s = B->s;
    sf_topology *t = B->t;
    int nf = t->nfaces;
    if (!isfinite(s->fixed_point[0]) || !isfinite(s->fixed_point[1]))
        return fail_line(B, s->fixed_line, "fixed point is not finite");
    int root = sf_topology_locate_face(t, s->fixed_point);
    if (root < 0)
        return fail_line(B, s->fixed_line, "fixed point (%g, %g) is outside the sheet",
                         s->fixed_point[0], s->fixed_point[1]);
    t->root = root;
    t->order = malloc(sizeof(int) * (size_t)(nf ? nf : 1));
    if (!t->order) return nomem(B);
    for (int f = 0; f < nf; f++) t->faces[f].depth = -1;
    t->faces[root].depth = 0;
    t->faces[root].parent = -1;
    t->faces[root].parent_fold = -1;
    int head = 0, tail = 0;
    t->order[tail++] = root;
    while (head < tail) {
        int f = t->order[head++];
        for (int i = 0; i < t->nfolds; i++) {
            const sf_fold_geom *g = &t->folds[i];
            int o = g->left == f ? g->right : g->right == f ? g->left : -1;
            if (o < 0 || t->faces[o].depth >= 0) continue;
            t->faces[o].depth = t->faces[f].depth + 1;
            t->faces[o].parent = f;
            t->faces[o].parent_fold = i;
            t->order[tail++] = o;
        }
    }
    for (int f = 0; f < nf; f++)
        if (t->faces[f].depth < 0)
            return fail_line(B, s->fixed_line, "%s cannot be reached from the fixed face by "
                             "crossing folds", FACEN(B, f).s);
    return SF_OK;
}

/* ------------------------------------------------------------ 6. bands */

/* Separating-axis test on the two band rectangles: they overlap when their
 * projections overlap by more than tol on all four edge directions. */
static int bands_overlap(const sf_fold_geom *g, const sf_fold_geom *h, double tol)
{
    const double *axes[4] = {g->m, g->n, h->m, h->n};
    for (int k = 0; k < 4; k++) {
        double lo1 = INFINITY, hi1 = -INFINITY, lo2 = INFINITY, hi2 = -INFINITY;
        for (int c = 0; c < 4; c++) {
            double p = dot2(g->corner[c], axes[k]), q = dot2(h->corner[c], axes[k]);
            if (p < lo1) lo1 = p;
            if (p > hi1) hi1 = p;
            if (q < lo2) lo2 = q;
            if (q > hi2) hi2 = q;
        }
        if (fmin(hi1, hi2) - fmax(lo1, lo2) <= tol) return 0;
    }
    return 1;
}

static int check_bands(topo_build *B)
{
    const sf_study *s = B->s;
    const sf_topology *t = B->t;
    for (int j = 0; j < t->nfolds; j++)
        for (int i = 0; i < j; i++) {
            if (!bands_overlap(&t->folds[i], &t->folds[j], B->tol)) continue;
            const sf_fold_def *fi = &s->folds[i], *fj = &s->folds[j];
            int common = (fi->a == fj->a || fi->a == fj->b) ? fi->a
                         : (fi->b == fj->a || fi->b == fj->b) ? fi->b : -1;
            if (common >= 0)
                return fail_line(B, fj->line, "bands of %s and %s overlap; increase their "
                                 "setbacks at %s or make them narrower",
                                 FN(B, j).s, FN(B, i).s, VN(B, common));
            return fail_line(B, fj->line, "bands of %s and %s overlap", FN(B, j).s, FN(B, i).s);
        }
    return SF_OK;
}

/* ------------------------------------------------------------ 7. bodies
 *
 * The body of a face is built by walking its crease-pattern polygon (ccw,
 * face on the left) and replacing every edge by a parallel line: the edge
 * itself for an outline edge, the band's edge line (offset w/2 into the
 * face) for a fold.  At each polygon vertex v, with incoming edge j and
 * outgoing edge i and the face's interior angle alpha there:
 *
 *  - two outline edges: v itself;
 *  - v an interior vertex (both edges folds), alpha <= pi: the band corner
 *    of fold j nearest v on the face's side, then that of fold i -- the
 *    segment MODEL.md section 1 prescribes (the small polygon cut off at v
 *    belongs to no face);
 *  - v an interior vertex, alpha > pi (a reflex corner, e.g. at a bent
 *    degree-2 vertex): the feet of v on the two band edge lines (the band
 *    ends' extensions up to v are cut away; joining the corners directly
 *    would cut across the neighbouring faces);
 *  - v on the outline with at least one fold, alpha < pi: the intersection
 *    of the two lines.  Thus a band's edge line runs on past the band's end
 *    up to the outline, and the strip between the band end and the outline
 *    (the band continued to the outline) joins neither face; between two
 *    folds meeting on the outline the face's body ends in the corner where
 *    the two edge lines meet;
 *  - v on the outline, alpha >= pi (nearly parallel or reflex): the feet
 *    of v on the two lines (v itself for an outline edge).
 *
 * This works for non-convex faces too: no convex clipping is involved.  The
 * result is then checked: every offset edge must keep its direction (a
 * reversed edge means a band wider than the face there), the polygon must
 * be simple, have positive area and lie inside the crease-pattern face.  A
 * failure is reported as a band too wide for the face, naming the widest
 * fold involved.
 */

typedef struct { double (*p)[2]; int *src; int n, cap; } ptlist;

static int pt_push(ptlist *L, const double x[2], int src)
{
    if (L->n == L->cap) {
        int cap = L->cap ? 2 * L->cap : 16;
        double (*p)[2] = realloc(L->p, sizeof *p * (size_t)cap);
        if (!p) return -1;
        L->p = p;
        int *q = realloc(L->src, sizeof(int) * (size_t)cap);
        if (!q) return -1;
        L->src = q;
        L->cap = cap;
    }
    L->p[L->n][0] = x[0];
    L->p[L->n][1] = x[1];
    L->src[L->n] = src;
    L->n++;
    return 0;
}

static int body_fail(topo_build *B, int f, const int *cand, int ncand)
{
    const sf_study *s = B->s;
    int best = -1;
    for (int k = 0; k < ncand; k++) {
        int i = cand[k];
        if (i < 0) continue;
        if (best < 0 || s->folds[i].width > s->folds[best].width ||
            (s->folds[i].width == s->folds[best].width && i < best))
            best = i;
    }
    if (best < 0)
        return sf_fail(B->err, SF_EINTERNAL, "%s: %s has an empty body", s->path, FACEN(B, f).s);
    return fail_line(B, s->folds[best].line, "band of %s (width %g) is too wide for %s: "
                     "the face body would be empty or inverted", FN(B, best).s,
                     s->folds[best].width, FACEN(B, f).s);
}

static int build_body(topo_build *B, int f, ptlist *L)
{
    const sf_study *s = B->s;
    sf_topology *t = B->t;
    sf_face *F = &t->faces[f];
    int n = F->nverts;
    double tol = B->tol;
    L->n = 0;

    for (int i = 0; i < n; i++) {
        int j = (i - 1 + n) % n;
        int v = F->verts[i];
        const double *x = VX(B, v);
        const double *pj = VX(B, F->verts[j]), *pk = VX(B, F->verts[(i + 1) % n]);
        double dj[2], di[2], nj[2], ni[2];
        sub2(x, pj, dj);
        sub2(pk, x, di);
        double lj = hypot(dj[0], dj[1]), li = hypot(di[0], di[1]);
        dj[0] /= lj; dj[1] /= lj;
        di[0] /= li; di[1] /= li;
        nj[0] = -dj[1]; nj[1] = dj[0];
        ni[0] = -di[1]; ni[1] = di[0];
        int fj = F->edge_fold[j], fi = F->edge_fold[i];
        double hj = fj >= 0 ? 0.5 * s->folds[fj].width : 0.0;
        double hi = fi >= 0 ? 0.5 * s->folds[fi].width : 0.0;
        double alpha = TOPO_PI - atan2(cross2(dj, di), dot2(dj, di));
        double foot_j[2] = {x[0] + hj * nj[0], x[1] + hj * nj[1]};
        double foot_i[2] = {x[0] + hi * ni[0], x[1] + hi * ni[1]};
        int rc = 0;
        if (fj < 0 && fi < 0) {
            rc |= pt_push(L, x, i);
        } else if (B->bpos[v] < 0) {
            if (alpha <= TOPO_PI + TOPO_ANG_TOL) {
                /* setbacks at v of the two folds */
                const sf_fold_def *Fj = &s->folds[fj], *Fi = &s->folds[fi];
                double sj = Fj->a == v ? Fj->setback[0] : Fj->setback[1];
                double si = Fi->a == v ? Fi->setback[0] : Fi->setback[1];
                double cj[2] = {foot_j[0] - sj * dj[0], foot_j[1] - sj * dj[1]};
                double ci[2] = {foot_i[0] + si * di[0], foot_i[1] + si * di[1]};
                rc |= pt_push(L, cj, i);
                rc |= pt_push(L, ci, i);
            } else {
                rc |= pt_push(L, foot_j, i);
                rc |= pt_push(L, foot_i, i);
            }
        } else {
            double den = cross2(dj, di);
            if (alpha < TOPO_PI - TOPO_ANG_TOL && fabs(den) > TOPO_ANG_TOL) {
                double g[2];
                sub2(foot_i, foot_j, g);
                double u = cross2(g, di) / den;
                double X[2] = {foot_j[0] + u * dj[0], foot_j[1] + u * dj[1]};
                rc |= pt_push(L, X, i);
            } else {
                rc |= pt_push(L, foot_j, i);
                rc |= pt_push(L, foot_i, i);
            }
        }
        if (rc) return nomem(B);
    }

    /* offset edges must keep their direction: the segment from the last
     * point made at vertex i to the first point made at vertex i+1 runs
     * along edge i */
    for (int k = 0; k < L->n; k++) {
        int k2 = (k + 1) % L->n;
        if (L->src[k2] == L->src[k]) continue;        /* a connector at one vertex */
        int i = L->src[k], i2 = (i + 1) % n;
        double d[2], e[2];
        sub2(F->poly.p[i2], F->poly.p[i], e);
        sub2(L->p[k2], L->p[k], d);
        if (dot2(d, e) < -tol * hypot(e[0], e[1])) {
            int cand[3] = {F->edge_fold[i], F->edge_fold[(i - 1 + n) % n], F->edge_fold[i2]};
            return body_fail(B, f, cand, 3);
        }
    }
    /* drop repeated points */
    int m = 0;
    for (int k = 0; k < L->n; k++) {
        if (m > 0 && dist2(L->p[m - 1], L->p[k]) <= tol) continue;
        L->p[m][0] = L->p[k][0];
        L->p[m][1] = L->p[k][1];
        L->src[m] = L->src[k];
        m++;
    }
    while (m > 1 && dist2(L->p[m - 1], L->p[0]) <= tol) m--;
    L->n = m;

    int *all = malloc(sizeof(int) * (size_t)n);
    if (!all) return nomem(B);
    for (int i = 0; i < n; i++) all[i] = F->edge_fold[i];
    int bad = m < 3 || poly_area(m, L->p) <= tol * t->size;
    for (int k = 0; k < m && !bad; k++) {
        const double *p = L->p[k], *q = L->p[(k + 1) % m], *r = L->p[(k + 2) % m];
        double d1[2], d2[2];
        sub2(q, p, d1);
        sub2(r, q, d2);
        /* a spike: the next edge goes straight back */
        if (fabs(side(p, q, r)) <= tol && dot2(d1, d2) < 0.0) bad = 1;
        for (int l = k + 2; l < m && !bad; l++) {
            if (k == 0 && l == m - 1) continue;
            if (seg_seg(p, q, L->p[l], L->p[(l + 1) % m]) <= tol) bad = 1;
        }
        if (poly_classify(n, F->poly.p, p, tol, NULL) < 0) bad = 1;
    }
    if (bad) {
        int rc = body_fail(B, f, all, n);
        free(all);
        return rc;
    }
    free(all);
    F->body.p = malloc(sizeof *F->body.p * (size_t)m);
    if (!F->body.p) return nomem(B);
    F->body.n = m;
    memcpy(F->body.p, L->p, sizeof *L->p * (size_t)m);
    F->area = poly_centroid(m, F->body.p, F->centroid);
    return SF_OK;
}

static int build_bodies(topo_build *B)
{
    ptlist L = {NULL, NULL, 0, 0};
    int rc = SF_OK;
    for (int f = 0; f < B->t->nfaces && rc == SF_OK; f++) rc = build_body(B, f, &L);
    free(L.p);
    free(L.src);
    return rc;
}

/* ------------------------------------------------------------ driver */

int sf_topology_build(const sf_study *s, sf_topology *t, sf_error *err)
{
    memset(t, 0, sizeof *t);
    t->root = -1;
    topo_build B;
    memset(&B, 0, sizeof B);
    B.s = s;
    B.t = t;
    B.err = err;
    int nv = s->nvertices;
    if (nv < 0 || s->nfolds < 0 || (nv > 0 && !s->vertices) || (s->nfolds > 0 && !s->folds) ||
        (s->noutline > 0 && !s->outline))
        return sf_fail(err, SF_EINTERNAL, "%s: inconsistent study passed to the topology",
                       s->path);
    B.used = xcalloc((size_t)nv, 1);
    B.bpos = malloc(sizeof(int) * (size_t)(nv ? nv : 1));
    int rc = SF_OK;
    if (!B.used || !B.bpos) rc = nomem(&B);
    for (int v = 0; v < nv && rc == SF_OK; v++) B.bpos[v] = -1;
    if (rc == SF_OK) rc = check_outline(&B);
    if (rc == SF_OK) rc = check_folds_basic(&B);
    if (rc == SF_OK) rc = insert_boundary(&B);
    if (rc == SF_OK) rc = check_folds_geometry(&B);
    if (rc == SF_OK) rc = build_graph(&B);
    if (rc == SF_OK) rc = build_faces(&B);
    if (rc == SF_OK) rc = build_fold_geom(&B);
    if (rc == SF_OK) rc = build_ivertices(&B);
    if (rc == SF_OK) rc = build_tree(&B);
    if (rc == SF_OK) rc = check_bands(&B);
    if (rc == SF_OK) rc = build_bodies(&B);
    build_free(&B);
    if (rc != SF_OK) sf_topology_free(t);
    return rc;
}

void sf_topology_free(sf_topology *t)
{
    if (!t) return;
    for (int f = 0; t->faces && f < t->nfaces; f++) {
        free(t->faces[f].verts);
        free(t->faces[f].edge_fold);
        free(t->faces[f].poly.p);
        free(t->faces[f].body.p);
    }
    free(t->faces);
    free(t->folds);
    for (int v = 0; t->ivertices && v < t->nivertices; v++) {
        free(t->ivertices[v].folds);
        free(t->ivertices[v].sign);
        free(t->ivertices[v].faces);
    }
    free(t->ivertices);
    free(t->order);
    free(t->boundary);
    free(t->ivertex_of);
    memset(t, 0, sizeof *t);
    t->root = -1;
}
