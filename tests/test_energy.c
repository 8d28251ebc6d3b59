/* test_energy.c - potential energy and equilibrium residual (MODEL.md 5-6):
 * analytic gradient, Hessian and parameter derivative of Pi against central
 * differences; the dense Jacobian [H + lambda.d2g, J^T; J, -eps D] and
 * dF/dp of the equilibrium problem against central differences of the
 * residual, for the load, actuation and displacement parameters, exact and
 * penalty constraints; and closed forms of the bending, point-load and
 * gravity energies of strip3 (CASES.md). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_dense.h>

#define SF_TEST_SEED 123456789u
#include "sf_test.h"

#include "energy.h"
#include "equilibrium.h"
#include "kinematics.h"
#include "scene.h"
#include "study.h"
#include "topology.h"

/* check_fd (sf_test.h); a test whose differences are all zero checks
 * nothing, so that is a failure here. */
static void compare(const double *A, const double *F, size_t n, const char *what)
{
    assert_true(maxabs(F, n) > 0.0);
    check_fd(A, F, n, 1e-300, what);
}

/* ------------------------------------------------------------------------
 * Energy: gradient and Hessian
 * ------------------------------------------------------------------------ */

/* Pi, grad and H at a random state with random stage factors and rest
 * angles; grad against differences of Pi, H against differences of grad. */
static void check_energy_derivatives(const char *study, int nset, const char **sets,
                                     double amax, double amodes, const char *label)
{
    sf_scene sc;
    open_scene(&sc, study, nset, sets);
    const sf_model *m = &sc.model;
    sf_error err;
    sf_error_clear(&err);
    sf_energy e;
    if (sf_energy_init(&e, m, &err)) {
        print_error("%s: energy init: %s\n", label, err.msg);
        fail();
    }
    sf_params par;
    assert_int_equal(sf_params_alloc(&e, &par), SF_OK);
    for (int s = 0; s < e.nstages; s++) par.stage[s] = urand(0.3, 1.0);
    for (int i = 0; i < m->nfolds; i++) par.rest[i] = urand(-1.0, 1.0);
    int nq = m->nq;
    double *q = calloc(nq, sizeof *q), *qq = calloc(nq, sizeof *qq);
    double *gr = calloc(nq, sizeof *gr), *gfd = calloc(nq, sizeof *gr);
    double *gp = calloc(nq, sizeof *gr), *gm = calloc(nq, sizeof *gr);
    double *H = calloc((size_t)nq * nq, sizeof *H), *Hfd = calloc((size_t)nq * nq, sizeof *H);
    sf_kin k;
    assert_int_equal(sf_kin_alloc(m, &k), SF_OK);
    for (int trial = 0; trial < 2; trial++) {
        random_state(m, q, amax, amodes);
        sf_kin_eval(m, q, 2, &k);
        memset(gr, 0, sizeof(double) * nq);
        memset(H, 0, sizeof(double) * nq * nq);
        double Pi = sf_energy_eval(&e, &k, &par, gr, H, nq, NULL);
        assert_true(isfinite(Pi));
        /* Pi without derivatives is the same number */
        sf_kin_eval(m, q, 0, &k);
        CHECK_CLOSE(sf_energy_eval(&e, &k, &par, NULL, NULL, 0, NULL), Pi, 1e-14 * fabs(Pi),
                    "%s: Pi with and without derivatives", label);
        double h = 1e-5;
        for (int j = 0; j < nq; j++) {
            memcpy(qq, q, sizeof(double) * nq);
            qq[j] += h;
            sf_kin_eval(m, qq, 1, &k);
            memset(gp, 0, sizeof(double) * nq);
            double Ep = sf_energy_eval(&e, &k, &par, gp, NULL, 0, NULL);
            qq[j] -= 2 * h;
            sf_kin_eval(m, qq, 1, &k);
            memset(gm, 0, sizeof(double) * nq);
            double Em = sf_energy_eval(&e, &k, &par, gm, NULL, 0, NULL);
            gfd[j] = (Ep - Em) / (2 * h);
            for (int l = 0; l < nq; l++) Hfd[(size_t)l * nq + j] = (gp[l] - gm[l]) / (2 * h);
        }
        char what[160];
        snprintf(what, sizeof what, "%s: dPi/dq", label);
        compare(gr, gfd, nq, what);
        snprintf(what, sizeof what, "%s: d2Pi/dq2", label);
        compare(H, Hfd, (size_t)nq * nq, what);
        for (int a = 0; a < nq; a++)
            for (int b = 0; b < a; b++)
                CHECK_CLOSE(H[a * nq + b], H[b * nq + a], 1e-12 * maxabs(H, nq * nq),
                            "%s: Hessian symmetry (%d, %d)", label, a, b);
    }
    sf_kin_free(&k);
    sf_params_free(&par);
    sf_energy_free(&e);
    free(q); free(qq); free(gr); free(gfd); free(gp); free(gm); free(H); free(Hfd);
    sf_scene_close(&sc);
}

static void test_energy_derivatives(void **state)
{
    (void)state;
    /* waterbomb2: bending, the corner point load (stage 2) and gravity on
     * faces and folds (stage 1), K = 0 G1 as in the study */
    {
        const char *sets[] = {"solver.constraints=\"exact\""};
        check_energy_derivatives("waterbomb2", 1, sets, 1.5, 0.0, "waterbomb2 K=0 G1");
    }
    {
        const char *sets[] = {"defaults.modes=2", "defaults.continuity=2",
                              "solver.constraints=\"exact\""};
        check_energy_derivatives("waterbomb2", 3, sets, 1.5, 0.4, "waterbomb2 K=2 G2");
    }
    {
        const char *sets[] = {"defaults.modes=3", "defaults.continuity=1",
                              "solver.constraints=\"exact\""};
        check_energy_derivatives("waterbomb2", 3, sets, 1.5, 0.4, "waterbomb2 K=3 G1");
    }
    {
        /* the paper's penalty adds its energy to Pi */
        const char *sets[] = {"defaults.modes=1", "solver.constraints=\"penalty\""};
        check_energy_derivatives("waterbomb2", 2, sets, 1.2, 0.3, "waterbomb2 K=1 penalty");
    }
    {
        const char *sets[] = {"defaults.modes=2", "defaults.continuity=2",
                              "solver.constraints=\"penalty\""};
        check_energy_derivatives("square4-irregular", 3, sets, 1.0, 0.3,
                                 "square4-irregular K=2 G2 penalty");
    }
    {
        /* strip3 with gravity switched on and a second, oblique load */
        const char *sets[] = {"defaults.modes=2", "gravity.g=[1.0, -2.0, -9.81]",
                              "loads=( { at = [0.116, 0.015]; force = [0.0, 0.0, -0.2]; },"
                              " { at = [0.07, 0.02]; force = [0.1, 0.3, -0.05]; stage = 2; } )"};
        check_energy_derivatives("strip3", 3, sets, 2.5, 0.5, "strip3 K=2 gravity two loads");
    }
}

/* ------------------------------------------------------------------------
 * Energy: d(grad)/dp through sf_equil_set_param
 * ------------------------------------------------------------------------ */

static void grad_at(sf_equil *eq, const double *q, double p, double *grad, double *gp)
{
    sf_equil_set_param(eq, p);
    sf_kin_eval(eq->m, q, 1, &eq->k);
    memset(grad, 0, sizeof(double) * eq->nq);
    if (gp) memset(gp, 0, sizeof(double) * eq->nq);
    sf_energy_eval(&eq->e, &eq->k, &eq->par, grad, NULL, 0, gp);
}

static void check_param_derivative(const char *study, int nset, const char **sets, int param,
                                   const char *group, double load, double p, const char *label)
{
    sf_scene sc;
    open_scene(&sc, study, nset, sets);
    const sf_model *m = &sc.model;
    sf_error err;
    sf_error_clear(&err);
    int gi = group ? sf_study_group_index(&sc.study, group) : -1;
    if (group) assert_true(gi >= 0);
    sf_equil eq;
    if (sf_equil_init(&eq, m, param, gi, 0, 2, load, &err)) {
        print_error("%s: equil init: %s\n", label, err.msg);
        fail();
    }
    int nq = m->nq;
    double *q = calloc(nq, sizeof *q), *g0 = calloc(nq, sizeof *q), *gp = calloc(nq, sizeof *q);
    double *g1 = calloc(nq, sizeof *q), *g2 = calloc(nq, sizeof *q), *fd = calloc(nq, sizeof *q);
    random_state(m, q, 1.2, 0.3);
    grad_at(&eq, q, p, g0, gp);
    /* the gradient is linear in p inside a load stage and in the actuation
     * factor: a large step costs no truncation error and keeps roundoff of
     * the O(kref) gradient small */
    double h = 1e-3;
    grad_at(&eq, q, p + h, g1, NULL);
    grad_at(&eq, q, p - h, g2, NULL);
    for (int j = 0; j < nq; j++) fd[j] = (g1[j] - g2[j]) / (2 * h);
    char what[160];
    snprintf(what, sizeof what, "%s: d grad / dp at p = %g", label, p);
    compare(gp, fd, nq, what);
    sf_equil_free(&eq);
    free(q); free(g0); free(gp); free(g1); free(g2); free(fd);
    sf_scene_close(&sc);
}

/* An actuation group on strip3 made with --set: fold f2 (and f3 in the
 * second group) driven towards a rest angle. */
static const char *act_strip3[] = {
    "actuation=( { name = \"hinge\"; rest_angle = 0.8; }, { name = \"tipfold\"; rest_angle = -1.1; } )",
    "folds[f2].group=\"hinge\"", "folds[f3].group=\"tipfold\"", "folds[f1].rest_angle=0.3",
    "defaults.modes=2"};
/* ... and on waterbomb2 (exact loop constraints, gravity and the load) */
static const char *act_wb2[] = {
    "actuation=( { name = \"diag\"; rest_angle = 0.6; } )", "folds[0].group=\"diag\"",
    "folds[11].group=\"diag\"", "folds[5].group=\"diag\"", "defaults.modes=1",
    "solver.constraints=\"exact\""};
/* waterbomb2 defaults to the paper's penalty: these ask for exact closure */
static const char *wb2_exact[] = {"solver.constraints=\"exact\""};
static const char *wb2_k2g2[] = {"defaults.modes=2", "defaults.continuity=2",
                                 "solver.constraints=\"exact\""};

static void test_param_derivative(void **state)
{
    (void)state;
    /* load: gravity ramping (stage 1), the point load ramping (stage 2),
     * the linear extensions below 0 and above the last stage */
    const double ps[] = {0.37, 1.61, -0.2, 2.3};
    for (size_t i = 0; i < sizeof ps / sizeof *ps; i++)
        check_param_derivative("waterbomb2", 1, wb2_exact, SF_PARAM_LOAD, NULL, 0.0, ps[i],
                               "waterbomb2 load");
    check_param_derivative("waterbomb2", 3, wb2_k2g2, SF_PARAM_LOAD, NULL, 0.0, 0.81,
                           "waterbomb2 K=2 G2 load");
    /* actuation: one group, all groups, under a fixed load */
    check_param_derivative("strip3", 5, act_strip3, SF_PARAM_ACTUATION, "hinge", 0.5, 0.7,
                           "strip3 actuation of hinge");
    check_param_derivative("strip3", 5, act_strip3, SF_PARAM_ACTUATION, NULL, 0.5, -0.4,
                           "strip3 actuation of all groups");
    check_param_derivative("waterbomb2", 6, act_wb2, SF_PARAM_ACTUATION, "diag", 1.5, 0.9,
                           "waterbomb2 actuation");
}

/* ------------------------------------------------------------------------
 * Equilibrium residual and Jacobian
 * ------------------------------------------------------------------------ */

typedef struct jac_case {
    const char *label, *study;
    int nset;
    const char **sets;
    int param;
    const char *group;   /* actuation group or NULL (all) */
    int probe, comp;     /* displacement parameter */
    double load, p;
    int penalty_switch;  /* sf_equil_use_penalty(100, 1) after init */
} jac_case;

static SUNContext sun_ctx;

static void residual_at(sf_equil *eq, const double *y, double p, double *F)
{
    assert_int_equal(sf_equil_residual(y, p, F, eq), 0);
}

static void check_jacobian(const jac_case *c)
{
    sf_scene sc;
    open_scene(&sc, c->study, c->nset, c->sets);
    const sf_model *m = &sc.model;
    sf_error err;
    sf_error_clear(&err);
    int gi = c->group ? sf_study_group_index(&sc.study, c->group) : -1;
    if (c->group) assert_true(gi >= 0);
    sf_equil eq;
    if (sf_equil_init(&eq, m, c->param, gi, c->probe, c->comp, c->load, &err)) {
        print_error("%s: equil init: %s\n", c->label, err.msg);
        fail();
    }
    if (c->penalty_switch) sf_equil_use_penalty(&eq, 100.0, 1.0);
    int n = eq.n, nq = eq.nq;
    assert_true(n >= nq);
    if (c->param == SF_PARAM_DISPLACEMENT) assert_true(eq.disp_row >= 0);
    double *y = calloc(n, sizeof *y), *yy = calloc(n, sizeof *y);
    double *F = calloc(n, sizeof *y), *F1 = calloc(n, sizeof *y), *F2 = calloc(n, sizeof *y);
    double *Fp = calloc(n, sizeof *y), *Fpfd = calloc(n, sizeof *y);
    double *A = calloc((size_t)n * n, sizeof *A), *Afd = calloc((size_t)n * n, sizeof *A);
    random_state(m, y, 1.0, 0.3);
    /* multipliers of their natural size (1 / yscale: kref or kref / lref) */
    for (int r = nq; r < n; r++) y[r] = urand(-1.0, 1.0) / eq.yscale[r];
    SUNMatrix Jy = SUNDenseMatrix(n, n, sun_ctx);
    assert_non_null(Jy);
    residual_at(&eq, y, c->p, F);
    assert_int_equal(sf_equil_jacobian(y, c->p, Jy, Fp, &eq), 0);
    const sunrealtype *D = SUNDenseMatrix_Data(Jy);
    long ld = SUNDenseMatrix_LData(Jy) / SUNDenseMatrix_Columns(Jy);
    assert_int_equal(ld, n);
    /* The residual does not depend on a previous Jacobian call (scratch
     * reuse) */
    residual_at(&eq, y, c->p, F1);
    for (int i = 0; i < n; i++) CHECK_CLOSE(F1[i], F[i], 0.0, "%s: residual repeatable %d", c->label, i);
    /* central differences column by column, steps of 1e-5 in the Newton
     * scaling (1e-5 rad for angles, 1e-5 kref for multipliers): truncation
     * ~1e-10, roundoff ~1e-11 of the scaled residual (penalty terms of
     * 100 J make it O(10)) */
    for (int j = 0; j < n; j++) {
        double h = 1e-5 / eq.yscale[j];
        memcpy(yy, y, sizeof(double) * n);
        yy[j] += h;
        residual_at(&eq, yy, c->p, F1);
        yy[j] -= 2 * h;
        residual_at(&eq, yy, c->p, F2);
        for (int i = 0; i < n; i++) Afd[(size_t)j * n + i] = (F1[i] - F2[i]) / (2 * h);
    }
    double hp = 1e-2; /* F is linear in p (inside a load stage): no truncation error */
    residual_at(&eq, y, c->p + hp, F1);
    residual_at(&eq, y, c->p - hp, F2);
    for (int i = 0; i < n; i++) Fpfd[i] = (F1[i] - F2[i]) / (2 * hp);
    /* compare in the Newton scaling (rows fscale, columns 1/yscale) so that
     * rows of different units are judged alike; the multiplier-multiplier
     * block is left out (it carries only the -eps D regularisation) and
     * checked separately */
    size_t cnt = 0;
    double *a = calloc((size_t)n * n, sizeof *a), *b = calloc((size_t)n * n, sizeof *b);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            if (i >= nq && j >= nq) continue;
            double s = eq.fscale[i] / eq.yscale[j];
            a[cnt] = s * D[(size_t)j * ld + i];
            b[cnt] = s * Afd[(size_t)j * n + i];
            cnt++;
        }
    char what[200];
    snprintf(what, sizeof what, "%s: dF/dy (column-major, multiplier block left out)", c->label);
    compare(a, b, cnt, what);
    /* symmetric, as the Hessian of the Lagrangian with its bordering */
    for (int j = 0; j < n; j++)
        for (int i = 0; i < j; i++)
            CHECK_CLOSE(D[(size_t)j * ld + i], D[(size_t)i * ld + j],
                        1e-12 * fmax(fabs(D[(size_t)j * ld + i]), 1e-300) + 1e-13 * maxabs(D, (size_t)n * n),
                        "%s: Jacobian symmetry (%d, %d)", c->label, i, j);
    /* multiplier block: zero but on the diagonal, which is negative and
     * small (a regularisation, never seen by the residual) */
    for (int j = nq; j < n; j++)
        for (int i = nq; i < n; i++) {
            double v = D[(size_t)j * ld + i];
            if (i != j) CHECK_CLOSE(v, 0.0, 0.0, "%s: multiplier block (%d, %d)", c->label, i, j);
            else {
                assert_true(v < 0.0);
                CHECK_CLOSE(Afd[(size_t)j * n + i], 0.0, 1e-9 / (eq.yscale[j] * eq.fscale[i]),
                            "%s: residual independent of its own multiplier %d", c->label, i);
            }
        }
    for (int i = 0; i < n; i++) {
        Fp[i] *= eq.fscale[i];
        Fpfd[i] *= eq.fscale[i];
    }
    snprintf(what, sizeof what, "%s: dF/dp at p = %g", c->label, c->p);
    compare(Fp, Fpfd, n, what);
    if (c->param == SF_PARAM_DISPLACEMENT)
        CHECK_CLOSE(Fp[nq + eq.nloop + eq.disp_row] / eq.fscale[nq + eq.nloop + eq.disp_row],
                    -1.0, 0.0, "%s: dF/dp of the displacement row", c->label);
    SUNMatDestroy(Jy);
    sf_equil_free(&eq);
    free(y); free(yy); free(F); free(F1); free(F2); free(Fp); free(Fpfd); free(A); free(Afd);
    free(a); free(b);
    sf_scene_close(&sc);
}

static const char *wb2_k1g2[] = {"defaults.modes=1", "defaults.continuity=2",
                                 "solver.constraints=\"exact\""};
static const char *wb2_disp[] = {"defaults.modes=1", "solver.constraints=\"exact\"",
                                 "analysis.parameter=\"displacement\"",
                                 "analysis.probe=\"tip\"", "analysis.component=\"x\"",
                                 "supports=( { at = [0.157, 0.0675]; fix = [false, true, false]; "
                                 "value = [0.0, 0.002, 0.0]; } )"};
static const char *s3_disp[] = {"defaults.modes=3", "analysis.parameter=\"displacement\"",
                                "analysis.probe=\"tip\"", "analysis.component=\"z\""};
static const char *wb2_pen[] = {"solver.constraints=\"penalty\""};

static void test_equilibrium_jacobian(void **state)
{
    (void)state;
    const jac_case cases[] = {
        {"waterbomb2 exact, load in stage 2", "waterbomb2", 1, wb2_exact, SF_PARAM_LOAD, NULL, 0,
         0, 0.0, 1.4, 0},
        {"waterbomb2 exact K=1 G2, gravity stage", "waterbomb2", 3, wb2_k1g2, SF_PARAM_LOAD,
         NULL, 0, 0, 0.0, 0.6, 0},
        {"waterbomb2 penalty (study)", "waterbomb2", 1, wb2_pen, SF_PARAM_LOAD, NULL, 0, 0, 0.0,
         1.7, 0},
        {"waterbomb2 penalty (switched)", "waterbomb2", 3, wb2_k1g2, SF_PARAM_LOAD, NULL, 0, 0,
         0.0, 0.3, 1},
        {"strip3 actuation of hinge", "strip3", 5, act_strip3, SF_PARAM_ACTUATION, "hinge", 0, 0,
         0.6, 0.7, 0},
        {"strip3 actuation of all groups", "strip3", 5, act_strip3, SF_PARAM_ACTUATION, NULL, 0,
         0, 0.0, 1.3, 0},
        {"waterbomb2 exact actuation", "waterbomb2", 6, act_wb2, SF_PARAM_ACTUATION, "diag", 0, 0,
         1.2, 0.8, 0},
        {"strip3 displacement uz of tip", "strip3", 4, s3_disp, SF_PARAM_DISPLACEMENT, NULL, 0, 2,
         0.0, -0.01, 0},
        {"waterbomb2 exact displacement ux of tip + support", "waterbomb2", 6, wb2_disp,
         SF_PARAM_DISPLACEMENT, NULL, 0, 0, 1.0, -0.003, 0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) check_jacobian(&cases[i]);
}

/* The displacement parameter as the study selects it (analysis.parameter,
 * analysis.probe, analysis.component read through the study accessors as
 * src/cli/run_equilibrium.c does): the prescribed row is the probe's component minus p. */
static void test_displacement_row(void **state)
{
    (void)state;
    sf_scene sc;
    open_scene(&sc, "waterbomb2", 6, wb2_disp);
    const sf_study *s = &sc.study;
    sf_error err;
    sf_error_clear(&err);
    const char *param, *probe, *comp;
    assert_int_equal(sf_study_string(s, "analysis.parameter", "load", &param, &err), SF_OK);
    assert_int_equal(sf_study_string(s, "analysis.probe", "", &probe, &err), SF_OK);
    assert_int_equal(sf_study_string(s, "analysis.component", "z", &comp, &err), SF_OK);
    assert_string_equal(param, "displacement");
    int pi = sf_study_probe_index(s, probe);
    assert_int_equal(pi, 0);
    int ci = comp[0] - 'x';
    assert_int_equal(ci, 0);
    sf_equil eq;
    assert_int_equal(sf_equil_init(&eq, &sc.model, SF_PARAM_DISPLACEMENT, -1, pi, ci, 1.0, &err),
                     SF_OK);
    /* one support row (uy) and the displacement row (ux) */
    assert_int_equal(eq.nsup, 2);
    assert_int_equal(eq.nloop, 12);
    double *y = calloc(eq.n, sizeof *y), *F = calloc(eq.n, sizeof *y);
    random_state(&sc.model, y, 0.8, 0.2);
    double p = -0.0042;
    assert_int_equal(sf_equil_residual(y, p, F, &eq), 0);
    sf_mpoint pt;
    assert_int_equal(sf_model_locate(&sc.model, s->probes[pi].at, &pt, &err), SF_OK);
    sf_kin k;
    assert_int_equal(sf_kin_alloc(&sc.model, &k), SF_OK);
    sf_kin_eval(&sc.model, y, 0, &k);
    double x[3];
    sf_point_eval(&sc.model, &k, &pt, x, NULL);
    CHECK_CLOSE(F[eq.nq + eq.nloop + eq.disp_row], (x[0] - pt.X[0]) - p, 1e-15,
                "displacement row = u_x(tip) - p");
    /* the support row: u_y(0.157, 0.0675) - 0.002 */
    sf_mpoint sp;
    double at[2] = {0.157, 0.0675};
    assert_int_equal(sf_model_locate(&sc.model, at, &sp, &err), SF_OK);
    sf_point_eval(&sc.model, &k, &sp, x, NULL);
    int srow = eq.disp_row == 0 ? 1 : 0;
    CHECK_CLOSE(F[eq.nq + eq.nloop + srow], (x[1] - sp.X[1]) - 0.002, 1e-15,
                "support row = u_y - value");
    sf_kin_free(&k);
    free(y);
    free(F);
    sf_equil_free(&eq);
    sf_scene_close(&sc);
}

/* The regularisation of the multiplier block is meant to keep the Newton
 * matrix regular at redundant loop rows (equilibrium.h: "-eps D, eps =
 * 1e-10, D the row scales").  To do that the same way for every row and in
 * any units, it must be eps in the scaling the Newton solver works in
 * (unknowns times yscale, rows times fscale): fscale_r A_rr / yscale_r =
 * -eps.  src/analysis/equilibrium/equilibrium.c sets A_rr = -eps / (yscale_r fscale_r), which
 * in that scaling is -eps kref^2 (rotation rows) and -eps kref^2 / lref^2
 * (translation rows): dimensionally inverted, so it depends on the units
 * and the stiffness of the study (waterbomb2: 1.7e-13 .. 2.5e-9; with a
 * 1000 times stiffer fold material 1.7e-7 .. 2.5e-3, a visible error in
 * the Newton matrix).  Seen on whole paths: square4 with E x 1e4 and the
 * loads x 1e4 (the same equilibria, multipliers x 1e4) no longer starts
 * (Newton stalls in the start solve), and starts and runs with
 * A_rr = -eps yscale_r / fscale_r. */
static void test_regularisation_scale(void **state)
{
    (void)state;
    /* the same sheet with a 1000 times stiffer fold material must get the
     * same regularisation in Newton scaling: it is a matter of units */
    const char *stiff[] = {"solver.constraints=\"exact\"", "materials.fold.E=15.2e9"};
    const struct { const char *study, *label; int nset; const char **sets; } cases[] = {
        {"waterbomb2", "waterbomb2", 1, wb2_exact},
        {"waterbomb2", "waterbomb2 E x 1000", 2, stiff},
        {"square4", "square4", 1, wb2_exact},
    };
    int bad = 0;
    for (size_t s = 0; s < sizeof cases / sizeof *cases; s++) {
        sf_scene sc;
        open_scene(&sc, cases[s].study, cases[s].nset, cases[s].sets);
        sf_error err;
        sf_error_clear(&err);
        sf_equil eq;
        assert_int_equal(sf_equil_init(&eq, &sc.model, SF_PARAM_LOAD, -1, 0, 2, 0.0, &err), SF_OK);
        assert_true(eq.nloop > 0);
        int n = eq.n, nq = eq.nq;
        double *y = calloc(n, sizeof *y), *Fp = calloc(n, sizeof *y);
        random_state(&sc.model, y, 0.5, 0.1);
        SUNMatrix Jy = SUNDenseMatrix(n, n, sun_ctx);
        assert_int_equal(sf_equil_jacobian(y, 0.5, Jy, Fp, &eq), 0);
        const sunrealtype *D = SUNDenseMatrix_Data(Jy);
        double lo = INFINITY, hi = -INFINITY;
        for (int r = nq; r < n; r++) {
            double scaled = eq.fscale[r] * D[(size_t)r * n + r] / eq.yscale[r];
            lo = fmin(lo, scaled);
            hi = fmax(hi, scaled);
        }
        print_message("# %s: kref %.4g J, lref %.4g m: regularisation in Newton scaling from "
                      "%.3g to %.3g (expected -1e-10 on every row)\n",
                      cases[s].label, eq.kref, eq.lref, lo, hi);
        if (!(fabs(lo + 1e-10) <= 1e-12 && fabs(hi + 1e-10) <= 1e-12)) {
            print_error("%s: multiplier-block regularisation in Newton scaling is %.3g .. %.3g, "
                        "expected -1e-10 (kref %.3g J, lref %.3g m)\n",
                        cases[s].label, lo, hi, eq.kref, eq.lref);
            bad++;
        }
        SUNMatDestroy(Jy);
        free(y);
        free(Fp);
        sf_equil_free(&eq);
        sf_scene_close(&sc);
    }
    assert_int_equal(bad, 0);
}

/* ------------------------------------------------------------------------
 * Closed forms on strip3 (CASES.md material: E = 15.2e6 Pa, nu = 0.45,
 * h = 1.8e-3 m; folds of length L = 0.03 m and width w = 0.01 m)
 * ------------------------------------------------------------------------ */

static const double S3_E = 15.2e6, S3_NU = 0.45, S3_H = 1.8e-3, S3_L = 0.03, S3_W = 0.01;

static double plate_D(void) { return S3_E * S3_H * S3_H * S3_H / (12.0 * (1.0 - S3_NU * S3_NU)); }

/* bending energy: G1 circular arc U = 1/2 (D L / w) theta^2, with K modes
 * (shifted Legendre, orthogonal with int_0^1 P_k^2 = 1/(2k+1)) U = 1/2 (D L
 * / w) (theta^2 + sum a_k^2 / (2k+1)); G2 parabola U = 0.6 D L theta^2 / w;
 * a rest angle shifts theta. */
static void test_bending_closed_form(void **state)
{
    (void)state;
    const double D = plate_D(), k = D * S3_L / S3_W;
    const double th[3] = {0.7, -1.2, 2.1}, rest[3] = {0.0, 0.25, -0.4};
    for (int cont = 1; cont <= 2; cont++) {
        char set[64];
        snprintf(set, sizeof set, "defaults.continuity=%d", cont);
        const char *sets[] = {"defaults.modes=0", set};
        sf_scene sc;
        open_scene(&sc, "strip3", 2, sets);
        const sf_model *m = &sc.model;
        sf_error err;
        sf_error_clear(&err);
        sf_energy e;
        assert_int_equal(sf_energy_init(&e, m, &err), SF_OK);
        sf_params par;
        assert_int_equal(sf_params_alloc(&e, &par), SF_OK);
        assert_int_equal(m->nq, 3);
        double q[3];
        for (int i = 0; i < 3; i++) q[m->qoff[i]] = th[i];
        double c = cont == 1 ? 0.5 : 0.6, U0 = 0.0, U1 = 0.0;
        for (int i = 0; i < 3; i++) {
            U0 += c * k * th[i] * th[i];
            U1 += c * k * (th[i] - rest[i]) * (th[i] - rest[i]);
        }
        for (int i = 0; i < 3; i++) CHECK_CLOSE(e.stiff[i], k, 1e-14 * k, "G%d: D L / w of fold %d", cont, i + 1);
        CHECK_CLOSE(sf_energy_bending(&e, q, &par), U0, 1e-13 * U0, "G%d bending energy", cont);
        sf_kin k2;
        assert_int_equal(sf_kin_alloc(m, &k2), SF_OK);
        sf_kin_eval(m, q, 0, &k2);
        /* no load at stage factor 0: Pi is the bending energy */
        CHECK_CLOSE(sf_energy_eval(&e, &k2, &par, NULL, NULL, 0, NULL), U0, 1e-13 * U0,
                    "G%d Pi at zero load", cont);
        for (int i = 0; i < 3; i++) par.rest[i] = rest[i];
        CHECK_CLOSE(sf_energy_bending(&e, q, &par), U1, 1e-13 * U1, "G%d bending with rest angles",
                    cont);
        sf_kin_free(&k2);
        sf_params_free(&par);
        sf_energy_free(&e);
        sf_scene_close(&sc);
    }
    /* G1 with K = 3 modes */
    {
        const char *sets[] = {"defaults.modes=3"};
        sf_scene sc;
        open_scene(&sc, "strip3", 1, sets);
        const sf_model *m = &sc.model;
        sf_error err;
        sf_error_clear(&err);
        sf_energy e;
        assert_int_equal(sf_energy_init(&e, m, &err), SF_OK);
        sf_params par;
        assert_int_equal(sf_params_alloc(&e, &par), SF_OK);
        double q[12], U = 0.0;
        for (int i = 0; i < 3; i++) {
            par.rest[i] = rest[i];
            q[m->qoff[i]] = th[i];
            U += 0.5 * k * (th[i] - rest[i]) * (th[i] - rest[i]);
            for (int j = 1; j <= 3; j++) {
                double a = 0.1 * (i + 1) - 0.07 * j;
                q[m->qoff[i] + j] = a;
                U += 0.5 * k * a * a / (2 * j + 1);
            }
        }
        CHECK_CLOSE(sf_energy_bending(&e, q, &par), U, 1e-13 * U, "G1 K=3 bending energy");
        sf_params_free(&par);
        sf_energy_free(&e);
        sf_scene_close(&sc);
    }
}

/* Rotation about the y axis (the direction m of strip3's folds). */
static void rot_y(double a, const double v[3], double out[3])
{
    out[0] = cos(a) * v[0] + sin(a) * v[2];
    out[1] = v[1];
    out[2] = -sin(a) * v[0] + cos(a) * v[2];
}

/* strip3 with only its last fold f3 folded by t (K = 0, G1).  Fold f3 runs
 * from (0.09, 0) to (0.09, 0.03): m = e_y, left normal n = -e_x; its right
 * face (u = -w/2 side, x > 0.095) is the tip face, its left face the
 * middle face (x < 0.085), which stays where it is.  With T_3(x) = p_R +
 * c_n n + c_3 e3 + Rot(m, t)(x - p_L) (MODEL.md 3), a tip point X goes to
 *   x = T_3^-1(X) = p_L + Rot(m, -t)(X - p_R - c_n n - c_3 e3),
 * c = w (sin t / t, (1 - cos t) / t), p_R = (0.095, y, 0), p_L = (0.085, y, 0).
 * A band point at arclength s maps from its right face: local position
 * p_R + r_n(s) n + r_3(s) e3 with r = R (sin(s/R), 1 - cos(s/R)), R = w / t,
 * whose mean over the band is C = w ((1 - cos t) / t^2, (t - sin t) / t^2). */
static void tip_map(double t, const double X[3], double x[3])
{
    const double w = S3_W;
    double cn = w * sin(t) / t, c3 = w * (1.0 - cos(t)) / t;
    double v[3] = {X[0] - 0.095 + cn, 0.0, X[2] - c3}; /* X - p_R - cn n - c3 e3, n = -e_x */
    double r[3];
    rot_y(-t, v, r);
    x[0] = 0.085 + r[0];
    x[1] = X[1] + r[1];
    x[2] = r[2];
}

static void test_load_closed_form(void **state)
{
    (void)state;
    const double D = plate_D(), k = D * S3_L / S3_W, w = S3_W, g = 9.81;
    /* faces: rigid, 1040 kg/m^3, 2.0e-3 m; tip face x in [0.095, 0.12] */
    const double m_face = 1040.0 * 2.0e-3 * 0.025 * 0.03;
    const double m_band = 1200.0 * 1.8e-3 * w * S3_L;
    const char *sets[] = {"defaults.modes=0", "gravity.g=[0.0, 0.0, -9.81]"};
    sf_scene sc;
    open_scene(&sc, "strip3", 2, sets);
    const sf_model *m = &sc.model;
    sf_error err;
    sf_error_clear(&err);
    sf_energy e;
    assert_int_equal(sf_energy_init(&e, m, &err), SF_OK);
    assert_true(e.gravity);
    sf_params par;
    assert_int_equal(sf_params_alloc(&e, &par), SF_OK);
    sf_kin kin;
    assert_int_equal(sf_kin_alloc(m, &kin), SF_OK);
    /* |t| < 1 uses the library's series, |t| > 1 its closed forms */
    const double ts[] = {0.3, -0.8, 1.7, -2.2, 3.0};
    for (size_t it = 0; it < sizeof ts / sizeof *ts; it++) {
        double t = ts[it];
        double q[3] = {0.0, 0.0, 0.0};
        q[m->qoff[2]] = t;
        sf_kin_eval(m, q, 0, &kin);
        /* point load -0.2 e3 at (0.116, 0.015): Pi_load = -f . u = 0.2 u_z */
        double X[3] = {0.116, 0.015, 0.0}, x[3];
        tip_map(t, X, x);
        double Pload = 0.2 * x[2];
        /* also the probe position itself */
        {
            sf_mpoint pr;
            double at[2] = {0.12, 0.015}, xp[3], xl[3], Xp[3] = {0.12, 0.015, 0.0};
            assert_int_equal(sf_model_locate(m, at, &pr, &err), SF_OK);
            sf_point_eval(m, &kin, &pr, xl, NULL);
            tip_map(t, Xp, xp);
            for (int c = 0; c < 3; c++)
                CHECK_CLOSE(xl[c], xp[c], 1e-15, "t = %g: tip probe coordinate %d", t, c);
        }
        /* gravity: the tip face at its centroid (0.1075, 0.015) and the
         * band of f3 at its mean point; the other faces and bands stay
         * flat: Pi_grav = sum m g u_z */
        double Xc[3] = {0.1075, 0.015, 0.0}, xc[3];
        tip_map(t, Xc, xc);
        double Cn = w * (1.0 - cos(t)) / (t * t), C3 = w * (t - sin(t)) / (t * t);
        double Xb[3] = {0.095 - Cn, 0.015, C3}, xb[3]; /* p_R + C_n n + C_3 e3 */
        tip_map(t, Xb, xb);
        double Pgrav = g * (m_face * xc[2] + m_band * xb[2]);
        double U = 0.5 * k * t * t;
        /* the load and gravity are both stage 1: full, then half */
        par.stage[0] = 1.0;
        double Pi = sf_energy_eval(&e, &kin, &par, NULL, NULL, 0, NULL);
        double want = U + Pload + Pgrav;
        CHECK_CLOSE(Pi, want, 1e-13 * (fabs(U) + fabs(Pload) + fabs(Pgrav)),
                    "t = %g: Pi = U + 0.2 u_z(load) + g (m_face z_face + m_band z_band)", t);
        par.stage[0] = 0.5;
        Pi = sf_energy_eval(&e, &kin, &par, NULL, NULL, 0, NULL);
        want = U + 0.5 * (Pload + Pgrav);
        CHECK_CLOSE(Pi, want, 1e-13 * (fabs(U) + fabs(Pload) + fabs(Pgrav)),
                    "t = %g: Pi at stage factor 0.5", t);
        print_message("# strip3 f3 at t = %g: U %.6g J, load %.6g J, gravity %.6g J\n", t, U,
                      Pload, Pgrav);
    }
    sf_kin_free(&kin);
    sf_params_free(&par);
    sf_energy_free(&e);
    sf_scene_close(&sc);
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : SF_SRCDIR);
    if (SUNContext_Create(NULL, &sun_ctx) != 0) return 1;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bending_closed_form),
        cmocka_unit_test(test_load_closed_form),
        cmocka_unit_test(test_energy_derivatives),
        cmocka_unit_test(test_param_derivative),
        cmocka_unit_test(test_equilibrium_jacobian),
        cmocka_unit_test(test_displacement_row),
        cmocka_unit_test(test_regularisation_scale),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    SUNContext_Free(&sun_ctx);
    return rc;
}
