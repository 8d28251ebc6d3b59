/* test_sstab_qr.c - the rank-revealing QR of sstab_rows.c factorises C^T
 * alone (docs/design/linear-algebra.md, "Cost of the inertia method along a path").
 *
 * C: the difference rows x_b - x_a of the edges of a G x G grid graph
 * (an incidence matrix: rank n - 1, n = G^2 nodes, the constant vector
 * its null space; a set of rows is independent exactly when its edges
 * form no cycle).  One sf_rowbasis_select must
 *  - keep n - 1 rows whose edges form a spanning tree (union-find), each
 *    with a Heath residual above the QR's tolerance 1e-9;
 *  - do the operations of SuiteSparseQR on C^T alone (its own count, from
 *    an independent call on the same scaled matrix), not those of
 *    SuiteSparseQR_C_QR, which factorises [C^T, I] to form Q even when Q
 *    is not asked for (before 2026-11-27: 5 to 10 times the work on the
 *    Miura paths; here the test checks that the two counts differ). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <SuiteSparseQR_C.h>
#include <cmocka.h>

#include "sf_test.h"
#include "sstab_rows.h"

#define G 40 /* grid side */

static int find(int *up, int i)
{
    while (up[i] != i) i = up[i] = up[up[i]];
    return i;
}

/* SuiteSparseQR's operation count for the unit rows of C as columns, with
 * [C^T, I] (with_q) or C^T alone; *rank its rank. */
static double spqr_flops(const sf_csc *C, double scale, int with_q, long *rank)
{
    cholmod_common cc;
    cholmod_l_start(&cc);
    cc.print = 0;
    int n = C->ncol, m = C->nrow;
    long nnz = C->colptr[n];
    /* A = C^T (n x m): column i of A = row i of C */
    cholmod_sparse *A = cholmod_l_allocate_sparse((size_t)n, (size_t)m, (size_t)nnz, 1, 1, 0,
                                                  CHOLMOD_REAL, &cc);
    assert_non_null(A);
    SuiteSparse_long *Ap = A->p, *Ai = A->i;
    double *Ax = A->x;
    memset(Ap, 0, sizeof(SuiteSparse_long) * (size_t)(m + 1));
    for (long k = 0; k < nnz; k++) Ap[C->rowind[k] + 1]++;
    for (int i = 0; i < m; i++) Ap[i + 1] += Ap[i];
    SuiteSparse_long *next = malloc(sizeof(SuiteSparse_long) * (size_t)m);
    assert_non_null(next);
    memcpy(next, Ap, sizeof(SuiteSparse_long) * (size_t)m);
    for (int j = 0; j < n; j++)
        for (int k = C->colptr[j]; k < C->colptr[j + 1]; k++) {
            int i = C->rowind[k];
            Ai[next[i]] = j;
            Ax[next[i]++] = C->val[k] * scale;
        }
    free(next);
    cholmod_sparse *R = NULL;
    SuiteSparse_long *E = NULL;
    SuiteSparse_long r =
        with_q ? SuiteSparseQR_C_QR(SPQR_ORDERING_DEFAULT, 1e-9, 0, A, NULL, &R, &E, &cc)
               : SuiteSparseQR_C(SPQR_ORDERING_DEFAULT, 1e-9, 0, 0, A, NULL, NULL, NULL, NULL, &R,
                                 &E, NULL, NULL, NULL, &cc);
    double flops = cc.SPQR_flopcount;
    *rank = (long)r;
    cholmod_l_free_sparse(&R, &cc);
    if (E) cholmod_l_free((size_t)m, sizeof(SuiteSparse_long), E, &cc);
    cholmod_l_free_sparse(&A, &cc);
    cholmod_l_finish(&cc);
    return flops;
}

static void test_grid_rows(void **state)
{
    (void)state;
    enum { N = G * G, M = 2 * G * (G - 1) };
    static int ea[M], eb[M], cp[N + 1], ri[2 * M], rnew[M], up[N];
    static double cv[2 * M], rs[M];
    int m = 0;
    for (int y = 0; y < G; y++)
        for (int x = 0; x < G; x++) {
            int v = y * G + x;
            if (x + 1 < G) ea[m] = v, eb[m++] = v + 1;
            if (y + 1 < G) ea[m] = v, eb[m++] = v + G;
        }
    assert_int_equal(m, M);
    /* CSC of C (M x N): row e has -1 at ea[e], +1 at eb[e] */
    memset(cp, 0, sizeof cp);
    for (int e = 0; e < M; e++) cp[ea[e] + 1]++, cp[eb[e] + 1]++;
    for (int j = 0; j < N; j++) cp[j + 1] += cp[j];
    int fill[N];
    memcpy(fill, cp, sizeof fill);
    for (int e = 0; e < M; e++) { /* rows in increasing order within each column */
        ri[fill[ea[e]]] = e;
        cv[fill[ea[e]]++] = -1.0;
        ri[fill[eb[e]]] = e;
        cv[fill[eb[e]]++] = 1.0;
    }
    sf_csc C = {M, N, cp, ri, cv};
    for (int e = 0; e < M; e++) {
        rs[e] = 1.0 / sqrt(2.0);
        rnew[e] = e;
    }
    sf_rowbasis *b;
    sf_error err;
    sf_error_clear(&err);
    assert_int_equal(sf_rowbasis_create(&b, N, M, &err), SF_OK);
    int mk = 0, failed = 0;
    assert_int_equal(sf_rowbasis_select(b, &C, rs, rnew, M, &mk, &failed, &err), SF_OK);
    assert_int_equal(failed, 0);
    assert_int_equal(mk, N - 1);
    /* the kept edges: no cycle (then N - 1 of them span the N nodes) */
    const double *res = sf_rowbasis_resid(b);
    for (int v = 0; v < N; v++) up[v] = v;
    int kept = 0;
    for (int e = 0; e < M; e++) {
        if (rnew[e] < 0) continue;
        kept++;
        assert_true(res[e] > 1e-9);
        int a = find(up, ea[e]), c = find(up, eb[e]);
        assert_int_not_equal(a, c);
        up[a] = c;
    }
    assert_int_equal(kept, N - 1);
    /* the work: that of C^T alone */
    long r_alone = 0, r_q = 0;
    double alone = spqr_flops(&C, 1.0 / sqrt(2.0), 0, &r_alone);
    double with_q = spqr_flops(&C, 1.0 / sqrt(2.0), 1, &r_q);
    double got = sf_rowbasis_qr_flops(b);
    print_message("# grid %d x %d: rank %d, SuiteSparseQR operations %.4g (C^T alone %.4g, "
                  "[C^T, I] %.4g)\n", G, G, mk, got, alone, with_q);
    assert_int_equal(r_alone, N - 1);
    assert_int_equal(r_q, N - 1);
    assert_true(with_q > 1.5 * alone); /* the two ways differ on this matrix */
    assert_true(got == alone);
    sf_rowbasis_free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grid_rows),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
