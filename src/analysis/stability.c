/* stability.c - eigenvalues of the constrained Hessian (see stability.h). */
#include "stability.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <arpack/arpack.h>

/* LAPACK / BLAS (Fortran, LP64) */
extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, double *a,
                    const int *lda, double *s, double *u, const int *ldu, double *vt,
                    const int *ldvt, double *work, const int *lwork, int *info);
extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);
extern void dgemm_(const char *ta, const char *tb, const int *m, const int *n, const int *k,
                   const double *alpha, const double *a, const int *lda, const double *b,
                   const int *ldb, const double *beta, double *c, const int *ldc);
extern void dgeqp3_(const int *m, const int *n, double *a, const int *lda, int *jpvt, double *tau,
                    double *work, const int *lwork, int *info);
extern void dsytrf_(const char *uplo, const int *n, double *a, const int *lda, int *ipiv,
                    double *work, const int *lwork, int *info);
extern void dsytrs_(const char *uplo, const int *n, const int *nrhs, const double *a,
                    const int *lda, const int *ipiv, double *b, const int *ldb, int *info);

/* Singular values (or |R_ii|) below RANK_TOL times the largest count as
 * zero when the rank of the row-normalised constraint matrix is decided. */
#define RANK_TOL 1e-9
/* Rows shorter than this times the longest are zero rows (e.g. loop rows
 * of second order at the flat state). */
#define ZERO_ROW 1e-13
#define ARPACK_TOL 1e-13
#define ARPACK_MAXITER 1000
#define SF_EIG_EXTRA 6

const char *sf_stab_method_name(int method)
{
    return method == SF_EIG_DENSE ? "dense" : method == SF_EIG_ARPACK ? "arpack" : "auto";
}

int sf_stab_init(sf_stab *st, const sf_equil *q, int method, int nev, sf_error *err)
{
    memset(st, 0, sizeof *st);
    st->nq = q->nq;
    st->ncon = q->ncon;
    st->nev = nev < 1 ? 1 : nev;
    st->method = method;
    size_t nq = (size_t)q->nq, nc = (size_t)q->ncon, N = nq + nc;
    /* scratch: the largest of the dense and ARPACK needs (generous) */
    int ncv = 40 + 2 * st->nev;
    st->nwork = 6 * nq * nq + 4 * N * N + 3 * N + (size_t)ncv * (nq + ncv + 8) + 64 * N + 4 * nq +
                nc + 64;
    st->HL = calloc(nq * nq + 1, sizeof(double));
    st->C = calloc(nc * nq + 1, sizeof(double));
    st->work = calloc(st->nwork, sizeof(double));
    st->iwork = calloc(2 * N + 2, sizeof(int));
    st->res.eig = calloc((size_t)st->nev, sizeof(double));
    if (!st->HL || !st->C || !st->work || !st->iwork || !st->res.eig) {
        sf_stab_free(st);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    return SF_OK;
}

void sf_stab_free(sf_stab *st)
{
    free(st->HL);
    free(st->C);
    free(st->work);
    free(st->iwork);
    free(st->res.eig);
    memset(st, 0, sizeof *st);
}

/* Copy the constraint rows, each scaled to unit length (zero rows stay
 * zero), as the column-major nq x ncon matrix A = C^T. */
static void normalised_rows(const sf_stab *st, double *A)
{
    int nq = st->nq, nc = st->ncon;
    double big = 0.0;
    for (int r = 0; r < nc; r++) {
        double s = 0.0;
        for (int j = 0; j < nq; j++) s += st->C[(size_t)r * nq + j] * st->C[(size_t)r * nq + j];
        big = fmax(big, sqrt(s));
    }
    for (int r = 0; r < nc; r++) {
        const double *c = st->C + (size_t)r * nq;
        double s = 0.0;
        for (int j = 0; j < nq; j++) s += c[j] * c[j];
        s = sqrt(s);
        double f = (s > ZERO_ROW * big && s > 0.0) ? 1.0 / s : 0.0;
        for (int j = 0; j < nq; j++) A[(size_t)r * nq + j] = f * c[j];
    }
}

static void sort_ascending(double *v, int n)
{
    for (int i = 1; i < n; i++) {
        double x = v[i];
        int j = i - 1;
        while (j >= 0 && v[j] > x) {
            v[j + 1] = v[j];
            j--;
        }
        v[j + 1] = x;
    }
}

/* Dense: Z from the SVD of C^T, H_c = Z^T HL Z, all eigenvalues. */
static int eval_dense(sf_stab *st, sf_error *err)
{
    int nq = st->nq, nc = st->ncon, info = 0;
    sf_stab_result *R = &st->res;
    double *w = st->work;
    double *U = w;                        /* nq x nq */
    double *A = U + (size_t)nq * nq;      /* nq x nc */
    double *S = A + (size_t)nq * nc + 1;  /* min(nq, nc) */
    double *W = S + nq + nc + 1;          /* nq x nq */
    double *Hc = W + (size_t)nq * nq;     /* nq x nq */
    double *ev = Hc + (size_t)nq * nq;    /* nq */
    double *wk = ev + nq + 1;
    int lwk = (int)(st->nwork - (size_t)(wk - w));
    int rank = 0;
    const double *Z;
    if (nc > 0) {
        normalised_rows(st, A);
        double dum = 0;
        int one = 1;
        dgesvd_("A", "N", &nq, &nc, A, &nq, S, U, &nq, &dum, &one, wk, &lwk, &info);
        if (info != 0)
            return sf_fail(err, SF_ENUMERIC, "stability: dgesvd failed (info %d)", info);
        int mn = nq < nc ? nq : nc;
        for (int i = 0; i < mn; i++)
            if (S[i] > RANK_TOL * S[0] && S[0] > 0) rank++;
        Z = U + (size_t)rank * nq;
    } else {
        memset(U, 0, sizeof(double) * nq * nq);
        for (int i = 0; i < nq; i++) U[(size_t)i * nq + i] = 1.0;
        Z = U;
    }
    int d = nq - rank;
    R->method = SF_EIG_DENSE;
    R->rank = rank;
    R->dim = d;
    R->iters = R->nop = 0;
    if (d == 0) {
        R->morse = 0;
        R->stable = 1;
        R->neig = 0;
        return SF_OK;
    }
    double one = 1.0, zero = 0.0;
    dgemm_("N", "N", &nq, &d, &nq, &one, st->HL, &nq, Z, &nq, &zero, W, &nq);
    dgemm_("T", "N", &d, &d, &nq, &one, Z, &nq, W, &nq, &zero, Hc, &d);
    dsyev_("N", "U", &d, Hc, &d, ev, wk, &lwk, &info);
    if (info != 0) return sf_fail(err, SF_ENUMERIC, "stability: dsyev failed (info %d)", info);
    R->morse = 0;
    for (int i = 0; i < d; i++)
        if (ev[i] < 0.0) R->morse++;
    R->stable = R->morse == 0 && ev[0] > 0.0;
    R->neig = d < st->nev ? d : st->nev;
    memcpy(R->eig, ev, sizeof(double) * R->neig);
    return SF_OK;
}

/* Factorise K = [HL - sigma I, Cr^T; Cr, 0] (N = nq + r, column-major,
 * lower) and return the number of its negative eigenvalues, or -1 when it
 * is singular. */
static int kkt_factor(const sf_stab *st, const double *Cr, int r, double sigma, double *K,
                      int *ipiv, double *wk, int lwk)
{
    int nq = st->nq, N = nq + r, info = 0;
    memset(K, 0, sizeof(double) * N * N);
    for (int j = 0; j < nq; j++)
        for (int i = 0; i < nq; i++) K[(size_t)j * N + i] = st->HL[(size_t)j * nq + i];
    for (int i = 0; i < nq; i++) K[(size_t)i * N + i] -= sigma;
    for (int a = 0; a < r; a++)
        for (int j = 0; j < nq; j++) {
            K[(size_t)j * N + nq + a] = Cr[(size_t)a * nq + j];
            K[(size_t)(nq + a) * N + j] = Cr[(size_t)a * nq + j];
        }
    dsytrf_("L", &N, K, &N, ipiv, wk, &lwk, &info);
    if (info != 0) return -1;
    int neg = 0;
    for (int k = 0; k < N;) {
        if (ipiv[k] > 0) {
            if (K[(size_t)k * N + k] < 0) neg++;
            k++;
        } else {
            double a = K[(size_t)k * N + k], b = K[(size_t)k * N + k + 1],
                   c = K[(size_t)(k + 1) * N + k + 1];
            double det = a * c - b * b;
            if (det < 0) neg += 1;
            else if (a + c < 0) neg += 2;
            k += 2;
        }
    }
    return neg;
}

static int eval_arpack(sf_stab *st, sf_error *err)
{
    int nq = st->nq, nc = st->ncon, info = 0;
    sf_stab_result *R = &st->res;
    double *w = st->work;
    double *A = w;                               /* nq x nc */
    double *tau = A + (size_t)nq * nc + 1;       /* nc */
    double *Cr = tau + nc + nq + 1;              /* r x nq rows */
    int *jpvt = st->iwork;
    int r = 0;
    if (nc > 0) {
        normalised_rows(st, A);
        double *wk = Cr + (size_t)nq * nc + 1;
        int lwk = (int)(st->nwork - (size_t)(wk - w));
        memset(jpvt, 0, sizeof(int) * nc);
        dgeqp3_(&nq, &nc, A, &nq, jpvt, tau, wk, &lwk, &info);
        if (info != 0) return sf_fail(err, SF_ENUMERIC, "stability: dgeqp3 failed (info %d)", info);
        int mn = nq < nc ? nq : nc;
        double r0 = fabs(A[0]);
        for (int i = 0; i < mn; i++)
            if (r0 > 0 && fabs(A[(size_t)i * nq + i]) > RANK_TOL * r0) r++;
        /* the chosen rows, normalised again from the original C */
        normalised_rows(st, A);
        for (int a = 0; a < r; a++)
            memcpy(Cr + (size_t)a * nq, A + (size_t)(jpvt[a] - 1) * nq, sizeof(double) * nq);
    }
    int d = nq - r;
    R->method = SF_EIG_ARPACK;
    R->rank = r;
    R->dim = d;
    /* a few more than asked for: Lanczos finds the members of a cluster
     * (or copies of a multiple eigenvalue, frequent in symmetric sheets)
     * reliably only when the whole cluster is wanted */
    int nev = st->nev + SF_EIG_EXTRA < d - 1 ? st->nev + SF_EIG_EXTRA : d - 1;
    if (nev < 1) return -1; /* too small for ARPACK: the caller goes dense */
    int ncv = 2 * nev + 1 > 20 ? 2 * nev + 1 : 20;
    if (ncv > d) ncv = d;
    int N = nq + r;
    double *K = Cr + (size_t)r * nq + 1;         /* N x N */
    double *b = K + (size_t)N * N;               /* N */
    double *V = b + N;                           /* nq x ncv */
    double *workd = V + (size_t)nq * ncv;        /* 3 nq */
    double *workl = workd + 3 * nq;              /* ncv (ncv + 8) */
    double *resid = workl + (size_t)ncv * (ncv + 8);
    double *dval = resid + nq;                   /* nev */
    double *wk = dval + nev + 1;
    int lwk = (int)(st->nwork - (size_t)(wk - w));
    if (lwk < N) return sf_fail(err, SF_ENOMEM, "stability: workspace too small");
    int *ipiv = st->iwork + nc + 1;
    /* scale of HL, and sigma */
    double scale = 0.0, gersh = INFINITY;
    for (int i = 0; i < nq; i++) {
        double off = 0.0;
        for (int j = 0; j < nq; j++)
            if (j != i) off += fabs(st->HL[(size_t)i * nq + j]);
        scale = fmax(scale, fabs(st->HL[(size_t)i * nq + i]));
        gersh = fmin(gersh, st->HL[(size_t)i * nq + i] - off);
    }
    if (!(scale > 0)) scale = 1.0;
    double sigma = -1e-6 * scale;
    int neg = kkt_factor(st, Cr, r, sigma, K, ipiv, wk, lwk);
    for (int t = 0; neg < 0 && t < 4; t++) {
        sigma *= 3.0;
        neg = kkt_factor(st, Cr, r, sigma, K, ipiv, wk, lwk);
    }
    if (neg < 0) return -1;
    R->morse = neg - r;
    if (R->morse < 0) R->morse = 0; /* cannot happen with independent rows */
    if (R->morse > 0) {
        sigma = fmin(gersh, sigma) - 1e-3 * scale;
        if (kkt_factor(st, Cr, r, sigma, K, ipiv, wk, lwk) < 0) return -1;
    }
    /* start vector: a fixed pseudo-random vector mapped into null(C) */
    unsigned long x = 88172645463325252UL;
    for (int i = 0; i < N; i++) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        b[i] = i < nq ? (double)(x % 2000001UL) / 1000000.0 - 1.0 : 0.0;
    }
    int one = 1;
    dsytrs_("L", &N, &one, K, &N, ipiv, b, &N, &info);
    memcpy(resid, b, sizeof(double) * nq);
    a_int ido = 0, ainfo = 1, iparam[11] = {0}, ipntr[14] = {0};
    iparam[0] = 1;
    iparam[2] = ARPACK_MAXITER;
    iparam[6] = 1;
    int lworkl = ncv * (ncv + 8), nop = 0;
    for (;;) {
        dsaupd_c(&ido, "I", nq, "LM", nev, ARPACK_TOL, resid, ncv, V, nq, iparam, ipntr, workd,
                 workl, lworkl, &ainfo);
        if (ido != -1 && ido != 1) break;
        const double *xin = workd + ipntr[0] - 1;
        double *yout = workd + ipntr[1] - 1;
        memcpy(b, xin, sizeof(double) * nq);
        memset(b + nq, 0, sizeof(double) * r);
        dsytrs_("L", &N, &one, K, &N, ipiv, b, &N, &info);
        memcpy(yout, b, sizeof(double) * nq);
        nop++;
    }
    if (ainfo < 0 || ainfo == 1 || ainfo == 3)
        return sf_fail(err, SF_ENUMERIC, "stability: ARPACK dsaupd failed (info %d, %d of %d "
                       "eigenvalues converged)", (int)ainfo, (int)iparam[4], nev);
    a_int select[64] = {0};
    a_int *sel = ncv <= 64 ? select : calloc((size_t)ncv, sizeof(a_int));
    if (!sel) return sf_fail(err, SF_ENOMEM, "out of memory");
    double dummyz = 0;
    dseupd_c(0, "A", sel, dval, &dummyz, nq, sigma, "I", nq, "LM", nev, ARPACK_TOL, resid, ncv,
             V, nq, iparam, ipntr, workd, workl, lworkl, &ainfo);
    if (sel != select) free(sel);
    if (ainfo != 0)
        return sf_fail(err, SF_ENUMERIC, "stability: ARPACK dseupd failed (info %d)", (int)ainfo);
    int nconv = (int)iparam[4] < nev ? (int)iparam[4] : nev;
    for (int i = 0; i < nconv; i++) dval[i] = sigma + 1.0 / dval[i];
    sort_ascending(dval, nconv);
    R->neig = nconv < st->nev ? nconv : st->nev;
    memcpy(R->eig, dval, sizeof(double) * R->neig);
    R->stable = R->morse == 0 && nconv > 0 && R->eig[0] > 0.0;
    R->iters = (int)iparam[2];
    R->nop = nop;
    return SF_OK;
}

int sf_stab_eval(sf_stab *st, sf_equil *q, const double *y, double p, sf_error *err)
{
    if (sf_equil_kkt(q, y, p, st->HL, st->C))
        return sf_fail(err, SF_ENUMERIC, "stability: non-finite Hessian at p = %g", p);
    int method = st->method;
    if (method == SF_EIG_AUTO) method = st->nq > SF_EIG_DENSE_MAX ? SF_EIG_ARPACK : SF_EIG_DENSE;
    if (method == SF_EIG_ARPACK) {
        int rc = eval_arpack(st, err);
        if (rc >= 0) return rc;
        /* too small a tangent space for ARPACK, or a singular KKT matrix
         * at every shift tried: the dense method decides */
    }
    return eval_dense(st, err);
}
