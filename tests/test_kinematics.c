/* test_kinematics.c - folding maps, material points and loop constraints:
 * analytic derivatives against central differences, invariants of the
 * folding maps, and the crease limit of a degree-4 vertex. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SF_TEST_SEED 987654321u
#include "sf_test.h"

#include "kinematics.h"
#include "scene.h"
#include "study.h"
#include "topology.h"

/* check_fd (sf_test.h) with no absolute floor. */
static void compare(const double *A, const double *F, size_t n, const char *what)
{
    check_fd(A, F, n, 1e-300, what);
}

/* --- constraints: J and lambda . d2g against finite differences --- */
static void check_constraint_derivatives(const char *study, int nset, const char **sets)
{
    sf_scene sc;
    open_scene(&sc, study, nset, sets);
    const sf_model *m = &sc.model;
    int nq = m->nq, nc = m->ncon;
    assert_true(nc > 0);
    double *q = calloc(nq, sizeof *q), *qq = calloc(nq, sizeof *qq);
    double *g = calloc(nc, sizeof *g), *gp = calloc(nc, sizeof *gp), *gm = calloc(nc, sizeof *gm);
    double *J = calloc((size_t)nc * nq, sizeof *J), *Jfd = calloc((size_t)nc * nq, sizeof *J);
    double *Jp = calloc((size_t)nc * nq, sizeof *J), *Jm = calloc((size_t)nc * nq, sizeof *J);
    double *H = calloc((size_t)nq * nq, sizeof *H), *Hfd = calloc((size_t)nq * nq, sizeof *H);
    double *lam = calloc(nc, sizeof *lam);
    sf_kin k;
    assert_int_equal(sf_kin_alloc(m, &k), SF_OK);
    for (int trial = 0; trial < 2; trial++) {
        random_state(m, q, 2.0, 0.5);
        for (int c = 0; c < nc; c++) lam[c] = urand(-1, 1);
        sf_kin_eval(m, q, 2, &k);
        memset(H, 0, sizeof(double) * nq * nq);
        sf_constraints(m, &k, g, J, lam, H, nq);
        double h = 1e-6;
        for (int j = 0; j < nq; j++) {
            memcpy(qq, q, sizeof(double) * nq);
            qq[j] += h;
            sf_kin_eval(m, qq, 1, &k);
            sf_constraints(m, &k, gp, Jp, NULL, NULL, 0);
            qq[j] -= 2 * h;
            sf_kin_eval(m, qq, 1, &k);
            sf_constraints(m, &k, gm, Jm, NULL, NULL, 0);
            for (int c = 0; c < nc; c++) Jfd[(size_t)c * nq + j] = (gp[c] - gm[c]) / (2 * h);
            /* d/dq_j of (J^T lambda)_l */
            for (int l = 0; l < nq; l++) {
                double s = 0;
                for (int c = 0; c < nc; c++)
                    s += lam[c] * (Jp[(size_t)c * nq + l] - Jm[(size_t)c * nq + l]);
                Hfd[(size_t)l * nq + j] = s / (2 * h);
            }
        }
        char what[128];
        snprintf(what, sizeof what, "%s: dg/dq", study);
        compare(J, Jfd, (size_t)nc * nq, what);
        snprintf(what, sizeof what, "%s: sum lambda d2g", study);
        compare(H, Hfd, (size_t)nq * nq, what);
        /* symmetric */
        for (int a = 0; a < nq; a++)
            for (int b = 0; b < a; b++)
                CHECK_CLOSE(H[a * nq + b], H[b * nq + a], 1e-12 * maxabs(H, nq * nq),
                            "%s: Hessian symmetry", study);
    }
    sf_kin_free(&k);
    free(q); free(qq); free(g); free(gp); free(gm); free(J); free(Jfd); free(Jp); free(Jm);
    free(H); free(Hfd); free(lam);
    sf_scene_close(&sc);
}

static void test_constraint_derivatives_waterbomb(void **state)
{
    (void)state;
    check_constraint_derivatives("waterbomb2", 0, NULL);
    const char *sets[] = {"defaults.modes=2", "defaults.continuity=2"};
    check_constraint_derivatives("waterbomb2", 2, sets);
}

static void test_constraint_derivatives_square4(void **state)
{
    (void)state;
    const char *sets[] = {"defaults.modes=1"};
    check_constraint_derivatives("square4-irregular", 1, sets);
}

/* --- points: face points, band points and fold centroids --- */
typedef void (*point_fn)(const sf_model *m, const sf_kin *k, const void *ctx,
                         double x[3], double *dx, const double *f, double *H);

static void face_point_fn(const sf_model *m, const sf_kin *k, const void *ctx,
                          double x[3], double *dx, const double *f, double *H)
{
    const sf_mpoint *p = ctx;
    sf_point_eval(m, k, p, x, dx);
    if (H) sf_point_hess_add(m, k, p, f, H, m->nq);
}

static void centroid_fn(const sf_model *m, const sf_kin *k, const void *ctx,
                        double x[3], double *dx, const double *f, double *H)
{
    sf_fold_centroid(m, k, *(const int *)ctx, x, dx, f, H, m->nq);
}

static void check_point(const sf_model *m, point_fn fn, const void *ctx, const char *what)
{
    int nq = m->nq;
    double *q = calloc(nq, sizeof *q), *qq = calloc(nq, sizeof *qq);
    double *dx = calloc(3 * nq, sizeof *dx), *dfd = calloc(3 * nq, sizeof *dx);
    double *dp = calloc(3 * nq, sizeof *dx), *dm = calloc(3 * nq, sizeof *dx);
    double *H = calloc((size_t)nq * nq, sizeof *H), *Hfd = calloc((size_t)nq * nq, sizeof *H);
    sf_kin k;
    assert_int_equal(sf_kin_alloc(m, &k), SF_OK);
    random_state(m, q, 2.0, 0.5);
    double f[3] = {urand(-1, 1), urand(-1, 1), urand(-1, 1)}, x[3], xp[3], xm[3];
    sf_kin_eval(m, q, 2, &k);
    fn(m, &k, ctx, x, dx, f, H);
    double h = 1e-6;
    for (int j = 0; j < nq; j++) {
        memcpy(qq, q, sizeof(double) * nq);
        qq[j] += h;
        sf_kin_eval(m, qq, 1, &k);
        fn(m, &k, ctx, xp, dp, NULL, NULL);
        qq[j] -= 2 * h;
        sf_kin_eval(m, qq, 1, &k);
        fn(m, &k, ctx, xm, dm, NULL, NULL);
        for (int c = 0; c < 3; c++) dfd[c * nq + j] = (xp[c] - xm[c]) / (2 * h);
        for (int l = 0; l < nq; l++) {
            double s = 0;
            for (int c = 0; c < 3; c++) s += f[c] * (dp[c * nq + l] - dm[c * nq + l]);
            Hfd[(size_t)l * nq + j] = s / (2 * h);
        }
    }
    char buf[160];
    snprintf(buf, sizeof buf, "%s: dx/dq", what);
    compare(dx, dfd, 3 * (size_t)nq, buf);
    snprintf(buf, sizeof buf, "%s: f . d2x", what);
    compare(H, Hfd, (size_t)nq * nq, buf);
    sf_kin_free(&k);
    free(q); free(qq); free(dx); free(dfd); free(dp); free(dm); free(H); free(Hfd);
}

static void test_point_derivatives(void **state)
{
    (void)state;
    const char *sets[] = {"defaults.modes=2"};
    sf_scene sc;
    open_scene(&sc, "waterbomb2", 1, sets);
    const sf_model *m = &sc.model;
    sf_error err;
    sf_error_clear(&err);
    /* a point on a face far from the root, and points on bands */
    double pts[][2] = {{0.157, 0.0675}, {0.1588, 0.07383}, {0.0799, 0.041}, {0.12, 0.02}};
    for (size_t i = 0; i < sizeof pts / sizeof *pts; i++) {
        sf_mpoint p;
        assert_int_equal(sf_model_locate(m, pts[i], &p, &err), SF_OK);
        char what[96];
        snprintf(what, sizeof what, "point (%g, %g) face %d fold %d", pts[i][0], pts[i][1],
                 p.face, p.fold);
        check_point(m, face_point_fn, &p, what);
    }
    /* a point inside a band, located explicitly */
    const sf_fold_geom *g = &sc.topo.folds[7];
    double mid[2] = {0.5 * (g->a[0] + g->b[0]) + 0.2 * m->sec[7].w * g->n[0],
                     0.5 * (g->a[1] + g->b[1]) + 0.2 * m->sec[7].w * g->n[1]};
    sf_mpoint pb;
    assert_int_equal(sf_model_locate(m, mid, &pb, &err), SF_OK);
    assert_int_equal(pb.fold, 7);
    check_point(m, face_point_fn, &pb, "band point of fold 8");
    for (int i = 0; i < m->nfolds; i += 4) {
        char what[64];
        snprintf(what, sizeof what, "centroid of fold %d", i + 1);
        check_point(m, centroid_fn, &i, what);
    }
    sf_scene_close(&sc);
}

/* --- penalty energy: gradient and Hessian --- */
static void test_penalty_derivatives(void **state)
{
    (void)state;
    const char *sets[] = {"defaults.modes=1"};
    sf_scene sc;
    open_scene(&sc, "waterbomb2", 1, sets);
    const sf_model *m = &sc.model;
    int nq = m->nq;
    double *q = calloc(nq, sizeof *q), *qq = calloc(nq, sizeof *qq);
    double *gr = calloc(nq, sizeof *gr), *gfd = calloc(nq, sizeof *gr);
    double *gp = calloc(nq, sizeof *gr), *gm = calloc(nq, sizeof *gr);
    double *H = calloc((size_t)nq * nq, sizeof *H), *Hfd = calloc((size_t)nq * nq, sizeof *H);
    sf_kin k;
    assert_int_equal(sf_kin_alloc(m, &k), SF_OK);
    random_state(m, q, 1.5, 0.3);
    sf_kin_eval(m, q, 2, &k);
    sf_penalty(m, &k, 100.0, 1.0, gr, H, nq);
    double h = 1e-6;
    for (int j = 0; j < nq; j++) {
        memcpy(qq, q, sizeof(double) * nq);
        qq[j] += h;
        sf_kin_eval(m, qq, 1, &k);
        memset(gp, 0, sizeof(double) * nq);
        double Ep = sf_penalty(m, &k, 100.0, 1.0, gp, NULL, 0);
        qq[j] -= 2 * h;
        sf_kin_eval(m, qq, 1, &k);
        memset(gm, 0, sizeof(double) * nq);
        double Em = sf_penalty(m, &k, 100.0, 1.0, gm, NULL, 0);
        gfd[j] = (Ep - Em) / (2 * h);
        for (int l = 0; l < nq; l++) Hfd[(size_t)l * nq + j] = (gp[l] - gm[l]) / (2 * h);
    }
    compare(gr, gfd, nq, "penalty gradient");
    compare(H, Hfd, (size_t)nq * nq, "penalty Hessian");
    sf_kin_free(&k);
    free(q); free(qq); free(gr); free(gfd); free(gp); free(gm); free(H); free(Hfd);
    sf_scene_close(&sc);
}

/* --- invariants --- */

/* At the flat state every loop closes and every face map is the identity. */
static void test_flat_state(void **state)
{
    (void)state;
    const char *names[] = {"strip3", "waterbomb2", "square4", "square4-irregular",
                           "square4-narrow", "square4-corner", "square4-stiff", "fold1"};
    for (size_t s = 0; s < sizeof names / sizeof *names; s++) {
        const char *sets[] = {"defaults.modes=2"};
        sf_scene sc;
        open_scene(&sc, names[s], 1, sets);
        const sf_model *m = &sc.model;
        double *q = calloc(m->nq + 1, sizeof *q), *g = calloc(m->ncon + 1, sizeof *g);
        sf_kin k;
        assert_int_equal(sf_kin_alloc(m, &k), SF_OK);
        sf_kin_eval(m, q, 0, &k);
        sf_constraints(m, &k, g, NULL, NULL, NULL, 0);
        for (int c = 0; c < m->ncon; c++) CHECK_CLOSE(g[c], 0.0, 1e-15, "%s flat g[%d]", names[s], c);
        double I[12];
        sf_affine_identity(I);
        for (int f = 0; f < m->nfaces; f++)
            for (int e = 0; e < 12; e++)
                CHECK_CLOSE(k.X[12 * f + e], I[e], 1e-15, "%s flat face %d map", names[s], f);
        sf_kin_free(&k);
        free(q);
        free(g);
        sf_scene_close(&sc);
    }
}

/* For any angles and modes the sheet stays in one piece: a fold band's
 * left edge (s = w, mapped through its right face and cross-section)
 * coincides with the left face's map of the same material line, and the
 * band's end tangent is the left face's direction n rotated by theta. */
static void test_bands_meet_faces(void **state)
{
    (void)state;
    const char *cases[][2] = {{"strip3", "defaults.modes=0"}, {"strip3", "defaults.modes=3"},
                              {"waterbomb2", "defaults.continuity=2"}};
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        const char *sets[] = {cases[c][1]};
        sf_scene sc;
        open_scene(&sc, cases[c][0], 1, sets);
        const sf_model *m = &sc.model;
        double *q = calloc(m->nq + 1, sizeof *q);
        sf_kin k;
        assert_int_equal(sf_kin_alloc(m, &k), SF_OK);
        for (int trial = 0; trial < 3; trial++) {
            random_state(m, q, 3.0, 0.6);
            sf_kin_eval(m, q, 0, &k);
            for (int i = 0; i < m->nfolds; i++) {
                const sf_fold_geom *g = &sc.topo.folds[i];
                double w = m->sec[i].w, tpos = 0.5 * g->l;
                /* only tree folds are guaranteed to meet without loops */
                int tree = sc.topo.faces[g->left].parent_fold == i ||
                           sc.topo.faces[g->right].parent_fold == i;
                if (!tree) continue;
                for (int side = 0; side < 2; side++) {
                    double s = side ? w : 0.0;
                    sf_mpoint pb = {{g->a[0] + tpos * g->m[0] + (s - 0.5 * w) * g->n[0],
                                     g->a[1] + tpos * g->m[1] + (s - 0.5 * w) * g->n[1]},
                                    g->right, i, s, tpos};
                    double xb[3], xf[3], r[3] = {pb.X[0], pb.X[1], 0.0};
                    sf_point_eval(m, &k, &pb, xb, NULL);
                    sf_affine_apply(k.X + 12 * (side ? g->left : g->right), r, xf);
                    for (int e = 0; e < 3; e++)
                        CHECK_CLOSE(xb[e], xf[e], 1e-14, "%s fold %d edge %d coord %d",
                                    cases[c][0], i + 1, side, e);
                }
            }
        }
        sf_kin_free(&k);
        free(q);
        sf_scene_close(&sc);
    }
}

/* A hand-made study: square sheet [-1,1]^2 with one interior vertex at the
 * origin and folds to the outline in directions phi[k]; dir[k] = +1 when
 * the fold runs from the vertex outwards. */
typedef struct handmade {
    sf_study s;
    sf_vertex v[16];
    int outline[4];
    sf_fold_def f[8];
    sf_material mat;
} handmade;

static void make_vertex_study(handmade *h, int n, const double *phi, const int *dir,
                              double w)
{
    memset(h, 0, sizeof *h);
    double corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int i = 0; i < 4; i++) {
        snprintf(h->v[i].name, SF_NAME_MAX, "c%d", i + 1);
        h->v[i].x[0] = corners[i][0];
        h->v[i].x[1] = corners[i][1];
        h->outline[i] = i;
    }
    snprintf(h->v[4].name, SF_NAME_MAX, "o");
    for (int k = 0; k < n; k++) {
        double d[2] = {cos(phi[k]), sin(phi[k])};
        double t = 1.0 / fmax(fabs(d[0]), fabs(d[1])); /* ray hits the square */
        sf_vertex *v = &h->v[5 + k];
        snprintf(v->name, SF_NAME_MAX, "e%d", k + 1);
        v->x[0] = t * d[0];
        v->x[1] = t * d[1];
        sf_fold_def *f = &h->f[k];
        f->a = dir[k] > 0 ? 4 : 5 + k;
        f->b = dir[k] > 0 ? 5 + k : 4;
        f->width = w;
        /* setbacks keep the bands apart at the vertex; they do not enter
         * the folding maps, so this is still the crease limit as w -> 0 */
        f->setback[dir[k] > 0 ? 0 : 1] = 3.0 * w;
        f->continuity = 1;
        f->modes = 0;
        f->material = 0;
        f->group = -1;
        f->line = 1;
    }
    snprintf(h->mat.name, SF_NAME_MAX, "fold");
    h->mat.E = 1e7;
    h->mat.nu = 0.3;
    h->mat.thickness = 1e-3;
    h->mat.density = 1000;
    sf_study *s = &h->s;
    snprintf(s->name, SF_NAME_MAX, "vertex4");
    snprintf(s->path, sizeof s->path, "handmade");
    s->nvertices = 5 + n;
    s->vertices = h->v;
    s->noutline = 4;
    s->outline = h->outline;
    s->nfolds = n;
    s->folds = h->f;
    s->nmaterials = 1;
    s->materials = &h->mat;
    s->face_material = -1;
    s->fixed_point[0] = 0.5 * (cos(phi[0]) + cos(phi[1])) * 0.5;
    s->fixed_point[1] = 0.5 * (sin(phi[0]) + sin(phi[1])) * 0.5;
    s->nstages = 1;
    s->quadrature = 24;
    s->samples = 4;
}

static void vertex_residual(handmade *h, const double *theta, double *rot, double *tra)
{
    sf_topology t;
    sf_model m;
    sf_error err;
    sf_error_clear(&err);
    if (sf_topology_build(&h->s, &t, &err)) {
        print_error("topology: %s\n", err.msg);
        fail();
    }
    assert_int_equal(t.nivertices, 1);
    assert_int_equal(sf_model_init(&m, &h->s, &t, &err), SF_OK);
    sf_kin k;
    assert_int_equal(sf_kin_alloc(&m, &k), SF_OK);
    double q[8], g[6];
    /* theta[k] is the angle of the k-th fold counter-clockwise */
    for (int i = 0; i < m.nfolds; i++) q[m.qoff[i]] = theta[i];
    sf_kin_eval(&m, q, 0, &k);
    sf_constraints(&m, &k, g, NULL, NULL, NULL, 0);
    *rot = fmax(fabs(g[0]), fmax(fabs(g[1]), fabs(g[2])));
    *tra = sqrt(g[3] * g[3] + g[4] * g[4] + g[5] * g[5]);
    sf_kin_free(&k);
    sf_model_free(&m);
    sf_topology_free(&t);
}

/* Crease limit of a flat-foldable degree-4 vertex with sector angles
 * alpha, beta, pi - alpha, pi - beta (Huffman): the loop closes in rotation
 * along  rho1 = -rho3 = t,  rho2 = rho4 = 2 atan(tan(t/2) sin((a+b)/2) / sin((a-b)/2))
 * and    rho1 = rho3 = t,   rho2 = -rho4 = -2 atan(tan(t/2) cos((a+b)/2) / cos((a-b)/2)).
 * The rotation part of a folding map does not depend on the width, so the
 * relation holds for every width; the translation residual is then exactly
 * linear in the width (each map's translation is affine in w and vanishes
 * for creases through the vertex). */
static void test_degree4_crease_limit(void **state)
{
    (void)state;
    double al = 0.9, be = 1.3;
    double phi[4] = {0.2, 0.2 + al, 0.2 + al + be, 0.2 + al + be + M_PI - al};
    int dir[4] = {+1, -1, +1, -1};
    handmade h;
    for (int mode = 0; mode < 2; mode++)
        for (double t = -2.5; t <= 2.5; t += 0.5) {
            double th[4];
            if (mode == 0) {
                double r = 2 * atan(tan(t / 2) * sin((al + be) / 2) / sin((al - be) / 2));
                th[0] = t; th[1] = r; th[2] = -t; th[3] = r;
            } else {
                double r = -2 * atan(tan(t / 2) * cos((al + be) / 2) / cos((al - be) / 2));
                th[0] = t; th[1] = r; th[2] = t; th[3] = -r;
            }
            double rot, tra[3], ws[3] = {1e-6, 1e-4, 2e-4};
            for (int iw = 0; iw < 3; iw++) {
                make_vertex_study(&h, 4, phi, dir, ws[iw]);
                vertex_residual(&h, th, &rot, &tra[iw]);
                CHECK_CLOSE(rot, 0.0, 1e-12, "mode %d t %g w %g rotation residual", mode, t, ws[iw]);
            }
            if (fabs(t) > 0.1) {
                /* exactly linear: zero for creases, proportional to w */
                CHECK_CLOSE(tra[2] / tra[1], 2.0, 1e-9, "mode %d t %g: translation ratio 2w/w", mode, t);
                CHECK_CLOSE(tra[0] / ws[0], tra[1] / ws[1], 1e-7 * tra[1] / ws[1],
                            "mode %d t %g: translation residual / w", mode, t);
                assert_true(tra[1] > 1e-8);
            }
        }
    /* off the relation the rotation does not close */
    double th[4] = {0.5, 0.5, 0.5, 0.5}, rot, tra;
    make_vertex_study(&h, 4, phi, dir, 1e-3);
    vertex_residual(&h, th, &rot, &tra);
    assert_true(rot > 1e-3);
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : ".");
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_flat_state),
        cmocka_unit_test(test_bands_meet_faces),
        cmocka_unit_test(test_degree4_crease_limit),
        cmocka_unit_test(test_constraint_derivatives_waterbomb),
        cmocka_unit_test(test_constraint_derivatives_square4),
        cmocka_unit_test(test_point_derivatives),
        cmocka_unit_test(test_penalty_derivatives),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
