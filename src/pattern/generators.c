/* generators.c - Miura-ori, Yoshimura and waterbomb crease patterns
 * (generators.h, docs/guides/patterns.md). */
#include "generators.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *sf_gen_names(void) { return "miura, yoshimura, waterbomb"; }

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
    snprintf(cp->title, sizeof cp->title, "%s-%dx%d", name, o->m, o->n);
    int rc = strcmp(name, "miura") == 0 ? miura(o, cp, err)
           : strcmp(name, "yoshimura") == 0 ? yoshimura(o, cp, err)
           : waterbomb(o, cp, err);
    if (rc) sf_cp_free(cp);
    return rc;
}
