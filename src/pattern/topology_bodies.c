/* topology_bodies.c - step 7 of sf_topology_build (topology.c): the
 * rigid body of every face, its crease-pattern polygon with each fold edge
 * moved onto the band's edge line. */
#include "topology_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

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
        return sf_fail(B->err, SF_EINTERNAL, "%s: %s has an empty body", s->path, tp_FACEN(B, f).s);
    return tp_fail_line(B, s->folds[best].line, "band of %s (width %g) is too wide for %s: "
                     "the face body would be empty or inverted", tp_FN(B, best).s,
                     s->folds[best].width, tp_FACEN(B, f).s);
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
        tp_sub2(x, pj, dj);
        tp_sub2(pk, x, di);
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
                tp_sub2(foot_i, foot_j, g);
                double u = cross2(g, di) / den;
                double X[2] = {foot_j[0] + u * dj[0], foot_j[1] + u * dj[1]};
                rc |= pt_push(L, X, i);
            } else {
                rc |= pt_push(L, foot_j, i);
                rc |= pt_push(L, foot_i, i);
            }
        }
        if (rc) return tp_nomem(B);
    }

    /* offset edges must keep their direction: the segment from the last
     * point made at vertex i to the first point made at vertex i+1 runs
     * along edge i */
    for (int k = 0; k < L->n; k++) {
        int k2 = (k + 1) % L->n;
        if (L->src[k2] == L->src[k]) continue;        /* a connector at one vertex */
        int i = L->src[k], i2 = (i + 1) % n;
        double d[2], e[2];
        tp_sub2(F->poly.p[i2], F->poly.p[i], e);
        tp_sub2(L->p[k2], L->p[k], d);
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
    if (!all) return tp_nomem(B);
    for (int i = 0; i < n; i++) all[i] = F->edge_fold[i];
    int bad = m < 3 || tp_poly_area(m, L->p) <= tol * t->size;
    for (int k = 0; k < m && !bad; k++) {
        const double *p = L->p[k], *q = L->p[(k + 1) % m], *r = L->p[(k + 2) % m];
        double d1[2], d2[2];
        tp_sub2(q, p, d1);
        tp_sub2(r, q, d2);
        /* a spike: the next edge goes straight back */
        if (fabs(tp_side(p, q, r)) <= tol && dot2(d1, d2) < 0.0) bad = 1;
        for (int l = k + 2; l < m && !bad; l++) {
            if (k == 0 && l == m - 1) continue;
            if (tp_seg_seg(p, q, L->p[l], L->p[(l + 1) % m]) <= tol) bad = 1;
        }
        if (tp_poly_classify(n, F->poly.p, p, tol, NULL) < 0) bad = 1;
    }
    if (bad) {
        int rc = body_fail(B, f, all, n);
        free(all);
        return rc;
    }
    free(all);
    F->body.p = malloc(sizeof *F->body.p * (size_t)m);
    if (!F->body.p) return tp_nomem(B);
    F->body.n = m;
    memcpy(F->body.p, L->p, sizeof *L->p * (size_t)m);
    F->area = tp_poly_centroid(m, F->body.p, F->centroid);
    return SF_OK;
}

int tp_build_bodies(topo_build *B)
{
    ptlist L = {NULL, NULL, 0, 0};
    int rc = SF_OK;
    for (int f = 0; f < B->t->nfaces && rc == SF_OK; f++) rc = build_body(B, f, &L);
    free(L.p);
    free(L.src);
    return rc;
}
