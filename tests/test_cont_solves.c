/* test_cont_solves.c - the MUMPS solves the corrector makes with the
 * LDL^T of a symmetric Jy (block elimination, continuation/cont_blockelim.c).
 *
 * Every call of dmumps_c from the engine goes through __wrap_dmumps_c
 * (linked with -Wl,--wrap=dmumps_c, tests/cont.mk), which counts the
 * solves (JOB = 3) of the symmetric factorisation (SYM = 2) and those among
 * them whose right-hand side is zero.
 *
 * Bratu u'' + lambda e^u = 0 (N = 300, symmetric tridiagonal Jy) through its
 * limit point, reusing corrector, block elimination: the tangent system
 * [Jy Fp; c^T] v = e_n has b_y = 0, so Jy^{-1} b_y = 0 needs no solve.
 * Checked: block elimination used, solves made, none of them with a zero
 * right-hand side (each tangent of the old code made one), and the path
 * the same as the LU of the whole bordered matrix (the problem without the
 * symmetric flag, whose MUMPS calls are unsymmetric and not counted) to
 * 1e-9. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <dmumps_c.h>

#include "cont.h"
#include "cont_test.h"

#define N 300
#define FTOL 1e-10

void __real_dmumps_c(DMUMPS_STRUC_C *id);
void __wrap_dmumps_c(DMUMPS_STRUC_C *id);

static long sym_solves, sym_zero_solves;

void __wrap_dmumps_c(DMUMPS_STRUC_C *id)
{
    if (id->job == 3 && id->sym == 2) {
        sym_solves++;
        int zero = 1;
        for (int i = 0; i < id->n && zero; i++) zero = id->rhs[i] == 0.0;
        sym_zero_solves += zero;
    }
    __real_dmumps_c(id);
}

static bratu bratu_n = {N};

static cont_solver *solver(int sym)
{
    cont_problem prob = {.n = N, .residual = bratu_res, .jacobian = bratu_jac_sparse,
                         .jac_matrix = CONT_MATRIX_SPARSE, .jac_nnz = 3 * N, .user = &bratu_n,
                         .jac_symmetric = sym};
    cont_solver *s = NULL;
    assert_int_equal(cont_create(&prob, CONT_LINSOL_MUMPS, &s), CONT_OK);
    CHECK_OK(cont_set_step(s, 2.0, 1e-8, 2.0), s);
    CHECK_OK(cont_set_prange(s, 0.5, 3.6), s);
    CHECK_OK(cont_set_max_steps(s, 40), s);
    CHECK_OK(cont_set_newton(s, FTOL, 10, 0), s);
    return s;
}

static void test_no_solve_of_a_zero_rhs(void **state)
{
    (void)state;
    double u0[N];
    memset(u0, 0, sizeof u0);
    cont_solver *sa = solver(1), *sb = solver(0);
    sym_solves = sym_zero_solves = 0;
    CHECK_OK(cont_start(sa, u0, 0.5, +1), sa);
    int st = cont_run(sa);
    CHECK_TRUE(st == CONT_DONE, "status %d: %s", st, cont_errmsg(sa));
    long solves = sym_solves, zero = sym_zero_solves;
    CHECK_OK(cont_start(sb, u0, 0.5, +1), sb);
    st = cont_run(sb);
    CHECK_TRUE(st == CONT_DONE, "status %d: %s", st, cont_errmsg(sb));
    CHECK_TRUE(sym_solves == solves, "the LU run made %ld symmetric solves", sym_solves - solves);
    cont_stats ta, tb;
    cont_get_stats(sa, NULL, &ta);
    cont_get_stats(sb, NULL, &tb);
    long np = cont_num_points(sa);
    print_message("# Bratu: %ld points, %ld factorisations (%ld fell back to the LU), "
                  "%ld bordered solves, %ld MUMPS LDL^T solves, %ld of them with a zero "
                  "right-hand side\n", np, ta.nfactor, ta.nfallback, ta.nlinsolve, solves, zero);
    CHECK_TRUE(2 * ta.nfallback < ta.nfactor && solves > np,
               "block elimination used for %ld of %ld factorisations, %ld solves",
               ta.nfactor - ta.nfallback, ta.nfactor, solves);
    CHECK_TRUE(zero == 0, "%ld of %ld LDL^T solves had a zero right-hand side", zero, solves);
    CHECK_TRUE(np == cont_num_points(sb) && np > 10, "%ld points against %ld", np,
               cont_num_points(sb));
    path_diff d = compare_paths(sa, sb, N, bratu_res, &bratu_n, "Bratu");
    CHECK_TRUE(d.dx <= 1e-9 && d.dt <= 1e-9 && d.rmax <= FTOL,
               "points differ by %g, tangents by %g, largest residual %g", d.dx, d.dt, d.rmax);
    CHECK_TRUE(count_label(sa, "LP") == 1, "%d limit points", count_label(sa, "LP"));
    cont_free(sa);
    cont_free(sb);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_no_solve_of_a_zero_rhs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
