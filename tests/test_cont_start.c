/* test_cont_start.c - Newton at fixed p in cont_start with a symmetric Jy:
 * the engine's own LDL^T (block elimination) instead of KINSOL's
 * unsymmetric LU of the bordered matrix, and KINSOL's line search where
 * full Newton steps do not lower the residual.
 *
 * Every dmumps_c call of the engine goes through __wrap_dmumps_c (linked
 * with -Wl,--wrap=dmumps_c, tests/cont.mk), which counts factorisations
 * (JOB = 2) by symmetry: SYM = 2 is the engine's LDL^T of Jy, SYM = 0 the
 * LU of the bordered matrix.
 *
 * 1. Bratu u'' + lambda e^u = 0 (N = 300) from u = 0 at lambda = 2: no
 *    unsymmetric factorisation (the old start made one per Newton
 *    iteration), and the start point that of KINSOL with the dense LU to
 *    1e-10.
 * 2. atan(u_i) = p (N = 50, diagonal Jy) from u = 2 at p = 0.3: full
 *    Newton steps diverge there (|u| > 1.39), so the start must fall back
 *    to the line search (unsymmetric factorisations made) and still end on
 *    u_i = tan 0.3. */
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

#define FTOL 1e-10

void __real_dmumps_c(DMUMPS_STRUC_C *id);
void __wrap_dmumps_c(DMUMPS_STRUC_C *id);

static long sym_factors, unsym_factors;

void __wrap_dmumps_c(DMUMPS_STRUC_C *id)
{
    if (id->job == 2) {
        if (id->sym == 0) unsym_factors++;
        else sym_factors++;
    }
    __real_dmumps_c(id);
}

#define NB 300
static bratu bratu_n = {NB};

static cont_solver *bratu_solver(int linsol)
{
    cont_problem prob = {.n = NB, .residual = bratu_res, .jacobian = bratu_jac_sparse,
                         .jac_matrix = CONT_MATRIX_SPARSE, .jac_nnz = 3 * NB, .user = &bratu_n,
                         .jac_symmetric = 1};
    cont_solver *s = make(&prob, linsol);
    CHECK_OK(cont_set_prange(s, 0.5, 3.6), s);
    CHECK_OK(cont_set_newton(s, FTOL, 10, 0), s);
    return s;
}

static void test_start_uses_the_symmetric_factorisation(void **state)
{
    (void)state;
    double u0[NB];
    memset(u0, 0, sizeof u0);
    cont_solver *s = bratu_solver(CONT_LINSOL_MUMPS), *r = bratu_solver(CONT_LINSOL_DENSE);
    sym_factors = unsym_factors = 0;
    CHECK_OK(cont_start(s, u0, 2.0, +1), s);
    long sym = sym_factors, unsym = unsym_factors;
    print_message("# Bratu start: %ld LDL^T and %ld LU factorisations\n", sym, unsym);
    CHECK_TRUE(unsym == 0 && sym >= 1, "%ld LU and %ld LDL^T factorisations in the start",
               unsym, sym);
    CHECK_OK(cont_start(r, u0, 2.0, +1), r);
    const cont_point *a = cont_point_at(s, 0), *b = cont_point_at(r, 0);
    double d = 0.0;
    for (int i = 0; i < NB; i++) d = fmax(d, rel_diff(a->y[i], b->y[i]));
    CHECK_TRUE(d <= 1e-10 && a->p == 2.0, "start points differ by %g (p = %.17g)", d, a->p);
    CHECK_TRUE(a->y[NB / 2] > 0.3, "not the Bratu solution: u(1/2) = %g", a->y[NB / 2]);
    cont_free(s);
    cont_free(r);
}

#define NA 50

static int atan_res(const double *u, double p, double *F, void *ud)
{
    (void)ud;
    for (int i = 0; i < NA; i++) F[i] = atan(u[i]) - p;
    return 0;
}

static int atan_jac(const double *u, double p, SUNMatrix J, double *Fp, void *ud)
{
    (void)p;
    (void)ud;
    sunindextype *ptr = SM_INDEXPTRS_S(J), *idx = SM_INDEXVALS_S(J);
    double *val = SM_DATA_S(J);
    for (int j = 0; j < NA; j++) {
        ptr[j] = j;
        idx[j] = j;
        val[j] = 1.0 / (1.0 + u[j] * u[j]);
        Fp[j] = -1.0;
    }
    ptr[NA] = NA;
    return 0;
}

static void test_start_falls_back_to_the_line_search(void **state)
{
    (void)state;
    cont_problem prob = {.n = NA, .residual = atan_res, .jacobian = atan_jac,
                         .jac_matrix = CONT_MATRIX_SPARSE, .jac_nnz = NA, .jac_symmetric = 1};
    cont_solver *s = make(&prob, CONT_LINSOL_MUMPS);
    CHECK_OK(cont_set_prange(s, -1.0, 1.0), s);
    CHECK_OK(cont_set_newton(s, FTOL, 10, 0), s);
    double u0[NA];
    for (int i = 0; i < NA; i++) u0[i] = 2.0;
    sym_factors = unsym_factors = 0;
    CHECK_OK(cont_start(s, u0, 0.3, +1), s);
    print_message("# atan start: %ld LDL^T and %ld LU factorisations\n", sym_factors,
                  unsym_factors);
    CHECK_TRUE(unsym_factors > 0, "no line search (%ld LDL^T factorisations)", sym_factors);
    const cont_point *a = cont_point_at(s, 0);
    for (int i = 0; i < NA; i++) CHECK_CLOSE(a->y[i], tan(0.3), 1e-9);
    cont_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_start_uses_the_symmetric_factorisation),
        cmocka_unit_test(test_start_falls_back_to_the_line_search),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
