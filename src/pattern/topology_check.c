/* topology_check.c - the checks of sf_topology_build (topology.c) before
 * and after the graph: 1. the outline (vertices, edges, orientation, fold
 * ends inserted into the boundary), 2. the folds (widths, setbacks,
 * duplicates, crossings, folds through vertices or outside the outline),
 * 6. the bands (corners, overlaps by a separating-axis test). */
#include "topology_impl.h"

#include <math.h>
#include <stdlib.h>

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

int tp_check_folds_geometry(topo_build *B)
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
                return tp_fail_line(B, VL(B, v), "vertices %s and %s coincide at (%g, %g)",
                                 VN(B, u), VN(B, v), VX(B, v)[0], VX(B, v)[1]);
        }
    }
    for (int j = 0; j < nf; j++)
        for (int i = 0; i < j; i++) {
            const sf_fold_def *fi = &s->folds[i], *fj = &s->folds[j];
            if ((fi->a == fj->a && fi->b == fj->b) || (fi->a == fj->b && fi->b == fj->a))
                return tp_fail_line(B, fj->line, "%s duplicates %s", tp_FN(B, j).s, tp_FN(B, i).s);
        }
    for (int i = 0; i < nf; i++) {
        const sf_fold_def *f = &s->folds[i];
        for (int v = 0; v < nv; v++) {
            if (v == f->a || v == f->b || (!B->used[v] && B->bpos[v] < 0)) continue;
            if (tp_point_seg(VX(B, f->a), VX(B, f->b), VX(B, v), NULL) <= tol)
                return tp_fail_line(B, f->line, "%s passes through vertex %s, which is not one of its ends",
                                 tp_FN(B, i).s, VN(B, v));
        }
    }
    for (int i = 0; i < nf; i++) {
        const sf_fold_def *f = &s->folds[i];
        int pa = B->bpos[f->a], pb = B->bpos[f->b];
        if (pa >= 0 && pb >= 0 && ((pa + 1) % nb == pb || (pb + 1) % nb == pa))
            return tp_fail_line(B, f->line, "%s lies on the outline", tp_FN(B, i).s);
        for (int k = 0; k < nb; k++) {
            int p = t->boundary[k], q = t->boundary[(k + 1) % nb];
            if (tp_proper_cross(VX(B, f->a), VX(B, f->b), VX(B, p), VX(B, q), tol))
                return tp_fail_line(B, f->line, "%s crosses the outline (edge %s-%s)", tp_FN(B, i).s,
                                 VN(B, p), VN(B, q));
        }
    }
    for (int j = 0; j < nf; j++)
        for (int i = 0; i < j; i++) {
            const sf_fold_def *fi = &s->folds[i], *fj = &s->folds[j];
            const double *p = VX(B, fi->a), *q = VX(B, fi->b), *r = VX(B, fj->a), *w = VX(B, fj->b);
            if (!tp_proper_cross(p, q, r, w, tol)) continue;
            double d[2], e[2], g[2];
            tp_sub2(q, p, d);
            tp_sub2(w, r, e);
            tp_sub2(r, p, g);
            double u = cross2(g, e) / cross2(d, e);
            return tp_fail_line(B, fj->line, "%s crosses %s at (%g, %g) without a common vertex",
                             tp_FN(B, j).s, tp_FN(B, i).s, p[0] + u * d[0], p[1] + u * d[1]);
        }
    /* with no crossing and no foreign vertex on it, a fold is wholly inside
     * or wholly outside: its midpoint tells which */
    double (*P)[2] = malloc(sizeof *P * (size_t)nb);
    if (!P) return tp_nomem(B);
    for (int k = 0; k < nb; k++) {
        P[k][0] = VX(B, t->boundary[k])[0];
        P[k][1] = VX(B, t->boundary[k])[1];
    }
    int rc = SF_OK;
    for (int i = 0; i < nf && rc == SF_OK; i++) {
        const sf_fold_def *f = &s->folds[i];
        double mid[2] = {0.5 * (VX(B, f->a)[0] + VX(B, f->b)[0]),
                         0.5 * (VX(B, f->a)[1] + VX(B, f->b)[1])};
        if (tp_poly_classify(nb, P, mid, tol, NULL) <= 0)
            rc = tp_fail_line(B, f->line, "%s lies outside the outline", tp_FN(B, i).s);
    }
    free(P);
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

int tp_check_bands(topo_build *B)
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
                return tp_fail_line(B, fj->line, "bands of %s and %s overlap; increase their "
                                 "setbacks at %s or make them narrower",
                                 tp_FN(B, j).s, tp_FN(B, i).s, VN(B, common));
            return tp_fail_line(B, fj->line, "bands of %s and %s overlap", tp_FN(B, j).s, tp_FN(B, i).s);
        }
    return SF_OK;
}
