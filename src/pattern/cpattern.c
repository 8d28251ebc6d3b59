/* cpattern.c - the crease pattern between generators, FOLD files and
 * studies: building, checking as a planar graph, the outline loop and the
 * automatic setbacks (cpattern.h). */
#include "cpattern.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sf_cp_init(sf_cpattern *cp)
{
    memset(cp, 0, sizeof *cp);
    cp->unit = 1.0;
}

void sf_cp_free(sf_cpattern *cp)
{
    free(cp->v);
    free(cp->e);
    free(cp->face_start);
    free(cp->face_verts);
    sf_cp_init(cp);
}

int sf_cp_add_vertex(sf_cpattern *cp, double x, double y, const char *name)
{
    if (cp->nv == cp->vcap) {
        int cap = cp->vcap ? 2 * cp->vcap : 64;
        sf_cp_vertex *nv = realloc(cp->v, (size_t)cap * sizeof *nv);
        if (!nv) return -1;
        cp->v = nv;
        cp->vcap = cap;
    }
    sf_cp_vertex *v = &cp->v[cp->nv];
    v->x[0] = x;
    v->x[1] = y;
    snprintf(v->name, sizeof v->name, "%s", name ? name : "");
    return cp->nv++;
}

int sf_cp_vertex_at(sf_cpattern *cp, double x, double y, double tol)
{
    for (int i = 0; i < cp->nv; i++)
        if (fabs(cp->v[i].x[0] - x) <= tol && fabs(cp->v[i].x[1] - y) <= tol) return i;
    return sf_cp_add_vertex(cp, x, y, NULL);
}

int sf_cp_add_edge(sf_cpattern *cp, int a, int b, char assign, double angle_deg)
{
    if (cp->ne == cp->ecap) {
        int cap = cp->ecap ? 2 * cp->ecap : 64;
        sf_cp_edge *ne = realloc(cp->e, (size_t)cap * sizeof *ne);
        if (!ne) return -1;
        cp->e = ne;
        cp->ecap = cap;
    }
    sf_cp_edge *e = &cp->e[cp->ne];
    e->a = a;
    e->b = b;
    e->assign = assign;
    e->angle = angle_deg;
    e->name[0] = '\0';
    return cp->ne++;
}

/* ---- checks ------------------------------------------------------------- */

static double cross3(const double *o, const double *a, const double *b)
{
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

double sf_cp_size(const sf_cpattern *cp)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < cp->nv; i++)
        for (int k = 0; k < 2; k++) {
            if (cp->v[i].x[k] < lo[k]) lo[k] = cp->v[i].x[k];
            if (cp->v[i].x[k] > hi[k]) hi[k] = cp->v[i].x[k];
        }
    double s = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    return s > 0 && isfinite(s) ? s : 1.0;
}

/* Is p strictly inside segment a-b (within tol of the line, not at ends)? */
static int on_segment(const double *a, const double *b, const double *p, double tol)
{
    double d[2] = {b[0] - a[0], b[1] - a[1]};
    double l2 = d[0] * d[0] + d[1] * d[1];
    double t = ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / l2;
    double l = sqrt(l2);
    if (t * l <= tol || (1 - t) * l <= tol) return 0;
    return fabs(cross3(a, b, p)) / l <= tol;
}

#define FAILW(...) (sf_fail(err, SF_EINPUT, __VA_ARGS__), err->code)

static int check_edges(const sf_cpattern *cp, const char *w, double tol, sf_error *err)
{
    for (int i = 0; i < cp->ne; i++) {
        const sf_cp_edge *e = &cp->e[i];
        for (int k = 0; k < 2; k++) {
            int v = k ? e->b : e->a;
            if (v < 0 || v >= cp->nv)
                return FAILW("%sedges_vertices[%d]: vertex %d does not exist (vertices_coords has %d)",
                             w, i, v, cp->nv);
        }
        if (e->a == e->b)
            return FAILW("%sedges_vertices[%d]: both ends are vertex %d", w, i, e->a);
        const double *a = cp->v[e->a].x, *b = cp->v[e->b].x;
        if (hypot(b[0] - a[0], b[1] - a[1]) <= tol)
            return FAILW("%sedges_vertices[%d]: zero length (vertices %d and %d coincide)",
                         w, i, e->a, e->b);
    }
    for (int v = 0; v < cp->nv; v++)
        for (int u = v + 1; u < cp->nv; u++)
            if (hypot(cp->v[v].x[0] - cp->v[u].x[0], cp->v[v].x[1] - cp->v[u].x[1]) <= tol)
                return FAILW("%svertices_coords[%d]: same point as vertices_coords[%d]", w, u, v);
    for (int i = 0; i < cp->ne; i++) {
        const sf_cp_edge *e = &cp->e[i];
        const double *a = cp->v[e->a].x, *b = cp->v[e->b].x;
        for (int v = 0; v < cp->nv; v++)
            if (v != e->a && v != e->b && on_segment(a, b, cp->v[v].x, tol))
                return FAILW("%sedges_vertices[%d]: vertex %d lies inside the edge (split the edge there)",
                             w, i, v);
        for (int j = i + 1; j < cp->ne; j++) {
            const sf_cp_edge *f = &cp->e[j];
            if ((f->a == e->a && f->b == e->b) || (f->a == e->b && f->b == e->a))
                return FAILW("%sedges_vertices[%d]: duplicate of edges_vertices[%d] (vertices %d, %d)",
                             w, j, i, f->a, f->b);
            if (f->a == e->a || f->a == e->b || f->b == e->a || f->b == e->b) continue;
            const double *c = cp->v[f->a].x, *d = cp->v[f->b].x;
            double d1 = cross3(a, b, c), d2 = cross3(a, b, d);
            double d3 = cross3(c, d, a), d4 = cross3(c, d, b);
            /* on one line (the signs are rounding's): not a crossing; an
             * overlap has a vertex inside the other edge, tested above */
            double lab = hypot(b[0] - a[0], b[1] - a[1]), lcd = hypot(d[0] - c[0], d[1] - c[1]);
            if (fmax(fabs(d1), fabs(d2)) <= tol * lab && fmax(fabs(d3), fabs(d4)) <= tol * lcd) continue;
            if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) &&
                ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
                return FAILW("%sedges_vertices[%d]: crosses edges_vertices[%d] away from a vertex "
                             "(the crease pattern is not planar: add the crossing as a vertex)", w, j, i);
        }
    }
    return SF_OK;
}

static double loop_area(const sf_cpattern *cp, const int *vs, int n)
{
    double a = 0;
    for (int k = 0; k < n; k++) {
        const double *p = cp->v[vs[k]].x, *q = cp->v[vs[(k + 1) % n]].x;
        a += p[0] * q[1] - q[0] * p[1];
    }
    return 0.5 * a;
}

int sf_cp_outline(const sf_cpattern *cp, int **out, int *n, const char *where,
                  sf_error *err)
{
    char wb[1100];
    snprintf(wb, sizeof wb, "%s%s", where ? where : "", where ? ": " : "");
    const char *w = wb;
    *out = NULL;
    *n = 0;
    int nb = 0, first = -1;
    int *deg = calloc((size_t)cp->nv + 1, sizeof *deg);
    if (!deg) return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int i = 0; i < cp->ne; i++)
        if (cp->e[i].assign == 'B') {
            nb++;
            if (first < 0) first = i;
            deg[cp->e[i].a]++;
            deg[cp->e[i].b]++;
        }
    if (nb < 3) {
        free(deg);
        return FAILW("%sedges_assignment: %d boundary (\"B\") edges, the outline needs at least 3", w, nb);
    }
    for (int v = 0; v < cp->nv; v++)
        if (deg[v] != 0 && deg[v] != 2) {
            int d = deg[v];   /* read before the array is freed */
            free(deg);
            if (d == 1)
                return FAILW("%svertices_coords[%d] (%g, %g): a boundary edge ends there, meeting no other "
                             "(a gap in the outline? the outline must be one closed loop)", w, v, cp->v[v].x[0],
                             cp->v[v].x[1]);
            return FAILW("%svertices_coords[%d] (%g, %g): %d boundary edges meet there (two outlines touching, "
                         "or a stray boundary line? the outline must be one simple loop: 2 boundary edges at "
                         "each of its vertices)", w, v, cp->v[v].x[0], cp->v[v].x[1], d);
        }
    free(deg);
    int *loop = malloc((size_t)nb * sizeof *loop);
    char *used = calloc((size_t)cp->ne, 1);
    if (!loop || !used) { free(loop); free(used); return sf_fail(err, SF_ENOMEM, "out of memory"); }
    int cur = cp->e[first].b, prev_e = first, k = 0;
    loop[k++] = cp->e[first].a;
    used[first] = 1;
    while (cur != loop[0]) {
        if (k >= nb) break;
        loop[k++] = cur;
        int next = -1;
        for (int i = 0; i < cp->ne && next < 0; i++)
            if (!used[i] && i != prev_e && cp->e[i].assign == 'B' &&
                (cp->e[i].a == cur || cp->e[i].b == cur))
                next = i;
        if (next < 0) break;
        used[next] = 1;
        prev_e = next;
        cur = cp->e[next].a == cur ? cp->e[next].b : cp->e[next].a;
    }
    free(used);
    if (k != nb || cur != loop[0]) {
        free(loop);
        return FAILW("%sedges_assignment: the boundary (\"B\") edges form more than one loop "
                     "(%d of %d edges in the loop through vertex %d): a sheet is one piece with one outline, "
                     "without holes (several patterns in one file?)", w, k, nb, cp->e[first].a);
    }
    if (loop_area(cp, loop, nb) < 0)
        for (int i = 1, j = nb - 1; i < j; i++, j--) {
            int t = loop[i]; loop[i] = loop[j]; loop[j] = t;
        }
    *out = loop;
    *n = nb;
    return SF_OK;
}

int sf_cp_check(const sf_cpattern *cp, const char *where, sf_error *err)
{
    char wb[1100];
    snprintf(wb, sizeof wb, "%s%s", where ? where : "", where ? ": " : "");
    double tol = 1e-9 * sf_cp_size(cp);
    for (int i = 0; i < cp->nv; i++)
        if (!isfinite(cp->v[i].x[0]) || !isfinite(cp->v[i].x[1]))
            return FAILW("%svertices_coords[%d]: not a finite point", wb, i);
    for (int i = 0; i < cp->ne; i++)
        if (!strchr("BMVFU", cp->e[i].assign) || !cp->e[i].assign)
            return FAILW("%sedges_assignment[%d]: unknown assignment '%c'", wb, i, cp->e[i].assign);
    int rc = check_edges(cp, wb, tol, err);
    if (rc) return rc;
    int *loop, n;
    rc = sf_cp_outline(cp, &loop, &n, where, err);
    if (rc) return rc;
    double area = loop_area(cp, loop, n);
    free(loop);
    if (cp->nf > 0) {
        double sum = 0;
        for (int f = 0; f < cp->nf; f++) {
            int s0 = cp->face_start[f], s1 = cp->face_start[f + 1];
            if (s1 - s0 < 3)
                return FAILW("%sfaces_vertices[%d]: %d vertices, a face needs at least 3", wb, f, s1 - s0);
            for (int k = s0; k < s1; k++)
                if (cp->face_verts[k] < 0 || cp->face_verts[k] >= cp->nv)
                    return FAILW("%sfaces_vertices[%d]: vertex %d does not exist (vertices_coords has %d)",
                                 wb, f, cp->face_verts[k], cp->nv);
            double a = loop_area(cp, cp->face_verts + s0, s1 - s0);
            sum += fabs(a);
        }
        if (fabs(sum - area) > 1e-6 * area)
            return FAILW("%sfaces_vertices: the faces do not tile the outline (their areas add up to "
                         "%.6g, the outline encloses %.6g)", wb, sum, area);
    }
    return SF_OK;
}

/* ---- setbacks ----------------------------------------------------------- */

typedef struct ray { double ang; int edge; int end; double h; } ray;

static int ray_cmp(const void *pa, const void *pb)
{
    const ray *a = pa, *b = pb;
    return (a->ang > b->ang) - (a->ang < b->ang);
}

void sf_cp_setbacks(const sf_cpattern *cp, const double *width,
                    const int *outline, int noutline, double margin,
                    double min_frac, double (*sb)[2])
{
    for (int e = 0; e < cp->ne; e++)
        sb[e][0] = sb[e][1] = min_frac * width[e];
    ray *r = malloc((size_t)(cp->ne + 1) * sizeof *r);
    if (!r) return;
    for (int v = 0; v < cp->nv; v++) {
        int nr = 0;
        for (int e = 0; e < cp->ne; e++) {
            int end = cp->e[e].a == v ? 0 : cp->e[e].b == v ? 1 : -1;
            if (end < 0 || width[e] < 0) continue;
            int o = end ? cp->e[e].a : cp->e[e].b;
            double dx = cp->v[o].x[0] - cp->v[v].x[0], dy = cp->v[o].x[1] - cp->v[v].x[1];
            double ang = atan2(dy, dx);
            if (ang < 0) ang += 2 * M_PI;
            r[nr++] = (ray){ang, e, end, 0.5 * width[e]};
        }
        if (nr < 2) continue;
        qsort(r, (size_t)nr, sizeof *r, ray_cmp);
        /* the outside sector at a boundary vertex runs ccw from the ray to
         * the previous outline vertex to the ray to the next one */
        int prev = -1, next = -1;
        for (int k = 0; k < noutline; k++)
            if (outline[k] == v) {
                prev = outline[(k + noutline - 1) % noutline];
                next = outline[(k + 1) % noutline];
            }
        for (int k = 0; k < nr; k++) {
            const ray *r1 = &r[k], *r2 = &r[(k + 1) % nr];
            double alpha = r2->ang - r1->ang;
            if (alpha <= 0) alpha += 2 * M_PI;
            if (prev >= 0) {
                const sf_cp_edge *e1 = &cp->e[r1->edge], *e2 = &cp->e[r2->edge];
                int o1 = r1->end ? e1->a : e1->b, o2 = r2->end ? e2->a : e2->b;
                if (o1 == prev && o2 == next && e1->assign == 'B' && e2->assign == 'B') continue;
            }
            if (alpha >= M_PI - 1e-9) continue;
            double s = sin(alpha), c = cos(alpha);
            double t1 = (r2->h + r1->h * c) / s, t2 = (r1->h + r2->h * c) / s;
            if (margin * t1 > sb[r1->edge][r1->end]) sb[r1->edge][r1->end] = margin * t1;
            if (margin * t2 > sb[r2->edge][r2->end]) sb[r2->edge][r2->end] = margin * t2;
        }
    }
    free(r);
}

void sf_cp_real(char *buf, size_t n, double x)
{
    for (int p = 1; p <= 17; p++) {
        snprintf(buf, n, "%.*g", p, x);
        if (strtod(buf, NULL) == x) break;
    }
    if (!strpbrk(buf, ".eEn")) {
        size_t l = strlen(buf);
        if (l + 2 < n) memcpy(buf + l, ".0", 3);
    }
}
