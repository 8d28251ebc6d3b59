/* test_cont_block.c - the bordered systems solved by block elimination on
 * the LDL^T of a symmetric Jy (continuation/cont_blockelim.c, chosen by
 * cont_problem.jac_symmetric) against the LU of the whole bordered matrix
 * (the same problem without the flag), sparse Jy, MUMPS:
 *   Bratu  u'' + lambda e^u = 0, N = 300 (symmetric tridiagonal Jy), through
 *          its limit point: the start tangent (one fresh factorisation and
 *          solve each way) agrees to a bound from the condition number of
 *          the bordered matrix; the whole path (points, tangents, determinant
 *          signs, the limit point) to 1e-9, with block elimination used.
 *   line   F_0 = p - 1, F_i = y_i + y_i^3 / 2 - (i / (N-1)) p: the branch is
 *          the line p = 1 along y_0; Jy (row and column 0 zero) is singular
 *          at every point while [Jy Fp; t^T] is regular.  Every block
 *          elimination must be detected as unusable and fall back to the LU;
 *          the path is the LU's and the exact one.
 *   advection  u'' + u' + lambda e^u = 0, whose Jy is not symmetric, flagged
 *          symmetric: detected, every factorisation falls back, same path.
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

#include "cont.h"
#include "cont_test.h"

#define N 300
#define FTOL 1e-10
#define BLK_BERR 1e-12   /* backward error of a block solve (cont_blockelim.c) */

extern void dgetrf_(const int *m, const int *n, double *a, const int *lda, int *ipiv, int *info);
extern void dgecon_(const char *norm, const int *n, const double *a, const int *lda,
                    const double *anorm, double *rcond, double *work, int *iwork, int *info);

static bratu bratu_n = {N};

typedef int (*res_fn)(const double *, double, double *, void *);
typedef int (*jac_fn)(const double *, double, SUNMatrix, double *, void *);

/* branch p = 1 along y_0; y_i (i >= 1) solve y + y^3 / 2 = i / (N - 1) */
static int line_res(const double *y, double p, double *F, void *ud)
{
    (void)ud;
    F[0] = p - 1.0;
    for (long i = 1; i < N; i++) F[i] = y[i] + 0.5 * y[i] * y[i] * y[i] - (double)i / (N - 1.0) * p;
    return 0;
}

static int line_jac(const double *y, double p, SUNMatrix J, double *Fp, void *ud)
{
    (void)ud; (void)p;
    sunindextype *ptr = SM_INDEXPTRS_S(J), *idx = SM_INDEXVALS_S(J);
    double *val = SM_DATA_S(J);
    for (long j = 0; j < N; j++) {
        ptr[j] = j;
        idx[j] = j;
        val[j] = j == 0 ? 0.0 : 1.0 + 1.5 * y[j] * y[j];   /* (0, 0) stored, zero */
        Fp[j] = j == 0 ? 1.0 : -(double)j / (N - 1.0);
    }
    ptr[N] = N;
    return 0;
}

/* Bratu with advection, u'' + u' + lambda e^u = 0: Jy tridiagonal, not
 * symmetric (off-diagonals 1 -+ h / 2) */
static int adv_res(const double *u, double lam, double *F, void *ud)
{
    (void)ud;
    double h = 1.0 / (N + 1.0), h2 = h * h;
    for (long i = 0; i < N; i++) {
        double ul = i > 0 ? u[i - 1] : 0.0, ur = i < N - 1 ? u[i + 1] : 0.0;
        F[i] = (1.0 - 0.5 * h) * ul - 2.0 * u[i] + (1.0 + 0.5 * h) * ur + h2 * lam * exp(u[i]);
    }
    return 0;
}

static int adv_jac(const double *u, double lam, SUNMatrix J, double *Fp, void *ud)
{
    (void)ud;
    double h = 1.0 / (N + 1.0), h2 = h * h;
    sunindextype *ptr = SM_INDEXPTRS_S(J), *idx = SM_INDEXVALS_S(J);
    double *val = SM_DATA_S(J);
    sunindextype k = 0;
    for (long j = 0; j < N; j++) {   /* column j: rows j - 1, j, j + 1 */
        ptr[j] = k;
        if (j > 0) { idx[k] = j - 1; val[k++] = 1.0 + 0.5 * h; }
        idx[k] = j; val[k++] = -2.0 + h2 * lam * exp(u[j]);
        if (j < N - 1) { idx[k] = j + 1; val[k++] = 1.0 - 0.5 * h; }
        Fp[j] = h2 * exp(u[j]);
    }
    ptr[N] = k;
    return 0;
}

typedef struct run {
    cont_solver *s;
    cont_stats tot;
} run;

/* A solver for the problem, symmetric flag sym, MUMPS, reusing corrector. */
static cont_solver *solver(res_fn res, jac_fn jac, void *user, int sym, double p0, double p1,
                           double ds, long max_steps)
{
    cont_problem prob = {.n = N, .residual = res, .jacobian = jac,
                         .jac_matrix = CONT_MATRIX_SPARSE, .jac_nnz = 3 * N, .user = user,
                         .jac_symmetric = sym};
    cont_solver *s = NULL;
    assert_int_equal(cont_create(&prob, CONT_LINSOL_MUMPS, &s), CONT_OK);
    CHECK_OK(cont_set_step(s, ds, 1e-8, ds), s);
    CHECK_OK(cont_set_prange(s, p0, p1), s);
    CHECK_OK(cont_set_max_steps(s, max_steps), s);
    CHECK_OK(cont_set_newton(s, FTOL, 10, 0), s);
    return s;
}

static void finish(run *r, cont_solver *s)
{
    int st = cont_run(s);
    CHECK_TRUE(st == CONT_DONE, "status %d: %s", st, cont_errmsg(s));
    cont_get_stats(s, NULL, &r->tot);
    r->s = s;
}

/* The paths of a (flagged symmetric) and b (LU) agree to 1e-9; a's
 * residuals are below ftol. */
static void compare(const run *a, const run *b, res_fn res, void *user, const char *what)
{
    long np = cont_num_points(a->s);
    CHECK_TRUE(np == cont_num_points(b->s) && np > 10, "%s: %ld points against %ld", what, np,
               cont_num_points(b->s));
    path_diff d = compare_paths(a->s, b->s, N, res, user, what);
    double dx = d.dx, dt = d.dt, rmax = d.rmax;
    print_message("# %s: %ld points agree to %.2g, tangents to %.2g, largest residual %.2g; "
                  "factorisations %ld (%ld fell back to the LU) against %ld; solves %ld "
                  "against %ld\n", what, np, dx, dt, rmax, a->tot.nfactor, a->tot.nfallback,
                  b->tot.nfactor, a->tot.nlinsolve, b->tot.nlinsolve);
    CHECK_TRUE(dx <= 1e-9, "%s: points differ by %g relative", what, dx);
    CHECK_TRUE(dt <= 1e-9, "%s: tangents differ by %g relative", what, dt);
    CHECK_TRUE(rmax <= FTOL, "%s: a point's residual is %g > ftol", what, rmax);
    CHECK_TRUE(b->tot.nfallback == 0, "%s: the LU run counts %ld fallbacks", what,
               b->tot.nfallback);
}

/* The points and tangents of a and b are the same to the last bit. */
static int same_bits(const run *a, const run *b)
{
    for (long k = 0; k < cont_num_points(a->s); k++) {
        const cont_point *pa = cont_point_at(a->s, k), *pb = cont_point_at(b->s, k);
        if (pa->p != pb->p || pa->tp != pb->tp ||
            memcmp(pa->y, pb->y, N * sizeof(double)) != 0 ||
            memcmp(pa->ty, pb->ty, N * sizeof(double)) != 0)
            return 0;
    }
    return 1;
}

/* 1-norm condition number of the bordered matrix [Jy Fp; e_p^T] of Bratu
 * at (u, lambda), dense LAPACK. */
static double bratu_cond(const double *u, double lam)
{
    int m = N + 1, info = 0;
    double *A = calloc((size_t)m * m, sizeof(double)), *work = malloc(4 * sizeof(double) * m);
    int *ipiv = malloc(sizeof(int) * m), *iwork = malloc(sizeof(int) * m);
    SUNContext ctx;
    SUNContext_Create(NULL, &ctx);
    SUNMatrix J = SUNSparseMatrix(N, N, 3 * N, CSC_MAT, ctx);
    double Fp[N];
    bratu_jac_sparse(u, lam, J, Fp, &bratu_n);
    for (long j = 0; j < N; j++) {
        for (sunindextype k = SM_INDEXPTRS_S(J)[j]; k < SM_INDEXPTRS_S(J)[j + 1]; k++)
            A[j * m + SM_INDEXVALS_S(J)[k]] = SM_DATA_S(J)[k];
        A[(long)N * m + j] = Fp[j];
    }
    A[(long)N * m + N] = 1.0;
    double anorm = 0.0, rcond = 0.0;
    for (int j = 0; j < m; j++) {
        double c = 0.0;
        for (int i = 0; i < m; i++) c += fabs(A[j * m + i]);
        anorm = fmax(anorm, c);
    }
    dgetrf_(&m, &m, A, &m, ipiv, &info);
    assert_int_equal(info, 0);
    dgecon_("1", &m, A, &m, &anorm, &rcond, work, iwork, &info);
    assert_int_equal(info, 0);
    SUNMatDestroy(J);
    SUNContext_Free(&ctx);
    free(A); free(work); free(ipiv); free(iwork);
    return 1.0 / rcond;
}

static void test_bratu_block_agrees(void **state)
{
    (void)state;
    double u0[N];
    memset(u0, 0, sizeof u0);
    run a, b;
    cont_solver *sa = solver(bratu_res, bratu_jac_sparse, &bratu_n, 1, 0.5, 3.6, 2.0, 40);
    cont_solver *sb = solver(bratu_res, bratu_jac_sparse, &bratu_n, 0, 0.5, 3.6, 2.0, 40);
    CHECK_OK(cont_start(sa, u0, 0.5, +1), sa);
    CHECK_OK(cont_start(sb, u0, 0.5, +1), sb);
    /* the start tangent: [Jy Fp; e_p^T] v = e_p solved once each way, block
     * elimination refined to a backward error BLK_BERR, the LU's at rounding
     * level: the two agree to cond * (BLK_BERR + LU's), doubled by the
     * normalisation of v */
    const cont_point *ta = cont_point_at(sa, 0), *tb = cont_point_at(sb, 0);
    double kappa = bratu_cond(ta->y, ta->p), dt = fabs(ta->tp - tb->tp), tn = fabs(tb->tp);
    for (long i = 0; i < N; i++) {
        dt = fmax(dt, fabs(ta->ty[i] - tb->ty[i]));
        tn = fmax(tn, fabs(tb->ty[i]));
    }
    double tol = 2.0 * kappa * (BLK_BERR + 1e3 * 2.2e-16) * tn;
    print_message("# Bratu start tangent: block against LU %.3g, bound %.3g (cond %.3g)\n", dt,
                  tol, kappa);
    CHECK_TRUE(dt <= tol, "start tangents differ by %g > %g", dt, tol);
    finish(&a, sa);
    finish(&b, sb);
    compare(&a, &b, bratu_res, &bratu_n, "Bratu");
    CHECK_TRUE(2 * a.tot.nfallback < a.tot.nfactor, "block elimination used for %ld of %ld",
               a.tot.nfactor - a.tot.nfallback, a.tot.nfactor);
    const cont_point *lpa = find_label(a.s, "LP"), *lpb = find_label(b.s, "LP");
    CHECK_TRUE(lpa && lpb, "limit point missing (%p, %p)", (const void *)lpa, (const void *)lpb);
    if (lpa && lpb) {
        CHECK_CLOSE(lpa->p, lpb->p, 1e-9);
        CHECK_CLOSE(lpa->p, 3.513830719, 1e-4);   /* the continuous lambda*, to O(h^2) */
    }
    cont_free(a.s);
    cont_free(b.s);
}

static void test_singular_jy_falls_back(void **state)
{
    (void)state;
    double y0[N], t0[N];
    memset(y0, 0, sizeof y0);
    memset(t0, 0, sizeof t0);
    t0[0] = 1.0;
    for (long i = 1; i < N; i++) {   /* y + y^3 / 2 = c by Newton */
        double c = (double)i / (N - 1.0), y = c;
        for (int k = 0; k < 60; k++) y -= (y + 0.5 * y * y * y - c) / (1.0 + 1.5 * y * y);
        y0[i] = y;
    }
    run a, b;
    cont_solver *sa = solver(line_res, line_jac, NULL, 1, 0.0, 2.0, 0.1, 20);
    cont_solver *sb = solver(line_res, line_jac, NULL, 0, 0.0, 2.0, 0.1, 20);
    CHECK_OK(cont_start_tangent(sa, y0, 1.0, t0, 0.0), sa);
    CHECK_OK(cont_start_tangent(sb, y0, 1.0, t0, 0.0), sb);
    finish(&a, sa);
    finish(&b, sb);
    compare(&a, &b, line_res, NULL, "line");
    /* every factorisation fell back: the LU's path to the last bit */
    CHECK_TRUE(a.tot.nfallback >= a.tot.nfactor && same_bits(&a, &b),
               "singular Jy: %ld of %ld factorisations fell back", a.tot.nfallback,
               a.tot.nfactor);
    for (long k = 0; k < cont_num_points(a.s); k++) {   /* the exact branch */
        const cont_point *q = cont_point_at(a.s, k);
        CHECK_CLOSE(q->p, 1.0, 1e-12);
        for (long i = 1; i < N; i++) CHECK_CLOSE(q->y[i], y0[i], 1e-12);
    }
    CHECK_TRUE(cont_point_at(a.s, cont_num_points(a.s) - 1)->y[0] > 1.0,
               "the line was not followed");
    cont_free(a.s);
    cont_free(b.s);
}

static void test_unsymmetric_flagged_falls_back(void **state)
{
    (void)state;
    double u0[N];
    memset(u0, 0, sizeof u0);
    run a, b;
    cont_solver *sa = solver(adv_res, adv_jac, NULL, 1, 0.5, 3.6, 2.0, 40);
    cont_solver *sb = solver(adv_res, adv_jac, NULL, 0, 0.5, 3.6, 2.0, 40);
    CHECK_OK(cont_start(sa, u0, 0.5, +1), sa);
    CHECK_OK(cont_start(sb, u0, 0.5, +1), sb);
    finish(&a, sa);
    finish(&b, sb);
    compare(&a, &b, adv_res, NULL, "advection");
    /* every factorisation of the corrector fell back (KINSOL's at the
     * start are LU anyway): the LU's path to the last bit */
    CHECK_TRUE(a.tot.nfallback > 10 && same_bits(&a, &b),
               "unsymmetric Jy: %ld of %ld factorisations fell back", a.tot.nfallback,
               a.tot.nfactor);
    CHECK_TRUE(count_label(a.s, "LP") == 1 && count_label(b.s, "LP") == 1,
               "limit points: %d and %d", count_label(a.s, "LP"), count_label(b.s, "LP"));
    cont_free(a.s);
    cont_free(b.s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bratu_block_agrees),
        cmocka_unit_test(test_singular_jy_falls_back),
        cmocka_unit_test(test_unsymmetric_flagged_falls_back),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
