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
#include "topology_impl.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

int tp_fail_line(topo_build *B, int line, const char *fmt, ...)
{
    char msg[900];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (line > 0) return sf_fail(B->err, SF_EINPUT, "%s:%d: %s", B->s->path, line, msg);
    return sf_fail(B->err, SF_EINPUT, "%s: %s", B->s->path, msg);
}


label_t tp_FN(const topo_build *B, int i)
{
    label_t l;
    sf_topology_fold_name(B->s, i, l.s, sizeof l.s);
    return l;
}


flabel_t tp_FACEN(const topo_build *B, int f)
{
    flabel_t l;
    sf_topology_face_name(B->s, B->t, f, l.s, sizeof l.s);
    return l;
}

void *tp_xcalloc(size_t n, size_t size)
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

int tp_nomem(topo_build *B)
{
    return sf_fail(B->err, SF_ENOMEM, "%s: out of memory building the topology", B->s->path);
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
    B->vfirst = tp_xcalloc((size_t)nv + 1, sizeof(int));
    B->vdeg = tp_xcalloc((size_t)nv, sizeof(int));
    B->vout = malloc(sizeof(int) * (size_t)nh);
    if (!B->hfrom || !B->hto || !B->hcycle || !B->hnext || !B->hang || !B->vfirst ||
        !B->vdeg || !B->vout)
        return tp_nomem(B);
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
        tp_sub2(VX(B, B->hto[h]), VX(B, B->hfrom[h]), d);
        double ang = atan2(d[1], d[0]);
        if (ang < 0.0) ang += 2.0 * TOPO_PI;
        if (ang >= 2.0 * TOPO_PI) ang = 0.0;
        B->hang[h] = ang;
        B->vdeg[B->hfrom[h]]++;
    }
    for (int v = 0; v < nv; v++) B->vfirst[v + 1] = B->vfirst[v] + B->vdeg[v];
    int *fill = tp_xcalloc((size_t)nv, sizeof(int));
    if (!fill) return tp_nomem(B);
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
            return tp_fail_line(B, s->folds[i].line, "%s does not separate two different faces "
                             "(a dangling fold: one of its ends is free)", tp_FN(B, i).s);
        if (B->hcycle[h] == outer || B->hcycle[h + 1] == outer)
            return sf_fail(B->err, SF_EINTERNAL, "%s: %s borders the outside", s->path, tp_FN(B, i).s);
    }
    /* a cluster of folds that touches nothing else leaves a second cycle of
     * negative area (a hole) around it */
    int *first = malloc(sizeof(int) * (size_t)nc);
    B->cface = malloc(sizeof(int) * (size_t)nc);
    if (!first || !B->cface) {
        free(first);
        return tp_nomem(B);
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
            return tp_fail_line(B, s->folds[fi].line, "%s is not connected to the outline through "
                             "other folds (a face would have a hole)", tp_FN(B, fi).s);
        }
        B->cface[c] = nfaces++;
    }
    t->nfaces = nfaces;
    t->faces = tp_xcalloc((size_t)nfaces, sizeof(sf_face));
    if (!t->faces) {
        free(first);
        return tp_nomem(B);
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
            return tp_nomem(B);
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
                    return tp_fail_line(B, VL(B, F->verts[i]), "%s touches itself at vertex %s; "
                                     "faces must be simple polygons", tp_FACEN(B, f).s,
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
    t->folds = tp_xcalloc((size_t)nf, sizeof(sf_fold_geom));
    if (!t->folds) return tp_nomem(B);
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
    if (!t->ivertex_of) return tp_nomem(B);
    int niv = 0;
    for (int v = 0; v < nv; v++) {
        t->ivertex_of[v] = -1;
        if (B->used[v] && B->bpos[v] < 0) t->ivertex_of[v] = niv++;
    }
    t->nivertices = niv;
    t->ivertices = tp_xcalloc((size_t)niv, sizeof(sf_ivertex));
    if (!t->ivertices) return tp_nomem(B);
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
        if (!iv->folds || !iv->sign || !iv->faces) return tp_nomem(B);
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
        int c = tp_poly_classify(t->faces[f].poly.n, t->faces[f].poly.p, x, t->tol, &m);
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
        tp_sub2(x, g->a, d);
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
        return tp_fail_line(B, s->fixed_line, "fixed point is not finite");
    int root = sf_topology_locate_face(t, s->fixed_point);
    if (root < 0)
        return tp_fail_line(B, s->fixed_line, "fixed point (%g, %g) is outside the sheet",
                         s->fixed_point[0], s->fixed_point[1]);
    {   /* on a vertex shared by faces the point names no one face (on a
         * fold line the face with the larger margin is taken, as before) */
        int nface = 0, other = -1;
        for (int f = 0; f < nf; f++) {
            double m;
            if (tp_poly_classify(t->faces[f].poly.n, t->faces[f].poly.p, s->fixed_point, t->tol, &m) >= 0) {
                nface++;
                if (f != root) other = f;
            }
        }
        int vx = -1;
        for (int v = 0; v < s->nvertices && vx < 0; v++)
            if (hypot(s->vertices[v].x[0] - s->fixed_point[0],
                      s->vertices[v].x[1] - s->fixed_point[1]) <= t->tol) vx = v;
        if (nface > 1 && vx >= 0)
            return tp_fail_line(B, s->fixed_line, "fixed point (%g, %g) is vertex %s, a corner of "
                                "face %d and face %d: it must be inside one face",
                                s->fixed_point[0], s->fixed_point[1], s->vertices[vx].name, root + 1,
                                other + 1);
    }
    t->root = root;
    t->order = malloc(sizeof(int) * (size_t)(nf ? nf : 1));
    /* the folds of each face, ascending (CSR): the tree below takes, from
     * each face, its folds in that order */
    int *ffirst = calloc((size_t)nf + 1, sizeof(int));
    int *ffolds = malloc(sizeof(int) * (size_t)(2 * t->nfolds + 1));
    if (!t->order || !ffirst || !ffolds) {
        free(ffirst);
        free(ffolds);
        return tp_nomem(B);
    }
    for (int i = 0; i < t->nfolds; i++) {
        const sf_fold_geom *g = &t->folds[i];
        if (g->left >= 0 && g->left < nf) ffirst[g->left + 1]++;
        if (g->right >= 0 && g->right < nf && g->right != g->left) ffirst[g->right + 1]++;
    }
    for (int f = 0; f < nf; f++) ffirst[f + 1] += ffirst[f];
    for (int i = 0; i < t->nfolds; i++) {
        const sf_fold_geom *g = &t->folds[i];
        if (g->left >= 0 && g->left < nf) ffolds[ffirst[g->left]++] = i;
        if (g->right >= 0 && g->right < nf && g->right != g->left) ffolds[ffirst[g->right]++] = i;
    }
    for (int f = nf; f > 0; f--) ffirst[f] = ffirst[f - 1];
    ffirst[0] = 0;
    for (int f = 0; f < nf; f++) t->faces[f].depth = -1;
    t->faces[root].depth = 0;
    t->faces[root].parent = -1;
    t->faces[root].parent_fold = -1;
    int head = 0, tail = 0;
    t->order[tail++] = root;
    while (head < tail) {
        int f = t->order[head++];
        for (int e = ffirst[f]; e < ffirst[f + 1]; e++) {
            int i = ffolds[e];
            const sf_fold_geom *g = &t->folds[i];
            int o = g->left == f ? g->right : g->right == f ? g->left : -1;
            if (o < 0 || t->faces[o].depth >= 0) continue;
            t->faces[o].depth = t->faces[f].depth + 1;
            t->faces[o].parent = f;
            t->faces[o].parent_fold = i;
            t->order[tail++] = o;
        }
    }
    free(ffirst);
    free(ffolds);
    for (int f = 0; f < nf; f++)
        if (t->faces[f].depth < 0)
            return tp_fail_line(B, s->fixed_line, "%s cannot be reached from the fixed face by "
                             "crossing folds", tp_FACEN(B, f).s);
    return SF_OK;
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
    B.used = tp_xcalloc((size_t)nv, 1);
    B.bpos = malloc(sizeof(int) * (size_t)(nv ? nv : 1));
    int rc = SF_OK;
    if (!B.used || !B.bpos) rc = tp_nomem(&B);
    for (int v = 0; v < nv && rc == SF_OK; v++) B.bpos[v] = -1;
    if (rc == SF_OK) rc = tp_check_outline(&B);
    if (rc == SF_OK) rc = tp_check_folds_basic(&B);
    if (rc == SF_OK) rc = tp_insert_boundary(&B);
    if (rc == SF_OK) rc = tp_check_folds_geometry(&B);
    if (rc == SF_OK) rc = build_graph(&B);
    if (rc == SF_OK) rc = build_faces(&B);
    if (rc == SF_OK) rc = build_fold_geom(&B);
    if (rc == SF_OK) rc = build_ivertices(&B);
    if (rc == SF_OK) rc = build_tree(&B);
    if (rc == SF_OK) rc = tp_check_bands(&B);
    if (rc == SF_OK) rc = tp_build_bodies(&B);
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
