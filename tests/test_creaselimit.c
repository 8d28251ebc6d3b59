/* test_creaselimit.c - the rigid-origami limit of smooth folds and the
 * symmetry of symmetric sheets (issue 12; docs/design/crease-limit.md):
 *  - the closed form of a flat-foldable degree-4 vertex (sector angles
 *    alpha, beta, pi - alpha, pi - beta; Tachi 2009, Evans et al. 2015),
 *    checked first by the product of its four rotations (it must be I);
 *  - a Miura sheet actuated from flat with exact loop closure follows that
 *    closed form at every interior vertex and every point of branch.tsv
 *    (1e-6 rad), at two band widths a factor 100 apart and in both
 *    formulations: the rotation part of the folding map is the rigid one
 *    (MODEL.md 3-4), so the error is the Newton tolerance's at any width;
 *  - symmetric sheets under symmetric driving (the Miura sheet's mirror,
 *    square4's eight symmetries with its four loads, a waterbomb base's
 *    half turn and two mirrors): every symmetry found
 *    from the study's geometry maps fold i to fold j, and theta_i = theta_j
 *    to 1e-9 along the path.
 * The program is run as a user would (src/smoothfold pattern, run) and
 * branch.tsv is read by column name (tsv_test.h). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene.h"
#include "sf_test.h"
#include "tsv_test.h"

/* ------------------------------------------------- rotations, own code */

/* Right-handed rotation by t about the unit in-plane axis at angle phi
 * (Rodrigues), row-major. */
static void rot_inplane(double phi, double t, double R[9])
{
    double x = cos(phi), y = sin(phi), c = cos(t), s = sin(t), v = 1 - c;
    double M[9] = {c + x * x * v, x * y * v, y * s,
                   x * y * v, c + y * y * v, -x * s,
                   -y * s, x * s, c};
    memcpy(R, M, sizeof M);
}

static void mul3(const double A[9], const double B[9], double C[9])
{
    double T[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) T[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
    memcpy(C, T, sizeof T);
}

/* max |R - I| of R = Rot(e_1, rho_1) ... Rot(e_n, rho_n), e_k the outward
 * fold directions at angles phi_k, counter-clockwise: the loop closure of
 * rigid origami (MODEL.md 4 with w = 0). */
static double loop_residual(int n, const double *phi, const double *rho)
{
    double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, Q[9];
    for (int k = 0; k < n; k++) {
        rot_inplane(phi[k], rho[k], Q);
        mul3(R, Q, R);
    }
    double r = 0;
    for (int i = 0; i < 9; i++) r = fmax(r, fabs(R[i] - (i % 4 == 0)));
    return r;
}

/* The closed form (docs/design/crease-limit.md): sectors alpha (e1 -> e2), beta
 * (e2 -> e3), pi - alpha, pi - beta.  Mode "II": rho3 = -rho1, rho4 = rho2,
 * tan(rho1/2) = sin((alpha - beta)/2) / sin((alpha + beta)/2) tan(rho2/2). */
static double ratio2(double a, double b) { return sin(0.5 * (a - b)) / sin(0.5 * (a + b)); }
/* mode "I": rho3 = rho1, rho4 = -rho2,
 * tan(rho2/2) = -cos((alpha + beta)/2) / cos((alpha - beta)/2) tan(rho1/2) */
static double ratio1(double a, double b) { return -cos(0.5 * (a + b)) / cos(0.5 * (a - b)); }

static void test_closed_form(void **state)
{
    (void)state;
    const double g[][2] = {{M_PI - M_PI / 3, M_PI / 3}, {M_PI - 0.3, 0.3}, {M_PI - 1.4, 1.4},
                           {0.7, 1.1}, {2.0, 0.9}, {1.2, 2.6}};
    const double r2[] = {1e-3, 0.4, 1.5, 2.8, -0.9};
    double worst = 0, least_off = INFINITY;
    for (size_t c = 0; c < sizeof g / sizeof *g; c++) {
        double a = g[c][0], b = g[c][1];
        double phi[4] = {0, a, a + b, M_PI + b};
        for (size_t k = 0; k < sizeof r2 / sizeof *r2; k++) {
            double t = r2[k];
            double r1 = 2 * atan(ratio2(a, b) * tan(t / 2));
            double rho[4] = {r1, t, -r1, t};
            worst = fmax(worst, loop_residual(4, phi, rho));
            double s = 2 * atan(ratio1(a, b) * tan(t / 2));
            double rho1[4] = {t, s, t, -s};
            worst = fmax(worst, loop_residual(4, phi, rho1));
            /* a relation off by 1e-4 rad does not close: the check can fail */
            double off[4] = {r1 + 1e-4, t, -r1 - 1e-4, t};
            least_off = fmin(least_off, loop_residual(4, phi, off));
        }
    }
    print_message("# closed form: loop residual %.2g (16 digits), 1e-4 rad off: >= %.2g\n", worst, least_off);
    CHECK_LE(worst, 1e-13, "rotation loop of the closed form");
    assert_true(least_off > 1e-6);
}

/* ------------------------------------------------------- running it */

static void outdir(const char *name, char *dir, size_t n)
{
    const char *b = getenv("SF_BUILDDIR");
    snprintf(dir, n, "%s/tests/creaselimit-out/%s", b ? b : ".", name);
}

static void shell(const char *cmd)
{
    int rc = system(cmd);
    if (rc != 0) print_error("%s: exit %d\n", cmd, rc);
    assert_int_equal(rc, 0);
}

/* `smoothfold pattern miura ARGS -o DIR.cfg`, then `run` it into DIR with
 * EXTRA; the study's path into cfg. */
static void gen_and_run(const char *name, const char *args, const char *extra, char *dir, size_t n,
                        char *cfg, size_t ncfg)
{
    const char *b = getenv("SF_BUILDDIR");
    if (!b) b = ".";
    outdir(name, dir, n);
    snprintf(cfg, ncfg, "%s.cfg", dir);
    char cmd[16384];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s/tests/creaselimit-out' && rm -rf '%s' && "
             "'%s/src/smoothfold' pattern %s -o '%s' 2>/dev/null && '%s/src/smoothfold' run '%s' -o '%s' -q %s",
             b, dir, b, args, cfg, b, cfg, dir, extra);
    shell(cmd);
}

static void open_cfg(sf_scene *sc, const char *cfg)
{
    sf_error err;
    sf_error_clear(&err);
    if (sf_scene_open(sc, cfg, 0, NULL, &err)) {
        print_error("%s: %s\n", cfg, err.msg);
        fail();
    }
}

/* fold angles of row r of branch.tsv */
static void thetas(const tsv *t, int r, int nf, double *th)
{
    for (int i = 0; i < nf; i++) {
        char c[32];
        snprintf(c, sizeof c, "theta%d", i + 1);
        th[i] = tsv_num(t, r, c);
    }
}

/* Deviation [rad] of the fold angles th at interior vertex v from the
 * closed form, and the rigid loop residual of the same angles.  The
 * labelling comes from the geometry: e_k, e_{k+2} the collinear pair. */
static double vertex_deviation(const sf_topology *tp, const sf_ivertex *v, const double *th, double *loop)
{
    assert_int_equal(v->degree, 4);
    double phi[4], sec[4], rho[4];
    for (int k = 0; k < 4; k++) {
        const sf_fold_geom *f = &tp->folds[v->folds[k]];
        phi[k] = atan2(v->sign[k] * f->m[1], v->sign[k] * f->m[0]);
        rho[k] = th[v->folds[k]];
    }
    for (int k = 0; k < 4; k++) sec[k] = fmod(phi[(k + 1) % 4] - phi[k] + 4 * M_PI, 2 * M_PI);
    /* flat-foldable (Kawasaki) */
    CHECK_CLOSE(sec[0] + sec[2], M_PI, 1e-9, "Kawasaki at vertex %d", v->vertex);
    int k = fabs(sec[0] + sec[1] - M_PI) < 1e-9 ? 0 : 1;
    CHECK_CLOSE(sec[k] + sec[k + 1], M_PI, 1e-9, "a collinear pair at vertex %d", v->vertex);
    double r0 = rho[k], r1 = rho[k + 1], r2 = rho[k + 2], r3 = rho[(k + 3) % 4];
    double d = fmax(fabs(r0 + r2), fabs(r1 - r3));
    d = fmax(d, fabs(r0 - 2 * atan(ratio2(sec[k], sec[k + 1]) * tan(r1 / 2))));
    *loop = loop_residual(4, phi, rho);
    return d;
}

/* Max deviation from the closed form over every row of branch.tsv and
 * every interior vertex of a Miura run; the largest fold angle reached. */
static double miura_deviation(const char *name, const char *args, const char *extra, double *maxth,
                              double *maxloop, int *rows)
{
    char dir[2048], cfg[2100], p[2200];
    gen_and_run(name, args, extra, dir, sizeof dir, cfg, sizeof cfg);
    sf_scene sc;
    open_cfg(&sc, cfg);
    const sf_topology *tp = &sc.topo;
    snprintf(p, sizeof p, "%s/branch.tsv", dir);
    tsv t;
    tsv_read(&t, p);
    int nf = tp->nfolds;
    double *th = calloc((size_t)nf, sizeof *th), dev = 0;
    assert_non_null(th);
    assert_true(tp->nivertices >= 1);
    *maxth = 0;
    *maxloop = 0;
    for (int r = 0; r < t.nrow; r++) {
        thetas(&t, r, nf, th);
        for (int i = 0; i < nf; i++) *maxth = fmax(*maxth, fabs(th[i]));
        for (int v = 0; v < tp->nivertices; v++) {
            double loop;
            dev = fmax(dev, vertex_deviation(tp, &tp->ivertices[v], th, &loop));
            *maxloop = fmax(*maxloop, loop);
        }
    }
    assert_string_equal(tsv_str(&t, t.nrow - 1, "type"), "EP");
    assert_true(fabs(tsv_num(&t, t.nrow - 1, "p") - 1.0) < 1e-12);
    *rows = t.nrow;
    free(th);
    tsv_free(&t);
    sf_scene_close(&sc);
    return dev;
}

static void test_miura_crease_limit(void **state)
{
    (void)state;
    /* the generator's width is 0.1 x the shortest fold (4 mm of 40 mm);
     * 1e-3 x it is the crease limit; the 2x2 sheet has 9 vertices */
    static const struct { const char *name, *args, *extra; } c[] = {
        {"m1-w4e-3-folds", "miura --cells=1x1 --width=0.004", "--set 'solver.formulation=\"folds\"'"},
        {"m1-w4e-5-folds", "miura --cells=1x1 --width=0.00004", "--set 'solver.formulation=\"folds\"'"},
        {"m1-w4e-3-poses", "miura --cells=1x1 --width=0.004", "--set 'solver.formulation=\"poses\"'"},
        {"m1-w4e-4-poses", "miura --cells=1x1 --width=0.0004", "--set 'solver.formulation=\"poses\"'"},
        {"m2-w4e-5-folds", "miura --cells=2x2 --width=0.00004", "--set 'solver.formulation=\"folds\"'"},
    };
    for (size_t i = 0; i < sizeof c / sizeof *c; i++) {
        double maxth, loop;
        int rows;
        double d = miura_deviation(c[i].name, c[i].args, c[i].extra, &maxth, &loop, &rows);
        print_message("# %s: %d points, fold angles up to %.4f rad, max deviation from the closed form "
                      "%.2g rad, rigid loop residual %.2g\n", c[i].name, rows, maxth, d, loop);
        assert_true(rows >= 10);
        assert_true(maxth > 0.3); /* it did fold */
        CHECK_LE(d, 1e-6, "%s: deviation from the closed form", c[i].name);
        CHECK_LE(loop, 1e-6, "%s: rigid loop residual", c[i].name);
    }
}


/* ------------------------------------------------------- symmetries */

/* The eight candidate maps x -> c + G (x - c) of the square's symmetry
 * group about the centre c of the vertices' bounding box (G row-major). */
static void candidate(int k, double G[4])
{
    if (k < 4) { /* rotations by k quarter turns */
        static const double c[4] = {1, 0, -1, 0}, s[4] = {0, 1, 0, -1};
        double M[4] = {c[k], -s[k], s[k], c[k]};
        memcpy(G, M, sizeof M);
    } else { /* reflections across the lines at (k - 4) 45 degrees */
        double t = (k - 4) * M_PI / 2, a = cos(t), b = sin(t);
        double M[4] = {a, b, b, -a};
        for (int i = 0; i < 4; i++) M[i] = fabs(M[i]) < 1e-15 ? 0.0 : M[i];
        memcpy(G, M, sizeof M);
    }
}

static void apply(const double G[4], const double c[2], const double x[2], double y[2])
{
    double u = x[0] - c[0], v = x[1] - c[1];
    y[0] = c[0] + G[0] * u + G[1] * v;
    y[1] = c[1] + G[2] * u + G[3] * v;
}

static int vertex_at(const sf_study *s, const double x[2], double tol)
{
    for (int v = 0; v < s->nvertices; v++)
        if (hypot(s->vertices[v].x[0] - x[0], s->vertices[v].x[1] - x[1]) <= tol) return v;
    return -1;
}

static int same(double a, double b) { return fabs(a - b) <= 1e-12 * (1 + fabs(a) + fabs(b)); }

/* Does map G take the study to itself: vertices, folds with everything
 * that makes a fold (width, setbacks at the mapped ends, section,
 * material, actuation group, rest angle), loads (in-plane force turned
 * with the sheet), the fixed face?  Then perm[i] is the image of fold i. */
static int symmetry(const sf_scene *sc, const double G[4], const double c[2], int *perm)
{
    const sf_study *s = &sc->study;
    double tol = sc->topo.tol;
    if (s->nsupports) return 0;
    int *vmap = malloc(sizeof(int) * (size_t)s->nvertices);
    assert_non_null(vmap);
    int ok = 1;
    for (int v = 0; v < s->nvertices && ok; v++) {
        double y[2];
        apply(G, c, s->vertices[v].x, y);
        ok = (vmap[v] = vertex_at(s, y, tol)) >= 0;
    }
    for (int i = 0; i < s->nfolds && ok; i++) {
        const sf_fold_def *f = &s->folds[i];
        int a = vmap[f->a], b = vmap[f->b];
        perm[i] = -1;
        for (int j = 0; j < s->nfolds; j++) {
            const sf_fold_def *g = &s->folds[j];
            int fwd = g->a == a && g->b == b, rev = g->a == b && g->b == a;
            if (!fwd && !rev) continue;
            if (same(g->width, f->width) && same(g->setback[fwd ? 0 : 1], f->setback[0]) &&
                same(g->setback[fwd ? 1 : 0], f->setback[1]) && g->modes == f->modes &&
                g->continuity == f->continuity && g->material == f->material &&
                g->group == f->group && same(g->rest_angle, f->rest_angle))
                perm[i] = j;
            break;
        }
        ok = perm[i] >= 0;
    }
    for (int l = 0; l < s->nloads && ok; l++) {
        const sf_point_load *L = &s->loads[l];
        double y[2], o[2] = {0, 0}, f[2];
        apply(G, c, L->at, y);
        apply(G, o, L->force, f);
        int found = 0;
        for (int m = 0; m < s->nloads && !found; m++) {
            const sf_point_load *M = &s->loads[m];
            found = hypot(M->at[0] - y[0], M->at[1] - y[1]) <= tol && M->stage == L->stage &&
                    same(M->force[0], f[0]) && same(M->force[1], f[1]) && same(M->force[2], L->force[2]);
        }
        ok = found;
    }
    if (ok && (s->nloads || s->gravity_on)) {
        double y[2];
        apply(G, c, s->fixed_point, y);
        ok = sf_topology_locate_face(&sc->topo, y) == sf_topology_locate_face(&sc->topo, s->fixed_point);
    }
    free(vmap);
    return ok;
}

/* Run the study (generated by `smoothfold pattern ARGS` when args is not
 * NULL, else studies/NAME.cfg); find its symmetries; check theta_i =
 * theta_perm(i) to tol along the path.  Returns the number of
 * symmetries other than the identity. */
static int check_symmetric(const char *name, const char *args, const char *extra, double tol)
{
    char dir[2048], cfg[2100], p[2200];
    if (args) {
        gen_and_run(name, args, extra, dir, sizeof dir, cfg, sizeof cfg);
    } else {
        const char *sd = getenv("SF_SRCDIR");
        outdir(name, dir, sizeof dir);
        snprintf(cfg, sizeof cfg, "%s/studies/%s.cfg", sd ? sd : SF_SRCDIR, name);
        char cmd[16384], mk[2100];
        snprintf(mk, sizeof mk, "%s", dir);
        *strrchr(mk, '/') = '\0';
        snprintf(cmd, sizeof cmd, "mkdir -p '%s' && rm -rf '%s' && '%s/src/smoothfold' run '%s' -o '%s' -q %s", mk,
                 dir, getenv("SF_BUILDDIR") ? getenv("SF_BUILDDIR") : ".", cfg, dir, extra);
        shell(cmd);
    }
    sf_scene sc;
    open_cfg(&sc, cfg);
    const sf_study *s = &sc.study;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, c[2];
    for (int v = 0; v < s->nvertices; v++)
        for (int d = 0; d < 2; d++) {
            lo[d] = fmin(lo[d], s->vertices[v].x[d]);
            hi[d] = fmax(hi[d], s->vertices[v].x[d]);
        }
    for (int d = 0; d < 2; d++) c[d] = 0.5 * (lo[d] + hi[d]);
    snprintf(p, sizeof p, "%s/branch.tsv", dir);
    tsv t;
    tsv_read(&t, p);
    int nf = s->nfolds, nsym = 0;
    int *perm = malloc(sizeof(int) * (size_t)nf);
    double *th = malloc(sizeof(double) * (size_t)nf);
    assert_non_null(perm);
    assert_non_null(th);
    for (int k = 1; k < 8; k++) {
        double G[4];
        candidate(k, G);
        if (!symmetry(&sc, G, c, perm)) continue;
        nsym++;
        int moved = 0;
        for (int i = 0; i < nf; i++) moved += perm[i] != i;
        assert_true(moved > 0);
        double dev = 0, big = 0;
        for (int r = 0; r < t.nrow; r++) {
            thetas(&t, r, nf, th);
            for (int i = 0; i < nf; i++) {
                dev = fmax(dev, fabs(th[i] - th[perm[i]]));
                big = fmax(big, fabs(th[i]));
            }
        }
        print_message("# %s: symmetry %d (%s) moves %d of %d folds; %d points, fold angles up to %.4f rad, "
                      "max |theta_i - theta_j| %.2g rad\n", name, k, k < 4 ? "rotation" : "reflection",
                      moved, nf, t.nrow, big, dev);
        assert_true(big > 0.1);
        CHECK_LE(dev, tol, "%s: symmetry %d", name, k);
    }
    free(perm);
    free(th);
    tsv_free(&t);
    sf_scene_close(&sc);
    return nsym;
}

static void test_symmetric_states(void **state)
{
    (void)state;
    /* the Miura sheet's mirror y -> H - y (1 symmetry) in both formulations */
    assert_int_equal(check_symmetric("m2-sym-folds", "miura --cells=2x2",
                                     "--set 'solver.formulation=\"folds\"'", 1e-9), 1);
    assert_int_equal(check_symmetric("m2-sym-poses", "miura --cells=2x2",
                                     "--set 'solver.formulation=\"poses\"'", 1e-9), 1);
    /* square4: the square's 7 symmetries besides the identity map its
     * folds, its four loads and its central fixed face to themselves */
    assert_int_equal(check_symmetric("square4", NULL, "--set output.shapes=0", 1e-9), 7);
    /* a waterbomb base (degree 6) with all its folds driven: the
     * rectangle's half turn and two mirrors; solved to 1e-12, since the
     * start's first point meets the Newton tolerance and no more, and at
     * the default 1e-10 the states are symmetric to 1.4e-9 rad only */
    assert_int_equal(check_symmetric("wb1-sym", "waterbomb --cells=1x1 --drive=all", "--set solver.tolerance=1e-12", 1e-9), 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_closed_form),
        cmocka_unit_test(test_miura_crease_limit),
        cmocka_unit_test(test_symmetric_states),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
