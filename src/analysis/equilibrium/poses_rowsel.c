/* poses_rowsel.c - a maximal independent set of the pose formulation's
 * fold rows (see poses_rowsel.h): SuiteSparseQR's rank-revealing QR of the
 * scaled C^T at one state. */
#include "poses_rowsel.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <SuiteSparseQR_C.h>

/* Uniform in [-0.5, 0.5) from a 64-bit LCG state (local: no global state). */
static double next_u(uint64_t *s)
{
    *s = *s * 6364136223846793005u + 1442695040888963407u;
    return (double)((*s >> 11) & ((UINT64_C(1) << 52) - 1)) / 4503599627370496.0 - 0.5;
}

int sf_rowsel_generic_state(const sf_poses *P, double lref, double amp, unsigned seed, double *x)
{
    uint64_t s = seed ? seed : 1u;
    for (int j = 0; j < P->nq; j++) x[j] = next_u(&s);
    if (sf_poses_from_folds(P, x, x)) return SF_ENOMEM;
    for (int j = P->nq; j < P->nx; j++) {
        int pos = (j - P->nq) % 6 >= 3;
        x[j] += amp * next_u(&s) * (pos ? lref : 1.0);
    }
    return SF_OK;
}

/* A = C^T (nx x 6 N) at x, column r = fold row r, scaled as Newton sees
 * it: row r of fold i by 1 (rotation) or 1 / lref (translation), position
 * columns by lref.  *longest: the longest column.  NULL: out of memory. */
static cholmod_sparse *rows_transposed(const sf_poses *P, const double *x, double lref,
                                       double *longest, cholmod_common *cc)
{
    const sf_model *m = P->m;
    int nx = P->nx, nrows = 6 * m->nfolds, nv = P->maxnv;
    int *col = malloc(sizeof(int) * ((size_t)nv + 1));
    int *ord = malloc(sizeof(int) * ((size_t)nv + 1));
    double *dg = malloc(sizeof(double) * (6 * (size_t)nv + 1));
    double *work = malloc(sizeof(double) * (sf_poses_work_size(P) + 1));
    cholmod_sparse *A = NULL;
    if (col && ord && dg && work)
        A = cholmod_l_allocate_sparse((size_t)nx, (size_t)nrows, (size_t)nrows * nv, 1, 1, 0,
                                      CHOLMOD_REAL, cc);
    *longest = 0.0;
    if (A) {
        SuiteSparse_long *Ap = A->p, *Ai = A->i;
        double *Ax = A->x;
        long nz = 0;
        int fold = -1, n = 0;
        for (int k = 0; k < nrows; k++) {
            int i = k / 6, c = k % 6;
            if (i != fold) {
                fold = i;
                n = sf_poses_fold_vars(P, i, col);
                double g[6];
                sf_poses_fold_rows(P, x, i, g, dg, NULL, NULL, work);
                /* the columns of a fold ascending (CHOLMOD wants sorted rows) */
                for (int a = 0; a < n; a++) ord[a] = a;
                for (int a = 1; a < n; a++)
                    for (int b = a; b > 0 && col[ord[b - 1]] > col[ord[b]]; b--) {
                        int t = ord[b];
                        ord[b] = ord[b - 1];
                        ord[b - 1] = t;
                    }
            }
            double f = c < 3 ? 1.0 : 1.0 / lref, len = 0.0;
            Ap[k] = nz;
            for (int b = 0; b < n; b++) {
                int j = col[ord[b]];
                if (j < 0) continue;
                int pos = j >= P->nq && (j - P->nq) % 6 >= 3;
                double v = f * dg[c * n + ord[b]] * (pos ? lref : 1.0);
                if (v == 0.0) continue;
                Ai[nz] = j;
                Ax[nz++] = v;
                len += v * v;
            }
            *longest = fmax(*longest, sqrt(len));
        }
        Ap[nrows] = nz;
    }
    free(col);
    free(ord);
    free(dg);
    free(work);
    return A;
}

/* Rank of A (Heath's rank detection, tolerance rtol times the longest
 * column); the columns of a maximal independent set into indep[] (0/1).
 * Returns the rank, or -1 (error in err). */
static long independent_columns(cholmod_sparse *A, double longest, double rtol, int *indep,
                                cholmod_common *cc, sf_error *err)
{
    long ncol = (long)A->ncol;
    cholmod_sparse *R = NULL;
    SuiteSparse_long *E = NULL;
    /* no right-hand side: SuiteSparseQR_C_QR would factorise [A, I] to form
     * an unused Q (docs/guides/stability.md, "The QR of C^T alone") */
    SuiteSparse_long rank = SuiteSparseQR_C(SPQR_ORDERING_DEFAULT, rtol * longest, 0, 0, A, NULL,
                                            NULL, NULL, NULL, &R, &E, NULL, NULL, NULL, cc);
    if (R) cholmod_l_free_sparse(&R, cc);
    if (rank < 0) {
        if (E) cholmod_l_free((size_t)ncol, sizeof(SuiteSparse_long), E, cc);
        return cc->status == CHOLMOD_OUT_OF_MEMORY
                   ? (sf_fail(err, SF_ENOMEM, "out of memory (SuiteSparseQR)"), -1)
                   : (sf_fail(err, SF_ENUMERIC, "pose rows: SuiteSparseQR failed (status %d)",
                              cc->status), -1);
    }
    /* A E = Q R with the rank-revealing permutation last: the first
     * `rank` columns of A E are the independent ones (E = NULL: identity) */
    for (long k = 0; k < ncol; k++) indep[k] = 0;
    for (SuiteSparse_long k = 0; k < rank; k++) indep[E ? E[k] : k] = 1;
    if (E) cholmod_l_free((size_t)ncol, sizeof(SuiteSparse_long), E, cc);
    return (long)rank;
}

int sf_rowsel_select(const sf_poses *P, const double *x, double lref, double rtol, int *keep,
                     int *nkeep, int *rank_out, sf_error *err)
{
    int nx = P->nx, nrows = 6 * P->m->nfolds;
    *nkeep = nrows;
    *rank_out = nrows;
    for (int r = 0; r < nrows; r++) keep[r] = 1;
    if (nrows == 0) return SF_OK;
    int *ind = malloc(sizeof(int) * ((size_t)nrows + 1));
    if (!ind) return sf_fail(err, SF_ENOMEM, "out of memory");
    cholmod_common cc;
    cholmod_l_start(&cc);
    cc.print = 0;
    cc.error_handler = NULL;
    int rc = SF_OK;
    double longest;
    cholmod_sparse *A = rows_transposed(P, x, lref, &longest, &cc);
    long rank = A ? independent_columns(A, longest, rtol, ind, &cc, err) : -2;
    if (A) cholmod_l_free_sparse(&A, &cc);
    if (rank == -2) rc = sf_fail(err, SF_ENOMEM, "out of memory (CHOLMOD)");
    else if (rank < 0) rc = err->code;
    else {
        *rank_out = (int)rank;
        if (rank < nrows && rank < nx) {
            for (int r = 0; r < nrows; r++) keep[r] = ind[r];
            *nkeep = (int)rank;
        }
    }
    cholmod_l_finish(&cc);
    free(ind);
    return rc;
}
