/* cont_switch.c - branch switching at a simple branch point
 * (cont_branch_direction, cont.h): the second null vector of the augmented
 * Jacobian, dense (LAPACK SVD) or sparse (bordered solves with KLU or
 * MUMPS, whichever the solver uses). */
#include "cont_impl.h"

#include <stdlib.h>
#include <string.h>

/* LAPACK (Fortran interface, LP64) */
extern void dgesvd_(const char *jobu, const char *jobvt, const int *m,
                    const int *n, double *a, const int *lda, double *s,
                    double *u, const int *ldu, double *vt, const int *ldvt,
                    double *work, const int *lwork, int *info);

/* Dense: SVD of A_s = [Jy, Fp/theta] (scaled coordinates).  t1w is the
 * known tangent weighted by the norm (t1s itself without cont_set_weights). */
static int branch_dense(cont_solver *s, const double *t1s, const double *t1w, double *u,
                        double *sigratio)
{
    long n = s->n, m = s->m;
    int in = (int)n, im = (int)m, one = 1, info = 0, lwork = -1;
    double *A = calloc((size_t)(n * m), sizeof(double));
    double *S = calloc((size_t)n, sizeof(double));
    double *VT = calloc((size_t)(m * m), sizeof(double));
    double wq, udummy = 0.0;
    if (!A || !S || !VT) {
        free(A); free(S); free(VT);
        return ci_fail(s, CONT_ENOMEM, "out of memory");
    }
    ci_jy_dense(s, A, n);
    for (long i = 0; i < n; i++) A[n * n + i] = s->Fp[i] / s->theta;
    dgesvd_("N", "A", &in, &im, A, &in, S, &udummy, &one, VT, &im, &wq, &lwork, &info);
    lwork = info == 0 ? (int)wq + 1 : 5 * im + 10;
    double *work = malloc((size_t)lwork * sizeof(double));
    if (!work) {
        free(A); free(S); free(VT);
        return ci_fail(s, CONT_ENOMEM, "out of memory");
    }
    dgesvd_("N", "A", &in, &im, A, &in, S, &udummy, &one, VT, &im, work, &lwork, &info);
    free(work);
    free(A);
    if (info != 0) {
        free(S); free(VT);
        return ci_fail(s, CONT_ENUMERIC, "cont_branch_direction: dgesvd failed (info = %d)", info);
    }
    /* rows n-1 and n of VT (column-major m x m: VT[i + j*m] is row i) */
    double scale = n >= 2 ? S[0] : 1.0;
    double smin = S[n - 1];
    *sigratio = scale > 0 ? smin / scale : 0.0;
    double second = n >= 2 ? S[n - 2] / scale : 1.0;
    double a = 0.0, bb = 0.0, aw = 0.0, bw = 0.0;
    for (long j = 0; j < m; j++) {
        a += VT[(n - 1) + j * m] * t1s[j];
        bb += VT[n + j * m] * t1s[j];
        aw += VT[(n - 1) + j * m] * t1w[j];
        bw += VT[n + j * m] * t1w[j];
    }
    for (long j = 0; j < m; j++) u[j] = bw * VT[(n - 1) + j * m] - aw * VT[n + j * m];
    free(S);
    free(VT);
    if (!(*sigratio <= BP_NULL_TOL))
        return ci_fail(s, CONT_ENUMERIC, "cont_branch_direction: not a branch point: [Jy Fp] "
                    "has full rank (smallest/largest singular value %.3g > %.1e)",
                    *sigratio, BP_NULL_TOL);
    if (n >= 2 && second <= BP_NULL_TOL)
        return ci_fail(s, CONT_ENUMERIC, "cont_branch_direction: the null space of [Jy Fp] has "
                    "dimension > 2 (two singular values below %.1e): not a simple branch "
                    "point", BP_NULL_TOL);
    if (a * a + bb * bb < 0.9)
        return ci_fail(s, CONT_ENUMERIC, "cont_branch_direction: the given tangent is not in the "
                    "null space of [Jy Fp] (component %.3g)", sqrt(a * a + bb * bb));
    return CONT_OK;
}

/* KLU or MUMPS: bordered system [[A_s; t1w^T] bv; cv^T 0] [phi; mu] = [0; 1]. */
static int branch_sparse(cont_solver *s, const double *t1w, double *u, double *resid)
{
    long n = s->n, m = s->m, M = m + 1;
    int rc = CONT_OK;
    double *bv = malloc((size_t)m * sizeof(double)), *cv = malloc((size_t)m * sizeof(double));
    N_Vector x = N_VNew_Serial(M, s->ctx), rhs = N_VNew_Serial(M, s->ctx);
    sunindextype nnz = ci_jy_nnz(s) + 4 * (sunindextype)m + 2;
    SUNMatrix B = SUNSparseMatrix(M, M, nnz, CSC_MAT, s->ctx);
    SUNLinearSolver LS = NULL;
    if (B && x)
        LS = s->linsol == CONT_LINSOL_MUMPS ? cont_mumps(x, B, s->ctx) : SUNLinSol_KLU(x, B, s->ctx);
    if (!bv || !cv || !x || !rhs || !B || !LS) {
        rc = ci_fail(s, CONT_ENOMEM, "out of memory");
        goto done;
    }
    /* fixed pseudo-random border vectors, entries in [0.5, 1.5] */
    unsigned long long st = 0x9E3779B97F4A7C15ULL;
    for (long i = 0; i < m; i++) {
        st = st * 6364136223846793005ULL + 1442695040888963407ULL;
        bv[i] = 0.5 + (double)(st >> 11) / 9007199254740992.0;
        st = st * 6364136223846793005ULL + 1442695040888963407ULL;
        cv[i] = 0.5 + (double)(st >> 11) / 9007199254740992.0;
    }
    sunindextype *bp = SM_INDEXPTRS_S(B), *bi = SM_INDEXVALS_S(B);
    double *bx = SM_DATA_S(B);
    sunindextype k = 0;
    int jsp = s->prob.jac_matrix == CONT_MATRIX_SPARSE;
    double anorm2 = 0.0;
    for (long j = 0; j < n; j++) {
        bp[j] = k;
        k = ci_jy_column(s, j, bi, bx, k, &anorm2);
        bi[k] = n; bx[k++] = t1w[j];
        bi[k] = m; bx[k++] = cv[j];
    }
    bp[n] = k;
    for (long i = 0; i < n; i++) {
        bi[k] = i; bx[k++] = s->Fp[i] / s->theta;
        anorm2 += s->Fp[i] * s->Fp[i] / (s->theta * s->theta);
    }
    bi[k] = n; bx[k++] = t1w[n];
    bi[k] = m; bx[k++] = cv[n];
    bp[m] = k;
    for (long i = 0; i < m; i++) {
        bi[k] = i; bx[k++] = bv[i];
    }
    bp[M] = k;
    s->stp.nfactor++;
    if (SUNLinSolInitialize(LS) != 0 || SUNLinSolSetup(LS, B) != 0) {
        rc = ci_fail(s, CONT_ENUMERIC, "cont_branch_direction: the bordered system is singular: "
                  "not a simple branch point");
        goto done;
    }
    N_VConst(0.0, rhs);
    NV_Ith_S(rhs, m) = 1.0;
    s->stp.nlinsolve++;
    if (SUNLinSolSolve(LS, B, x, rhs, 0.0) != 0 || !ci_all_finite(N_VGetArrayPointer(x), M)) {
        rc = ci_fail(s, CONT_ENUMERIC, "cont_branch_direction: bordered solve failed");
        goto done;
    }
    double *ph = N_VGetArrayPointer(x);
    double np = 0.0;
    for (long i = 0; i < m; i++) np += ph[i] * ph[i];
    np = sqrt(np);
    if (!(np > 0)) {
        rc = ci_fail(s, CONT_ENUMERIC, "cont_branch_direction: zero null vector");
        goto done;
    }
    for (long i = 0; i < m; i++) u[i] = ph[i] / np;
    /* residual |A_s u| / |A_s|_F */
    double r2 = 0.0;
    for (long i = 0; i < n; i++) s->w1[i] = s->Fp[i] / s->theta * u[n];
    if (jsp) {
        sunindextype *ptr = SM_INDEXPTRS_S(s->Jy), *idx = SM_INDEXVALS_S(s->Jy);
        double *val = SM_DATA_S(s->Jy);
        for (long j = 0; j < n; j++)
            for (sunindextype q = ptr[j]; q < ptr[j + 1]; q++) s->w1[idx[q]] += val[q] * u[j];
    } else {
        for (long j = 0; j < n; j++)
            for (long i = 0; i < n; i++) s->w1[i] += SM_ELEMENT_D(s->Jy, i, j) * u[j];
    }
    for (long i = 0; i < n; i++) r2 += s->w1[i] * s->w1[i];
    /* relative to |A_s|_F, except for n = 1, where [Jy Fp] vanishes as a
     * whole at a branch point (a 1 x 2 matrix with a 2-D null space), so
     * its norm is no scale: absolute, as branch_dense does */
    *resid = (n >= 2 && anorm2 > 0) ? sqrt(r2 / anorm2) : sqrt(r2);
    if (!(*resid <= BP_NULL_TOL))
        rc = ci_fail(s, CONT_ENUMERIC, "cont_branch_direction: not a branch point: no second "
                  "null vector of [Jy Fp] (relative residual %.3g > %.1e)", *resid, BP_NULL_TOL);
done:
    if (LS) SUNLinSolFree(LS);
    if (B) SUNMatDestroy(B);
    if (x) N_VDestroy(x);
    if (rhs) N_VDestroy(rhs);
    free(bv);
    free(cv);
    return rc;
}

int cont_branch_direction(cont_solver *s, const double *y, double p,
                          const double *ty, double tp, double *ty_new, double *tp_new)
{
    NEED(s);
    long n = s->n, m = s->m;
    if (!y || !ty || !ty_new || !tp_new || !isfinite(p) || !ci_all_finite(y, n) ||
        !ci_all_finite(ty, n) || !isfinite(tp))
        return ci_fail(s, CONT_EINPUT, "cont_branch_direction: bad arguments");
    double t0 = ci_now_sec();
    double *t1s = malloc((size_t)m * sizeof(double)), *u = calloc((size_t)m, sizeof(double));
    double *t1w = malloc((size_t)m * sizeof(double));
    if (!t1s || !u || !t1w) {
        free(t1s); free(u); free(t1w);
        return ci_fail(s, CONT_ENOMEM, "out of memory");
    }
    double nrm = 0.0;
    for (long i = 0; i < n; i++) t1s[i] = ty[i];
    t1s[n] = s->theta * tp;
    for (long i = 0; i < m; i++) nrm += t1s[i] * t1s[i];
    nrm = sqrt(nrm);
    int rc = CONT_OK;
    if (!(nrm > 0)) rc = ci_fail(s, CONT_EINPUT, "cont_branch_direction: zero tangent");
    if (rc == CONT_OK) {
        for (long i = 0; i < m; i++) t1s[i] /= nrm;
        /* the norm in the scaled coordinates (y, theta p) is diag(wy, 1) */
        for (long i = 0; i < m; i++) t1w[i] = (s->wy && i < n) ? s->wy[i] * t1s[i] : t1s[i];
        if (ci_call_jacobian(s, y, p) != 0)
            rc = ci_fail(s, CONT_ENUMERIC, "cont_branch_direction: %s", s->why);
    }
    double q;
    if (rc == CONT_OK)
        rc = s->linsol != CONT_LINSOL_DENSE ? branch_sparse(s, t1w, u, &q)
                                          : branch_dense(s, t1s, t1w, u, &q);
    if (rc == CONT_OK) {
        /* remove any t1 component, normalise, fix the sign */
        double d = 0.0, tt = 0.0, nu = 0.0;
        for (long i = 0; i < m; i++) {
            d += u[i] * t1w[i];
            tt += t1s[i] * t1w[i];
        }
        if (tt > 0)
            for (long i = 0; i < m; i++) u[i] -= d / tt * t1s[i];
        for (long i = 0; i < m; i++) nu += u[i] * u[i] * ((s->wy && i < n) ? s->wy[i] : 1.0);
        nu = sqrt(nu);
        if (!(nu > 0)) {
            rc = ci_fail(s, CONT_ENUMERIC, "cont_branch_direction: no direction orthogonal to "
                      "the tangent");
        } else {
            /* the sign: the first component within SIGN_TIE_RTOL of the
             * largest magnitude is positive (a symmetric sheet has many
             * components of equal magnitude, which rounding orders) */
            double umax = 0.0;
            for (long i = 0; i < m; i++) {
                u[i] /= nu;
                umax = fmax(umax, fabs(u[i]));
            }
            long imax = 0;
            while (imax < m - 1 && fabs(u[imax]) < (1.0 - SIGN_TIE_RTOL) * umax) imax++;
            double sg = u[imax] < 0 ? -1.0 : 1.0;
            for (long i = 0; i < n; i++) ty_new[i] = sg * u[i];
            *tp_new = sg * u[n] / s->theta;
        }
    }
    free(t1s);
    free(t1w);
    free(u);
    if (s->state != ST_RUN) ci_flush_stats(s, t0, 0);
    return rc;
}
