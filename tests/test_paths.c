/* test_paths.c - equilibrium paths with exact loop closure off the flat
 * state, and the mobility left by the loop constraints (MODEL.md 4, 6):
 *  - cont_set_weights: arclength in the weighted norm on a linear problem
 *    whose step lengths are known in closed form;
 *  - the limit start (src/analysis/start/flatstart.c) of waterbomb2: its guess is off the
 *    exact solution by O(dp^2), and the multipliers of the in-plane rows
 *    tend to finite, non-zero values as dp -> 0;
 *  - mobility (src/analysis/stability/mobility.c): a degree-4 vertex with K = 0 and finite
 *    widths is locked (named), the same vertex with K = 1, or with its four
 *    folds on two straight lines, moves; waterbomb2 and square4 move, with
 *    the degrees of freedom that counting gives at a generic folded state;
 *    and, independently of the mobility code, the penalty solution of the
 *    locked vertex shrinks like 1/k as the penalty stiffness k grows, that
 *    of the mobile one does not.
 * Studies: studies/ and tests/studies/.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#define SF_TEST_SEED 987654321u
#include "sf_test.h"

#include "cont.h"
#include "equilibrium.h"
#include "flatstart.h"
#include "mobility.h"
#include "scene.h"

static char tests_dir[1024];

static void open_test_scene(sf_scene *sc, const char *name, int nset, const char **sets)
{
    char path[1200];
    sf_error err;
    sf_error_clear(&err);
    snprintf(path, sizeof path, "%s/%s.cfg", tests_dir, name);
    if (sf_scene_open(sc, path, nset, sets, &err)) {
        print_error("cannot open %s: %s\n", path, err.msg);
        fail();
    }
}

/* ------------------------------------------------------------------------
 * cont_set_weights
 * ------------------------------------------------------------------------ */

/* F = (y0 - p, y1 - 1000 p): the branch is the straight line y = (p, 1000 p).
 * With weights (1, 0) and theta = 1 the unit tangent has t_p = 1/sqrt(2),
 * so a step of arclength ds advances p by ds/sqrt(2); with the default
 * weights, by ds/sqrt(1 + 1e6 + 1). */
static int lin_res(const double *y, double p, double *F, void *u)
{
    (void)u;
    F[0] = y[0] - p;
    F[1] = y[1] - 1000.0 * p;
    return 0;
}

static int lin_jac(const double *y, double p, SUNMatrix J, double *Fp, void *u)
{
    (void)y; (void)p; (void)u;
    SM_ELEMENT_D(J, 0, 0) = 1.0;
    SM_ELEMENT_D(J, 1, 1) = 1.0;
    Fp[0] = -1.0;
    Fp[1] = -1000.0;
    return 0;
}

static double first_step_dp(const double *w)
{
    cont_problem pr;
    memset(&pr, 0, sizeof pr);
    pr.n = 2;
    pr.residual = lin_res;
    pr.jacobian = lin_jac;
    cont_solver *cs = NULL;
    assert_int_equal(cont_create(&pr, CONT_LINSOL_DENSE, &cs), CONT_OK);
    if (w) assert_int_equal(cont_set_weights(cs, w), CONT_OK);
    assert_int_equal(cont_set_step(cs, 0.1, 1e-8, 0.1), CONT_OK);
    assert_int_equal(cont_set_detect(cs, 0u, 1e-10), CONT_OK);
    double y0[2] = {0.0, 0.0};
    assert_int_equal(cont_start(cs, y0, 0.0, +1), CONT_OK);
    assert_int_equal(cont_step(cs), CONT_CONTINUE);
    const cont_point *pt = cont_get_point(cs);
    CHECK_CLOSE(pt->s, 0.1, 1e-12, "arclength of the first step");
    CHECK_CLOSE(pt->y[1], 1000.0 * pt->p, 1e-9, "point on the branch");
    double dp = pt->p;
    cont_free(cs);
    return dp;
}

static void test_weights(void **state)
{
    (void)state;
    double w[2] = {1.0, 0.0};
    CHECK_CLOSE(first_step_dp(w), 0.1 / sqrt(2.0), 1e-12, "dp with weights (1, 0)");
    CHECK_CLOSE(first_step_dp(NULL), 0.1 / sqrt(1.0 + 1e6 + 1.0), 1e-12, "dp, default weights");
    double bad[2] = {0.0, 0.0};
    cont_problem pr;
    memset(&pr, 0, sizeof pr);
    pr.n = 2;
    pr.residual = lin_res;
    pr.jacobian = lin_jac;
    cont_solver *cs = NULL;
    assert_int_equal(cont_create(&pr, CONT_LINSOL_DENSE, &cs), CONT_OK);
    assert_int_equal(cont_set_weights(cs, bad), CONT_EINPUT);
    cont_free(cs);
}

/* ------------------------------------------------------------------------
 * Limit start of waterbomb2 (exact loop closure)
 * ------------------------------------------------------------------------ */

static const char *wb2_exact[] = {"solver.constraints=\"exact\""};

/* Limit guess at p = dp, then the exact solution from it; returns the
 * errors of the guess in q (max, rad) and in the multipliers (max, N or
 * J), and the exact solution's largest multiplier magnitude. */
static void limit_error(sf_equil *eq, double dp, double *eq_err, double *el_err, double *lmax)
{
    int n = eq->n, nq = eq->nq;
    double *y = calloc((size_t)n, sizeof(double)), *yg = calloc((size_t)n, sizeof(double));
    assert_non_null(y);
    assert_non_null(yg);
    sf_error err;
    sf_error_clear(&err);
    sf_flatstart_info info;
    if (sf_equil_start_limit(eq, 0.0, dp, yg, &info, &err)) {
        print_error("limit start: %s\n", err.msg);
        fail();
    }
    assert_true(info.residual <= 1e-9);
    memcpy(y, yg, sizeof(double) * (size_t)n);
    cont_solver *cs = NULL;
    assert_int_equal(sf_equil_create_solver(eq, &cs), CONT_OK);
    cont_set_newton(cs, 1e-11, 12, 0);
    if (cont_solve_fixed(cs, y, dp) != CONT_OK) {
        print_error("exact solve at p = %g from the limit guess: %s\n", dp, cont_errmsg(cs));
        fail();
    }
    double Pi, rr, rt;
    sf_equil_report(eq, y, dp, &Pi, &rr, &rt);
    assert_true(rr < 1e-12 && rt < 1e-14);
    *eq_err = 0.0;
    *el_err = 0.0;
    *lmax = 0.0;
    for (int j = 0; j < nq; j++) *eq_err = fmax(*eq_err, fabs(y[j] - yg[j]));
    for (int j = nq; j < n; j++) {
        *el_err = fmax(*el_err, fabs(y[j] - yg[j]));
        *lmax = fmax(*lmax, fabs(y[j]));
    }
    cont_free(cs);
    free(y);
    free(yg);
}

static void test_limit_start(void **state)
{
    (void)state;
    sf_scene sc;
    open_scene(&sc, "waterbomb2", 1, wb2_exact);
    sf_equil eq;
    sf_error err;
    sf_error_clear(&err);
    assert_int_equal(sf_equil_init(&eq, &sc.model, SF_PARAM_LOAD, -1, 0, 2, 0.0, &err), SF_OK);
    double e1, l1, m1, e2, l2, m2;
    limit_error(&eq, 0.04, &e1, &l1, &m1);
    limit_error(&eq, 0.02, &e2, &l2, &m2);
    print_message("# waterbomb2 limit start: |dq| %.3g -> %.3g, |dlambda| %.3g -> %.3g N, "
                  "max |lambda| %.3g -> %.3g\n", e1, e2, l1, l2, m1, m2);
    /* q = dp u + O(dp^2): halving dp quarters the error of the guess */
    assert_true(e2 < 0.35 * e1);
    /* multipliers: nu + O(dp), nu finite and non-zero (tens of newtons
     * on the in-plane translation rows: much more than the 0.013 N of
     * gravity at p = 0.05) */
    assert_true(l2 < 0.6 * l1);
    assert_true(m1 > 1.0 && m2 > 1.0);
    CHECK_CLOSE(m2, m1, 0.05 * m1, "largest multiplier at dp = 0.02 and 0.04");
    sf_equil_free(&eq);
    sf_scene_close(&sc);
}

/* ------------------------------------------------------------------------
 * Mobility
 * ------------------------------------------------------------------------ */

static void mobility(sf_scene *sc, sf_mobility *mb)
{
    sf_error err;
    sf_error_clear(&err);
    if (sf_mobility_analyse(&sc->model, NULL, mb, &err)) {
        print_error("mobility: %s\n", err.msg);
        fail();
    }
}

static void test_degree4_locked(void **state)
{
    (void)state;
    sf_scene sc;
    open_test_scene(&sc, "deg4", 0, NULL);
    sf_mobility mb;
    mobility(&sc, &mb);
    /* at the flat state only the two in-plane rotation rows are of first
     * order (every fold line passes through the vertex): 4 - 2 */
    assert_int_equal(mb.first_order, 2);
    assert_int_equal(mb.nvertices, 1);
    assert_int_equal(mb.v[0].dof, 0);
    assert_int_equal(mb.dof, 0);
    assert_int_equal(mb.nlocked, 1);
    assert_true(mb.v[0].certificate > 1e-7);
    assert_true(mb.gap > 1e-3 * mb.radius * mb.radius);
    assert_true(sf_mobility_locked(&mb));
    char what[1500];
    sf_mobility_describe(&sc.model, &mb, what, sizeof what);
    print_message("# %s\n", what);
    assert_non_null(strstr(what, "vertex c (degree 4"));
    sf_mobility_free(&mb);
    sf_scene_close(&sc);
}

/* sum_{i<j} rho_i rho_j sin(phi_j - phi_i) */
static double rigid_commutator(const double phi[4], const double rho[4])
{
    double q = 0.0;
    for (int i = 0; i < 4; i++)
        for (int j = i + 1; j < 4; j++) q += rho[i] * rho[j] * sin(phi[j] - phi[i]);
    return q;
}

/* The two folding modes of a rigid degree-4 vertex at flat, in closed
 * form: fold angles rho_i about the outward fold directions at angles
 * phi_i (counter-clockwise) close the loop to first order when
 * sum rho_i (cos phi_i, sin phi_i) = 0 (a plane of rho), and to second
 * order when sum_{i<j} rho_i rho_j sin(phi_j - phi_i) = 0 (the normal
 * component of the rotations' commutators): a quadratic on that plane,
 * whose two roots are the modes.  Writes them unit into out; returns how
 * many are real. */
static int rigid_degree4_modes(const double phi[4], double out[2][4])
{
    /* rho = s u + t w with u = (1, 0, u2, u3), w = (0, 1, w2, w3) */
    double c2 = cos(phi[2]), s2 = sin(phi[2]), c3 = cos(phi[3]), s3 = sin(phi[3]);
    double det = c2 * s3 - c3 * s2, u[4], w[4], uw[4];
    for (int k = 0; k < 2; k++) {
        double *x = k ? w : u, bx = -cos(phi[k]), by = -sin(phi[k]);
        x[0] = k == 0;
        x[1] = k == 1;
        x[2] = (bx * s3 - c3 * by) / det;
        x[3] = (c2 * by - s2 * bx) / det;
    }
    for (int i = 0; i < 4; i++) uw[i] = u[i] + w[i];
    double A = rigid_commutator(phi, u), C = rigid_commutator(phi, w);
    double B = rigid_commutator(phi, uw) - A - C, disc = B * B - 4 * A * C;
    if (disc < 0) return 0;
    for (int k = 0; k < 2; k++) {
        /* the roots of A s^2 + B s t + C t^2 = 0: (s, t) = (2C, -B +- sqrt
         * disc) or (-B +- sqrt disc, 2A), whichever divides by the larger
         * coefficient */
        double sgn = k ? -1.0 : 1.0, ss, tt;
        if (fabs(C) > fabs(A)) { ss = 2 * C; tt = -B + sgn * sqrt(disc); }
        else { tt = 2 * A; ss = -B + sgn * sqrt(disc); }
        double n = 0.0;
        for (int i = 0; i < 4; i++) {
            out[k][i] = ss * u[i] + tt * w[i];
            n += out[k][i] * out[k][i];
        }
        for (int i = 0; i < 4; i++) out[k][i] /= sqrt(n);
    }
    return 2;
}

/* A degree-4 vertex has exactly two folding modes at flat: the mobility
 * analysis of each vertex alone (finite widths, K = 1) finds two, and
 * their fold angles are the rigid vertex's two (closed form above), on a
 * generic vertex (deg4) and on the flat-foldable vertices of a Miura
 * sheet, where one mode folds the straight line alone. */
static void test_degree4_two_modes(void **state)
{
    (void)state;
    const char *k1[] = {"defaults.modes=1"};
    const char *names[] = {"deg4", "miura2"};
    for (int c = 0; c < 2; c++) {
        sf_scene sc;
        sf_mobility mb;
        open_test_scene(&sc, names[c], c == 0, k1);
        mobility(&sc, &mb);
        const sf_study *st = &sc.study;
        for (int v = 0; v < mb.nvertices; v++) {
            const sf_ivertex *iv = &sc.topo.ivertices[v];
            const sf_mobility_vertex *mv = &mb.v[v];
            assert_int_equal(iv->degree, 4);
            assert_int_equal(mv->nfolds, 4);
            if (mv->modes != 2) {
                print_error("%s, vertex %s: %d folding modes, expected 2\n", names[c],
                            st->vertices[iv->vertex].name, mv->modes);
                fail();
            }
            double phi[4], want[2][4];
            const double *x0 = st->vertices[iv->vertex].x;
            for (int a = 0; a < 4; a++) {
                const sf_fold_def *f = &st->folds[iv->folds[a]];
                const double *x1 = st->vertices[f->a == iv->vertex ? f->b : f->a].x;
                phi[a] = atan2(x1[1] - x0[1], x1[0] - x0[0]);
            }
            assert_int_equal(rigid_degree4_modes(phi, want), 2);
            for (int k = 0; k < 2; k++) {
                double best = 0.0;
                for (int l = 0; l < 2; l++) {
                    double cs = 0.0;
                    for (int a = 0; a < 4; a++) cs += want[l][a] * mv->mode[k * 4 + a];
                    best = fmax(best, fabs(cs));
                }
                if (v == 0)
                    print_message("# %s, vertex %s: mode %d (%.5f %.5f %.5f %.5f), 1 - |cos| to the "
                                  "rigid vertex's %.2g\n", names[c], st->vertices[iv->vertex].name,
                                  k, mv->mode[k * 4], mv->mode[k * 4 + 1], mv->mode[k * 4 + 2],
                                  mv->mode[k * 4 + 3], 1.0 - best);
                CHECK_LE(1.0 - best, 1e-8, "a mode's fold angles against the rigid vertex's mode");
            }
        }
        sf_mobility_free(&mb);
        sf_scene_close(&sc);
    }
}

static void test_degree3_locked(void **state)
{
    (void)state;
    sf_scene sc;
    sf_mobility mb;
    /* K = 1: six coordinates; three first-order motions (the rotation rows
     * about the in-plane axes and the normal translation are of first
     * order); no prestress, but no second-order motion either */
    open_test_scene(&sc, "deg3", 0, NULL);
    mobility(&sc, &mb);
    assert_int_equal(mb.first_order, 3);
    assert_int_equal(mb.dof, 0);
    assert_int_equal(mb.nlocked, 1);
    assert_int_equal(mb.v[0].cert_kind, SF_CERT_SECOND_ORDER);
    assert_true(mb.v[0].certificate > 1e-8);
    assert_true(sf_mobility_locked(&mb));
    print_message("# degree-3 vertex, K = 1: sum of squares gamma %.4g\n", mb.v[0].certificate);
    sf_mobility_free(&mb);
    sf_scene_close(&sc);
    /* K = 0: three fold angles, locked already by a prestress */
    const char *k0[] = {"defaults.modes=0"};
    open_test_scene(&sc, "deg3", 1, k0);
    mobility(&sc, &mb);
    assert_int_equal(mb.dof, 0);
    assert_int_equal(mb.v[0].cert_kind, SF_CERT_PRESTRESS);
    sf_mobility_free(&mb);
    sf_scene_close(&sc);
}

/* The sum-of-squares certificate on forms with closed-form answers.
 * Q1 = v1^2 - v2^2, Q2 = 2 v1 v2: Q1^2 + Q2^2 = |v|^4, no real common
 * zero, and every combination of Q1, Q2 is traceless, so no prestress
 * exists; the Gram matrix of the sum (basis v1^2, sqrt2 v1 v2, v2^2) has
 * largest eigenvalue 2, so gamma = 1 / 2.  Q1 alone vanishes on v1 = v2:
 * no certificate. */
static void test_sos_closed_form(void **state)
{
    (void)state;
    double G[8] = {1, 0, 0, -1, 0, 1, 1, 0};
    int st = -2;
    double g = sf_mobility_sos(2, 2, G, &st);
    assert_int_equal(st, 0);
    CHECK_CLOSE(g, 0.5, 1e-6, "gamma of (v1^2 - v2^2)^2 + (2 v1 v2)^2");
    g = sf_mobility_sos(2, 1, G, &st);
    assert_int_equal(st, 0);
    assert_true(g < 1e-8);
    /* with a third variable and Q3 = -v0^2: sum = v0^4 + (v1^2 + v2^2)^2,
     * whose minimum on the unit sphere is 1/2 (v0^2 = 1/2); the Gram
     * matrix's largest eigenvalue is 2 again: gamma = 1/4 */
    double H[27] = {0};
    H[0 * 9 + 4] = 1; H[0 * 9 + 8] = -1;           /* Q1 on (v1, v2) */
    H[1 * 9 + 5] = 1; H[1 * 9 + 7] = 1;            /* Q2 */
    H[2 * 9 + 0] = -1;                             /* Q3 */
    g = sf_mobility_sos(3, 3, H, &st);
    assert_int_equal(st, 0);
    CHECK_CLOSE(g, 0.25, 1e-6, "gamma of v0^4 + |v12|^4");
}

static void test_degree4_mobile(void **state)
{
    (void)state;
    sf_scene sc;
    sf_mobility mb;
    /* K = 1: 8 coordinates, 6 independent rows at a folded state */
    const char *k1[] = {"defaults.modes=1"};
    open_test_scene(&sc, "deg4", 1, k1);
    mobility(&sc, &mb);
    assert_int_equal(mb.dof, 8 - 6);
    assert_int_equal(mb.v[0].dof, 8 - 6);
    assert_int_equal(mb.nlocked, 0);
    assert_false(sf_mobility_locked(&mb));
    sf_mobility_free(&mb);
    sf_scene_close(&sc);
    /* K = 0 with the folds on two straight lines (a plus sign): each line
     * folds alone, a one-parameter motion */
    const char *plus[] = {"vertices.e1=[0.1, 0.0]", "vertices.e2=[0.0, 0.1]",
                          "vertices.e3=[-0.1, 0.0]", "vertices.e4=[0.0, -0.1]"};
    open_test_scene(&sc, "deg4", 4, plus);
    mobility(&sc, &mb);
    assert_int_equal(mb.dof, 1);
    assert_int_equal(mb.nlocked, 0);
    sf_mobility_free(&mb);
    sf_scene_close(&sc);
}

static void test_studies_mobile(void **state)
{
    (void)state;
    sf_scene sc;
    sf_mobility mb;
    /* waterbomb2, K = 0: 15 fold angles, 2 x 6 rows; each degree-8 vertex
     * 8 - 6; at the flat state 15 - 2 x 2 first-order motions */
    open_scene(&sc, "waterbomb2", 0, NULL);
    mobility(&sc, &mb);
    assert_int_equal(mb.first_order, 15 - 4);
    assert_int_equal(mb.dof, 15 - 12);
    for (int v = 0; v < 2; v++) assert_int_equal(mb.v[v].dof, 8 - 6);
    sf_mobility_free(&mb);
    sf_scene_close(&sc);
    /* square4 (K = 1 by default): 48 coordinates, 4 x 6 rows; each
     * degree-7 vertex 14 - 6 */
    open_scene(&sc, "square4", 0, NULL);
    mobility(&sc, &mb);
    assert_int_equal(mb.nq, 48);
    assert_int_equal(mb.dof, 48 - 24);
    for (int v = 0; v < 4; v++) assert_int_equal(mb.v[v].dof, 14 - 6);
    assert_false(sf_mobility_locked(&mb));
    sf_mobility_free(&mb);
    sf_scene_close(&sc);
}

static void test_mobility_bad_state(void **state)
{
    (void)state;
    sf_scene sc;
    open_scene(&sc, "waterbomb2", 0, NULL);
    double *q = calloc((size_t)sc.model.nq, sizeof(double));
    assert_non_null(q);
    q[0] = 0.3;   /* one fold of v7 alone: the loop does not close */
    sf_mobility mb;
    sf_error err;
    sf_error_clear(&err);
    assert_int_equal(sf_mobility_analyse(&sc.model, q, &mb, &err), SF_EINPUT);
    assert_non_null(strstr(err.msg, "v7"));
    free(q);
    sf_scene_close(&sc);
}

/* Independent of the mobility code.  Under the paper's penalty with
 * stiffness k, a vertex locked at second order can only deform by opening
 * its loop by O(theta^2), at an energy cost k theta^4 against the work
 * f theta of the load: its deformation falls like k^(-1/3) as k grows (a
 * factor 10 for k x 1000).  The mobile one has an exact equilibrium off the
 * flat state: Newton on the exact problem from the penalty solution at
 * k = 1e4 (multipliers k g) closes the loops with a finite deformation.
 * Penalty stiffness in units of the mean fold stiffness, reached through
 * k = 1e2, 1e3, ...; the largest fold angle at full load in *a (k = 1e7)
 * and *b (k = 1e10), y (eq.n values, exact layout) from k = 1e4. */
static void penalty_path(sf_scene *sc, double *a, double *b, double *yex, double *kref)
{
    sf_equil eq;
    sf_error err;
    sf_error_clear(&err);
    assert_int_equal(sf_equil_init(&eq, &sc->model, SF_PARAM_LOAD, -1, 0, 2, 0.0, &err), SF_OK);
    int nq = eq.nq, nloop = eq.nloop;
    *kref = eq.kref;
    double *y = calloc((size_t)eq.n + 1, sizeof(double)), *yt = calloc((size_t)eq.n + 1, sizeof(double));
    assert_non_null(y);
    assert_non_null(yt);
    for (int e = 2; e <= 10; e++) {
        double kk = pow(10.0, e), lR = kk * eq.kref, ld = kk * eq.kref / (eq.lref * eq.lref);
        sf_equil_use_penalty(&eq, lR, ld);
        cont_solver *cs = NULL;
        assert_int_equal(sf_equil_create_solver(&eq, &cs), CONT_OK);
        cont_set_newton(cs, 1e-8, 50, 1);
        cont_set_newton_init(cs, 200, 1);
        memcpy(yt, y, sizeof(double) * (size_t)eq.n);
        int ok = cont_solve_fixed(cs, yt, 1.0) == CONT_OK;
        if (ok) memcpy(y, yt, sizeof(double) * (size_t)eq.n);
        if (!ok && (e == 4 || e == 7 || e == 10)) {
            print_error("penalty k = %g: %s\n", kk, cont_errmsg(cs));
            fail();
        }
        cont_free(cs);
        double amax = 0.0;
        for (int j = 0; j < nq; j++) amax = fmax(amax, fabs(y[j]));
        if (e == 7) *a = amax;
        if (e == 10) *b = amax;
        if (e == 4) {
            /* the exact problem's unknowns: q, and the penalty forces */
            sf_kin_eval(&sc->model, y, 0, &eq.k);
            sf_constraints(&sc->model, &eq.k, eq.g, NULL, NULL, NULL, 0);
            memcpy(yex, y, sizeof(double) * (size_t)nq);
            for (int c = 0; c < nloop; c++) yex[nq + c] = (c % 6 < 3 ? lR : ld) * eq.g[c];
        }
    }
    free(y);
    free(yt);
    sf_equil_free(&eq);
}

static void test_penalty_locking(void **state)
{
    (void)state;
    sf_scene sc;
    double a, b, kref;
    double yex[64];
    open_test_scene(&sc, "deg4", 0, NULL);
    penalty_path(&sc, &a, &b, yex, &kref);
    sf_scene_close(&sc);
    print_message("# deg4 K = 0 penalty: max |q| %.4g at k = 1e7, %.4g at k = 1e10\n", a, b);
    CHECK_CLOSE(b / a, 0.1, 0.02, "K = 0: deformation ratio for k x 1000 (k^(-1/3))");

    const char *k1[] = {"defaults.modes=1"};
    open_test_scene(&sc, "deg4", 1, k1);
    penalty_path(&sc, &a, &b, yex, &kref);
    sf_equil eq;
    sf_error err;
    sf_error_clear(&err);
    assert_int_equal(sf_equil_init(&eq, &sc.model, SF_PARAM_LOAD, -1, 0, 2, 0.0, &err), SF_OK);
    assert_true(eq.n <= 64);
    cont_solver *cs = NULL;
    assert_int_equal(sf_equil_create_solver(&eq, &cs), CONT_OK);
    cont_set_newton(cs, 1e-11, 12, 0);
    cont_set_newton_init(cs, 30, 0);   /* plain Newton steps from the close estimate */
    if (cont_solve_fixed(cs, yex, 1.0) != CONT_OK) {
        print_error("deg4 K = 1: no exact equilibrium from the penalty solution: %s\n",
                    cont_errmsg(cs));
        fail();
    }
    double Pi, rr, rt, amax = 0.0;
    sf_equil_report(&eq, yex, 1.0, &Pi, &rr, &rt);
    for (int j = 0; j < eq.nq; j++) amax = fmax(amax, fabs(yex[j]));
    print_message("# deg4 K = 1 exact: max |q| %.4g, loop residual %.2g rad, %.2g m\n", amax, rr, rt);
    assert_true(rr < 1e-12 && rt < 1e-14);
    assert_true(amax > 1e-3);
    cont_free(cs);
    sf_equil_free(&eq);
    sf_scene_close(&sc);
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : SF_SRCDIR);
    snprintf(tests_dir, sizeof tests_dir, "%s/tests/studies", src ? src : SF_SRCDIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_weights),
        cmocka_unit_test(test_limit_start),
        cmocka_unit_test(test_degree4_locked),
        cmocka_unit_test(test_degree4_mobile),
        cmocka_unit_test(test_studies_mobile),
        cmocka_unit_test(test_degree3_locked),
        cmocka_unit_test(test_degree4_two_modes),
        cmocka_unit_test(test_sos_closed_form),
        cmocka_unit_test(test_mobility_bad_state),
        cmocka_unit_test(test_penalty_locking),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
