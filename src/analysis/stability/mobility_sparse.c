/* mobility_sparse.c - first-order mobility of a whole sheet from the
 * sparse loop-row Jacobian (see mobility.h, sf_mobility_first_order). */
#include "mobility.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <SuiteSparseQR_C.h>

#define RANK_RTOL 1e-8 /* as the dense analysis: relative to the largest (here: longest row) */
#define RANK_ATOL 1e-12
#define LOCAL_MAX 64   /* coordinates of one vertex (sf_constraints_vertex) */

int sf_mobility_first_order(const sf_model *m, const double *q, int *first, sf_error *err)
{
    const sf_topology *t = m->topo;
    int nq = m->nq, nv = t->nivertices, ncon = 6 * nv;
    *first = nq;
    if (nv == 0) return SF_OK;
    double lref = 0.0;
    for (int i = 0; i < m->nfolds; i++) lref += m->study->folds[i].width / m->nfolds;
    if (!(lref > 0)) lref = 1.0;
    sf_kin k;
    if (sf_kin_alloc(m, &k)) return sf_fail(err, SF_ENOMEM, "out of memory");
    double *q0 = calloc((size_t)nq + 1, sizeof(double));
    if (!q0) {
        sf_kin_free(&k);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    if (q) memcpy(q0, q, sizeof(double) * (size_t)nq);
    sf_kin_eval(m, q0, 1, &k);
    free(q0);
    cholmod_common cc;
    cholmod_l_start(&cc);
    cc.print = 0;
    cc.error_handler = NULL;
    /* A = J^T (nq x ncon): column 6 v + e is loop row e of vertex v, scaled
     * as the dense analysis scales it (translation rows by 1 / mean width) */
    cholmod_sparse *A = cholmod_l_allocate_sparse((size_t)nq, (size_t)ncon,
                                                  (size_t)ncon * LOCAL_MAX, 1, 1, 0, CHOLMOD_REAL,
                                                  &cc);
    int rc = SF_OK;
    if (!A) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory (CHOLMOD)");
        goto out;
    }
    SuiteSparse_long *Ap = A->p, *Ai = A->i;
    double *Ax = A->x;
    long nz = 0;
    double longest = 0.0;
    int cols[LOCAL_MAX];
    double J[6 * LOCAL_MAX];
    for (int v = 0; v < nv; v++) {
        int nl = 0;
        if (sf_constraints_vertex(m, &k, v, NULL, cols, &nl, J, NULL, NULL)) {
            rc = sf_fail(err, SF_ENOMEM, "mobility: vertex %d: out of memory or more than %d "
                         "coordinates", v, LOCAL_MAX);
            goto out;
        }
        /* the column order of a vertex: its coordinates ascending */
        int ord[LOCAL_MAX];
        for (int a = 0; a < nl; a++) ord[a] = a;
        for (int a = 1; a < nl; a++)
            for (int b = a; b > 0 && cols[ord[b - 1]] > cols[ord[b]]; b--) {
                int tmp = ord[b];
                ord[b] = ord[b - 1];
                ord[b - 1] = tmp;
            }
        for (int e = 0; e < 6; e++) {
            double f = e < 3 ? 1.0 : 1.0 / lref, len = 0.0;
            Ap[6 * v + e] = nz;
            for (int b = 0; b < nl; b++) {
                double x = f * J[(size_t)e * nl + ord[b]];
                if (x == 0.0) continue;
                Ai[nz] = cols[ord[b]];
                Ax[nz++] = x;
                len += x * x;
            }
            longest = fmax(longest, sqrt(len));
        }
    }
    Ap[ncon] = nz;
    double tol = fmax(RANK_RTOL * longest, RANK_ATOL);
    cholmod_sparse *R = NULL;
    SuiteSparse_long *E = NULL;
    /* no right-hand side: SuiteSparseQR_C_QR would factorise [A, I] to form
     * an unused Q (docs/guides/stability.md, "The QR of C^T alone") */
    SuiteSparse_long r = SuiteSparseQR_C(SPQR_ORDERING_DEFAULT, tol, 0, 0, A, NULL, NULL, NULL,
                                         NULL, &R, &E, NULL, NULL, NULL, &cc);
    if (R) cholmod_l_free_sparse(&R, &cc);
    if (E) cholmod_l_free((size_t)ncon, sizeof(SuiteSparse_long), E, &cc);
    if (r < 0) {
        rc = cc.status == CHOLMOD_OUT_OF_MEMORY
                 ? sf_fail(err, SF_ENOMEM, "out of memory (SuiteSparseQR)")
                 : sf_fail(err, SF_ENUMERIC, "mobility: SuiteSparseQR failed (status %d)",
                           cc.status);
        goto out;
    }
    *first = nq - (int)r;
out:
    if (A) cholmod_l_free_sparse(&A, &cc);
    cholmod_l_finish(&cc);
    sf_kin_free(&k);
    return rc;
}
