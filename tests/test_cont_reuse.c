/* test_cont_reuse.c - the corrector CONT_CORRECTOR_REUSE (continuation/
 * cont.h: the engine's Newton, the tangent and determinant sign of a
 * corrected point from the factors of the last Newton iteration, refined)
 * against CONT_CORRECTOR_NEWTON (KINSOL and a fresh factorisation per
 * point), on sparse problems with MUMPS:
 *   Bratu   u'' + lambda e^u = 0, N = 300 central differences, through its
 *           limit point
 *   chain   x0 (p - x0^2) = 0 with 299 components z_i + z_i^3 / 2 =
 *           (i/299) (p + x0^2): branch point at p = 0 on the trivial branch
 * The two paths must be the same: the same points, tangents, determinant
 * signs and special points to 1e-9, with fewer factorisations; every
 * accepted point's residual is recomputed here and must be below ftol.
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

static bratu bratu_n = {N};   /* the user data of bratu_res */

static int chain_res(const double *y, double p, double *F, void *ud)
{
    (void)ud;
    double x = y[0];
    F[0] = x * (p - x * x);
    for (long i = 1; i < N; i++)
        F[i] = y[i] + 0.5 * y[i] * y[i] * y[i] - (double)i / (N - 1.0) * (p + x * x);
    return 0;
}

static int chain_jac(const double *y, double p, SUNMatrix J, double *Fp, void *ud)
{
    (void)ud;
    double x = y[0];
    sunindextype *ptr = SM_INDEXPTRS_S(J), *idx = SM_INDEXVALS_S(J);
    double *val = SM_DATA_S(J);
    sunindextype k = 0;
    ptr[0] = 0;   /* column 0: dF0/dx, dFi/dx */
    idx[k] = 0; val[k++] = p - 3.0 * x * x;
    for (long i = 1; i < N; i++) { idx[k] = i; val[k++] = -2.0 * x * (double)i / (N - 1.0); }
    for (long j = 1; j < N; j++) {
        ptr[j] = k;
        idx[k] = j; val[k++] = 1.0 + 1.5 * y[j] * y[j];
    }
    ptr[N] = k;
    Fp[0] = x;
    for (long i = 1; i < N; i++) Fp[i] = -(double)i / (N - 1.0);
    return 0;
}

typedef struct run {
    cont_solver *s;
    cont_stats tot;
} run;

static void follow(run *r, int corrector, int (*res)(const double *, double, double *, void *),
                   int (*jac)(const double *, double, SUNMatrix, double *, void *),
                   void *user, double p0, double p1, double ds, long max_steps)
{
    cont_problem prob = {.n = N, .residual = res, .jacobian = jac,
                         .jac_matrix = CONT_MATRIX_SPARSE, .jac_nnz = 3 * N, .user = user};
    cont_solver *s = NULL;
    assert_int_equal(cont_create(&prob, CONT_LINSOL_MUMPS, &s), CONT_OK);
    CHECK_TRUE(cont_get_corrector(s) == CONT_CORRECTOR_REUSE, "default corrector with MUMPS");
    CHECK_OK(cont_set_corrector(s, corrector), s);
    CHECK_OK(cont_set_step(s, ds, 1e-8, ds), s);
    CHECK_OK(cont_set_prange(s, p0, p1), s);
    CHECK_OK(cont_set_max_steps(s, max_steps), s);
    CHECK_OK(cont_set_newton(s, FTOL, 10, 0), s);
    double *y = calloc(N, sizeof(double));
    CHECK_OK(cont_start(s, y, p0, +1), s);
    int st = cont_run(s);
    CHECK_TRUE(st == CONT_DONE, "status %d: %s", st, cont_errmsg(s));
    cont_get_stats(s, NULL, &r->tot);
    r->s = s;
    free(y);
}

/* the paths of a (REUSE) and b (NEWTON) agree; a's residuals are below ftol */
static void compare(const run *a, const run *b,
                    int (*res)(const double *, double, double *, void *), void *user,
                    const char *what)
{
    long np = cont_num_points(a->s);
    CHECK_TRUE(np == cont_num_points(b->s) && np > 10, "%s: %ld points against %ld", what, np,
               cont_num_points(b->s));
    path_diff d = compare_paths(a->s, b->s, N, res, user, what);
    double dx = d.dx, dt = d.dt, rmax = d.rmax;
    print_message("# %s: %ld points, points agree to %.2g, tangents to %.2g, largest residual "
                  "%.2g; factorisations %ld (reuse) against %ld, Newton iterations %ld and %ld\n",
                  what, np, dx, dt, rmax, a->tot.nfactor, b->tot.nfactor, a->tot.newton_iters,
                  b->tot.newton_iters);
    CHECK_TRUE(dx <= 1e-9, "%s: points differ by %g relative", what, dx);
    CHECK_TRUE(dt <= 1e-9, "%s: tangents differ by %g relative", what, dt);
    CHECK_TRUE(rmax <= FTOL, "%s: a point's residual is %g > ftol", what, rmax);
    CHECK_TRUE(a->tot.newton_iters == b->tot.newton_iters, "%s: Newton iterations %ld, %ld",
               what, a->tot.newton_iters, b->tot.newton_iters);
    /* one factorisation saved at every regular point of the path */
    CHECK_TRUE(a->tot.nfactor + np - 1 - cont_num_special(a->s) <= b->tot.nfactor,
               "%s: %ld factorisations against %ld", what, a->tot.nfactor, b->tot.nfactor);
}

static void test_bratu_same_path(void **state)
{
    (void)state;
    run a, b;
    follow(&a, CONT_CORRECTOR_REUSE, bratu_res, bratu_jac_sparse, &bratu_n, 0.5, 3.6, 2.0, 40);
    follow(&b, CONT_CORRECTOR_NEWTON, bratu_res, bratu_jac_sparse, &bratu_n, 0.5, 3.6, 2.0, 40);
    compare(&a, &b, bratu_res, &bratu_n, "Bratu");
    const cont_point *lp = NULL;
    for (long k = 0; k < cont_num_special(a.s); k++)
        if (cont_special_at(a.s, k)->type == CONT_PT_LP) lp = cont_special_at(a.s, k);
    CHECK_TRUE(lp != NULL, "no limit point on the Bratu path");
    /* lambda* of the N = 300 scheme is within 1e-4 of the continuous 3.513830719 */
    if (lp) CHECK_CLOSE(lp->p, 3.513830719, 1e-4);
    cont_free(a.s);
    cont_free(b.s);
}

static void test_chain_branch_point(void **state)
{
    (void)state;
    run a, b;
    follow(&a, CONT_CORRECTOR_REUSE, chain_res, chain_jac, NULL, -1.0, 1.0, 0.15, 100);
    follow(&b, CONT_CORRECTOR_NEWTON, chain_res, chain_jac, NULL, -1.0, 1.0, 0.15, 100);
    compare(&a, &b, chain_res, NULL, "chain");
    int nbp = 0;
    for (long k = 0; k < cont_num_special(a.s); k++) {
        const cont_point *q = cont_special_at(a.s, k);
        if (q->type != CONT_PT_BP) continue;
        nbp++;
        CHECK_CLOSE(q->p, 0.0, 1e-8);
        CHECK_CLOSE(q->y[0], 0.0, 1e-8);
    }
    CHECK_TRUE(nbp == 1, "%d branch points on the chain path (expected 1 at p = 0)", nbp);
    cont_free(a.s);
    cont_free(b.s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bratu_same_path),
        cmocka_unit_test(test_chain_branch_point),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
