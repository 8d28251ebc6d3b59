/* cont_bordered.c - the engine's bordered linear algebra (cont.h,
 * ALGORITHM): the user's residual and Jacobian wrapped (counting,
 * non-finite checks, checks of a sparse Jy's pattern), and the bordered
 * matrices [Jy Fp; c^T]: assembly (dense or sparse CSC), LU factorisation
 * (LAPACK, KLU or MUMPS; or by block elimination on the LDL^T of a
 * symmetric Jy, cont_blockelim.c, with this LU as its fallback), sign and
 * log of the determinant, solves. */
#include "cont_impl.h"

#include <stdlib.h>
#include <string.h>

/* F at (y, p) into F (n values).  0 ok, -1 failed (reason in s->why). */
int ci_call_residual(cont_solver *s, const double *y, double p, double *F)
{
    s->stp.nres++;
    int r = s->prob.residual(y, p, F, s->prob.user);
    if (r != 0) {
        s->last_fnorm = NAN;
        ci_why(s, "residual function returned %d at p = %.10g", r, p);
        return -1;
    }
    s->last_fnorm = ci_norm_inf(F, s->n);
    if (!isfinite(s->last_fnorm)) {
        long i = 0;
        while (i < s->n && isfinite(F[i])) i++;
        ci_why(s, "residual function produced a non-finite value (F[%ld] = %g) "
            "at p = %.10g", i, i < s->n ? F[i] : 0.0, p);
        return -1;
    }
    return 0;
}

static int check_sparse_jy(cont_solver *s, double p)
{
    SUNMatrix J = s->Jy;
    long n = s->n;
    sunindextype *ptr = SM_INDEXPTRS_S(J), *idx = SM_INDEXVALS_S(J);
    if (SM_SPARSETYPE_S(J) != CSC_MAT || SM_ROWS_S(J) != n || SM_COLUMNS_S(J) != n) {
        ci_why(s, "Jacobian matrix was replaced by one of the wrong type or size");
        return -1;
    }
    if (ptr[0] != 0) {
        ci_why(s, "sparse Jacobian at p = %.10g: column pointer 0 is %ld, "
            "not 0", p, (long)ptr[0]);
        return -1;
    }
    for (long j = 0; j < n; j++)
        if (ptr[j + 1] < ptr[j]) {
            ci_why(s, "sparse Jacobian at p = %.10g: column pointers decrease "
                "at column %ld", p, j);
            return -1;
        }
    if (ptr[n] > SM_NNZ_S(J)) {
        ci_why(s, "sparse Jacobian at p = %.10g: %ld entries exceed the "
            "capacity %ld (use SUNSparseMatrix_Reallocate)", p, (long)ptr[n],
            (long)SM_NNZ_S(J));
        return -1;
    }
    for (long i = 0; i < n; i++) s->stamp[i] = -1;
    for (long j = 0; j < n; j++)
        for (sunindextype k = ptr[j]; k < ptr[j + 1]; k++) {
            if (idx[k] < 0 || idx[k] >= n) {
                ci_why(s, "sparse Jacobian at p = %.10g: row index %ld out of range "
                    "(column %ld, entry %ld)", p, (long)idx[k], j, (long)k);
                return -1;
            }
            if (s->stamp[idx[k]] == j) {
                ci_why(s, "sparse Jacobian at p = %.10g: duplicate entry (%ld, %ld)",
                    p, (long)idx[k], j);
                return -1;
            }
            s->stamp[idx[k]] = j;
        }
    if (!ci_all_finite(SM_DATA_S(J), (long)ptr[n])) {
        ci_why(s, "sparse Jacobian at p = %.10g has a non-finite entry", p);
        return -1;
    }
    return 0;
}

/* Jy, Fp at (y, p).  0 ok, -1 failed (reason in s->why). */
int ci_call_jacobian(cont_solver *s, const double *y, double p)
{
    long n = s->n;
    s->stp.njac++;
    SUNMatZero(s->Jy);
    memset(s->Fp, 0, (size_t)n * sizeof(double));
    int r = s->prob.jacobian(y, p, s->Jy, s->Fp, s->prob.user);
    if (r != 0) {
        ci_why(s, "Jacobian function returned %d at p = %.10g", r, p);
        return -1;
    }
    if (!ci_all_finite(s->Fp, n)) {
        ci_why(s, "Jacobian function produced a non-finite dF/dp at p = %.10g", p);
        return -1;
    }
    if (s->prob.jac_matrix == CONT_MATRIX_SPARSE) return check_sparse_jy(s, p);
    if (!ci_all_finite(SM_DATA_D(s->Jy), n * n)) {
        ci_why(s, "Jacobian function produced a non-finite dF/dy at p = %.10g", p);
        return -1;
    }
    return 0;
}

int ci_bm_init(cont_solver *s, cont_bmat *bm, long m, int linsol,
               sunindextype nnz, N_Vector tmpl)
{
    memset(bm, 0, sizeof *bm);
    bm->m = m;
    bm->sparse = linsol != CONT_LINSOL_DENSE;
    bm->mumps = linsol == CONT_LINSOL_MUMPS;
    if (bm->sparse) {
        bm->A = SUNSparseMatrix(m, m, nnz, CSC_MAT, s->ctx);
        if (!bm->A) return CONT_ENOMEM;
        bm->LS = bm->mumps ? cont_mumps(tmpl, bm->A, s->ctx)        /* cont_mumps.h */
                           : SUNLinSol_KLU(tmpl, bm->A, s->ctx);
    } else {
        bm->A = SUNDenseMatrix(m, m, s->ctx);
        if (!bm->A) return CONT_ENOMEM;
        bm->LS = cont_lapack_dense(tmpl, bm->A, s->ctx);   /* LAPACK LU (cont_lapack.h) */
    }
    if (!bm->LS) return CONT_ENOMEM;
    if (SUNLinSolInitialize(bm->LS) != 0) return CONT_ENOMEM;
    return CONT_OK;
}

void ci_bm_free(cont_bmat *bm)
{
    ci_blk_free(bm);
    if (bm->LS) SUNLinSolFree(bm->LS);
    if (bm->A) SUNMatDestroy(bm->A);
    free(bm->pat_ptr);
    free(bm->pat_idx);
    memset(bm, 0, sizeof *bm);
}

/* Number of stored entries of Jy (sparse: actual; dense: n^2). */
sunindextype ci_jy_nnz(const cont_solver *s)
{
    if (s->prob.jac_matrix == CONT_MATRIX_SPARSE) return SM_INDEXPTRS_S(s->Jy)[s->n];
    return (sunindextype)s->n * s->n;
}

/* Jy added into the leading n x n block of the column-major array A
 * (leading dimension ld), which the caller has zeroed. */
void ci_jy_dense(const cont_solver *s, double *A, long ld)
{
    long n = s->n;
    if (s->prob.jac_matrix == CONT_MATRIX_SPARSE) {
        const sunindextype *ptr = SM_INDEXPTRS_S(s->Jy), *idx = SM_INDEXVALS_S(s->Jy);
        const double *val = SM_DATA_S(s->Jy);
        for (long j = 0; j < n; j++)
            for (sunindextype k = ptr[j]; k < ptr[j + 1]; k++) A[j * ld + idx[k]] += val[k];
    } else {
        for (long j = 0; j < n; j++)
            memcpy(A + j * ld, SM_COLUMN_D(s->Jy, j), (size_t)n * sizeof(double));
    }
}

/* Column j of Jy into CSC arrays bi, bx from position k (a dense Jy: all n
 * entries); returns the position after it.  Adds the squares of the
 * entries to *norm2 unless norm2 is NULL. */
sunindextype ci_jy_column(const cont_solver *s, long j, sunindextype *bi, double *bx,
                          sunindextype k, double *norm2)
{
    if (s->prob.jac_matrix == CONT_MATRIX_SPARSE) {
        const sunindextype *ptr = SM_INDEXPTRS_S(s->Jy), *idx = SM_INDEXVALS_S(s->Jy);
        const double *val = SM_DATA_S(s->Jy);
        for (sunindextype q = ptr[j]; q < ptr[j + 1]; q++) {
            bi[k] = idx[q];
            bx[k++] = val[q];
            if (norm2) *norm2 += val[q] * val[q];
        }
    } else {
        const double *col = SM_COLUMN_D(s->Jy, j);
        for (long i = 0; i < s->n; i++) {
            bi[k] = i;
            bx[k++] = col[i];
            if (norm2) *norm2 += col[i] * col[i];
        }
    }
    return k;
}

/* After filling a sparse bordered matrix: tell KLU or MUMPS to re-analyse
 * when the pattern differs from the one it has factorised before. */
static int bm_pattern_check(cont_bmat *bm)
{
    sunindextype *ptr = SM_INDEXPTRS_S(bm->A), *idx = SM_INDEXVALS_S(bm->A);
    sunindextype nnz = ptr[bm->m];
    int same = bm->pat_valid;
    if (same) {
        same = memcmp(ptr, bm->pat_ptr, (size_t)(bm->m + 1) * sizeof *ptr) == 0 &&
               memcmp(idx, bm->pat_idx, (size_t)nnz * sizeof *idx) == 0;
    }
    if (same) return 0;
    if (bm->pat_cap < nnz || !bm->pat_ptr) {
        sunindextype *np = realloc(bm->pat_ptr, (size_t)(bm->m + 1) * sizeof *np);
        if (!np) return -1;
        bm->pat_ptr = np;
        sunindextype *ni = realloc(bm->pat_idx, (size_t)(nnz > 0 ? nnz : 1) * sizeof *ni);
        if (!ni) return -1;
        bm->pat_idx = ni;
        bm->pat_cap = nnz;
    }
    memcpy(bm->pat_ptr, ptr, (size_t)(bm->m + 1) * sizeof *ptr);
    memcpy(bm->pat_idx, idx, (size_t)nnz * sizeof *idx);
    ci_blk_new_pattern(bm);
    if (bm->mumps)
        cont_mumps_new_pattern(bm->LS);
    else if (bm->pat_valid)
        SUNLinSol_KLUReInit(bm->LS, bm->A, SM_NNZ_S(bm->A), SUNKLU_REINIT_PARTIAL);
    bm->pat_valid = 1;
    return 0;
}

/* Assemble [Jy Fp; c^T] ((n+1) x (n+1)) from s->Jy, s->Fp. */
int ci_bm_build(cont_solver *s, cont_bmat *bm, const double *c)
{
    long n = s->n, m = n + 1;
    bm->gen++;     /* the factors (dense: stored in A) no longer match */
    if (!bm->sparse) {
        SUNMatZero(bm->A);
        ci_jy_dense(s, SM_DATA_D(bm->A), m);
        for (long j = 0; j < n; j++) SM_ELEMENT_D(bm->A, n, j) = c[j];
        double *col = SM_COLUMN_D(bm->A, n);
        memcpy(col, s->Fp, (size_t)n * sizeof(double));
        col[n] = c[n];
        return 0;
    }
    sunindextype need = ci_jy_nnz(s) + 2 * (sunindextype)n + 1;
    if (SM_NNZ_S(bm->A) < need) {
        if (SUNSparseMatrix_Reallocate(bm->A, need) != 0) {
            ci_why(s, "out of memory enlarging the bordered matrix");
            return -1;
        }
    }
    sunindextype *bp = SM_INDEXPTRS_S(bm->A), *bi = SM_INDEXVALS_S(bm->A);
    double *bx = SM_DATA_S(bm->A);
    sunindextype k = 0;
    for (long j = 0; j < n; j++) {
        bp[j] = k;
        k = ci_jy_column(s, j, bi, bx, k, NULL);
        bi[k] = n;
        bx[k++] = c[j];
    }
    bp[n] = k;
    for (long i = 0; i < n; i++) {
        bi[k] = i;
        bx[k++] = s->Fp[i];
    }
    bi[k] = n;
    bx[k++] = c[n];
    bp[m] = k;
    (void)m;
    if (bm_pattern_check(bm) != 0) {
        ci_why(s, "out of memory saving the sparsity pattern");
        return -1;
    }
    return 0;
}

/* Parity (+1/-1) of a permutation given as perm[k] = image of k. */
static int perm_parity(const sunindextype *perm, long m, char *mark)
{
    int par = 1;
    memset(mark, 0, (size_t)m);
    for (long i = 0; i < m; i++) {
        if (mark[i]) continue;
        long len = 0, j = i;
        while (!mark[j]) {
            mark[j] = 1;
            j = (long)perm[j];
            len++;
        }
        if (len % 2 == 0) par = -par;
    }
    return par;
}

static int bm_lu(cont_solver *s, cont_bmat *bm, int *sign, double *logdet);

/* Factorise bm (LU, or block elimination where cont_blockelim.c allows
 * it); sign and log|.| of its determinant.  0 ok, -1 singular or failed
 * (reason in s->why). */
int ci_bm_factor(cont_solver *s, cont_bmat *bm, int *sign, double *logdet)
{
    s->stp.nfactor++;
    bm->gen++;
    bm->blk_active = 0;
    if (bm->blk) {
        if (ci_blk_factor(s, bm) == 0) {
            bm->blk_active = 1;
            return ci_blk_det(bm, sign, logdet);
        }
        s->stp.nfallback++;
    }
    return bm_lu(s, bm, sign, logdet);
}

/* The LU factorisation of the whole bordered matrix. */
static int bm_lu(cont_solver *s, cont_bmat *bm, int *sign, double *logdet)
{
    int r = SUNLinSolSetup(bm->LS, bm->A);
    if (r != 0) {
        if (bm->mumps)
            ci_why(s, "MUMPS could not factorise the bordered matrix (INFOG(1) = %ld%s)",
                (long)SUNLinSolLastFlag(bm->LS), r == SUNLS_LUFACT_FAIL ? ", singular" : "");
        else if (bm->sparse)
            ci_why(s, "KLU could not factorise the bordered matrix (flag %d, "
                "singular or not finite)", r);
        else
            ci_why(s, "the bordered matrix is singular (zero pivot in column %ld)",
                (long)SUNLinSolLastFlag(bm->LS) - 1);
        return -1;
    }
    return ci_bm_det(s, bm, sign, logdet);
}

/* Sign and log|.| of the determinant of bm from its factors (made by
 * ci_bm_factor or by KINSOL's setup).  0 ok, -1 singular or no factors. */
int ci_bm_det(cont_solver *s, cont_bmat *bm, int *sign, double *logdet)
{
    long m = bm->m;
    int sg = 1;
    double ld = 0.0;
    if (bm->blk_active) return ci_blk_det(bm, sign, logdet);
    if (!bm->sparse) {
        const int *piv = cont_lapack_pivots(bm->LS);
        if (!piv) {
            ci_why(s, "no LU factors of the bordered matrix");
            return -1;
        }
        for (long k = 0; k < m; k++) {
            double d = SM_ELEMENT_D(bm->A, k, k);
            if (d < 0) sg = -sg;
            else if (d == 0) sg = 0;
            ld += log(fabs(d));
            if (piv[k] - 1 != k) sg = -sg;
        }
    } else if (bm->mumps) {
        if (cont_mumps_det(bm->LS, &sg, &ld) != 0) {
            ci_why(s, "MUMPS factorisation not available");
            return -1;
        }
    } else {
        sun_klu_numeric *num = SUNLinSol_KLUGetNumeric(bm->LS);
        sun_klu_symbolic *sym = SUNLinSol_KLUGetSymbolic(bm->LS);
        if (!num || !sym) {
            ci_why(s, "KLU factorisation not available");
            return -1;
        }
        const double *ud = (const double *)num->Udiag;
        for (long k = 0; k < m; k++) {
            if (ud[k] < 0) sg = -sg;
            else if (ud[k] == 0) sg = 0;
            ld += log(fabs(ud[k]));
            if (num->Rs) ld += log(num->Rs[k]);   /* rows were divided by Rs > 0 */
        }
        sg *= perm_parity((const sunindextype *)num->Pnum, m, s->mark);
        sg *= perm_parity((const sunindextype *)sym->Q, m, s->mark);
    }
    if (sign) *sign = sg;
    if (logdet) *logdet = ld;
    if (sg == 0) {
        ci_why(s, "the bordered matrix is singular");
        return -1;
    }
    return 0;
}

/* out = [Jy Fp; c^T] v with the Jy, Fp last evaluated (v, out: m values) */
void ci_bm_apply(const cont_solver *s, const double *c, const double *v, double *out)
{
    long n = s->n;
    double g = 0.0;
    for (long i = 0; i < n; i++) out[i] = s->Fp[i] * v[n];
    if (s->prob.jac_matrix == CONT_MATRIX_SPARSE) {
        const sunindextype *ptr = SM_INDEXPTRS_S(s->Jy), *idx = SM_INDEXVALS_S(s->Jy);
        const double *val = SM_DATA_S(s->Jy);
        for (long j = 0; j < n; j++)
            for (sunindextype k = ptr[j]; k < ptr[j + 1]; k++) out[idx[k]] += val[k] * v[j];
    } else {
        for (long j = 0; j < n; j++) {
            const double *col = SM_COLUMN_D(s->Jy, j);
            for (long i = 0; i < n; i++) out[i] += col[i] * v[j];
        }
    }
    for (long i = 0; i <= n; i++) g += c[i] * v[i];
    out[n] = g;
}

/* Solve with the factors of bm: x = A^{-1} b (vectors of length bm->m).
 * With block factors the solve is refined against A (cont_blockelim.c)
 * unless raw, where the caller refines it against a matrix of its own. */
int ci_bm_solve_as(cont_solver *s, cont_bmat *bm, N_Vector x, N_Vector b, int raw)
{
    s->stp.nlinsolve++;
    if (bm->blk_active) {
        if (ci_blk_solve(s, bm, N_VGetArrayPointer(x), N_VGetArrayPointer(b), raw) == 0)
            return 0;
        /* the same matrix, factorised whole: the factors' generation and
         * the determinant (same sign) stay */
        bm->blk_active = 0;
        s->stp.nfallback++;
        if (bm_lu(s, bm, NULL, NULL) != 0) return -1;
    }
    int r = SUNLinSolSolve(bm->LS, bm->A, x, b, 0.0);
    if (r != 0 || !ci_all_finite(N_VGetArrayPointer(x), bm->m)) {
        ci_why(s, "linear solve with the bordered matrix failed (flag %d)", r);
        return -1;
    }
    return 0;
}

int ci_bm_solve(cont_solver *s, cont_bmat *bm, N_Vector x, N_Vector b)
{
    return ci_bm_solve_as(s, bm, x, b, 0);
}
