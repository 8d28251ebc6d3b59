/* test_cont.c - unit tests of the continuation engine (continuation/cont.h)
 * on textbook problems with known answers:
 *   fold       x^2 + p = 0: limit point at p = 0
 *   pitchfork  (x (p - x^2), y - x^2) = 0: branch point at p = 0, branches
 *              x = +-sqrt(p), y = p
 *   Bratu      u'' + lambda e^u = 0 on (0,1), u(0) = u(1) = 0, central
 *              differences: limit point lambda* -> 3.51383071912516 as N
 *              grows; the discrete lambda*_N is checked against an
 *              independent shooting computation (see bratu_shoot_lstar)
 *   failure    a residual that turns NaN (or returns an error) beyond p = 0.7
 *   stop rules p window (EP exactly on p_max), max steps, max arclength
 * A failing check prints what it expected, what it got and the tolerance.
 * The determinant and sparse-pattern tests are in test_cont_det.c.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <kinsol/kinsol.h>

#include "cont.h"
#include "cont_test.h"

/* ------------------------------------------------------------------ */
/* fold: x^2 + p = 0, user test x - 0.5                                */

static int fold_res(const double *y, double p, double *F, void *u)
{
    (void)u;
    F[0] = y[0] * y[0] + p;
    return 0;
}

static int fold_jac(const double *y, double p, SUNMatrix J, double *Fp, void *u)
{
    (void)p; (void)u;
    SM_ELEMENT_D(J, 0, 0) = 2.0 * y[0];
    Fp[0] = 1.0;
    return 0;
}

static int fold_test(const double *y, double p, const double *ty, double tp, double *out,
                     void *u)
{
    (void)p; (void)ty; (void)tp; (void)u;
    out[0] = y[0] - 0.5;
    return 0;
}

/* the same checks with every linear solver (a dense Jy is stored whole in
 * the sparse bordered matrix) */
static void fold_case(int linsol)
{
    static const char *const labels[] = {"X05"};
    cont_problem prob = {.n = 1, .residual = fold_res, .jacobian = fold_jac,
                         .jac_matrix = CONT_MATRIX_DENSE, .ntest = 1, .test = fold_test,
                         .test_labels = labels};
    cont_solver *s = make(&prob, linsol);
    CHECK_TRUE(linsol == CONT_LINSOL_AUTO || cont_get_linsol(s) == linsol,
               "linear solver %d, asked for %d", cont_get_linsol(s), linsol);
    CHECK_OK(cont_set_step(s, 0.05, 1e-8, 0.2), s);
    CHECK_OK(cont_set_prange(s, -1.0, 1.0), s);
    double y0 = 1.0;
    CHECK_OK(cont_start(s, &y0, -1.0, +1), s);
    const cont_point *p0 = cont_get_point(s);
    /* initial tangent: 2x tx + tp = 0 with tp > 0: (-1/2, 1)/|.| at x = 1 */
    CHECK_CLOSE(p0->tp, 1.0 / sqrt(1.25), 1e-12);
    CHECK_CLOSE(p0->ty[0], -0.5 / sqrt(1.25), 1e-12);
    int st = cont_run(s);
    CHECK_TRUE(st == CONT_DONE, "status %d, message: %s", st, cont_errmsg(s));
    CHECK_TRUE(count_label(s, "LP") == 1, "expected 1 LP, got %d", count_label(s, "LP"));
    CHECK_TRUE(count_label(s, "BP") == 0, "expected no BP, got %d", count_label(s, "BP"));
    const cont_point *lp = find_label(s, "LP");
    if (!lp) fail();
    CHECK_CLOSE(lp->p, 0.0, 1e-8);
    CHECK_CLOSE(lp->y[0], 0.0, 1e-6);
    CHECK_CLOSE(lp->tp, 0.0, 1e-6);
    CHECK_TRUE(lp->type == CONT_PT_LP, "type %d", lp->type);
    /* the user test function x = 0.5 at p = -0.25 */
    const cont_point *ux = find_label(s, "X05");
    CHECK_TRUE(ux != NULL, "user test point X05 not reported");
    if (ux) {
        CHECK_CLOSE(ux->y[0], 0.5, 1e-8);
        CHECK_CLOSE(ux->p, -0.25, 1e-8);
        CHECK_TRUE(ux->type == CONT_PT_USER && ux->user_index == 0, "type %d index %d",
                   ux->type, ux->user_index);
    }
    /* after the LP: x < 0 and p decreasing, down to the EP at p = -1 */
    long i_lp = -1, np = cont_num_points(s);
    for (long i = 0; i < np; i++)
        if (strcmp(cont_point_at(s, i)->label, "LP") == 0) i_lp = i;
    CHECK_TRUE(i_lp > 0 && i_lp < np - 2, "LP at index %ld of %ld points", i_lp, np);
    for (long i = i_lp + 1; i < np; i++) {
        const cont_point *a = cont_point_at(s, i), *b = cont_point_at(s, i - 1);
        CHECK_TRUE(a->y[0] < 0, "point %ld after the LP has x = %g >= 0", i, a->y[0]);
        CHECK_TRUE(a->p < b->p, "p not decreasing after the LP: %g then %g", b->p, a->p);
        CHECK_TRUE(a->tp < 0, "tangent p-component %g >= 0 after the LP", a->tp);
        CHECK_CLOSE(a->y[0] * a->y[0] + a->p, 0.0, 1e-9);
        CHECK_TRUE(a->s > b->s, "arclength not increasing");
    }
    const cont_point *ep = cont_get_point(s);
    CHECK_TRUE(strcmp(ep->label, "EP") == 0, "last label '%s'", ep->label);
    CHECK_TRUE(ep->p == -1.0, "EP p = %.17g, expected exactly -1", ep->p);
    CHECK_CLOSE(ep->y[0], -1.0, 1e-9);
    CHECK_TRUE(cont_stop_reason(s) == CONT_STOP_PMIN, "stop reason %s",
               cont_stop_name(cont_stop_reason(s)));
    /* the arclength of the parabola p = -x^2 from x = 1 to x = -1 */
    double arc = sqrt(5.0) + 0.5 * asinh(2.0);
    CHECK_CLOSE(ep->s, arc, 2e-2 * arc);   /* pseudo-arclength <= true arclength */
    cont_free(s);
}

static void test_fold_limit_point(void **state)
{
    (void)state;
    fold_case(CONT_LINSOL_AUTO);
}

static void test_fold_klu_mumps(void **state)
{
    (void)state;
    fold_case(CONT_LINSOL_KLU);
    fold_case(CONT_LINSOL_MUMPS);
}

/* ------------------------------------------------------------------ */
/* pitchfork: F = (x (p - x^2), y - x^2)                                */

static void pf_dense(const double *v, double p, double *a, double *Fp)
{
    double x = v[0];
    a[0] = p - 3 * x * x; a[1] = -2 * x;   /* column 0 */
    a[2] = 0.0; a[3] = 1.0;                /* column 1 */
    Fp[0] = x;
    Fp[1] = 0.0;
}

static int pf_res(const double *v, double p, double *F, void *u)
{
    (void)u;
    F[0] = v[0] * (p - v[0] * v[0]);
    F[1] = v[1] - v[0] * v[0];
    return 0;
}

static int pf_jac(const double *v, double p, SUNMatrix J, double *Fp, void *u)
{
    (void)u;
    double a[4];
    pf_dense(v, p, a, Fp);
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) SM_ELEMENT_D(J, i, j) = a[j * 2 + i];
    return 0;
}

static int pf_jac_sparse(const double *v, double p, SUNMatrix J, double *Fp, void *u)
{
    (void)u;
    double a[4];
    pf_dense(v, p, a, Fp);
    dense_to_csc(J, 2, a);
    return 0;
}

static void pitchfork_case(int linsol)
{
    int sparse = linsol != CONT_LINSOL_DENSE;
    cont_problem prob = {.n = 2, .residual = pf_res,
                         .jacobian = sparse ? pf_jac_sparse : pf_jac,
                         .jac_matrix = sparse ? CONT_MATRIX_SPARSE : CONT_MATRIX_DENSE};
    cont_solver *s = make(&prob, linsol);
    CHECK_TRUE(cont_get_linsol(s) == linsol, "linear solver %d", cont_get_linsol(s));
    CHECK_OK(cont_set_step(s, 0.1, 1e-8, 0.3), s);
    CHECK_OK(cont_set_prange(s, -1.0, 1.0), s);
    double y0[2] = {0.0, 0.0};
    CHECK_OK(cont_start(s, y0, -1.0, +1), s);
    int st = cont_run(s);
    CHECK_TRUE(st == CONT_DONE, "status %d: %s", st, cont_errmsg(s));
    CHECK_TRUE(count_label(s, "BP") == 1, "expected 1 BP, got %d", count_label(s, "BP"));
    CHECK_TRUE(count_label(s, "LP") == 0, "expected no LP, got %d", count_label(s, "LP"));
    const cont_point *bp = find_label(s, "BP");
    if (!bp) {
        cont_free(s);
        fail();
        return;
    }
    CHECK_CLOSE(bp->p, 0.0, 1e-8);
    CHECK_CLOSE(bp->y[0], 0.0, 1e-12);
    CHECK_TRUE(bp->type == CONT_PT_BP, "type %d", bp->type);
    /* copy the BP: the next cont_start discards the stored points */
    double ybp[2] = {bp->y[0], bp->y[1]}, pbp = bp->p;
    double tbp[2] = {bp->ty[0], bp->ty[1]}, tpbp = bp->tp;
    double tn[2], tpn;
    CHECK_OK(cont_branch_direction(s, ybp, pbp, tbp, tpbp, tn, &tpn), s);
    /* independent: the null space of [Jy Fp] at (0,0,0) is span(e_x, e_p);
     * orthogonal to the trivial branch (e_p): e_x */
    CHECK_CLOSE(tn[0], 1.0, 1e-8);
    CHECK_CLOSE(tn[1], 0.0, 1e-8);
    CHECK_CLOSE(tpn, 0.0, 1e-8);
    CHECK_OK(cont_set_prange(s, -1.0, 0.25), s);
    for (int sg = 1; sg >= -1; sg -= 2) {
        double t[2] = {sg * tn[0], sg * tn[1]};
        CHECK_OK(cont_start_tangent(s, ybp, pbp, t, sg * tpn), s);
        st = cont_run(s);
        CHECK_TRUE(st == CONT_DONE, "branch %+d: status %d: %s", sg, st, cont_errmsg(s));
        const cont_point *ep = cont_get_point(s);
        CHECK_TRUE(ep->p == 0.25, "EP p = %.17g, expected exactly 0.25", ep->p);
        CHECK_CLOSE(ep->y[0], sg * 0.5, 1e-10);   /* x = +-sqrt(p) */
        CHECK_CLOSE(ep->y[1], 0.25, 1e-10);       /* y = p */
        for (long i = 1; i < cont_num_points(s); i++) {
            const cont_point *q = cont_point_at(s, i);
            CHECK_TRUE(sg * q->y[0] > 0, "branch %+d: point %ld has x = %g", sg, i, q->y[0]);
            CHECK_CLOSE(q->y[0] * q->y[0], q->p, 1e-9);
        }
        CHECK_TRUE(cont_num_special(s) == 1, "branch %+d: %ld special points, expected only "
                   "the EP (the start BP must not be reported again)", sg, cont_num_special(s));
    }
    cont_free(s);
}

static void test_pitchfork_dense(void **state)
{
    (void)state;
    pitchfork_case(CONT_LINSOL_DENSE);
}

static void test_pitchfork_klu(void **state)
{
    (void)state;
    pitchfork_case(CONT_LINSOL_KLU);
}

static void test_pitchfork_mumps(void **state)
{
    (void)state;
    pitchfork_case(CONT_LINSOL_MUMPS);
}

/* Going up the bifurcated branch x = sqrt(p) from p = 0.25 down through the
 * BP: t_p and the determinant change sign together; one BP is reported. */
static void pitchfork_branch_case(int linsol)
{
    int sparse = linsol != CONT_LINSOL_DENSE;
    cont_problem prob = {.n = 2, .residual = pf_res,
                         .jacobian = sparse ? pf_jac_sparse : pf_jac,
                         .jac_matrix = sparse ? CONT_MATRIX_SPARSE : CONT_MATRIX_DENSE};
    cont_solver *s = make(&prob, linsol);
    CHECK_OK(cont_set_step(s, 0.05, 1e-8, 0.1), s);
    CHECK_OK(cont_set_prange(s, -1.0, 0.5), s);
    CHECK_OK(cont_set_max_steps(s, 200), s);
    double y0[2] = {0.5, 0.25};
    CHECK_OK(cont_start(s, y0, 0.25, -1), s);
    int st = cont_run(s);
    CHECK_TRUE(st == CONT_DONE, "status %d: %s", st, cont_errmsg(s));
    CHECK_TRUE(count_label(s, "BP") == 1 && count_label(s, "LP") == 0,
               "expected one BP and no LP, got %d BP, %d LP", count_label(s, "BP"),
               count_label(s, "LP"));
    const cont_point *bp = find_label(s, "BP");
    if (bp) {
        CHECK_CLOSE(bp->p, 0.0, 1e-8);
        CHECK_CLOSE(bp->y[0], 0.0, 1e-4);
    }
    const cont_point *ep = cont_get_point(s);
    CHECK_TRUE(ep->p == 0.5, "EP p = %.17g, expected 0.5", ep->p);
    CHECK_CLOSE(ep->y[0], -sqrt(0.5), 1e-10);
    cont_free(s);
}

static void test_pitchfork_through_bp_on_branch(void **state)
{
    (void)state;
    pitchfork_branch_case(CONT_LINSOL_DENSE);
    pitchfork_branch_case(CONT_LINSOL_KLU);
    pitchfork_branch_case(CONT_LINSOL_MUMPS);
}

/* The determinant sign point by point along the trivial branch of the
 * pitchfork, through its BP: the three solvers see the same path and must
 * give the same signs, and the sign must change exactly once, at the BP. */
static void test_det_sign_solvers_agree(void **state)
{
    (void)state;
    int ls[3] = {CONT_LINSOL_DENSE, CONT_LINSOL_KLU, CONT_LINSOL_MUMPS};
    int sg[3][64];
    long np[3];
    for (int k = 0; k < 3; k++) {
        cont_problem prob = {.n = 2, .residual = pf_res, .jacobian = pf_jac_sparse,
                             .jac_matrix = CONT_MATRIX_SPARSE};
        cont_solver *s = make(&prob, ls[k]);
        CHECK_OK(cont_set_step(s, 0.1, 1e-8, 0.1), s);
        CHECK_OK(cont_set_prange(s, -1.0, 1.0), s);
        double y0[2] = {0.0, 0.0};
        CHECK_OK(cont_start(s, y0, -1.0, +1), s);
        CHECK_TRUE(cont_run(s) == CONT_DONE, "solver %d: %s", ls[k], cont_errmsg(s));
        np[k] = cont_num_points(s);
        CHECK_TRUE(np[k] > 10 && np[k] <= 64, "solver %d: %ld points", ls[k], np[k]);
        int changes = 0;
        for (long i = 0; i < np[k] && i < 64; i++) {
            const cont_point *q = cont_point_at(s, i);
            sg[k][i] = q->det_sign;
            if (q->type == CONT_PT_BP) continue;
            CHECK_TRUE(q->det_sign == (q->p < 0 ? 1 : -1) * sg[k][0],
                       "solver %d, point %ld (p = %g): det sign %d", ls[k], i, q->p, q->det_sign);
            if (i > 0 && sg[k][i] != sg[k][i - 1] && cont_point_at(s, i - 1)->type != CONT_PT_BP)
                changes++;
        }
        CHECK_TRUE(count_label(s, "BP") == 1, "solver %d: %d BP", ls[k], count_label(s, "BP"));
        cont_free(s);
    }
    for (int k = 1; k < 3; k++) {
        CHECK_TRUE(np[k] == np[0], "solver %d: %ld points, dense %ld", ls[k], np[k], np[0]);
        for (long i = 0; i < np[0] && i < np[k] && i < 64; i++)
            CHECK_TRUE(sg[k][i] == sg[0][i], "solver %d, point %ld: det sign %d, dense %d",
                       ls[k], i, sg[k][i], sg[0][i]);
    }
}

/* ------------------------------------------------------------------ */
/* Bratu                                                                */

static int bratu_jac_dense(const double *u, double lam, SUNMatrix J, double *Fp, void *ud)
{
    long N = ((bratu *)ud)->N;
    double h = 1.0 / (double)(N + 1), h2 = h * h;
    for (long i = 0; i < N; i++) {
        SM_ELEMENT_D(J, i, i) = -2.0 + h2 * lam * exp(u[i]);
        if (i > 0) SM_ELEMENT_D(J, i, i - 1) = 1.0;
        if (i < N - 1) SM_ELEMENT_D(J, i, i + 1) = 1.0;
        Fp[i] = h2 * exp(u[i]);
    }
    return 0;
}

static int stop_at_lp(const cont_point *pt, void *data)
{
    (void)data;
    return pt->type == CONT_PT_LP;
}

/* Independent value of the discrete limit point by shooting: u_0 = 0,
 * u_1 = a, u_{i+1} = 2 u_i - u_{i-1} - h^2 lam e^{u_i}; lam(a) solves
 * u_{N+1} = 0 (bisection), and lam*_N = max_a lam(a) (golden section). */
static double bratu_shoot(double a, double lam, long N)
{
    double h = 1.0 / (double)(N + 1), u0 = 0.0, u1 = a;
    for (long i = 1; i <= N; i++) {
        double u2 = 2.0 * u1 - u0 - h * h * lam * exp(u1);
        u0 = u1;
        u1 = u2;
    }
    return u1;
}

static double bratu_lam_of_a(double a, long N)
{
    double lo = 0.0, hi = 50.0;
    for (int it = 0; it < 70; it++) {
        double mid = 0.5 * (lo + hi);
        if (bratu_shoot(a, mid, N) > 0) lo = mid;
        else hi = mid;
    }
    return 0.5 * (lo + hi);
}

static double bratu_shoot_lstar(long N)
{
    double h = 1.0 / (double)(N + 1), lo = 0.5 * h, hi = 8.0 * h;
    double g = 0.5 * (sqrt(5.0) - 1.0);
    double c = hi - g * (hi - lo), d = lo + g * (hi - lo);
    double fc = bratu_lam_of_a(c, N), fd = bratu_lam_of_a(d, N);
    for (int it = 0; it < 60; it++) {
        if (fc > fd) {
            hi = d; d = c; fd = fc;
            c = hi - g * (hi - lo); fc = bratu_lam_of_a(c, N);
        } else {
            lo = c; c = d; fc = fd;
            d = lo + g * (hi - lo); fd = bratu_lam_of_a(d, N);
        }
    }
    return fmax(fc, fd);
}

/* Continue from lam0 (lower branch) to the LP; returns lam* (NAN on failure). */
static double bratu_lp(long N, int jac_matrix, int linsol, double lam0, int *used_linsol,
                       cont_stats *tot)
{
    bratu B = {N};
    cont_problem prob = {.n = N, .residual = bratu_res,
                         .jacobian = jac_matrix == CONT_MATRIX_SPARSE ? bratu_jac_sparse
                                                                      : bratu_jac_dense,
                         .jac_matrix = jac_matrix, .jac_nnz = 5, .user = &B};   /* grows */
    cont_solver *s = make(&prob, linsol);
    double sq = sqrt((double)N);
    CHECK_OK(cont_set_step(s, 0.2 * sq, 1e-8, 0.5 * sq), s);
    CHECK_OK(cont_set_prange(s, 0.0, 10.0), s);
    CHECK_OK(cont_set_callback(s, stop_at_lp, NULL), s);
    CHECK_OK(cont_set_detect(s, CONT_DETECT_LP, 1e-10), s);
    double *u = calloc((size_t)N, sizeof(double));
    CHECK_OK(cont_start(s, u, lam0, +1), s);
    int st = cont_run(s);
    CHECK_TRUE(st == CONT_DONE && cont_stop_reason(s) == CONT_STOP_CALLBACK,
               "N = %ld: status %d (%s): %s", N, st, cont_stop_name(cont_stop_reason(s)),
               cont_errmsg(s));
    const cont_point *lp = find_label(s, "LP");
    double lam = lp ? lp->p : NAN;
    if (used_linsol) *used_linsol = cont_get_linsol(s);
    if (tot) cont_get_stats(s, NULL, tot);
    /* u is symmetric about x = 1/2 at the LP, and F = 0 */
    if (lp) {
        CHECK_CLOSE(lp->y[0], lp->y[N - 1], 1e-8);
        CHECK_TRUE(lp->resnorm <= 1e-10, "LP residual %g", lp->resnorm);
    }
    free(u);
    cont_free(s);
    return lam;
}

static void test_bratu_convergence(void **state)
{
    (void)state;
    const double lstar = 3.51383071912516;   /* continuum lambda_c */
    long Ns[3] = {20, 40, 80};
    double err[3];
    for (int k = 0; k < 3; k++) {
        double lam = bratu_lp(Ns[k], CONT_MATRIX_DENSE, CONT_LINSOL_DENSE, 0.0, NULL, NULL);
        double ref = bratu_shoot_lstar(Ns[k]);
        CHECK_CLOSE(lam, ref, 1e-8 * ref);        /* discrete LP, independent method */
        err[k] = fabs(lam - lstar);
        print_message("# Bratu N = %ld: lambda* = %.12f (shooting %.12f), error %.3e\n",
                      Ns[k], lam, ref, err[k]);
    }
    /* O(h^2): error ratio (h1/h2)^2 = ((2N+1+... )) about 3.8 when N doubles */
    for (int k = 0; k < 2; k++) {
        double h1 = 1.0 / (double)(Ns[k] + 1), h2 = 1.0 / (double)(Ns[k + 1] + 1);
        CHECK_CLOSE(err[k] / err[k + 1], (h1 * h1) / (h2 * h2), 0.1 * (h1 * h1) / (h2 * h2));
    }
    CHECK_TRUE(err[2] / lstar < 1e-3, "relative error at N = 80: %g", err[2] / lstar);
}

static void test_bratu_klu_vs_dense(void **state)
{
    (void)state;
    long N = 400;
    int ls_auto = -1, ls_dense = -1, ls_klu = -1;
    cont_stats ta, td, tk;
    double lam_mumps = bratu_lp(N, CONT_MATRIX_SPARSE, CONT_LINSOL_AUTO, 3.0, &ls_auto, &ta);
    double lam_dense = bratu_lp(N, CONT_MATRIX_SPARSE, CONT_LINSOL_DENSE, 3.0, &ls_dense, &td);
    double lam_klu = bratu_lp(N, CONT_MATRIX_SPARSE, CONT_LINSOL_KLU, 3.0, &ls_klu, &tk);
    CHECK_TRUE(ls_auto == CONT_LINSOL_MUMPS, "AUTO with a sparse Jy and n = 400 chose %d",
               ls_auto);
    CHECK_TRUE(ls_dense == CONT_LINSOL_DENSE, "forced dense gave %d", ls_dense);
    CHECK_TRUE(ls_klu == CONT_LINSOL_KLU, "forced KLU gave %d", ls_klu);
    CHECK_CLOSE(lam_klu, lam_dense, 1e-8 * lam_dense);
    CHECK_CLOSE(lam_mumps, lam_dense, 1e-8 * lam_dense);
    double ref = bratu_shoot_lstar(N);
    CHECK_CLOSE(lam_klu, ref, 1e-8 * ref);
    CHECK_CLOSE(lam_mumps, ref, 1e-8 * ref);
    print_message("# Bratu N = 400: MUMPS %.12f (%.3f s), KLU %.12f (%.3f s), dense %.12f "
                  "(%.3f s), shooting %.12f\n", lam_mumps, ta.wall, lam_klu, tk.wall, lam_dense,
                  td.wall, ref);
}

/* ------------------------------------------------------------------ */
/* failure: F = x - p, NaN (or an error code) for p > 0.7               */

static int nan_res(const double *y, double p, double *F, void *ud)
{
    int mode = *(int *)ud;
    if (p > 0.7) {
        if (mode == 1) return -3;
        F[0] = NAN;
        return 0;
    }
    F[0] = y[0] - p;
    return 0;
}

static int nan_jac(const double *y, double p, SUNMatrix J, double *Fp, void *ud)
{
    (void)y; (void)p; (void)ud;
    SM_ELEMENT_D(J, 0, 0) = 1.0;
    Fp[0] = -1.0;
    return 0;
}

/* Run s from y0 at p = 0 (steps 0.1 down to ds_min = 1e-6, p in [-1,
 * pmax]), which must stop at ds_min; its message, printed with what and k. */
static const char *run_to_dsmin(cont_solver *s, const double *y0, double pmax, const char *what,
                                int k)
{
    CHECK_OK(cont_set_step(s, 0.1, 1e-6, 0.2), s);
    CHECK_OK(cont_set_prange(s, -1.0, pmax), s);
    CHECK_OK(cont_start(s, y0, 0.0, +1), s);
    int st = cont_run(s);
    CHECK_TRUE(st == CONT_FAIL, "%s %d: status %d, expected CONT_FAIL", what, k, st);
    CHECK_TRUE(cont_stop_reason(s) == CONT_STOP_DSMIN, "stop reason %s",
               cont_stop_name(cont_stop_reason(s)));
    const char *m = cont_errmsg(s);
    print_message("# %s message (%d): %s\n", what, k, m);
    return m;
}

static void test_failure_diagnosis(void **state)
{
    (void)state;
    for (int mode = 0; mode < 2; mode++) {
        cont_problem prob = {.n = 1, .residual = nan_res, .jacobian = nan_jac,
                             .jac_matrix = CONT_MATRIX_DENSE, .user = &mode};
        cont_solver *s = make(&prob, CONT_LINSOL_DENSE);
        double y0 = 0.0;
        const char *m = run_to_dsmin(s, &y0, 2.0, "failure", mode);
        CHECK_TRUE(m[0] != '\0', "empty message");
        CHECK_TRUE(strstr(m, "step size") && strstr(m, "ds_min") && strstr(m, "p = "),
                   "message does not name the step size, ds_min and p: %s", m);
        CHECK_TRUE(strstr(m, mode == 0 ? "non-finite" : "returned -3"),
                   "message does not give the cause: %s", m);
        CHECK_TRUE(!strstr(m, "diverged"), "a NaN failure called a divergence: %s", m);
        CHECK_TRUE(!strstr(m, "anchored corrector"), "a NaN failure called a floor: %s", m);
        long np = cont_num_points(s);
        CHECK_TRUE(np > 2, "only %ld points", np);
        for (long i = 0; i < np; i++) {
            const cont_point *q = cont_point_at(s, i);
            CHECK_TRUE(isfinite(q->p) && isfinite(q->y[0]) && isfinite(q->tp) &&
                       isfinite(q->ty[0]) && isfinite(q->resnorm),
                       "point %ld is not finite", i);
            CHECK_TRUE(q->p <= 0.7, "point %ld beyond the NaN region: p = %g", i, q->p);
        }
        /* it got close to the failure before giving up */
        CHECK_CLOSE(cont_point_at(s, np - 1)->p, 0.7, 1e-4);
        /* cont_step after a failure keeps failing, no crash */
        CHECK_TRUE(cont_step(s) == CONT_FAIL, "cont_step after failure");
        cont_free(s);
    }
}

/* ------------------------------------------------------------------ */
/* divergence: F = (y1^3 + y1 - p, y2 - y1^2 / 10) with dF2/dy2 given as  */
/* -1/10 instead of 1, so that Newton multiplies the error of y2 by 11   */
/* at every iteration: every attempt starts near the branch (its error   */
/* in y2 is the predictor's, ds^2 / 20) and diverges; the stop at ds_min */
/* must say so, and the NaN failure above must not                      */

static int div_res(const double *y, double p, double *F, void *u)
{
    (void)u;
    F[0] = y[0] * y[0] * y[0] + y[0] - p;
    F[1] = y[1] - 0.1 * y[0] * y[0];
    return 0;
}

static int div_jac(const double *y, double p, SUNMatrix J, double *Fp, void *u)
{
    (void)p; (void)u;
    SM_ELEMENT_D(J, 0, 0) = 3 * y[0] * y[0] + 1.0;
    SM_ELEMENT_D(J, 0, 1) = 0.0;
    SM_ELEMENT_D(J, 1, 0) = -0.2 * y[0];
    SM_ELEMENT_D(J, 1, 1) = -0.1;   /* wrong: 1 */
    Fp[0] = -1.0;
    Fp[1] = 0.0;
    return 0;
}

static void test_divergence_diagnosis(void **state)
{
    (void)state;
    for (int corrector = 0; corrector < 2; corrector++) {
        cont_problem prob = {.n = 2, .residual = div_res, .jacobian = div_jac,
                             .jac_matrix = CONT_MATRIX_DENSE};
        cont_solver *s = make(&prob, CONT_LINSOL_DENSE);
        CHECK_OK(cont_set_corrector(s, corrector ? CONT_CORRECTOR_REUSE : CONT_CORRECTOR_NEWTON), s);
        CHECK_OK(cont_set_newton(s, 1e-10, 12, KIN_NONE), s);
        double y0[2] = {0.0, 0.0};
        const char *m = run_to_dsmin(s, y0, 1.0, "divergence", corrector);
        CHECK_TRUE(strstr(m, "diagnosis") && strstr(m, "then diverged") &&
                   strstr(m, "not a turning point"), "no divergence diagnosis: %s", m);
        CHECK_TRUE(!strstr(m, "residual floor"), "called a floor: %s", m);
        /* the lowest residual it names is below the Newton tolerance's
         * 1e4 and the end above 100 times that */
        const char *q = strstr(m, "scaled residual of ");
        CHECK_TRUE(q != NULL, "no residual in: %s", m);
        double lo = 0, hi = 0, end = 0;
        CHECK_TRUE(q && sscanf(q, "scaled residual of %lf to %lf", &lo, &hi) == 2, "%s", m);
        const char *e = strstr(m, "diverged to ");
        CHECK_TRUE(e && sscanf(e, "diverged to %lf", &end) == 1, "%s", m);
        CHECK_TRUE(lo <= hi && hi <= 1e-6 && end > 100 * lo, "lo %g hi %g end %g", lo, hi, end);
        /* at most a step or two short enough for the predictor to meet
         * the tolerance before Newton moved away */
        long np = cont_num_points(s);
        CHECK_TRUE(np >= 1 && np <= 3 && cont_point_at(s, np - 1)->p < 1e-3,
                   "%ld points, the last at p = %g", np, cont_point_at(s, np - 1)->p);
        cont_free(s);
    }
}

/* ------------------------------------------------------------------ */
/* a floor of the anchored corrector: F as div_res, the plain Jacobian   */
/* as div_jac (Newton diverges), the anchored one exact (Newton          */
/* converges), and beyond p = 0.5 a term a sgn(e) in F2 (e = y2 -        */
/* y1^2 / 10) that no Newton step removes: the anchored iterates then    */
/* alternate e = +-a, residual 2a = 1.5e-10 against the tolerance 1e-10, */
/* up to the iteration limit (lower where an iterate's p is below 0.5).  */
/* The path crawls to p = 0.5, accepted points in between, and its last  */
/* step fails at fewer attempts than tail_note counts; the stop must say */
/* what the anchored corrector did.                                      */
/* With a NaN residual beyond p = 0.5 instead (nan = 1) it must not.     */

typedef struct { int on, nan; double eps, ya2; } afl_anchor;

static int afl_res(const double *y, double p, double *F, void *u)
{
    const afl_anchor *a = u;
    double e = y[1] - 0.1 * y[0] * y[0];
    F[0] = y[0] * y[0] * y[0] + y[0] - p;
    F[1] = e + (p > 0.5 ? 0.75e-10 * ((e > 0) - (e < 0)) : 0.0);
    if (a->nan && p > 0.5) F[1] = NAN;
    if (a->on) F[1] -= a->eps * (y[1] - a->ya2);
    return 0;
}

static int afl_jac(const double *y, double p, SUNMatrix J, double *Fp, void *u)
{
    const afl_anchor *a = u;
    div_jac(y, p, J, Fp, NULL);
    if (a->on) SM_ELEMENT_D(J, 1, 1) = 1.0 - a->eps;   /* exact (but the floor term) */
    return 0;
}

static int afl_anchor_fn(const double *y, double p, int on, void *u)
{
    (void)p;
    afl_anchor *a = u;
    a->on = on;
    if (on) {
        a->eps = 1e-10 * pow(0.1, on - 1);
        a->ya2 = y[1];
    }
    return 0;
}

static void test_anchored_floor_diagnosis(void **state)
{
    (void)state;
    for (int nan = 0; nan < 2; nan++) {
        afl_anchor an = {0, nan, 0.0, 0.0};
        cont_problem prob = {.n = 2, .residual = afl_res, .jacobian = afl_jac,
                             .jac_matrix = CONT_MATRIX_DENSE, .anchor = afl_anchor_fn,
                             .user = &an};
        cont_solver *s = make(&prob, CONT_LINSOL_DENSE);
        CHECK_OK(cont_set_corrector(s, CONT_CORRECTOR_REUSE), s);
        CHECK_OK(cont_set_anchor_first(s, 1), s);
        CHECK_OK(cont_set_newton(s, 1e-10, 12, KIN_NONE), s);
        double y0[2] = {0.0, 0.0};
        const char *m = run_to_dsmin(s, y0, 1.0, "anchored floor", nan);
        long np = cont_num_points(s);
        CHECK_CLOSE(cont_point_at(s, np - 1)->p, 0.5, 1e-5);
        if (nan) {
            CHECK_TRUE(!strstr(m, "diagnosis"), "a NaN failure diagnosed: %s", m);
            cont_free(s);
            continue;
        }
        CHECK_TRUE(strstr(m, "diagnosis") &&
                   strstr(m, "anchored corrector at its iteration limit") &&
                   strstr(m, "not a turning point") && strstr(m, "Newton tolerance above"),
                   "no diagnosis of the anchored floor: %s", m);
        CHECK_TRUE(!strstr(m, "then diverged"), "called a divergence: %s", m);
        /* the residual range is the floor, 2a, and points came in between */
        int na = 0;
        long pts = -1;
        double lo = 0, hi = 0;
        const char *q = strstr(m, "the last ");
        CHECK_TRUE(q && sscanf(q, "the last %d failed attempts", &na) == 1 && na >= 3, "%s", m);
        q = strstr(m, "ds_min, ");
        CHECK_TRUE(q && sscanf(q, "ds_min, %ld points accepted", &pts) == 1 && pts >= 1, "%s",
                   m);
        q = strstr(m, "scaled residual of ");
        CHECK_TRUE(q && sscanf(q, "scaled residual of %lf to %lf", &lo, &hi) == 2, "%s", m);
        CHECK_TRUE(0 < lo && lo <= hi && 1e-10 < hi && hi < 2e-10, "lo %g hi %g", lo, hi);
        cont_free(s);
    }
}

/* ------------------------------------------------------------------ */
/* stop rules: F = x^3 + x - p                                          */

static int cub_res(const double *y, double p, double *F, void *u)
{
    (void)u;
    F[0] = y[0] * y[0] * y[0] + y[0] - p;
    return 0;
}

static int cub_jac(const double *y, double p, SUNMatrix J, double *Fp, void *u)
{
    (void)p; (void)u;
    SM_ELEMENT_D(J, 0, 0) = 3 * y[0] * y[0] + 1.0;
    Fp[0] = -1.0;
    return 0;
}

static double cardano(double p)   /* real root of x^3 + x = p */
{
    double d = sqrt(p * p / 4.0 + 1.0 / 27.0);
    return cbrt(p / 2.0 + d) + cbrt(p / 2.0 - d);
}

typedef struct counter {
    long calls, last_index;
    int order_ok;
} counter;

static int count_points(const cont_point *pt, void *data)
{
    counter *c = data;
    if (pt->index != c->calls) c->order_ok = 0;
    c->calls++;
    c->last_index = pt->index;
    return 0;
}

static void test_stop_rules(void **state)
{
    (void)state;
    cont_problem prob = {.n = 1, .residual = cub_res, .jacobian = cub_jac,
                         .jac_matrix = CONT_MATRIX_DENSE};
    cont_solver *s = make(&prob, CONT_LINSOL_DENSE);
    /* (1) p window: EP exactly on p_max, driven step by step */
    const double pmax = 1.2345;
    CHECK_OK(cont_set_step(s, 0.1, 1e-8, 0.3), s);
    CHECK_OK(cont_set_prange(s, -1.0, pmax), s);
    counter cnt = {0, -1, 1};
    CHECK_OK(cont_set_callback(s, count_points, &cnt), s);
    double y0 = 0.3;   /* not a solution: cont_start corrects it at p = 0 */
    CHECK_OK(cont_start(s, &y0, 0.0, +1), s);
    CHECK_CLOSE(cont_get_point(s)->y[0], 0.0, 1e-10);   /* |F| <= ftol = 1e-10, F' >= 1 */
    int st, nstep = 0;
    double plast = 0.0;
    while ((st = cont_step(s)) == CONT_CONTINUE) {
        const cont_point *q = cont_get_point(s);
        CHECK_TRUE(q->p > plast, "p not increasing");
        CHECK_TRUE(q->p < pmax, "p beyond p_max before the end: %.17g", q->p);
        CHECK_CLOSE(q->y[0], cardano(q->p), 1e-10);
        plast = q->p;
        nstep++;
    }
    CHECK_TRUE(st == CONT_DONE, "status %d: %s", st, cont_errmsg(s));
    const cont_point *ep = cont_get_point(s);
    CHECK_TRUE(ep->p == pmax, "EP p = %.17g, expected exactly %.17g", ep->p, pmax);
    CHECK_CLOSE(ep->y[0], cardano(pmax), 1e-12);
    CHECK_TRUE(ep->resnorm <= 1e-10, "EP residual %g", ep->resnorm);
    CHECK_TRUE(strcmp(ep->label, "EP") == 0 && ep->type == CONT_PT_EP, "label '%s'", ep->label);
    CHECK_TRUE(cont_stop_reason(s) == CONT_STOP_PMAX, "reason %s",
               cont_stop_name(cont_stop_reason(s)));
    CHECK_TRUE(cnt.order_ok && cnt.calls == cont_num_points(s) && cnt.last_index == ep->index,
               "callback saw %ld points (order ok %d), stored %ld", cnt.calls, cnt.order_ok,
               cont_num_points(s));
    CHECK_TRUE(cont_step(s) == CONT_DONE, "cont_step after the end");
    cont_stats last, tot;
    CHECK_OK(cont_get_stats(s, &last, &tot), s);
    CHECK_TRUE(tot.steps == nstep + 1 && tot.points == nstep + 2,
               "stats: %ld steps, %ld points; loop saw %d steps", tot.steps, tot.points, nstep);
    CHECK_TRUE(tot.newton_iters >= tot.steps && tot.njac > 0 && tot.nres > 0 &&
               tot.nfactor >= tot.njac && tot.nlinsolve > 0 && tot.wall >= 0 &&
               last.steps == 1 && last.ds > 0,
               "stats not plausible: newton %ld, jac %ld, res %ld, fact %ld, solves %ld",
               tot.newton_iters, tot.njac, tot.nres, tot.nfactor, tot.nlinsolve);
    /* (2) max steps */
    CHECK_OK(cont_set_callback(s, NULL, NULL), s);
    CHECK_OK(cont_set_prange(s, -10.0, 10.0), s);
    CHECK_OK(cont_set_max_steps(s, 5), s);
    y0 = 0.0;
    CHECK_OK(cont_start(s, &y0, 0.0, -1), s);
    st = cont_run(s);
    CHECK_TRUE(st == CONT_DONE && cont_stop_reason(s) == CONT_STOP_MAXSTEPS,
               "status %d reason %s", st, cont_stop_name(cont_stop_reason(s)));
    CHECK_TRUE(cont_num_points(s) == 6, "%ld points after 5 steps", cont_num_points(s));
    CHECK_TRUE(cont_get_point(s)->p < 0, "direction -1 did not decrease p");
    /* (3) max arclength: lands on it */
    CHECK_OK(cont_set_max_steps(s, 0), s);
    CHECK_OK(cont_set_max_arclength(s, 0.777), s);
    CHECK_OK(cont_start(s, &y0, 0.0, +1), s);
    st = cont_run(s);
    CHECK_TRUE(st == CONT_DONE && cont_stop_reason(s) == CONT_STOP_MAXARC,
               "status %d reason %s", st, cont_stop_name(cont_stop_reason(s)));
    CHECK_CLOSE(cont_get_point(s)->s, 0.777, 1e-12);
    /* cont_solve_fixed on its own */
    double yf = 5.0;
    CHECK_OK(cont_solve_fixed(s, &yf, -2.5), s);
    CHECK_CLOSE(yf, cardano(-2.5), 1e-10);
    /* store = 0: only the current point is kept, the run is the same */
    CHECK_OK(cont_set_store(s, 0), s);
    CHECK_OK(cont_set_max_arclength(s, 1e300), s);
    CHECK_OK(cont_set_max_steps(s, 7), s);
    CHECK_OK(cont_start(s, &y0, 0.0, +1), s);
    CHECK_TRUE(cont_run(s) == CONT_DONE && cont_num_points(s) == 0 &&
               cont_get_point(s)->index == 7, "store = 0: %ld stored, last index %ld",
               cont_num_points(s), cont_get_point(s)->index);
    /* bad options are refused with a message */
    CHECK_TRUE(cont_set_step(s, 0.1, 0.2, 0.3) == CONT_EINPUT, "bad ds accepted");
    cont_free(s);
}

/* ------------------------------------------------------------------ */

static void test_bad_input(void **state)
{
    (void)state;
    cont_problem prob = {.n = 0, .residual = cub_res, .jacobian = cub_jac};
    cont_solver *s = NULL;
    CHECK_TRUE(cont_create(&prob, CONT_LINSOL_AUTO, &s) == CONT_EINPUT, "n = 0 accepted");
    CHECK_TRUE(s && strstr(cont_errmsg(s), "n = 0"), "message: %s", s ? cont_errmsg(s) : "");
    cont_free(s);
    prob.n = 1;
    s = make(&prob, CONT_LINSOL_AUTO);
    CHECK_TRUE(cont_step(s) == CONT_FAIL && strstr(cont_errmsg(s), "before cont_start"),
               "cont_step before start: %s", cont_errmsg(s));
    /* no tangent at a limit point with cont_start */
    cont_problem fold = {.n = 1, .residual = fold_res, .jacobian = fold_jac};
    cont_solver *f = make(&fold, CONT_LINSOL_DENSE);
    double y0 = 0.0;
    CHECK_TRUE(cont_start(f, &y0, 0.0, +1) == CONT_ENUMERIC &&
               strstr(cont_errmsg(f), "cont_start_tangent"), "start at the LP: %s",
               cont_errmsg(f));
    /* not a branch point */
    double tn, tpn, ty = 0.0;
    y0 = 1.0;
    CHECK_TRUE(cont_branch_direction(f, &y0, -1.0, &ty, 1.0, &tn, &tpn) == CONT_ENUMERIC,
               "branch direction at a regular point");
    cont_free(f);
    cont_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fold_limit_point),
        cmocka_unit_test(test_fold_klu_mumps),
        cmocka_unit_test(test_pitchfork_dense),
        cmocka_unit_test(test_pitchfork_klu),
        cmocka_unit_test(test_pitchfork_mumps),
        cmocka_unit_test(test_pitchfork_through_bp_on_branch),
        cmocka_unit_test(test_det_sign_solvers_agree),
        cmocka_unit_test(test_bratu_convergence),
        cmocka_unit_test(test_bratu_klu_vs_dense),
        cmocka_unit_test(test_failure_diagnosis),
        cmocka_unit_test(test_divergence_diagnosis),
        cmocka_unit_test(test_anchored_floor_diagnosis),
        cmocka_unit_test(test_stop_rules),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
