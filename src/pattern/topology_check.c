/* topology_check.c - the checks of sf_topology_build (topology.c) before
 * and after the graph: 1. the outline (vertices, edges, orientation, fold
 * ends inserted into the boundary), 2. the folds (widths, setbacks,
 * duplicates, crossings, folds through vertices or outside the outline),
 * 6. the bands (corners, overlaps by a separating-axis test). */
#include "topology_impl.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>

/* The pairs of the checks come from tp_box_pairs in no set order; each
 * check reports the pair its loop over all pairs (k1 ascending, then k2)
 * would have met first: the least failing one. */
typedef struct pair_check {
    const topo_build *B;
    int k1, k2;       /* least failing pair so far, INT_MAX: none */
    int *least_edge;  /* outline crossings: per fold, the least edge crossed */
} pair_check;

static void pair_check_init(pair_check *c, const topo_build *B)
{
    c->B = B;
    c->k1 = c->k2 = INT_MAX;
    c->least_edge = NULL;
}

static void take(pair_check *c, int k1, int k2)
{
    if (k1 < c->k1 || (k1 == c->k1 && k2 < c->k2)) {
        c->k1 = k1;
        c->k2 = k2;
    }
}

static void point_box(const double p[2], tp_box *b)
{
    tp_box_empty(b);
    tp_box_add(b, p);
}

static void segment_box(const double p[2], const double q[2], tp_box *b)
{
    point_box(p, b);
    tp_box_add(b, q);
}

/* ------------------------------------------------------------ 1. outline */

int tp_check_outline(topo_build *B)
{
    const sf_study *s = B->s;
    int n = s->noutline;
    int line0 = (n > 0 && s->outline[0] >= 0 && s->outline[0] < s->nvertices)
                ? VL(B, s->outline[0]) : 0;
    if (n < 3)
        return tp_fail_line(B, line0, "outline needs at least 3 vertices (got %d)", n);
    for (int i = 0; i < n; i++)
        if (s->outline[i] < 0 || s->outline[i] >= s->nvertices)
            return tp_fail_line(B, line0, "outline vertex %d refers to no vertex", i + 1);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < i; j++)
            if (s->outline[i] == s->outline[j])
                return tp_fail_line(B, VL(B, s->outline[i]),
                                 "outline lists vertex %s twice", VN(B, s->outline[i]));

    /* sheet size from the outline's bounding box sets the tolerance */
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 2; k++) {
            double c = VX(B, s->outline[i])[k];
            if (!isfinite(c))
                return tp_fail_line(B, VL(B, s->outline[i]), "vertex %s has a non-finite coordinate",
                                 VN(B, s->outline[i]));
            if (c < lo[k]) lo[k] = c;
            if (c > hi[k]) hi[k] = c;
        }
    double size = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (!(size > 0.0)) return tp_fail_line(B, line0, "outline has zero size");
    B->t->size = size;
    B->tol = B->t->tol = TOPO_REL_TOL * size;
    double tol = B->tol;

    for (int i = 0; i < n; i++) {
        int a = s->outline[i], b = s->outline[(i + 1) % n];
        if (dist2(VX(B, a), VX(B, b)) <= tol)
            return tp_fail_line(B, VL(B, b), "outline edge %s-%s has zero length", VN(B, a), VN(B, b));
    }
    for (int i = 0; i < n; i++) {
        int a = s->outline[i], b = s->outline[(i + 1) % n];
        /* an edge folding straight back onto the previous one */
        int c = s->outline[(i + 2) % n];
        double d1[2], d2[2];
        tp_sub2(VX(B, b), VX(B, a), d1);
        tp_sub2(VX(B, c), VX(B, b), d2);
        if (fabs(tp_side(VX(B, a), VX(B, b), VX(B, c))) <= tol && dot2(d1, d2) < 0.0)
            return tp_fail_line(B, VL(B, b), "outline is self-intersecting: it doubles back at vertex %s",
                             VN(B, b));
        for (int j = i + 2; j < n; j++) {
            if (i == 0 && j == n - 1) continue;   /* adjacent through the closure */
            int p = s->outline[j], q = s->outline[(j + 1) % n];
            if (tp_seg_seg(VX(B, a), VX(B, b), VX(B, p), VX(B, q)) <= tol)
                return tp_fail_line(B, VL(B, p), "outline is self-intersecting: edges %s-%s and %s-%s meet",
                                 VN(B, a), VN(B, b), VN(B, p), VN(B, q));
        }
    }
    B->outline = malloc(sizeof(int) * (size_t)n);
    if (!B->outline) return tp_nomem(B);
    B->noutline = n;
    double (*P)[2] = malloc(sizeof *P * (size_t)n);
    if (!P) return tp_nomem(B);
    for (int i = 0; i < n; i++) {
        P[i][0] = VX(B, s->outline[i])[0];
        P[i][1] = VX(B, s->outline[i])[1];
    }
    double area = tp_poly_area(n, P);
    free(P);
    if (fabs(area) <= tol * size) return tp_fail_line(B, line0, "outline encloses no area");
    for (int i = 0; i < n; i++) B->outline[i] = area > 0.0 ? s->outline[i] : s->outline[n - 1 - i];
    B->t->sheet_area = fabs(area);
    return SF_OK;
}

/* ------------------------------------------------------------ 2. folds */

int tp_check_folds_basic(topo_build *B)
{
    const sf_study *s = B->s;
    for (int i = 0; i < s->nfolds; i++) {
        const sf_fold_def *f = &s->folds[i];
        if (f->a < 0 || f->a >= s->nvertices || f->b < 0 || f->b >= s->nvertices)
            return tp_fail_line(B, f->line, "%s refers to an unknown vertex", tp_FN(B, i).s);
        if (f->a == f->b || dist2(VX(B, f->a), VX(B, f->b)) <= B->tol)
            return tp_fail_line(B, f->line, "%s has zero length", tp_FN(B, i).s);
        if (!isfinite(VX(B, f->a)[0]) || !isfinite(VX(B, f->a)[1]) ||
            !isfinite(VX(B, f->b)[0]) || !isfinite(VX(B, f->b)[1]))
            return tp_fail_line(B, f->line, "%s has an end with a non-finite coordinate", tp_FN(B, i).s);
        if (!(f->width > 0.0) || !isfinite(f->width))
            return tp_fail_line(B, f->line, "%s: width must be positive (got %g)", tp_FN(B, i).s, f->width);
        if (!(f->setback[0] >= 0.0) || !(f->setback[1] >= 0.0) ||
            !isfinite(f->setback[0]) || !isfinite(f->setback[1]))
            return tp_fail_line(B, f->line, "%s: setbacks must be non-negative (got %g, %g)",
                             tp_FN(B, i).s, f->setback[0], f->setback[1]);
        double l = dist2(VX(B, f->a), VX(B, f->b));
        if (f->setback[0] + f->setback[1] >= l - B->tol)
            return tp_fail_line(B, f->line, "%s: setbacks %g + %g leave no band (fold length %g)",
                             tp_FN(B, i).s, f->setback[0], f->setback[1], l);
        B->used[f->a] = B->used[f->b] = 1;
    }
    return SF_OK;
}

/* Put every fold end that lies on an outline edge into the boundary. */
int tp_insert_boundary(topo_build *B)
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
        return tp_nomem(B);
    }
    char *listed = tp_xcalloc((size_t)nv, 1);
    if (!listed) {
        free(par);
        free(cand);
        return tp_nomem(B);
    }
    for (int i = 0; i < n; i++) listed[B->outline[i]] = 1;
    int nb = 0, rc = SF_OK;
    for (int i = 0; i < n && rc == SF_OK; i++) {
        int a = B->outline[i], b = B->outline[(i + 1) % n];
        t->boundary[nb++] = a;
        int nc = 0;
        for (int v = 0; v < nv; v++) {
            if (!B->used[v] || listed[v]) continue;
            double u, d = tp_point_seg(VX(B, a), VX(B, b), VX(B, v), &u);
            if (d > B->tol) continue;
            if (dist2(VX(B, v), VX(B, a)) <= B->tol || dist2(VX(B, v), VX(B, b)) <= B->tol) {
                int o = dist2(VX(B, v), VX(B, a)) <= B->tol ? a : b;
                rc = tp_fail_line(B, VL(B, v), "vertices %s and %s coincide at (%g, %g)",
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
                rc = tp_fail_line(B, VL(B, cand[k]), "vertex %s lies on two outline edges",
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

/* vertices a > b at one place */
static void coincide_pair(void *ctx, int a, int b)
{
    pair_check *c = ctx;
    if (dist2(VX(c->B, b), VX(c->B, a)) <= c->B->tol) take(c, a, b);
}

/* folds a > b with the same ends */
static void duplicate_pair(void *ctx, int a, int b)
{
    pair_check *c = ctx;
    const sf_fold_def *fi = &c->B->s->folds[b], *fj = &c->B->s->folds[a];
    if ((fi->a == fj->a && fi->b == fj->b) || (fi->a == fj->b && fi->b == fj->a)) take(c, a, b);
}

/* fold a through vertex v, not one of its ends */
static void through_pair(void *ctx, int i, int v)
{
    pair_check *c = ctx;
    const sf_fold_def *f = &c->B->s->folds[i];
    if (v == f->a || v == f->b) return;
    if (tp_point_seg(VX(c->B, f->a), VX(c->B, f->b), VX(c->B, v), NULL) <= c->B->tol)
        take(c, i, v);
}

/* fold i across boundary edge k */
static void outline_pair(void *ctx, int i, int k)
{
    pair_check *c = ctx;
    const topo_build *B = c->B;
    const sf_fold_def *f = &B->s->folds[i];
    int nb = B->t->nboundary, p = B->t->boundary[k], q = B->t->boundary[(k + 1) % nb];
    if (k < c->least_edge[i] && tp_proper_cross(VX(B, f->a), VX(B, f->b), VX(B, p), VX(B, q), B->tol))
        c->least_edge[i] = k;
}

/* folds j > i crossing with no common vertex */
static void cross_pair(void *ctx, int j, int i)
{
    pair_check *c = ctx;
    const topo_build *B = c->B;
    const sf_fold_def *fi = &B->s->folds[i], *fj = &B->s->folds[j];
    if (tp_proper_cross(VX(B, fi->a), VX(B, fi->b), VX(B, fj->a), VX(B, fj->b), B->tol))
        take(c, j, i);
}

int tp_check_folds_geometry(topo_build *B)
{
    const sf_study *s = B->s;
    const sf_topology *t = B->t;
    int nv = s->nvertices, nf = s->nfolds, nb = t->nboundary;
    double tol = B->tol;

    /* the pairs below: nearby ones only (tp_box_pairs), each check
     * reporting the first failing pair of the loop over all pairs */
    tp_box *vbox = malloc(sizeof(tp_box) * (size_t)(nv ? nv : 1));
    tp_box *fbox = malloc(sizeof(tp_box) * (size_t)(nf ? nf : 1));
    tp_box *ebox = malloc(sizeof(tp_box) * (size_t)(nb ? nb : 1));
    int *least_edge = malloc(sizeof(int) * (size_t)(nf ? nf : 1));
    pair_check c;
    int rc = SF_OK;
    if (!vbox || !fbox || !ebox || !least_edge) {
        rc = tp_nomem(B);
        goto done;
    }
    for (int v = 0; v < nv; v++) {
        if (!B->used[v] && B->bpos[v] < 0) tp_box_empty(&vbox[v]);
        else point_box(VX(B, v), &vbox[v]);
    }
    for (int i = 0; i < nf; i++) segment_box(VX(B, s->folds[i].a), VX(B, s->folds[i].b), &fbox[i]);
    for (int k = 0; k < nb; k++)
        segment_box(VX(B, t->boundary[k]), VX(B, t->boundary[(k + 1) % nb]), &ebox[k]);
    /* distinct pattern vertices at distinct places */
    pair_check_init(&c, B);
    if (tp_box_pairs(nv, vbox, 0, NULL, tol, coincide_pair, &c)) {
        rc = tp_nomem(B);
        goto done;
    }
    if (c.k1 < INT_MAX) {
        int v = c.k1, u = c.k2;
        rc = tp_fail_line(B, VL(B, v), "vertices %s and %s coincide at (%g, %g)",
                          VN(B, u), VN(B, v), VX(B, v)[0], VX(B, v)[1]);
        goto done;
    }
    pair_check_init(&c, B);
    if (tp_box_pairs(nf, fbox, 0, NULL, tol, duplicate_pair, &c)) {
        rc = tp_nomem(B);
        goto done;
    }
    if (c.k1 < INT_MAX) {
        int j = c.k1, i = c.k2;
        rc = tp_fail_line(B, s->folds[j].line, "%s duplicates %s", tp_FN(B, j).s, tp_FN(B, i).s);
        goto done;
    }
    pair_check_init(&c, B);
    if (tp_box_pairs(nf, fbox, nv, vbox, tol, through_pair, &c)) {
        rc = tp_nomem(B);
        goto done;
    }
    if (c.k1 < INT_MAX) {
        int i = c.k1, v = c.k2;
        rc = tp_fail_line(B, s->folds[i].line, "%s passes through vertex %s, which is not one of "
                          "its ends", tp_FN(B, i).s, VN(B, v));
        goto done;
    }
    pair_check_init(&c, B);
    c.least_edge = least_edge;
    for (int i = 0; i < nf; i++) least_edge[i] = INT_MAX;
    if (tp_box_pairs(nf, fbox, nb, ebox, tol, outline_pair, &c)) {
        rc = tp_nomem(B);
        goto done;
    }
    for (int i = 0; i < nf; i++) {
        const sf_fold_def *f = &s->folds[i];
        int pa = B->bpos[f->a], pb = B->bpos[f->b];
        if (pa >= 0 && pb >= 0 && ((pa + 1) % nb == pb || (pb + 1) % nb == pa)) {
            rc = tp_fail_line(B, f->line, "%s lies on the outline", tp_FN(B, i).s);
            goto done;
        }
        if (least_edge[i] < INT_MAX) {
            int k = least_edge[i], p = t->boundary[k], q = t->boundary[(k + 1) % nb];
            rc = tp_fail_line(B, f->line, "%s crosses the outline (edge %s-%s)", tp_FN(B, i).s,
                              VN(B, p), VN(B, q));
            goto done;
        }
    }
    pair_check_init(&c, B);
    if (tp_box_pairs(nf, fbox, 0, NULL, tol, cross_pair, &c)) {
        rc = tp_nomem(B);
        goto done;
    }
    if (c.k1 < INT_MAX) {
        int j = c.k1, i = c.k2;
        const sf_fold_def *fi = &s->folds[i], *fj = &s->folds[j];
        const double *p = VX(B, fi->a), *q = VX(B, fi->b), *r = VX(B, fj->a), *w = VX(B, fj->b);
        double d[2], e[2], g[2];
        tp_sub2(q, p, d);
        tp_sub2(w, r, e);
        tp_sub2(r, p, g);
        double u = cross2(g, e) / cross2(d, e);
        rc = tp_fail_line(B, fj->line, "%s crosses %s at (%g, %g) without a common vertex",
                          tp_FN(B, j).s, tp_FN(B, i).s, p[0] + u * d[0], p[1] + u * d[1]);
        goto done;
    }
    /* with no crossing and no foreign vertex on it, a fold is wholly inside
     * or wholly outside: its midpoint tells which */
    double (*P)[2] = malloc(sizeof *P * (size_t)nb);
    if (!P) {
        rc = tp_nomem(B);
        goto done;
    }
    for (int k = 0; k < nb; k++) {
        P[k][0] = VX(B, t->boundary[k])[0];
        P[k][1] = VX(B, t->boundary[k])[1];
    }
    for (int i = 0; i < nf && rc == SF_OK; i++) {
        const sf_fold_def *f = &s->folds[i];
        double mid[2] = {0.5 * (VX(B, f->a)[0] + VX(B, f->b)[0]),
                         0.5 * (VX(B, f->a)[1] + VX(B, f->b)[1])};
        if (tp_poly_classify(nb, P, mid, tol, NULL) <= 0)
            rc = tp_fail_line(B, f->line, "%s lies outside the outline", tp_FN(B, i).s);
    }
    free(P);
done:
    free(vbox);
    free(fbox);
    free(ebox);
    free(least_edge);
    return rc;
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

/* bands of folds j > i that overlap */
static void band_pair(void *ctx, int j, int i)
{
    pair_check *c = ctx;
    const sf_topology *t = c->B->t;
    if (bands_overlap(&t->folds[i], &t->folds[j], c->B->tol)) take(c, j, i);
}

int tp_check_bands(topo_build *B)
{
    const sf_study *s = B->s;
    const sf_topology *t = B->t;
    int nf = t->nfolds;
    tp_box *box = malloc(sizeof(tp_box) * (size_t)(nf ? nf : 1));
    if (!box) return tp_nomem(B);
    for (int i = 0; i < nf; i++) {
        tp_box_empty(&box[i]);
        for (int c = 0; c < 4; c++) tp_box_add(&box[i], t->folds[i].corner[c]);
    }
    pair_check c;
    pair_check_init(&c, B);
    int rc = tp_box_pairs(nf, box, 0, NULL, B->tol, band_pair, &c);
    free(box);
    if (rc) return tp_nomem(B);
    if (c.k1 < INT_MAX) {
        int j = c.k1, i = c.k2;
        const sf_fold_def *fi = &s->folds[i], *fj = &s->folds[j];
        int common = (fi->a == fj->a || fi->a == fj->b) ? fi->a
                     : (fi->b == fj->a || fi->b == fj->b) ? fi->b : -1;
        if (common >= 0)
            return tp_fail_line(B, fj->line, "bands of %s and %s overlap; increase their "
                                "setbacks at %s or make them narrower",
                                tp_FN(B, j).s, tp_FN(B, i).s, VN(B, common));
        return tp_fail_line(B, fj->line, "bands of %s and %s overlap", tp_FN(B, j).s, tp_FN(B, i).s);
    }
    return SF_OK;
}
