/* validity.c - folds beyond +-180 degrees and parts of the sheet through
 * each other (validity.h): the triangles of the shape, the R*-tree of
 * libspatialindex over the parts' boxes, the pairs judged by tritri.h. */
#include "validity.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <spatialindex/capi/sidx_api.h>

#include "tritri.h"

/* A point of the shape: its place in the flat sheet and how it moves. */
typedef struct vpoint {
    double X[2];
    int face;          /* moves with this face (band points: -1) */
    sf_mpoint band;    /* band points: the material point on the band */
} vpoint;

/* The disc about an interior vertex through its bands' nearest corners. */
typedef struct vregion {
    double c[2], r;
} vregion;

struct sf_validity {
    const sf_model *m;
    int npts, ntri, nparts;      /* parts: faces 0..nfaces-1, then bands */
    vpoint *pt;
    int (*tri)[3];
    int *part_first;             /* triangles of part p: part_first[p] .. [p+1]-1 */
    int nreg;
    vregion *reg;
    double delta, eps;
    /* per state */
    sf_kin k;
    double (*x)[3];              /* places of the points */
    double (*tbox)[6];           /* triangle boxes (min xyz, max xyz) */
    double (*pbox)[6];           /* part boxes */
};

static double cross2(const double a[2], const double b[2], const double c[2])
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Is p inside or on triangle abc (ccw)? */
static int in_tri(const double a[2], const double b[2], const double c[2], const double p[2])
{
    return cross2(a, b, p) >= 0 && cross2(b, c, p) >= 0 && cross2(c, a, p) >= 0;
}

/* Ear clipping of a simple ccw polygon (a face body, a few corners):
 * appends the triangles, as indices off + k, to tri; collinear corners
 * are dropped without a triangle.  Returns the triangles written. */
static int triangulate(const sf_polygon *poly, int off, int (*tri)[3], double tol)
{
    int n = poly->n, nt = 0;
    int *idx = malloc(sizeof(int) * (size_t)n);
    if (!idx) return -1;
    for (int i = 0; i < n; i++) idx[i] = i;
    double tol2 = tol * tol;
    while (n >= 3) {
        int cut = -1, flat = -1;
        for (int i = 0; i < n && cut < 0; i++) {
            const double *a = poly->p[idx[(i + n - 1) % n]], *b = poly->p[idx[i]],
                         *c = poly->p[idx[(i + 1) % n]];
            double cr = cross2(a, b, c);
            double l2 = fmax(hypot(b[0] - a[0], b[1] - a[1]), hypot(c[0] - b[0], c[1] - b[1]));
            if (fabs(cr) <= tol2 + 1e-12 * l2 * l2) {
                if (flat < 0) flat = i;
                continue;
            }
            if (cr < 0) continue;   /* reflex */
            int ear = 1;
            for (int j = 0; j < n && ear; j++) {
                int v = idx[j];
                if (v == idx[i] || v == idx[(i + n - 1) % n] || v == idx[(i + 1) % n]) continue;
                if (in_tri(a, b, c, poly->p[v])) ear = 0;
            }
            if (ear) cut = i;
        }
        if (cut < 0 && flat < 0) break;   /* not simple: what is left stays out */
        if (cut >= 0) {
            tri[nt][0] = off + idx[(cut + n - 1) % n];
            tri[nt][1] = off + idx[cut];
            tri[nt][2] = off + idx[(cut + 1) % n];
            nt++;
        } else {
            cut = flat;
        }
        memmove(idx + cut, idx + cut + 1, sizeof(int) * (size_t)(n - cut - 1));
        n--;
    }
    free(idx);
    return nt;
}

int sf_validity_create(const sf_model *m, int samples, sf_validity **out, sf_error *err)
{
    const sf_topology *t = m->topo;
    const sf_study *s = m->study;
    int ns = samples < 1 ? 1 : samples;
    sf_validity *v = calloc(1, sizeof *v);
    if (!v) return sf_fail(err, SF_ENOMEM, "out of memory");
    *out = v;
    v->m = m;
    int nbody = 0, maxtri = 0;
    for (int f = 0; f < t->nfaces; f++)
        if (t->faces[f].body.n >= 3) {
            nbody += t->faces[f].body.n;
            maxtri += t->faces[f].body.n - 2;
        }
    v->npts = nbody + m->nfolds * 2 * (ns + 1);
    maxtri += m->nfolds * 2 * ns;
    v->nparts = t->nfaces + m->nfolds;
    v->pt = calloc((size_t)v->npts + 1, sizeof *v->pt);
    v->tri = calloc((size_t)maxtri + 1, sizeof *v->tri);
    v->part_first = calloc((size_t)v->nparts + 1, sizeof *v->part_first);
    v->x = calloc((size_t)v->npts + 1, sizeof *v->x);
    v->tbox = calloc((size_t)maxtri + 1, sizeof *v->tbox);
    v->pbox = calloc((size_t)v->nparts + 1, sizeof *v->pbox);
    v->nreg = t->nivertices;   /* and below, the band ends at other vertices */
    v->reg = calloc((size_t)t->nivertices + 2 * (size_t)m->nfolds + 1, sizeof *v->reg);
    if (!v->pt || !v->tri || !v->part_first || !v->x || !v->tbox || !v->pbox || !v->reg ||
        sf_kin_alloc(m, &v->k))
        return sf_fail(err, SF_ENOMEM, "out of memory");
    v->eps = t->tol;
    int np = 0, nt = 0;
    for (int f = 0; f < t->nfaces; f++) {
        v->part_first[f] = nt;
        const sf_polygon *b = &t->faces[f].body;
        if (b->n < 3) continue;
        for (int j = 0; j < b->n; j++) {
            v->pt[np + j].X[0] = b->p[j][0];
            v->pt[np + j].X[1] = b->p[j][1];
            v->pt[np + j].face = f;
        }
        int k = triangulate(b, np, v->tri + nt, t->tol);
        if (k < 0) return sf_fail(err, SF_ENOMEM, "out of memory");
        nt += k;
        np += b->n;
    }
    double wmin = INFINITY;
    for (int i = 0; i < m->nfolds; i++) {
        v->part_first[t->nfaces + i] = nt;
        const sf_fold_geom *g = &t->folds[i];
        const sf_fold_def *d = &s->folds[i];
        double w = m->sec[i].w;
        wmin = fmin(wmin, w);
        int base[2];
        for (int end = 0; end < 2; end++) {
            double tpos = end == 0 ? d->setback[0] : g->l - d->setback[1];
            base[end] = np;
            for (int j = 0; j <= ns; j++, np++) {
                vpoint *p = &v->pt[np];
                p->face = -1;
                p->band = (sf_mpoint){{0, 0}, g->right, i, w * j / ns, tpos};
                for (int e = 0; e < 2; e++)
                    p->band.X[e] = g->a[e] + tpos * g->m[e] + (w * j / ns - 0.5 * w) * g->n[e];
                memcpy(p->X, p->band.X, sizeof p->X);
            }
        }
        for (int j = 0; j < ns; j++) {
            int a0 = base[0] + j, a1 = base[0] + j + 1, b0 = base[1] + j, b1 = base[1] + j + 1;
            v->tri[nt][0] = a0, v->tri[nt][1] = b0, v->tri[nt][2] = b1, nt++;
            v->tri[nt][0] = a0, v->tri[nt][1] = b1, v->tri[nt][2] = a1, nt++;
        }
    }
    v->part_first[v->nparts] = nt;
    v->ntri = nt;
    v->delta = isfinite(wmin) ? 0.1 * wmin : t->size;
    for (int r = 0; r < t->nivertices; r++) {
        const sf_ivertex *iv = &t->ivertices[r];
        vregion *g = &v->reg[r];
        memcpy(g->c, s->vertices[iv->vertex].x, sizeof g->c);
        g->r = 0;
        for (int k = 0; k < iv->degree; k++) {
            const sf_fold_geom *fg = &t->folds[iv->folds[k]];
            /* corners p1, p4 at vertex a (t = d^a); p2, p3 at vertex b */
            int c0 = iv->sign[k] > 0 ? 0 : 1, c1 = iv->sign[k] > 0 ? 3 : 2;
            g->r = fmax(g->r, hypot(fg->corner[c0][0] - g->c[0], fg->corner[c0][1] - g->c[1]));
            g->r = fmax(g->r, hypot(fg->corner[c1][0] - g->c[0], fg->corner[c1][1] - g->c[1]));
        }
    }
    /* a band that ends at a vertex on the outline leaves the same kind of
     * gap there, between its set-back end and the faces either side: the
     * disc about that vertex through the band's two corners at that end */
    for (int f = 0; f < m->nfolds; f++) {
        const sf_fold_geom *fg = &t->folds[f];
        const sf_fold_def *d = &m->study->folds[f];
        for (int e = 0; e < 2; e++) {
            const double *c = e ? fg->b : fg->a;
            int ca = e ? 1 : 0, cb = e ? 2 : 3;
            if (t->ivertex_of[e ? d->b : d->a] >= 0) continue;   /* an interior vertex's region */
            vregion *g = &v->reg[v->nreg++];
            g->c[0] = c[0];
            g->c[1] = c[1];
            g->r = fmax(hypot(fg->corner[ca][0] - c[0], fg->corner[ca][1] - c[1]),
                        hypot(fg->corner[cb][0] - c[0], fg->corner[cb][1] - c[1]));
        }
    }
    return SF_OK;
}

void sf_validity_free(sf_validity *v)
{
    if (!v) return;
    if (v->k.q) sf_kin_free(&v->k);
    free(v->pt);
    free(v->tri);
    free(v->part_first);
    free(v->x);
    free(v->tbox);
    free(v->pbox);
    free(v->reg);
    free(v);
}

double sf_validity_delta(const sf_validity *v) { return v->delta; }
long sf_validity_ntriangles(const sf_validity *v) { return v->ntri; }

void sf_validity_part_name(const sf_validity *v, int part, char *buf, size_t size)
{
    const sf_model *m = v->m;
    if (part < m->topo->nfaces) {
        sf_topology_face_name(m->study, m->topo, part, buf, size);
        return;
    }
    char f[200];
    sf_topology_fold_name(m->study, part - m->topo->nfaces, f, sizeof f);
    snprintf(buf, size, "the band of %s", f);
}

static int boxes_overlap(const double *a, const double *b)
{
    for (int c = 0; c < 3; c++)
        if (a[c] > b[3 + c] || b[c] > a[3 + c]) return 0;
    return 1;
}

/* Places of the points, boxes of the triangles and parts at q. */
static int place(sf_validity *v, const double *q, sf_error *err)
{
    const sf_model *m = v->m;
    sf_kin_eval(m, q, 0, &v->k);
    for (int i = 0; i < v->npts; i++) {
        const vpoint *p = &v->pt[i];
        if (p->face >= 0) {
            double r[3] = {p->X[0], p->X[1], 0.0};
            sf_affine_apply(v->k.X + 12 * p->face, r, v->x[i]);
        } else {
            sf_point_eval(m, &v->k, &p->band, v->x[i], NULL);
        }
        for (int c = 0; c < 3; c++)
            if (!isfinite(v->x[i][c]))
                return sf_fail(err, SF_ENUMERIC, "validity check: non-finite place of shape point %d", i);
    }
    for (int p = 0; p < v->nparts; p++) {
        double *B = v->pbox[p];
        for (int c = 0; c < 3; c++) B[c] = INFINITY, B[3 + c] = -INFINITY;
        for (int j = v->part_first[p]; j < v->part_first[p + 1]; j++) {
            double *T = v->tbox[j];
            for (int c = 0; c < 3; c++) T[c] = INFINITY, T[3 + c] = -INFINITY;
            for (int e = 0; e < 3; e++)
                for (int c = 0; c < 3; c++) {
                    double xc = v->x[v->tri[j][e]][c];
                    T[c] = fmin(T[c], xc - v->eps);
                    T[3 + c] = fmax(T[3 + c], xc + v->eps);
                }
            for (int c = 0; c < 3; c++) B[c] = fmin(B[c], T[c]), B[3 + c] = fmax(B[3 + c], T[3 + c]);
        }
    }
    return SF_OK;
}

/* Do the material points of a meeting vertex both lie in one vertex
 * region (the sheet the model leaves out around a vertex between them)? */
static int in_one_region(const sf_validity *v, const double XP[2], const double XQ[2])
{
    for (int r = 0; r < v->nreg; r++) {
        const vregion *g = &v->reg[r];
        double lim = g->r + v->delta;
        if (hypot(XP[0] - g->c[0], XP[1] - g->c[1]) <= lim && hypot(XQ[0] - g->c[0], XQ[1] - g->c[1]) <= lim)
            return 1;
    }
    return 0;
}

static void tri3(const sf_validity *v, int j, sf_tri3 *T)
{
    for (int e = 0; e < 3; e++) {
        int i = v->tri[j][e];
        memcpy(T->x[e], v->x[i], sizeof T->x[e]);
        memcpy(T->X[e], v->pt[i].X, sizeof T->X[e]);
    }
}

/* Parts a <= b: the largest separation of a penetrating meeting of their
 * triangles (-1: none), with the place. */
static double part_pair(sf_validity *v, int a, int b, sf_validity_report *rep, double at[3])
{
    double worst = -1;
    for (int i = v->part_first[a]; i < v->part_first[a + 1]; i++)
        for (int j = a == b ? i + 1 : v->part_first[b]; j < v->part_first[b + 1]; j++) {
            if (!boxes_overlap(v->tbox[i], v->tbox[j])) continue;
            sf_tri3 P, Q;
            sf_tri_meet M;
            tri3(v, i, &P);
            tri3(v, j, &Q);
            rep->tri_tests++;
            if (!sf_tritri(&P, &Q, v->eps, &M)) continue;
            for (int k = 0; k < M.n; k++) {
                double sep = sf_tri_meet_sep(&M, k);
                if (sep <= v->delta || sep <= worst || in_one_region(v, M.XP[k], M.XQ[k])) continue;
                worst = sep;
                memcpy(at, M.x[k], 3 * sizeof(double));
            }
        }
    return worst;
}

static void pair_result(sf_validity *v, int a, int b, sf_validity_report *rep)
{
    double at[3];
    rep->part_pairs++;
    double sep = part_pair(v, a, b, rep, at);
    if (sep < 0) return;
    rep->ncross++;
    /* the worst pair; near-ties (mirror images of a symmetric sheet) to
     * the lower part numbers, so that rounding does not choose */
    double tie = 1e-9 * rep->cross_sep;
    if (sep > rep->cross_sep + tie ||
        (sep >= rep->cross_sep - tie &&
         (a < rep->cross_part[0] || (a == rep->cross_part[0] && b < rep->cross_part[1])))) {
        rep->cross_sep = sep;
        rep->cross_part[0] = a;
        rep->cross_part[1] = b;
        memcpy(rep->cross_at, at, sizeof rep->cross_at);
    }
}

/* The pairs of parts whose boxes overlap, from the R*-tree. */
static int tree_pairs(sf_validity *v, sf_validity_report *rep, sf_error *err)
{
    IndexPropertyH props = IndexProperty_Create();
    if (!props) return sf_fail(err, SF_ENOMEM, "validity check: libspatialindex: no index properties");
    IndexProperty_SetIndexType(props, RT_RTree);
    IndexProperty_SetIndexStorage(props, RT_Memory);
    IndexProperty_SetIndexVariant(props, RT_Quadratic);
    IndexProperty_SetFillFactor(props, 0.4);
    IndexProperty_SetDimension(props, 3);
    IndexH idx = Index_Create(props);
    IndexProperty_Destroy(props);
    if (!idx) return sf_fail(err, SF_ENUMERIC, "validity check: libspatialindex: %s", Error_GetLastErrorMsg());
    int rc = SF_OK;
    for (int p = 0; p < v->nparts && !rc; p++) {
        if (v->part_first[p] == v->part_first[p + 1]) continue;
        if (Index_InsertData(idx, p, v->pbox[p], v->pbox[p] + 3, 3, NULL, 0) != RT_None)
            rc = sf_fail(err, SF_ENUMERIC, "validity check: libspatialindex: %s", Error_GetLastErrorMsg());
    }
    for (int p = 0; p < v->nparts && !rc; p++) {
        if (v->part_first[p] == v->part_first[p + 1]) continue;
        int64_t *ids = NULL;
        uint64_t n = 0;
        if (Index_Intersects_id(idx, v->pbox[p], v->pbox[p] + 3, 3, &ids, &n) != RT_None) {
            rc = sf_fail(err, SF_ENUMERIC, "validity check: libspatialindex: %s", Error_GetLastErrorMsg());
            break;
        }
        for (uint64_t k = 0; k < n; k++) {
            int o = (int)ids[k];
            /* each pair once; a band also with itself (its strips), a
             * flat face never */
            if (o < p || (o == p && p < v->m->topo->nfaces)) continue;
            pair_result(v, p, o, rep);
        }
        Index_Free(ids);
    }
    Index_Destroy(idx);
    return rc;
}

int sf_validity_check(sf_validity *v, const double *q, int brute, sf_validity_report *rep,
                      sf_error *err)
{
    const sf_model *m = v->m;
    memset(rep, 0, sizeof *rep);
    rep->beyond_fold = rep->cross_part[0] = rep->cross_part[1] = -1;
    for (int i = 0; i < m->nfolds; i++) {
        double th = q[m->qoff[i]];
        if (!(fabs(th) > M_PI + SF_VALIDITY_ANGLE_TOL)) continue;
        rep->nbeyond++;
        if (rep->beyond_fold < 0 || fabs(th) > fabs(rep->beyond_angle)) {
            rep->beyond_fold = i;
            rep->beyond_angle = th;
        }
    }
    if (place(v, q, err)) return err->code;
    if (!brute) return tree_pairs(v, rep, err);
    for (int a = 0; a < v->nparts; a++)
        for (int b = a; b < v->nparts; b++) {
            if (a == b && a < m->topo->nfaces) continue;
            if (!boxes_overlap(v->pbox[a], v->pbox[b])) continue;
            pair_result(v, a, b, rep);
        }
    return SF_OK;
}
