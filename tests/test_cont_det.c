/* test_cont_det.c - the continuation engine's determinant of the augmented
 * Jacobian, dense (LAPACK) and sparse (KLU, MUMPS), against an independent
 * Gaussian elimination, the check of a sparse Jacobian's pattern (a
 * duplicate entry is refused with a message), and MUMPS's SCOTCH ordering
 * held to one thread. */
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
/* determinant of the augmented Jacobian: dense, KLU, MUMPS against an  */
/* independent Gaussian elimination; F = A y - p b (linear), theta = 2  */

#define LN 7

static void lin_A(double *a)   /* column-major LN x LN, needs row pivoting */
{
    memset(a, 0, sizeof(double) * LN * LN);
    for (int i = 0; i < LN; i++) {
        a[((i + 1) % LN) * LN + i] = 1.0 + 0.1 * i;
        a[i * LN + i] = 1e-3 * (i + 1);
        a[((i + 3) % LN) * LN + i] += 0.05 * (i % 2 ? -1.0 : 1.0);
    }
}

static int lin_res(const double *y, double p, double *F, void *u)
{
    (void)u;
    double a[LN * LN];
    lin_A(a);
    for (int i = 0; i < LN; i++) {
        F[i] = -p * (1.0 + 0.2 * i);
        for (int j = 0; j < LN; j++) F[i] += a[j * LN + i] * y[j];
    }
    return 0;
}

static int lin_jac_sparse(const double *y, double p, SUNMatrix J, double *Fp, void *u)
{
    (void)y; (void)p; (void)u;
    double a[LN * LN];
    lin_A(a);
    dense_to_csc(J, LN, a);
    for (int i = 0; i < LN; i++) Fp[i] = -(1.0 + 0.2 * i);
    return 0;
}

/* sign and log|det| of an m x m column-major matrix (destroyed) */
static double ge_logdet(double *a, int m, int *sign)
{
    int sg = 1;
    double ld = 0.0;
    for (int k = 0; k < m; k++) {
        int piv = k;
        for (int i = k + 1; i < m; i++)
            if (fabs(a[k * m + i]) > fabs(a[k * m + piv])) piv = i;
        if (piv != k) {
            sg = -sg;
            for (int j = 0; j < m; j++) {
                double t = a[j * m + k]; a[j * m + k] = a[j * m + piv]; a[j * m + piv] = t;
            }
        }
        double d = a[k * m + k];
        if (d < 0) sg = -sg;
        ld += log(fabs(d));
        for (int i = k + 1; i < m; i++) {
            double l = a[k * m + i] / d;
            for (int j = k; j < m; j++) a[j * m + i] -= l * a[j * m + k];
        }
    }
    *sign = sg;
    return ld;
}

static void test_det_dense_klu(void **state)
{
    (void)state;
    const double theta = 2.0;
    static const int solver[3] = {CONT_LINSOL_DENSE, CONT_LINSOL_KLU, CONT_LINSOL_MUMPS};
    static const char *const name[3] = {"dense", "KLU", "MUMPS"};
    for (int ls = 0; ls < 3; ls++) {
        cont_problem prob = {.n = LN, .residual = lin_res, .jacobian = lin_jac_sparse,
                             .jac_matrix = CONT_MATRIX_SPARSE, .jac_nnz = 2};  /* grows */
        cont_solver *s = make(&prob, solver[ls]);
        CHECK_OK(cont_set_theta(s, theta), s);
        CHECK_OK(cont_set_max_steps(s, 3), s);
        double y0[LN] = {0};
        for (int dir = 1; dir >= -1; dir -= 2) {
            CHECK_OK(cont_start(s, y0, 0.5, dir), s);
            CHECK_TRUE(cont_run(s) == CONT_DONE, "run: %s", cont_errmsg(s));
            for (long k = 0; k < cont_num_points(s); k++) {
                const cont_point *q = cont_point_at(s, k);
                /* tangent: A ty = b tp, |ty|^2 + theta^2 tp^2 = 1, sign(tp) = dir */
                double a[LN * LN], r[LN], nt = theta * theta * q->tp * q->tp;
                lin_A(a);
                for (int i = 0; i < LN; i++) {
                    r[i] = -(1.0 + 0.2 * i) * q->tp;
                    for (int j = 0; j < LN; j++) r[i] += a[j * LN + i] * q->ty[j];
                    nt += q->ty[i] * q->ty[i];
                }
                CHECK_CLOSE(norm_inf(r, LN), 0.0, 1e-12);
                CHECK_CLOSE(nt, 1.0, 1e-12);
                CHECK_TRUE(q->tp * dir > 0, "tangent orientation: tp = %g, dir %d", q->tp, dir);
                /* independent det [A -b; ty^T theta^2 tp] */
                int m = LN + 1, sg;
                double M[(LN + 1) * (LN + 1)];
                for (int j = 0; j < LN; j++) {
                    for (int i = 0; i < LN; i++) M[j * m + i] = a[j * LN + i];
                    M[j * m + LN] = q->ty[j];
                }
                for (int i = 0; i < LN; i++) M[LN * m + i] = -(1.0 + 0.2 * i);
                M[LN * m + LN] = theta * theta * q->tp;
                double ld = ge_logdet(M, m, &sg);
                CHECK_TRUE(q->det_sign == sg, "%s, dir %d, point %ld: det sign %d, expected %d",
                           name[ls], dir, k, q->det_sign, sg);
                CHECK_CLOSE(q->log_abs_det, ld, 1e-10 * (1.0 + fabs(ld)));
            }
        }
        cont_free(s);
    }
}

/* A MUMPS solver sets SCOTCH_PTHREAD_NUMBER = 1 before its first analysis,
 * over the environment's value (cont_mumps_single_thread): SCOTCH, the
 * ordering of large matrices where MUMPS lacks METIS, gives other
 * orderings of one matrix from run to run with several threads.  First
 * in the group, before any MUMPS solver of this process. */
static void test_mumps_scotch_one_thread(void **state)
{
    (void)state;
    setenv("SCOTCH_PTHREAD_NUMBER", "4", 1);
    cont_problem prob = {.n = LN, .residual = lin_res, .jacobian = lin_jac_sparse,
                         .jac_matrix = CONT_MATRIX_SPARSE, .jac_nnz = 2};
    cont_solver *s = make(&prob, CONT_LINSOL_MUMPS);
    double y0[LN] = {0};
    CHECK_OK(cont_start(s, y0, 0.5, +1), s);
    const char *v = getenv("SCOTCH_PTHREAD_NUMBER");
    CHECK_TRUE(v && strcmp(v, "1") == 0, "SCOTCH_PTHREAD_NUMBER = %s", v ? v : "(unset)");
    cont_free(s);
}

static int dup_jac(const double *y, double p, SUNMatrix J, double *Fp, void *u)
{
    (void)y; (void)p; (void)u;
    sunindextype *ptr = SM_INDEXPTRS_S(J), *idx = SM_INDEXVALS_S(J);
    double *val = SM_DATA_S(J);
    ptr[0] = 0; idx[0] = 0; val[0] = 1.0; idx[1] = 0; val[1] = 0.5; ptr[1] = 2;
    Fp[0] = -1.0;
    return 0;
}

static int lin1_res(const double *y, double p, double *F, void *u)
{
    (void)u;
    F[0] = 1.5 * y[0] - p;
    return 0;
}

static void test_sparse_pattern_errors(void **state)
{
    (void)state;
    cont_problem prob = {.n = 1, .residual = lin1_res, .jacobian = dup_jac,
                         .jac_matrix = CONT_MATRIX_SPARSE, .jac_nnz = 4};
    cont_solver *s = make(&prob, CONT_LINSOL_KLU);
    double y0 = 0.0;
    CHECK_TRUE(cont_start(s, &y0, 0.0, +1) != CONT_OK, "duplicate entries accepted");
    CHECK_TRUE(strstr(cont_errmsg(s), "duplicate entry (0, 0)") != NULL, "message: %s",
               cont_errmsg(s));
    cont_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mumps_scotch_one_thread),
        cmocka_unit_test(test_det_dense_klu),
        cmocka_unit_test(test_sparse_pattern_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
