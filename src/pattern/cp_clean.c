/* cp_clean.c - drawn line work made into a planar crease pattern
 * (sf_cp_planarize), and the outer face of a pattern's graph
 * (sf_cp_outer_edges).  cpattern.h.
 *
 * Drawings (SVG) are segments whose ends nearly meet, that cross without a
 * vertex, that end on another segment's middle or lie on top of each
 * other.  sf_cp_planarize turns them into a planar straight-line graph:
 *   1. vertices closer than tol merged (to the last of them: a crossing
 *      point, exact where two lines meet, is appended after the drawn
 *      ends, which meet only nearly);
 *   2. every edge split where another edge crosses it or where a vertex
 *      lies within tol of it (a T-junction, or an overlapping collinear
 *      edge's end), the new vertices merged as in 1;
 *   3. zero-length edges dropped, duplicates merged (a line drawn over the
 *      outline is the outline, a fold over a facet or unassigned line is
 *      the fold, a mountain over a valley is an error unless the edge is
 *      shorter than 10 tol: a sliver where two lines nearly meet, whose
 *      first drawn stays).
 * Pairs are tested through a uniform grid of cells of the mean edge length,
 * so the work grows with the number of nearby pairs. */
#include "cpattern.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FAILC(...) (sf_fail(err, SF_EINPUT, __VA_ARGS__), err->code)

/* ---- a grid of edge boxes ------------------------------------------------ */

typedef struct grid {
    double lo[2], cell;
    int nx, ny;
    int *start, *item;        /* CSR: cell -> edges */
} grid;

static void grid_free(grid *g) { free(g->start); free(g->item); }

static void ebox(const sf_cpattern *cp, int e, double pad, double lo[2], double hi[2])
{
    const double *a = cp->v[cp->e[e].a].x, *b = cp->v[cp->e[e].b].x;
    for (int k = 0; k < 2; k++) {
        lo[k] = fmin(a[k], b[k]) - pad;
        hi[k] = fmax(a[k], b[k]) + pad;
    }
}

static void cell_range(const grid *g, const double lo[2], const double hi[2], int r[4])
{
    r[0] = (int)floor((lo[0] - g->lo[0]) / g->cell);
    r[1] = (int)floor((lo[1] - g->lo[1]) / g->cell);
    r[2] = (int)floor((hi[0] - g->lo[0]) / g->cell);
    r[3] = (int)floor((hi[1] - g->lo[1]) / g->cell);
    r[0] = r[0] < 0 ? 0 : r[0] >= g->nx ? g->nx - 1 : r[0];
    r[2] = r[2] < 0 ? 0 : r[2] >= g->nx ? g->nx - 1 : r[2];
    r[1] = r[1] < 0 ? 0 : r[1] >= g->ny ? g->ny - 1 : r[1];
    r[3] = r[3] < 0 ? 0 : r[3] >= g->ny ? g->ny - 1 : r[3];
}

static int grid_build(grid *g, const sf_cpattern *cp, double pad)
{
    memset(g, 0, sizeof *g);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, len = 0;
    for (int i = 0; i < cp->nv; i++)
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], cp->v[i].x[k]);
            hi[k] = fmax(hi[k], cp->v[i].x[k]);
        }
    for (int e = 0; e < cp->ne; e++)
        len += hypot(cp->v[cp->e[e].b].x[0] - cp->v[cp->e[e].a].x[0],
                     cp->v[cp->e[e].b].x[1] - cp->v[cp->e[e].a].x[1]);
    double span = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    g->cell = cp->ne ? len / cp->ne : span;
    if (!(g->cell > 0)) g->cell = span > 0 ? span : 1;
    if (g->cell < span / 1024) g->cell = span / 1024;   /* at most 1024 x 1024 cells */
    g->lo[0] = lo[0] - pad;
    g->lo[1] = lo[1] - pad;
    g->nx = (int)((hi[0] - lo[0] + 2 * pad) / g->cell) + 1;
    g->ny = (int)((hi[1] - lo[1] + 2 * pad) / g->cell) + 1;
    size_t nc = (size_t)g->nx * (size_t)g->ny;
    g->start = calloc(nc + 1, sizeof *g->start);
    if (!g->start) return SF_ENOMEM;
    size_t total = 0;
    for (int pass = 0; pass < 2; pass++) {
        for (int e = 0; e < cp->ne; e++) {
            double blo[2], bhi[2];
            int r[4];
            ebox(cp, e, pad, blo, bhi);
            cell_range(g, blo, bhi, r);
            for (int y = r[1]; y <= r[3]; y++)
                for (int x = r[0]; x <= r[2]; x++) {
                    size_t c = (size_t)y * (size_t)g->nx + (size_t)x;
                    if (pass == 0) { g->start[c + 1]++; total++; }
                    else g->item[g->start[c]++] = e;
                }
        }
        if (pass == 0) {
            for (size_t c = 0; c < nc; c++) g->start[c + 1] += g->start[c];
            g->item = malloc((total + 1) * sizeof *g->item);
            if (!g->item) return SF_ENOMEM;
        } else {
            for (size_t c = nc; c > 0; c--) g->start[c] = g->start[c - 1];
            g->start[0] = 0;
        }
    }
    return SF_OK;
}

/* ---- step 1: merging close vertices ---------------------------------------- */

static int find(int *par, int i)
{
    while (par[i] != i) i = par[i] = par[par[i]];
    return i;
}

typedef struct sortkey { double x; int i; } sortkey;

static int key_cmp(const void *pa, const void *pb)
{
    const sortkey *a = pa, *b = pb;
    if (a->x != b->x) return (a->x > b->x) - (a->x < b->x);
    return (a->i > b->i) - (a->i < b->i);
}

/* Vertices within tol of a later one take its place; edges renumbered,
 * unused vertices dropped.  Sweep over x. */
static int merge_vertices(sf_cpattern *cp, double tol, sf_error *err)
{
    int n = cp->nv;
    int *par = malloc((size_t)(n + 1) * sizeof *par);
    int *map = malloc((size_t)(n + 1) * sizeof *map);
    sortkey *k = malloc((size_t)(n + 1) * sizeof *k);
    char *used = calloc((size_t)n + 1, 1);
    if (!par || !map || !k || !used) {
        free(par); free(map); free(k); free(used);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int i = 0; i < n; i++) { par[i] = i; k[i] = (sortkey){cp->v[i].x[0], i}; }
    qsort(k, (size_t)n, sizeof *k, key_cmp);
    for (int s = 0; s < n; s++)
        for (int t = s + 1; t < n && k[t].x - k[s].x <= tol; t++) {
            int i = k[s].i, j = k[t].i;
            if (hypot(cp->v[i].x[0] - cp->v[j].x[0], cp->v[i].x[1] - cp->v[j].x[1]) > tol) continue;
            int ri = find(par, i), rj = find(par, j);
            if (ri > rj) par[rj] = ri;   /* the later one stays: a crossing */
            else if (rj > ri) par[ri] = rj;   /* point is appended after the ends */
        }
    for (int e = 0; e < cp->ne; e++) {
        cp->e[e].a = find(par, cp->e[e].a);
        cp->e[e].b = find(par, cp->e[e].b);
        used[cp->e[e].a] = used[cp->e[e].b] = 1;
    }
    int m = 0;
    for (int i = 0; i < n; i++) {
        map[i] = -1;
        if (used[i]) { cp->v[m] = cp->v[i]; map[i] = m++; }
    }
    cp->nv = m;
    for (int e = 0; e < cp->ne; e++) {
        cp->e[e].a = map[cp->e[e].a];
        cp->e[e].b = map[cp->e[e].b];
    }
    free(par); free(map); free(k); free(used);
    return SF_OK;
}

/* ---- step 2: splitting ------------------------------------------------------ */

typedef struct cut { int e; double t; int v; } cut;

static int cut_cmp(const void *pa, const void *pb)
{
    const cut *a = pa, *b = pb;
    if (a->e != b->e) return a->e - b->e;
    return (a->t > b->t) - (a->t < b->t);
}

typedef struct cuts { cut *c; int n, cap; } cuts;

static int add_cut(cuts *cs, int e, double t, int v)
{
    if (cs->n == cs->cap) {
        int cap = cs->cap ? 2 * cs->cap : 256;
        cut *nc = realloc(cs->c, (size_t)cap * sizeof *nc);
        if (!nc) return SF_ENOMEM;
        cs->c = nc;
        cs->cap = cap;
    }
    cs->c[cs->n++] = (cut){e, t, v};
    return SF_OK;
}

/* parameter of p along a->b, and its distance from the line */
static double param(const double *a, const double *b, const double *p, double *dist)
{
    double d[2] = {b[0] - a[0], b[1] - a[1]}, l2 = d[0] * d[0] + d[1] * d[1];
    double t = ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / l2;
    double q[2] = {a[0] + t * d[0], a[1] + t * d[1]};
    *dist = hypot(p[0] - q[0], p[1] - q[1]);
    return t;
}

/* the cuts of edge pair (e, f): f's ends on e, e's ends on f, a crossing */
static int pair_cuts(sf_cpattern *cp, int e, int f, double tol, cuts *cs)
{
    const sf_cp_edge *E = &cp->e[e], *F = &cp->e[f];
    int ends[2][2] = {{E->a, E->b}, {F->a, F->b}};
    int idx[2] = {e, f};
    int touched = 0;
    for (int s = 0; s < 2; s++) {     /* the ends of one on the other */
        const double *a = cp->v[ends[s][0]].x, *b = cp->v[ends[s][1]].x;
        double len = hypot(b[0] - a[0], b[1] - a[1]);
        if (!(len > tol)) continue;
        for (int k = 0; k < 2; k++) {
            int v = ends[1 - s][k];
            if (v == ends[s][0] || v == ends[s][1]) continue;
            double dist, t = param(a, b, cp->v[v].x, &dist);
            if (dist <= tol && t * len > tol && (1 - t) * len > tol) {
                if (add_cut(cs, idx[s], t, v)) return SF_ENOMEM;
                touched = 1;
            }
        }
    }
    if (touched) return SF_OK;
    if (E->a == F->a || E->a == F->b || E->b == F->a || E->b == F->b) return SF_OK;
    const double *p = cp->v[E->a].x, *q = cp->v[E->b].x, *r = cp->v[F->a].x, *s = cp->v[F->b].x;
    double d1[2] = {q[0] - p[0], q[1] - p[1]}, d2[2] = {s[0] - r[0], s[1] - r[1]};
    double den = d1[0] * d2[1] - d1[1] * d2[0];
    double l1 = hypot(d1[0], d1[1]), l2 = hypot(d2[0], d2[1]);
    if (fabs(den) <= 1e-12 * l1 * l2) return SF_OK;   /* parallel */
    double w[2] = {r[0] - p[0], r[1] - p[1]};
    double t = (w[0] * d2[1] - w[1] * d2[0]) / den;
    double u = (w[0] * d1[1] - w[1] * d1[0]) / den;
    if (t <= 0 || t >= 1 || u <= 0 || u >= 1) return SF_OK;
    int near_e = t * l1 <= tol || (1 - t) * l1 <= tol, near_f = u * l2 <= tol || (1 - u) * l2 <= tol;
    if (near_e && near_f) return SF_OK;   /* two ends within tol: merged */
    if (near_e || near_f) {
        /* the crossing is next to an end of one edge: the other is cut there
         * (the end lies within tol of it, but beyond the T-junction test
         * when its foot is next to the other's end) */
        int cutme = near_e ? f : e, end = near_e ? (t * l1 <= tol ? E->a : E->b) : (u * l2 <= tol ? F->a : F->b);
        const sf_cp_edge *C = &cp->e[cutme];
        double dist, w2 = param(cp->v[C->a].x, cp->v[C->b].x, cp->v[end].x, &dist);
        if (w2 > 0 && w2 < 1 && add_cut(cs, cutme, w2, end)) return SF_ENOMEM;
        return SF_OK;
    }
    int v = sf_cp_add_vertex(cp, p[0] + t * d1[0], p[1] + t * d1[1], NULL);
    if (v < 0) return SF_ENOMEM;
    if (add_cut(cs, e, t, v) || add_cut(cs, f, u, v)) return SF_ENOMEM;
    return SF_OK;
}

static int split_edges(sf_cpattern *cp, double tol, sf_error *err)
{
    if (cp->ne < 2) return SF_OK;
    grid g;
    cuts cs = {0};
    int rc = grid_build(&g, cp, tol);
    int ne = cp->ne;
    char *seen = rc ? NULL : calloc((size_t)ne + 1, 1);
    int *list = rc ? NULL : malloc((size_t)ne * sizeof *list + 1);
    if (rc || !seen || !list) { grid_free(&g); free(seen); free(list); return sf_fail(err, SF_ENOMEM, "out of memory"); }
    for (int e = 0; e < ne && !rc; e++) {
        double lo[2], hi[2];
        int r[4], nl = 0;
        ebox(cp, e, tol, lo, hi);
        cell_range(&g, lo, hi, r);
        for (int y = r[1]; y <= r[3]; y++)
            for (int x = r[0]; x <= r[2]; x++) {
                size_t c = (size_t)y * (size_t)g.nx + (size_t)x;
                for (int k = g.start[c]; k < g.start[c + 1]; k++) {
                    int f = g.item[k];
                    if (f > e && !seen[f]) { seen[f] = 1; list[nl++] = f; }
                }
            }
        for (int k = 0; k < nl; k++) {
            seen[list[k]] = 0;
            double flo[2], fhi[2];
            ebox(cp, list[k], tol, flo, fhi);
            if (flo[0] > hi[0] || fhi[0] < lo[0] || flo[1] > hi[1] || fhi[1] < lo[1]) continue;
            if (pair_cuts(cp, e, list[k], tol, &cs)) { rc = SF_ENOMEM; break; }
        }
    }
    grid_free(&g);
    free(seen);
    free(list);
    if (rc) { free(cs.c); return sf_fail(err, SF_ENOMEM, "out of memory"); }
    if (cs.n) qsort(cs.c, (size_t)cs.n, sizeof *cs.c, cut_cmp);   /* cs.c is NULL without cuts */
    for (int i = 0; i < cs.n;) {
        int e = cs.c[i].e, j = i;
        while (j < cs.n && cs.c[j].e == e) j++;
        sf_cp_edge orig = cp->e[e];
        int prev = orig.a;
        for (int k = i; k <= j; k++) {
            int next = k < j ? cs.c[k].v : orig.b;
            if (next == prev) continue;
            if (prev == orig.a) { cp->e[e].b = next; }
            else {
                int ne2 = sf_cp_add_edge(cp, prev, next, orig.assign, orig.angle);
                if (ne2 < 0) { free(cs.c); return sf_fail(err, SF_ENOMEM, "out of memory"); }
            }
            prev = next;
        }
        i = j;
    }
    free(cs.c);
    return SF_OK;
}

/* ---- step 3: dropping degenerate and duplicate edges ------------------------ */

typedef struct ekey { int a, b, e; } ekey;

static int ekey_cmp(const void *pa, const void *pb)
{
    const ekey *x = pa, *y = pb;
    if (x->a != y->a) return x->a - y->a;
    if (x->b != y->b) return x->b - y->b;
    return x->e - y->e;
}

/* which of two assignments a duplicate keeps: a fold over a facet or
 * unassigned line; 0 when they conflict */
static char stronger(char p, char q)
{
    if (p == q) return p;
    static const char rank[] = "UFMV";   /* M and V outrank F and U */
    if (p == 'B' || q == 'B') return 'B';   /* a line on the outline is the outline */
    if ((p == 'M' && q == 'V') || (p == 'V' && q == 'M')) return 0;
    return strchr(rank, p) > strchr(rank, q) ? p : q;
}

static int dedupe(sf_cpattern *cp, double tol, const char *where, sf_error *err)
{
    ekey *k = malloc((size_t)(cp->ne + 1) * sizeof *k);
    char *drop = calloc((size_t)cp->ne + 1, 1);
    if (!k || !drop) { free(k); free(drop); return sf_fail(err, SF_ENOMEM, "out of memory"); }
    int n = 0;
    for (int e = 0; e < cp->ne; e++) {
        int a = cp->e[e].a, b = cp->e[e].b;
        if (a == b) { drop[e] = 1; continue; }
        k[n++] = (ekey){a < b ? a : b, a < b ? b : a, e};
    }
    qsort(k, (size_t)n, sizeof *k, ekey_cmp);
    int rc = SF_OK;
    for (int i = 1; i < n && !rc; i++) {
        if (k[i].a != k[i - 1].a || k[i].b != k[i - 1].b) continue;
        int keep = k[i - 1].e, dup = k[i].e;
        char s = stronger(cp->e[keep].assign, cp->e[dup].assign);
        const double *pa = cp->v[k[i].a].x, *pb = cp->v[k[i].b].x;
        if (!s && hypot(pb[0] - pa[0], pb[1] - pa[1]) <= 10 * tol) {
            /* a sliver between two nearly meeting lines of the other kind:
             * the first drawn stays */
            s = cp->e[keep].assign;
        }
        if (!s) {
            const double *p = cp->v[k[i].a].x, *q = cp->v[k[i].b].x;
            rc = FAILC("%s%sa line from (%g, %g) to (%g, %g) is drawn twice, as %s and as %s",
                       where ? where : "", where ? ": " : "", p[0], p[1], q[0], q[1],
                       cp->e[keep].assign == 'B' ? "boundary" : cp->e[keep].assign == 'M' ? "mountain" :
                       cp->e[keep].assign == 'V' ? "valley" : cp->e[keep].assign == 'F' ? "facet" : "unassigned",
                       cp->e[dup].assign == 'B' ? "boundary" : cp->e[dup].assign == 'M' ? "mountain" :
                       cp->e[dup].assign == 'V' ? "valley" : cp->e[dup].assign == 'F' ? "facet" : "unassigned");
            break;
        }
        if (s != cp->e[keep].assign) { cp->e[keep].assign = s; cp->e[keep].angle = cp->e[dup].angle; }
        drop[dup] = 1;
        k[i].e = keep;
    }
    int m = 0;
    for (int e = 0; e < cp->ne; e++)
        if (!drop[e]) cp->e[m++] = cp->e[e];
    cp->ne = m;
    free(k);
    free(drop);
    return rc;
}

int sf_cp_planarize(sf_cpattern *cp, double tol, const char *where, sf_error *err)
{
    /* the grid's cells count in ints: coordinates whose differences
     * overflow have no cells */
    for (int i = 0; i < cp->nv; i++)
        if (!(fabs(cp->v[i].x[0]) < 1e150 && fabs(cp->v[i].x[1]) < 1e150))
            return FAILC("%s%svertex at (%g, %g): coordinates beyond 1e150", where ? where : "",
                         where ? ": " : "", cp->v[i].x[0], cp->v[i].x[1]);
    if (!(tol >= 0) || !isfinite(tol)) return FAILC("%s%sno finite merge tolerance", where ? where : "", where ? ": " : "");
    if (cp->nf) {   /* faces no longer match the edges */
        free(cp->face_start); free(cp->face_verts);
        cp->face_start = cp->face_verts = NULL;
        cp->nf = 0;
    }
    int rc = merge_vertices(cp, tol, err);
    if (!rc) rc = dedupe(cp, tol, where, err);
    if (!rc) rc = split_edges(cp, tol, err);
    if (!rc) rc = merge_vertices(cp, tol, err);
    if (!rc) rc = dedupe(cp, tol, where, err);
    /* a split can leave a vertex within tol of a third edge: once more */
    if (!rc) rc = split_edges(cp, tol, err);
    if (!rc) rc = merge_vertices(cp, tol, err);
    if (!rc) rc = dedupe(cp, tol, where, err);
    return rc;
}

/* ---- the outer face ---------------------------------------------------------- */

typedef struct half { double ang; int to, e; } half;

static int half_cmp(const void *pa, const void *pb)
{
    const half *a = pa, *b = pb;
    return (a->ang > b->ang) - (a->ang < b->ang);
}

int sf_cp_outer_edges(const sf_cpattern *cp, char *outer, sf_error *err)
{
    memset(outer, 0, (size_t)cp->ne);
    if (cp->nv == 0 || cp->ne == 0) return SF_OK;
    int *start = calloc((size_t)cp->nv + 1, sizeof *start);
    half *h = malloc((size_t)(2 * cp->ne + 1) * sizeof *h);
    int *fill = calloc((size_t)cp->nv + 1, sizeof *fill);
    if (!start || !h || !fill) { free(start); free(h); free(fill); return sf_fail(err, SF_ENOMEM, "out of memory"); }
    for (int e = 0; e < cp->ne; e++) { start[cp->e[e].a + 1]++; start[cp->e[e].b + 1]++; }
    for (int v = 0; v < cp->nv; v++) start[v + 1] += start[v];
    int v0 = -1;
    for (int e = 0; e < cp->ne; e++)
        for (int s = 0; s < 2; s++) {
            int v = s ? cp->e[e].b : cp->e[e].a, o = s ? cp->e[e].a : cp->e[e].b;
            double ang = atan2(cp->v[o].x[1] - cp->v[v].x[1], cp->v[o].x[0] - cp->v[v].x[0]);
            h[start[v] + fill[v]++] = (half){ang, o, e};
            if (v0 < 0 || cp->v[v].x[0] < cp->v[v0].x[0] ||
                (cp->v[v].x[0] == cp->v[v0].x[0] && cp->v[v].x[1] < cp->v[v0].x[1]))
                v0 = v;
        }
    for (int v = 0; v < cp->nv; v++)
        qsort(h + start[v], (size_t)(start[v + 1] - start[v]), sizeof *h, half_cmp);
    /* walk with the outer face on the right: at v, arriving along the
     * direction back to u, leave by the next half-edge counter-clockwise
     * after it; at the leftmost vertex the arrival is from the west */
    int v = v0;
    double back = M_PI;
    int first = -1, steps = 0;
    for (;;) {
        int s0 = start[v], n = start[v + 1] - s0, pick = -1;
        double best = INFINITY;
        for (int k = 0; k < n; k++) {
            double d = h[s0 + k].ang - back;
            while (d <= 1e-12) d += 2 * M_PI;
            if (d < best) { best = d; pick = s0 + k; }
        }
        if (pick < 0) break;
        if (pick == first) break;
        if (first < 0) first = pick;
        outer[h[pick].e] = 1;
        int u = v;
        v = h[pick].to;
        back = atan2(cp->v[u].x[1] - cp->v[v].x[1], cp->v[u].x[0] - cp->v[v].x[0]);
        if (++steps > 2 * cp->ne + 2) break;
    }
    free(start); free(h); free(fill);
    return SF_OK;
}
