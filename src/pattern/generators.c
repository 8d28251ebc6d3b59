/* generators.c - Miura-ori, Yoshimura and waterbomb crease patterns
 * (generators.h, docs/guides/patterns.md). */
#include "generators.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *sf_gen_names(void) { return "miura, yoshimura, waterbomb, twist, hypar"; }

int sf_gen_defaults(const char *name, sf_gen_opts *o, sf_error *err)
{
    memset(o, 0, sizeof *o);
    o->m = 2;
    o->n = 2;
    if (strcmp(name, "miura") == 0) {
        o->a = 0.04; o->b = 0.04; o->angle = 60; o->fold_angle = 180 / M_PI;
    } else if (strcmp(name, "yoshimura") == 0) {
        o->a = 0.06; o->b = 0.03;
    } else if (strcmp(name, "waterbomb") == 0) {
        o->a = 0.06; o->b = 0.03;
    } else if (strcmp(name, "twist") == 0) {
        o->m = o->n = 1;
        o->a = 0.1; o->b = 0.04; o->angle = 22.5;
    } else if (strcmp(name, "hypar") == 0) {
        o->m = o->n = 4;
        o->a = 0.12; o->b = 0.12;
    } else {
        return sf_fail(err, SF_EINPUT, "unknown pattern '%s' (patterns: %s)", name, sf_gen_names());
    }
    return SF_OK;
}

/* coordinates to 12 significant digits: 0.02, not 0.020000000000000004 */
static double snap(double x)
{
    char b[40];
    snprintf(b, sizeof b, "%.12g", x);
    return strtod(b, NULL);
}

#define OOM(x) do { if ((x) < 0) return sf_fail(err, SF_ENOMEM, "out of memory"); } while (0)

/* V positive, M negative */
static char mv(int s) { return s > 0 ? 'V' : 'M'; }

static int miura(const sf_gen_opts *o, sf_cpattern *cp, sf_error *err)
{
    int ni = 2 * o->m, nj = 2 * o->n;
    double g = o->angle * M_PI / 180;
    for (int j = 0; j <= nj; j++)
        for (int i = 0; i <= ni; i++) {
            char nm[32];
            snprintf(nm, sizeof nm, "v%d_%d", i, j);
            OOM(sf_cp_add_vertex(cp, snap(i * o->a + (j % 2 ? o->b * cos(g) : 0.0)), snap(j * o->b * sin(g)), nm));
        }
#define VID(i, j) ((j) * (ni + 1) + (i))
    /* zigzag line i: all one sign s_i, alternating with i; straight line j:
     * segment i -> i+1 has -s_i on even j, s_i on odd j: at every vertex
     * the straight crease inside the zigzag's 2*angle wedge has the sign
     * opposite to the zigzag's, the one outside the zigzag's sign (three
     * of one kind, one of the other: Maekawa), the rigid folding mode of
     * the vertex (tests/test_pattern.c solves its loop closure) */
    /* rigid folding: tan(r_straight / 2) = cos(angle) tan(r_zigzag / 2) */
    double rz = o->fold_angle, rs = 2 * atan(cos(g) * tan(0.5 * rz * M_PI / 180)) * 180 / M_PI;
    for (int j = 0; j <= nj; j++)
        for (int i = 0; i < ni; i++) {
            int s = i % 2 ? -1 : 1, sg = j % 2 ? s : -s;
            int bd = j == 0 || j == nj;
            OOM(sf_cp_add_edge(cp, VID(i, j), VID(i + 1, j), bd ? 'B' : mv(sg), bd ? NAN : sg * rs));
        }
    for (int i = 0; i <= ni; i++)
        for (int j = 0; j < nj; j++) {
            int sg = i % 2 ? -1 : 1, bd = i == 0 || i == ni;
            OOM(sf_cp_add_edge(cp, VID(i, j), VID(i, j + 1), bd ? 'B' : mv(sg), bd ? NAN : sg * rz));
        }
#undef VID
    snprintf(cp->description, sizeof cp->description,
             "Miura-ori, %d x %d cells, panels %g m x %g m, sector angle %g degrees",
             o->m, o->n, o->a, o->b, o->angle);
    return SF_OK;
}

typedef struct bpt { double s; int v; } bpt;
static int bpt_cmp(const void *pa, const void *pb)
{
    const bpt *a = pa, *b = pb;
    return (a->s > b->s) - (a->s < b->s);
}

/* B edges around the rectangle [0, W] x [0, H] through every vertex on it */
static int rect_boundary(sf_cpattern *cp, double W, double H, double tol, sf_error *err)
{
    bpt *p = malloc((size_t)cp->nv * sizeof *p);
    if (!p) return sf_fail(err, SF_ENOMEM, "out of memory");
    int n = 0;
    for (int v = 0; v < cp->nv; v++) {
        double x = cp->v[v].x[0], y = cp->v[v].x[1], s;
        if (fabs(y) <= tol) s = x;
        else if (fabs(x - W) <= tol) s = W + y;
        else if (fabs(y - H) <= tol) s = W + H + (W - x);
        else if (fabs(x) <= tol) s = 2 * W + H + (H - y);
        else continue;
        p[n++] = (bpt){s, v};
    }
    qsort(p, (size_t)n, sizeof *p, bpt_cmp);
    for (int k = 0; k < n; k++)
        if (sf_cp_add_edge(cp, p[k].v, p[(k + 1) % n].v, 'B', NAN) < 0) {
            free(p);
            return sf_fail(err, SF_ENOMEM, "out of memory");
        }
    free(p);
    return SF_OK;
}

/* creases along the horizontal line y through every vertex on it */
static int hline(sf_cpattern *cp, double y, double tol, char as, sf_error *err)
{
    bpt *p = malloc((size_t)cp->nv * sizeof *p);
    if (!p) return sf_fail(err, SF_ENOMEM, "out of memory");
    int n = 0;
    for (int v = 0; v < cp->nv; v++)
        if (fabs(cp->v[v].x[1] - y) <= tol) p[n++] = (bpt){cp->v[v].x[0], v};
    qsort(p, (size_t)n, sizeof *p, bpt_cmp);
    for (int k = 0; k + 1 < n; k++)
        if (sf_cp_add_edge(cp, p[k].v, p[k + 1].v, as, NAN) < 0) {
            free(p);
            return sf_fail(err, SF_ENOMEM, "out of memory");
        }
    free(p);
    return SF_OK;
}

static int yoshimura(const sf_gen_opts *o, sf_cpattern *cp, sf_error *err)
{
    double W = o->m * o->a, H = o->n * o->b, tol = 1e-9 * fmax(W, H), h = 0.5 * o->a;
    /* row j: x = k a/2 with k = j (mod 2), and both ends */
    for (int j = 0; j <= o->n; j++)
        for (int k = 0; k <= 2 * o->m; k++)
            if ((k - j) % 2 == 0 || k == 0 || k == 2 * o->m)
                OOM(sf_cp_vertex_at(cp, k * h, j * o->b, tol));
    for (int j = 0; j < o->n; j++)
        for (int k = 0; k <= 2 * o->m; k++)
            for (int d = -1; d <= 1; d += 2) {
                int k2 = k + d;
                if (k2 < 0 || k2 > 2 * o->m) continue;
                int ok1 = (k - j) % 2 == 0 || k == 0 || k == 2 * o->m;
                int ok2 = (k2 - j - 1) % 2 == 0 || k2 == 0 || k2 == 2 * o->m;
                if (!ok1 || !ok2) continue;
                int a = sf_cp_vertex_at(cp, k * h, j * o->b, tol);
                int b = sf_cp_vertex_at(cp, k2 * h, (j + 1) * o->b, tol);
                OOM(sf_cp_add_edge(cp, a, b, 'V', NAN));
            }
    for (int j = 1; j < o->n; j++)
        if (hline(cp, j * o->b, tol, 'M', err)) return err->code;
    if (rect_boundary(cp, W, H, tol, err)) return err->code;
    snprintf(cp->description, sizeof cp->description,
             "Yoshimura pattern, %d diamonds x %d rows, cells %g m x %g m", o->m, o->n, o->a, o->b);
    return SF_OK;
}

static int waterbomb(const sf_gen_opts *o, sf_cpattern *cp, sf_error *err)
{
    double W = o->m * o->a, H = o->n * o->b, tol = 1e-9 * fmax(W, H);
    for (int r = 0; r < o->n; r++) {
        double sh = r % 2 ? 0.5 * o->a : 0.0, yc = (r + 0.5) * o->b;
        for (int i = -1; i <= o->m; i++) {
            double xc = sh + (i + 0.5) * o->a;
            if (xc < -tol || xc > W + tol) continue;
            int c = sf_cp_vertex_at(cp, xc, yc, tol);
            OOM(c);
            for (int dx = -1; dx <= 1; dx += 2)
                for (int dy = -1; dy <= 1; dy += 2) {
                    double x = xc + dx * 0.5 * o->a, y = yc + dy * 0.5 * o->b;
                    if (x < -tol || x > W + tol) continue;
                    int k = sf_cp_vertex_at(cp, x, y, tol);
                    OOM(k);
                    OOM(sf_cp_add_edge(cp, c, k, 'V', NAN));
                }
            OOM(sf_cp_vertex_at(cp, 0.0, yc, tol));
            OOM(sf_cp_vertex_at(cp, W, yc, tol));
        }
        if (hline(cp, yc, tol, 'M', err)) return err->code;
    }
    for (int r = 1; r < o->n; r++) {
        OOM(sf_cp_vertex_at(cp, 0.0, r * o->b, tol));
        OOM(sf_cp_vertex_at(cp, W, r * o->b, tol));
        if (hline(cp, r * o->b, tol, 'M', err)) return err->code;
    }
    OOM(sf_cp_vertex_at(cp, 0.0, 0.0, tol));
    OOM(sf_cp_vertex_at(cp, W, 0.0, tol));
    OOM(sf_cp_vertex_at(cp, W, H, tol));
    OOM(sf_cp_vertex_at(cp, 0.0, H, tol));
    if (rect_boundary(cp, W, H, tol, err)) return err->code;
    snprintf(cp->description, sizeof cp->description,
             "waterbomb tessellation, %d x %d bases of %g m x %g m", o->m, o->n, o->a, o->b);
    return SF_OK;
}

/* Square twist: a square sheet of side a, a central square of side b
 * turned by the twist angle, and from each of its edges a pleat of two
 * parallel creases to the sheet's side facing it (9 quadrilateral faces:
 * the square, 4 pleats, 4 corners).  Every vertex of the square has
 * sectors 90, 90 + angle, 90, 90 - angle degrees: flat-foldable (Kawasaki),
 * not rigidly foldable.  The square's edges are valleys; of the two pleat
 * creases at a vertex the one bounding the small sector (90 - angle) is a
 * mountain (big-little-big), the other a valley (Maekawa: 3 V, 1 M). */
static int twist(const sf_gen_opts *o, sf_cpattern *cp, sf_error *err)
{
    double S = o->a, c = o->b, al = o->angle * M_PI / 180, h = 0.5 * S, tol = 1e-9 * S;
    double P[4][2];
    static const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int k = 0; k < 4; k++) {
        double x = 0.5 * c * corner[k][0], y = 0.5 * c * corner[k][1];
        P[k][0] = h + cos(al) * x - sin(al) * y;
        P[k][1] = h + sin(al) * x + cos(al) * y;
        if (P[k][0] <= tol || P[k][0] >= S - tol || P[k][1] <= tol || P[k][1] >= S - tol)
            return sf_fail(err, SF_EINPUT, "twist: the central square (side %g m turned by %g degrees) "
                           "does not fit inside the sheet (side %g m)", c, o->angle, S);
    }
    int iv[4];
    for (int k = 0; k < 4; k++) {
        char nm[16];
        snprintf(nm, sizeof nm, "c%d", k);
        OOM(iv[k] = sf_cp_add_vertex(cp, snap(P[k][0]), snap(P[k][1]), nm));
    }
    for (int k = 0; k < 4; k++) OOM(sf_cp_add_edge(cp, iv[k], iv[(k + 1) % 4], 'V', NAN));
    /* pleat of edge k: direction u_k = (0,-1) turned by k x 90 degrees */
    static const double u[4][2] = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};
    for (int k = 0; k < 4; k++)
        for (int e = 0; e < 2; e++) {
            int v = (k + e) % 4;
            double bx = u[k][0] ? (u[k][0] > 0 ? S : 0.0) : P[v][0];
            double by = u[k][1] ? (u[k][1] > 0 ? S : 0.0) : P[v][1];
            int b = sf_cp_vertex_at(cp, snap(bx), snap(by), tol);
            OOM(b);
            /* for a ccw twist the small sector at a vertex lies between
             * the square's edge and the pleat crease of the edge for which
             * the vertex is the second one (e = 1) */
            char as = (al > 0) == (e == 1) ? 'M' : 'V';
            OOM(sf_cp_add_edge(cp, iv[v], b, as, NAN));
        }
    OOM(sf_cp_vertex_at(cp, 0.0, 0.0, tol));
    OOM(sf_cp_vertex_at(cp, S, 0.0, tol));
    OOM(sf_cp_vertex_at(cp, S, S, tol));
    OOM(sf_cp_vertex_at(cp, 0.0, S, tol));
    if (rect_boundary(cp, S, S, tol, err)) return err->code;
    snprintf(cp->description, sizeof cp->description,
             "square twist, sheet %g m, central square %g m turned by %g degrees", S, c, o->angle);
    return SF_OK;
}

/* Hyperbolic paraboloid (hypar): a square sheet of side a, m rings of
 * concentric squares (ring j of half-side j a / (2 m); ring m is the
 * outline), alternately mountain (odd j) and valley, and the diagonal
 * creases from each ring's corners to the next ring's; the innermost
 * square is one face.  A diagonal segment from ring j to ring j + 1 takes
 * ring j + 1's assignment, so that every corner from ring 2 on has three
 * creases of one kind and one of the other (Maekawa); the corners of ring
 * 1 are of degree 3: the pattern folds only if its faces bend. */
static int hypar(const sf_gen_opts *o, sf_cpattern *cp, sf_error *err)
{
    int R = o->m;
    if (R < 2) return sf_fail(err, SF_EINPUT, "hypar: %d ring: at least 2 (ring 1 the central square, the last the outline)", R);
    double S = o->a, h = 0.5 * S, tol = 1e-9 * S;
    static const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    int *iv = malloc((size_t)(4 * R) * sizeof *iv);
    if (!iv) return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int j = 1; j <= R; j++)
        for (int k = 0; k < 4; k++) {
            double r = j * S / (2.0 * R);
            char nm[24];
            snprintf(nm, sizeof nm, "r%d_%d", j, k);
            iv[4 * (j - 1) + k] = sf_cp_add_vertex(cp, snap(h + r * corner[k][0]), snap(h + r * corner[k][1]), nm);
            if (iv[4 * (j - 1) + k] < 0) { free(iv); return sf_fail(err, SF_ENOMEM, "out of memory"); }
        }
#define RING(j, k) iv[4 * ((j) - 1) + ((k) % 4)]
    int rc = SF_OK;
    for (int j = 1; j < R && !rc; j++) {
        char a = j % 2 ? 'M' : 'V', anext = (j + 1) % 2 ? 'M' : 'V';
        for (int k = 0; k < 4 && !rc; k++) {
            if (sf_cp_add_edge(cp, RING(j, k), RING(j, k + 1), a, NAN) < 0
                || sf_cp_add_edge(cp, RING(j, k), RING(j + 1, k), anext, NAN) < 0)
                rc = sf_fail(err, SF_ENOMEM, "out of memory");
        }
    }
#undef RING
    free(iv);
    if (rc) return rc;
    if (rect_boundary(cp, S, S, tol, err)) return err->code;
    snprintf(cp->description, sizeof cp->description,
             "hyperbolic paraboloid (hypar), sheet %g m, %d rings", S, R);
    return SF_OK;
}

int sf_generate(const char *name, const sf_gen_opts *o, sf_cpattern *cp, sf_error *err)
{
    sf_cp_init(cp);
    sf_gen_opts d;
    if (sf_gen_defaults(name, &d, err)) return err->code;
    if (o->m < 1 || o->n < 1 || o->m > 50 || o->n > 50)
        return sf_fail(err, SF_EINPUT, "%s: cells %dx%d: each count must be in 1..50", name, o->m, o->n);
    if (!(o->a > 0) || !(o->b > 0) || !isfinite(o->a) || !isfinite(o->b))
        return sf_fail(err, SF_EINPUT, "%s: panel sizes %gx%g: must be positive", name, o->a, o->b);
    if (strcmp(name, "miura") == 0 && !(o->fold_angle > 0 && o->fold_angle < 180))
        return sf_fail(err, SF_EINPUT, "miura: fold angle %g degrees: must be in (0, 180)", o->fold_angle);
    if (strcmp(name, "miura") == 0 && !(o->angle > 0 && o->angle < 90))
        return sf_fail(err, SF_EINPUT, "miura: sector angle %g degrees: must be in (0, 90)", o->angle);
    if (strcmp(name, "twist") == 0 && !(o->angle > 0 && o->angle < 45))
        return sf_fail(err, SF_EINPUT, "twist: twist angle %g degrees: must be in (0, 45)", o->angle);
    if (strcmp(name, "twist") == 0)
        snprintf(cp->title, sizeof cp->title, "twist");
    else if (strcmp(name, "hypar") == 0)
        snprintf(cp->title, sizeof cp->title, "hypar-%d", o->m);
    else
        snprintf(cp->title, sizeof cp->title, "%s-%dx%d", name, o->m, o->n);
    int rc = strcmp(name, "miura") == 0 ? miura(o, cp, err)
           : strcmp(name, "yoshimura") == 0 ? yoshimura(o, cp, err)
           : strcmp(name, "twist") == 0 ? twist(o, cp, err)
           : strcmp(name, "hypar") == 0 ? hypar(o, cp, err)
           : waterbomb(o, cp, err);
    if (rc) sf_cp_free(cp);
    return rc;
}
