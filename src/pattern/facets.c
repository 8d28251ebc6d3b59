/* facets.c - bending faces (faces.bending; docs/guides/bending-faces.md): every
 * face of the crease pattern is split into rigid triangles joined by facet
 * hinges, which become folds of the ordinary model, appended after the
 * study's own folds (sf_fold_def.facet = 1).  So the kinematics, loop rows,
 * poses and sparse assembly of folds carry over unchanged; what is new is
 * which lines the hinges lie on and how stiff they are.
 *
 *   lines      faces.facets (FOLD's F edges, "from to") split a face first;
 *              what is left is ear-clipped, always cutting the ear with the
 *              shortest diagonal: a convex quadrilateral gets its shorter
 *              diagonal, larger and non-convex simple polygons a
 *              triangulation without slivers where one exists.  Vertices
 *              where a face's side runs straight on are no corners.
 *   band       a facet is a narrow smooth fold: width w = facet_width x the
 *              shortest side of its face, K = 0 (circular arc), rest angle 0,
 *              setbacks from sf_cp_setbacks so that it overlaps no band; a
 *              fold of the study whose sector a facet narrows below what its
 *              band's corner needs gets a longer setback (facet_setbacks).
 *   stiffness  its rotational stiffness equals the bar-and-hinge panel
 *              bending stiffness of Filipov et al. (IJSS 2017),
 *                K_B = C_B (l / t)^(1/3) E t^3 / (12 (1 - nu^2))   [N m / rad]
 *              with l the facet's length, t, E, nu the face material's.  A
 *              band of K = 0 has stiffness D_f L / w (MODEL.md 5), L its band
 *              length, so its plate stiffness is D_f = K_B w / L: the facet
 *              gets a material of its own, the face's with E scaled by
 *              C_B (l / t)^(1/3) w / L (same t, nu and density: its band
 *              weighs what the face material it replaces weighed).
 */
#include "facets.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libconfig.h>

#include "cpattern.h"
#include "study.h"
#include "topology.h"

typedef struct facet_list {
    int n, cap;
    int (*ab)[2];
    int *face;
} facet_list;

static int facet_push(facet_list *L, int a, int b, int face)
{
    if (L->n == L->cap) {
        int cap = L->cap ? 2 * L->cap : 16;
        int (*ab)[2] = realloc(L->ab, (size_t)cap * sizeof *ab);
        if (!ab) return -1;
        L->ab = ab;
        int *fc = realloc(L->face, (size_t)cap * sizeof *fc);
        if (!fc) return -1;
        L->face = fc;
        L->cap = cap;
    }
    L->ab[L->n][0] = a;
    L->ab[L->n][1] = b;
    L->face[L->n] = face;
    L->n++;
    return 0;
}

static const double *X(const sf_study *s, int v) { return s->vertices[v].x; }

static double cross3(const double *o, const double *a, const double *b)
{
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

static double dist(const double *a, const double *b) { return hypot(a[0] - b[0], a[1] - b[1]); }

/* Is p inside or on triangle abc (ccw)? */
static int in_triangle(const double *a, const double *b, const double *c, const double *p, double tol)
{
    return cross3(a, b, p) >= -tol && cross3(b, c, p) >= -tol && cross3(c, a, p) >= -tol;
}

/* Proper crossing of segments pq and rs (no shared end). */
static int segments_cross(const double *p, const double *q, const double *r, const double *u, double tol)
{
    double d1 = cross3(p, q, r), d2 = cross3(p, q, u), d3 = cross3(r, u, p), d4 = cross3(r, u, q);
    return ((d1 > tol && d2 < -tol) || (d1 < -tol && d2 > tol))
        && ((d3 > tol && d4 < -tol) || (d3 < -tol && d4 > tol));
}

/* Is the segment between polygon vertices i and j (not neighbours) inside
 * the ccw polygon v[0..n-1]?  It must cross no side and leave i into the
 * polygon's interior angle. */
static int is_diagonal(const sf_study *s, const int *v, int n, int i, int j, double tol)
{
    const double *a = X(s, v[i]), *b = X(s, v[j]);
    for (int k = 0; k < n; k++) {
        int k2 = (k + 1) % n;
        if (k == i || k == j || k2 == i || k2 == j) continue;
        if (segments_cross(a, b, X(s, v[k]), X(s, v[k2]), tol)) return 0;
    }
    for (int k = 0; k < n; k++) {   /* no vertex on the open segment */
        if (k == i || k == j) continue;
        const double *p = X(s, v[k]);
        double l = dist(a, b);
        if (fabs(cross3(a, b, p)) <= tol * l
            && (p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1]) > 0
            && (p[0] - b[0]) * (a[0] - b[0]) + (p[1] - b[1]) * (a[1] - b[1]) > 0) return 0;
    }
    /* inside the interior angle at i: between the side to i+1 and from i-1 */
    const double *pn = X(s, v[(i + 1) % n]), *pp = X(s, v[(i + n - 1) % n]);
    double c1 = cross3(a, pn, b), c2 = cross3(a, b, pp);
    if (cross3(pp, a, pn) >= 0) return c1 > tol && c2 > tol;      /* convex corner */
    return !(c1 <= tol && c2 <= tol);                            /* reflex corner */
}

/* Ear clipping of the ccw polygon v[0..n-1] (corners only), the ear with
 * the shortest diagonal first; diagonals appended to L. */
static int ear_clip(const sf_study *s, int *v, int n, int face, facet_list *L, double tol,
                    sf_error *err, const char *fname)
{
    while (n > 3) {
        int best = -1;
        double bl = INFINITY;
        for (int i = 0; i < n; i++) {
            int ip = (i + n - 1) % n, in = (i + 1) % n;
            const double *a = X(s, v[ip]), *b = X(s, v[i]), *c = X(s, v[in]);
            if (cross3(a, b, c) <= tol * dist(a, c)) continue;   /* reflex or straight */
            int empty = 1;
            for (int k = 0; k < n && empty; k++)
                if (k != ip && k != i && k != in && in_triangle(a, b, c, X(s, v[k]), tol * dist(a, c)))
                    empty = 0;
            if (!empty) continue;
            double l = dist(a, c);
            if (l < bl - tol) { bl = l; best = i; }
        }
        if (best < 0)
            return sf_fail(err, SF_EINPUT, "faces.bending: %s: cannot be triangulated (no ear: "
                           "is its outline self-touching?); give its facet edges in faces.facets", fname);
        int ip = (best + n - 1) % n, in = (best + 1) % n;
        if (facet_push(L, v[ip], v[in], face)) return sf_fail(err, SF_ENOMEM, "out of memory");
        memmove(v + best, v + best + 1, (size_t)(n - best - 1) * sizeof *v);
        n--;
    }
    return SF_OK;
}

/* Split polygon v[0..n-1] by the first given facet that is one of its
 * diagonals, recursively; ear-clip what no given facet splits. */
static int split_face(const sf_study *s, int *v, int n, int face, const int (*given)[2], int ngiven,
                      int *used, facet_list *L, double tol, sf_error *err, const char *fname)
{
    for (int g = 0; g < ngiven; g++) {
        int i = -1, j = -1;
        for (int k = 0; k < n; k++) {
            if (v[k] == given[g][0]) i = k;
            if (v[k] == given[g][1]) j = k;
        }
        if (i < 0 || j < 0 || (i + 1) % n == j || (j + 1) % n == i) continue;
        if (!is_diagonal(s, v, n, i, j, tol)) continue;
        used[g] = 1;
        if (facet_push(L, v[i], v[j], face)) return sf_fail(err, SF_ENOMEM, "out of memory");
        if (i > j) { int t = i; i = j; j = t; }
        int n1 = j - i + 1, n2 = n - (j - i) + 1;
        int *p1 = malloc((size_t)n1 * sizeof *p1), *p2 = malloc((size_t)n2 * sizeof *p2);
        if (!p1 || !p2) { free(p1); free(p2); return sf_fail(err, SF_ENOMEM, "out of memory"); }
        for (int k = 0; k < n1; k++) p1[k] = v[i + k];
        for (int k = 0; k < n2; k++) p2[k] = v[(j + k) % n];
        int rc = split_face(s, p1, n1, face, given, ngiven, used, L, tol, err, fname);
        if (!rc) rc = split_face(s, p2, n2, face, given, ngiven, used, L, tol, err, fname);
        free(p1);
        free(p2);
        return rc;
    }
    return ear_clip(s, v, n, face, L, tol, err, fname);
}

/* faces.facets: "from to" pairs of vertex names (read from the libconfig
 * tree; messages name the key and the element) into s->facet_edges. */
static int read_given(sf_study *s, sf_error *err)
{
    const config_setting_t *fs = s->cfg ? config_lookup((config_t *)s->cfg, "faces.facets") : NULL;
    int n = fs ? config_setting_length(fs) : 0;
    if (n <= 0) return SF_OK;
    int (*given)[2] = calloc((size_t)n, sizeof *given);
    if (!given) return sf_fail(err, SF_ENOMEM, "out of memory");
    s->facet_edges = given;
    for (int g = 0; g < n; g++) {
        char a[SF_NAME_MAX], b[SF_NAME_MAX], extra[2];
        const char *txt = config_setting_get_string_elem(fs, (unsigned)g);
        if (!txt) txt = "";
        if (sscanf(txt, "%63s %63s %1s", a, b, extra) != 2)
            return sf_study_fail(s, err, SF_EINPUT, "faces.facets", "faces.facets[%d]: '%s': a facet edge is "
                                 "two vertex names, \"from to\"", g, txt);
        int ia = sf_study_vertex_index(s, a), ib = sf_study_vertex_index(s, b);
        if (ia < 0 || ib < 0)
            return sf_study_fail(s, err, SF_EINPUT, "faces.facets", "faces.facets[%d]: '%s': unknown vertex '%s'",
                                 g, txt, ia < 0 ? a : b);
        if (ia == ib)
            return sf_study_fail(s, err, SF_EINPUT, "faces.facets", "faces.facets[%d]: '%s': from and to are "
                                 "the same vertex", g, txt);
        for (int f = 0; f < s->nfolds; f++) {
            int fa = s->folds[f].a, fb = s->folds[f].b;
            if ((fa == ia && fb == ib) || (fa == ib && fb == ia))
                return sf_study_fail(s, err, SF_EINPUT, "faces.facets", "faces.facets[%d]: '%s': the same line "
                                     "as fold %d: a line is a fold or a facet edge, not both", g, txt, f + 1);
        }
        given[g][0] = ia;
        given[g][1] = ib;
    }
    s->nfacet_edges = n;
    return SF_OK;
}

/* Setbacks by sf_cp_setbacks (the generators' margin 1.25 and floor
 * 0.1 w) over the study's folds (width w), the facets (width wf, when L
 * is not NULL) and the outline; sb gets one row per fold, then per facet. */
static int auto_setbacks(const sf_study *s, const sf_topology *t, const facet_list *L,
                         const double *wf, double (*sb)[2])
{
    sf_cpattern cp;
    sf_cp_init(&cp);
    int nfac = L ? L->n : 0, ne = s->nfolds + nfac + t->nboundary;
    double *w = calloc((size_t)ne, sizeof *w);
    double (*all)[2] = calloc((size_t)ne, sizeof *all);
    int rc = w && all ? SF_OK : SF_ENOMEM;
    for (int v = 0; !rc && v < s->nvertices; v++)
        if (sf_cp_add_vertex(&cp, X(s, v)[0], X(s, v)[1], "") < 0) rc = SF_ENOMEM;
    for (int i = 0; !rc && i < s->nfolds; i++) {
        w[cp.ne] = s->folds[i].width;
        if (sf_cp_add_edge(&cp, s->folds[i].a, s->folds[i].b, 'U', NAN) < 0) rc = SF_ENOMEM;
    }
    for (int k = 0; !rc && k < nfac; k++) {
        w[cp.ne] = wf[k];
        if (sf_cp_add_edge(&cp, L->ab[k][0], L->ab[k][1], 'F', NAN) < 0) rc = SF_ENOMEM;
    }
    for (int k = 0; !rc && k < t->nboundary; k++)
        if (sf_cp_add_edge(&cp, t->boundary[k], t->boundary[(k + 1) % t->nboundary], 'B', NAN) < 0)
            rc = SF_ENOMEM;
    if (!rc) {
        sf_cp_setbacks(&cp, w, t->boundary, t->nboundary, 1.25, 0.1, all);
        memcpy(sb, all, (size_t)(s->nfolds + nfac) * sizeof *sb);
    }
    free(w);
    free(all);
    sf_cp_free(&cp);
    return rc;
}

typedef struct ray { double ang; int fold; int end; } ray;   /* fold: study fold i, facet nfolds + k, -1 outline */
static int ray_cmp(const void *pa, const void *pb)
{
    const ray *a = pa, *b = pb;
    return (a->ang > b->ang) - (a->ang < b->ang);
}

/* The facets' setbacks (sbf, as the generators size them), and the study's
 * folds' where a facet narrows their sector so much that their band's
 * corner would leave the face: a band of half-width h beside a facet at
 * the sector alpha needs a setback beyond h / tan(alpha) (10 % margin) for
 * its corner to lie inside the face; a fold end short of that is set to
 * 1.25 times the distance at which its band edge meets the facet band's
 * (the rule of sf_cp_setbacks).  Elsewhere the study's setbacks stand, so
 * that the path with stiff faces is the rigid-face path of the same folds. */
static int facet_setbacks(sf_study *s, const sf_topology *t, const facet_list *L,
                          const double *wf, double (*sbf)[2], sf_error *err)
{
    int nf = s->nfolds;
    double (*sb1)[2] = calloc((size_t)(nf + L->n) + 1, sizeof *sb1);
    ray *r = malloc((size_t)(nf + L->n + t->nboundary + 1) * sizeof *r);
    if (!sb1 || !r || auto_setbacks(s, t, L, wf, sb1)) {
        free(sb1);
        free(r);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int k = 0; k < L->n; k++) {
        sbf[k][0] = sb1[nf + k][0];
        sbf[k][1] = sb1[nf + k][1];
    }
    for (int v = 0; v < s->nvertices; v++) {
        /* on the outline a face's body runs along the band's edge line up
         * to the outline whatever the setback (topology_bodies.c) */
        if (t->ivertex_of[v] < 0) continue;
        int n = 0;
        for (int i = 0; i < nf + L->n; i++) {
            int a = i < nf ? s->folds[i].a : L->ab[i - nf][0], b = i < nf ? s->folds[i].b : L->ab[i - nf][1];
            if (a != v && b != v) continue;
            const double *o = X(s, a == v ? b : a);
            double ang = atan2(o[1] - X(s, v)[1], o[0] - X(s, v)[0]);
            r[n++] = (ray){ang < 0 ? ang + 2 * M_PI : ang, i, a == v ? 0 : 1};
        }
        for (int k = 0; k < t->nboundary; k++) {
            int a = t->boundary[k], b = t->boundary[(k + 1) % t->nboundary];
            if (a != v && b != v) continue;
            const double *o = X(s, a == v ? b : a);
            double ang = atan2(o[1] - X(s, v)[1], o[0] - X(s, v)[0]);
            r[n++] = (ray){ang < 0 ? ang + 2 * M_PI : ang, -1, 0};
        }
        if (n < 2) continue;
        qsort(r, (size_t)n, sizeof *r, ray_cmp);
        for (int k = 0; k < n; k++)
            for (int side = 0; side < 2; side++) {   /* the fold's neighbour ccw, then cw */
                const ray *f = &r[k], *g = &r[side ? (k + n - 1) % n : (k + 1) % n];
                if (f->fold < 0 || f->fold >= nf || g->fold < nf) continue;
                double alpha = side ? f->ang - g->ang : g->ang - f->ang;
                if (alpha <= 0) alpha += 2 * M_PI;
                if (alpha >= M_PI / 2) continue;
                double h1 = 0.5 * s->folds[f->fold].width, h2 = 0.5 * wf[g->fold - nf];
                double *d = &s->folds[f->fold].setback[f->end];
                if (*d >= 1.1 * h1 / tan(alpha)) continue;
                *d = 1.25 * (h2 + h1 * cos(alpha)) / sin(alpha);
                s->nraised++;
            }
    }
    free(sb1);
    free(r);
    return SF_OK;
}

double sf_facet_stiffness(double E, double nu, double t, double l, double cb)
{
    return cb * cbrt(l / t) * E * t * t * t / (12.0 * (1.0 - nu * nu));
}

/* Append the facets of L to the study as folds, each with its material. */
static int append_facets(sf_study *s, const facet_list *L, const double *wf, const double (*sb)[2],
                         sf_error *err)
{
    sf_fold_def *nf = realloc(s->folds, (size_t)(s->nfolds + L->n) * sizeof *nf);
    if (!nf) return sf_fail(err, SF_ENOMEM, "out of memory");
    s->folds = nf;
    sf_material *nm = realloc(s->materials, (size_t)(s->nmaterials + L->n) * sizeof *nm);
    if (!nm) return sf_fail(err, SF_ENOMEM, "out of memory");
    s->materials = nm;
    const sf_material fm = s->materials[s->face_material];
    for (int k = 0; k < L->n; k++) {
        int a = L->ab[k][0], b = L->ab[k][1];
        double l = dist(X(s, a), X(s, b)), Lb = l - sb[k][0] - sb[k][1];
        if (!(Lb > 0))
            return sf_fail(err, SF_EINPUT, "faces.bending: the facet %s-%s (%.3g m) is shorter than its "
                           "setbacks (%.3g m): lower faces.facet_width or the widths of the folds at its ends",
                           s->vertices[a].name, s->vertices[b].name, l, sb[k][0] + sb[k][1]);
        sf_material *m = &s->materials[s->nmaterials];
        *m = fm;
        snprintf(m->name, sizeof m->name, "(facet %d)", k + 1);
        double KB = sf_facet_stiffness(fm.E, fm.nu, fm.thickness, l, s->bending_coefficient);
        double D = KB * wf[k] / Lb;   /* D L / w = K_B */
        m->E = D * 12.0 * (1.0 - fm.nu * fm.nu) / (fm.thickness * fm.thickness * fm.thickness);
        sf_fold_def *f = &s->folds[s->nfolds];
        memset(f, 0, sizeof *f);
        f->a = a;
        f->b = b;
        f->width = wf[k];
        f->setback[0] = sb[k][0];
        f->setback[1] = sb[k][1];
        f->continuity = 1;
        f->modes = 0;
        f->material = s->nmaterials;
        f->group = -1;
        f->rest_angle = 0;
        f->facet = 1;
        f->line = s->fixed_line;
        s->nmaterials++;
        s->nfolds++;
        s->nfacets++;
    }
    return SF_OK;
}

/* The study's fold whose centre line passes through vertex v between its
 * ends (within tol), or -1. */
static int fold_through(const sf_study *s, int v, double tol)
{
    for (int f = 0; f < s->nfolds; f++) {
        const double *a = X(s, s->folds[f].a), *b = X(s, s->folds[f].b), *p = X(s, v);
        double l = dist(a, b), t = ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / (l * l);
        if (v != s->folds[f].a && v != s->folds[f].b && t > 0 && t < 1 && fabs(cross3(a, b, p)) <= tol * l)
            return f;
    }
    return -1;
}

int sf_study_add_facets(sf_study *s, sf_error *err)
{
    if (s->nfacets) return SF_OK;
    if (!s->facet_edges && read_given(s, err)) return err->code;
    if (!s->bending) return SF_OK;   /* the given facet edges stay for export (cp_from_study.c) */
    sf_topology t;
    if (sf_topology_build(s, &t, err)) return err->code;
    facet_list L = {0};
    const int (*given)[2] = (const int (*)[2])s->facet_edges;
    int ngiven = s->nfacet_edges, *used = NULL, *poly = NULL;
    double *wf = NULL, (*sb)[2] = NULL;
    double *shortest = calloc((size_t)t.nfaces + 1, sizeof *shortest);
    int rc = shortest ? SF_OK : sf_fail(err, SF_ENOMEM, "out of memory");
    if (!rc && ngiven && !(used = calloc((size_t)ngiven, sizeof *used)))
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
    for (int f = 0; !rc && f < t.nfaces; f++) {
        const sf_face *F = &t.faces[f];
        free(poly);
        poly = malloc((size_t)F->nverts * sizeof *poly);
        if (!poly) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); break; }
        int n = 0;
        for (int k = 0; k < F->nverts; k++) {   /* corners: drop straight-on vertices */
            const double *a = X(s, F->verts[(k + F->nverts - 1) % F->nverts]), *b = X(s, F->verts[k]),
                         *c = X(s, F->verts[(k + 1) % F->nverts]);
            if (fabs(cross3(a, b, c)) > t.tol * dist(a, c)
                || (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]) < 0)
                poly[n++] = F->verts[k];
        }
        double sh = INFINITY;
        for (int k = 0; k < n; k++) sh = fmin(sh, dist(X(s, poly[k]), X(s, poly[(k + 1) % n])));
        shortest[f] = sh;
        char fname[160];
        sf_topology_face_name(s, &t, f, fname, sizeof fname);
        rc = split_face(s, poly, n, f, given, ngiven, used, &L, t.tol, err, fname);
    }
    for (int g = 0; !rc && g < ngiven; g++)
        if (!used[g]) {
            int fe = -1, ve = -1;
            for (int k = 0; k < 2 && fe < 0; k++)
                if ((fe = fold_through(s, given[g][k], t.tol)) >= 0) ve = given[g][k];
            if (fe >= 0)   /* import joins collinear folds through the ends of facet edges */
                rc = sf_study_fail(s, err, SF_EINPUT, "faces.facets", "faces.facets[%d]: %s-%s ends at %s, which lies "
                                   "on fold %d (%s->%s) between its ends, not at a corner of a face; --set "
                                   "'faces.facets=[]' triangulates the faces automatically", g,
                                   s->vertices[given[g][0]].name, s->vertices[given[g][1]].name, s->vertices[ve].name,
                                   fe + 1, s->vertices[s->folds[fe].a].name, s->vertices[s->folds[fe].b].name);
            else
                rc = sf_study_fail(s, err, SF_EINPUT, "faces.facets", "faces.facets[%d]: %s-%s is not a diagonal of "
                                   "a face (a facet edge must join two corners of one face, inside it)", g,
                                   s->vertices[given[g][0]].name, s->vertices[given[g][1]].name);
        }
    if (!rc && L.n) {
        wf = malloc((size_t)L.n * sizeof *wf);
        sb = malloc((size_t)L.n * sizeof *sb);
        if (!wf || !sb) rc = sf_fail(err, SF_ENOMEM, "out of memory");
        for (int k = 0; !rc && k < L.n; k++)   /* width: a fraction of its face's shortest side */
            wf[k] = s->facet_width * shortest[L.face[k]];
        if (!rc) rc = facet_setbacks(s, &t, &L, wf, sb, err);
        if (!rc) rc = append_facets(s, &L, wf, (const double (*)[2])sb, err);
    }
    free(poly);
    free(shortest);
    free(used);
    free(wf);
    free(sb);
    free(L.ab);
    free(L.face);
    sf_topology_free(&t);
    return rc;
}
