/* test_cont_bigstep.c - two options of the engine for long steps
 * (continuation/cont.h), on Bratu u'' + lambda e^u = 0 (N = 300 central
 * differences, sparse, MUMPS, the reusing corrector) through its limit point:
 *   cont_set_predictor(s, 2)  the second-order predictor: with a fixed step
 *       the corrector solves the same systems (same hyperplanes) from a
 *       closer guess, so the path must be the tangent predictor's to 1e-9
 *       (points, tangents, determinant signs, the limit point) with fewer
 *       Newton iterations;
 *   cont_set_arc_scale(s, a)  the arclength norm a^2 |dy|^2 + dp^2: every
 *       delivered tangent is a unit vector of that norm and every step
 *       satisfies its border t_prev . W (x - x_prev) = ds in it, to the
 *       Newton tolerance.
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

static bratu bratu_n = {N};

static cont_solver *follow(int order, double arc, double ds, double ds_max)
{
    cont_problem prob = {.n = N, .residual = bratu_res, .jacobian = bratu_jac_sparse,
                         .jac_matrix = CONT_MATRIX_SPARSE, .jac_nnz = 3 * N, .user = &bratu_n};
    cont_solver *s = make(&prob, CONT_LINSOL_MUMPS);
    CHECK_OK(cont_set_predictor(s, order), s);
    if (arc > 0) CHECK_OK(cont_set_arc_scale(s, arc), s);
    CHECK_OK(cont_set_step(s, ds, 1e-8, ds_max), s);
    CHECK_OK(cont_set_prange(s, 0.5, 3.6), s);
    CHECK_OK(cont_set_max_steps(s, 1000), s);
    CHECK_OK(cont_set_newton(s, FTOL, 10, 0), s);
    double *y = calloc(N, sizeof(double));
    CHECK_OK(cont_start(s, y, 0.5, +1), s);
    int st = cont_run(s);
    CHECK_TRUE(st == CONT_DONE, "status %d: %s", st, cont_errmsg(s));
    free(y);
    return s;
}

static const cont_point *limit_point(const cont_solver *s)
{
    for (long k = 0; k < cont_num_special(s); k++)
        if (cont_special_at(s, k)->type == CONT_PT_LP) return cont_special_at(s, k);
    return NULL;
}

static void test_second_order_predictor(void **state)
{
    (void)state;
    /* a fixed step (ds = ds_max, no retry): both take the same hyperplanes */
    cont_solver *a = follow(1, 0.0, 1.0, 1.0), *b = follow(2, 0.0, 1.0, 1.0);
    cont_stats ta, tb;
    cont_get_stats(a, NULL, &ta);
    cont_get_stats(b, NULL, &tb);
    long np = cont_num_points(a);
    CHECK_TRUE(np == cont_num_points(b) && np > 10, "%ld points against %ld", np,
               cont_num_points(b));
    CHECK_TRUE(ta.retries == 0 && tb.retries == 0, "retries %ld, %ld", ta.retries, tb.retries);
    path_diff d = compare_paths(b, a, N, bratu_res, &bratu_n, "Bratu");
    const cont_point *la = limit_point(a), *lb = limit_point(b);
    print_message("# Bratu, fixed step 1: %ld points, agree to %.2g, tangents %.2g, largest "
                  "residual %.2g; Newton iterations %ld (order 2) against %ld (order 1)\n", np,
                  d.dx, d.dt, d.rmax, tb.newton_iters, ta.newton_iters);
    CHECK_TRUE(d.dx <= 1e-9 && d.dt <= 1e-9, "points differ by %g, tangents by %g", d.dx, d.dt);
    CHECK_TRUE(d.rmax <= FTOL, "a point's residual is %g", d.rmax);
    CHECK_TRUE(la && lb, "no limit point");
    if (la && lb) CHECK_CLOSE(lb->p, la->p, 1e-9 * la->p);
    /* closer guesses: fewer iterations (the first step is of order 1 in both) */
    CHECK_TRUE(tb.newton_iters < ta.newton_iters, "Newton iterations %ld (order 2) against %ld",
               tb.newton_iters, ta.newton_iters);
    cont_free(a);
    cont_free(b);
}

static void test_arc_scale(void **state)
{
    (void)state;
    const double a = 1.0 / sqrt((double)N);   /* the RMS change of u */
    cont_solver *s = follow(1, a, 0.05, 0.2);
    long np = cont_num_points(s);
    double tmax = 0.0, bmax = 0.0;
    for (long k = 0; k < np; k++) {
        const cont_point *q = cont_point_at(s, k);
        double t2 = 0.0;
        for (long i = 0; i < N; i++) t2 += q->ty[i] * q->ty[i];
        tmax = fmax(tmax, fabs(a * a * t2 + q->tp * q->tp - 1.0));
        if (k == 0 || q->type != CONT_PT_REGULAR) continue;
        /* the border of the step from the previous regular point */
        const cont_point *b = NULL;
        for (long j = k - 1; j >= 0 && !b; j--)
            if (cont_point_at(s, j)->type == CONT_PT_REGULAR || j == 0) b = cont_point_at(s, j);
        double g = (q->p - b->p) * b->tp;
        for (long i = 0; i < N; i++) g += a * a * b->ty[i] * (q->y[i] - b->y[i]);
        bmax = fmax(bmax, fabs(g - q->ds));
    }
    cont_solver *u = follow(1, 0.0, 0.05, 0.2);   /* the unscaled norm */
    print_message("# Bratu, arc scale 1/sqrt(N): %ld points (%ld unscaled); tangents unit to "
                  "%.2g, borders to %.2g\n", np, cont_num_points(u), tmax, bmax);
    CHECK_TRUE(np > 10, "%ld points", np);
    CHECK_TRUE(tmax <= 1e-12, "a tangent's scaled norm is off 1 by %g", tmax);
    CHECK_TRUE(bmax <= 1e-9, "a step's border is off by %g", bmax);
    CHECK_TRUE(np < cont_num_points(u), "%ld points against %ld unscaled", np,
               cont_num_points(u));
    CHECK_TRUE(limit_point(s) != NULL, "no limit point in the scaled norm");
    cont_free(s);
    cont_free(u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_second_order_predictor),
        cmocka_unit_test(test_arc_scale),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
