/* stability.c - eigenvalues of the constrained Hessian (see stability.h). */
#include "stability.h"

#include "equilibrium_poses.h"
#include "ldlt.h"
#include "study.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <stdio.h>

/* LAPACK / BLAS (Fortran, LP64) */
extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, double *a,
                    const int *lda, double *s, double *u, const int *ldu, double *vt,
                    const int *ldvt, double *work, const int *lwork, int *info);
extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);
extern void dgemm_(const char *ta, const char *tb, const int *m, const int *n, const int *k,
                   const double *alpha, const double *a, const int *lda, const double *b,
                   const int *ldb, const double *beta, double *c, const int *ldc);

/* Singular values (or |R_ii|) below RANK_TOL times the largest count as
 * zero when the rank of the row-normalised constraint matrix is decided. */
#define RANK_TOL 1e-9
/* Face poses, where no self-stress certificate (stab_cert.c) looks at
 * the rows below the cut: the numerical rank is put at the widest gap of
 * the singular values below RANK_WEAK of the largest (a drop of at least
 * RANK_GAP between neighbours), so that weak rows, exact loop conditions
 * nearly dependent on the others, count as long as they stand clear of
 * rounding (DBL_EPSILON times the size; below it nothing counts), and
 * never fewer than RANK_TOL keeps.  On the 2x2 Miura's
 * straight-line branch under a tip load 17 singular values fall evenly
 * from 2e-6 to 4e-12 of the largest, each growing in proportion to the
 * folding, then one of 1e-14 to 2e-13: the cut at 1e-9 kept a number of
 * the 17 that changed with the fold angles' last digits, and the verdict
 * with it (eigenvalue -0.11 or +0.023 at the same state). */
#define RANK_WEAK 1e-6
#define RANK_GAP 30.0
/* Rows shorter than this times the longest are zero rows (e.g. loop rows
 * of second order at the flat state). */
#define ZERO_ROW 1e-13
/* Eigenvalues of the reduced Hessian below this times the largest
 * magnitude are zero (the Hessian's assembly is not more accurate). */
#define ZERO_EIG 1e-10

/* Scratch of the dense method: U, W, Hc (nq x nq each), C^T (nq x nc),
 * singular and eigenvalues, and LAPACK's workspace (dgesvd with all of U:
 * at least max(3 min + max, 5 min); dsyev: 3 nq), generously. */
static size_t dense_work(int nqi, int nci)
{
    size_t nq = (size_t)nqi, nc = (size_t)nci, N = nq + nc;
    return 3 * nq * nq + nq * nc + 64 * N + 4 * nq + nc + 64;
}

const char *sf_stab_method_name(int method)
{
    return method == SF_EIG_DENSE     ? "dense"
           : method == SF_EIG_ARPACK  ? "arpack"
           : method == SF_EIG_INERTIA ? "inertia"
                                      : "auto";
}

/* The method that runs for a problem of nq coordinates. */
static int resolved_method(int method, int nq)
{
    if (method != SF_EIG_AUTO) return method;
    return nq > SF_EIG_DENSE_MAX ? SF_EIG_INERTIA : SF_EIG_DENSE;
}

int sf_stab_read_keys(sf_stab *st, const sf_study *s, sf_error *err)
{
    if (sf_study_has(s, "analysis.arpack_maxiter") &&
        sf_study_int(s, "analysis.arpack_maxiter", 1000, &st->arpack_maxiter, err))
        return err->code;
    return sf_study_int(s, "analysis.arpack_attempts", 4, &st->arpack_attempts, err);
}

void sf_stab_follow(sf_stab *st, const sf_stab *lead)
{
    st->lead = lead;
}

/* The sparse solver, created at the first use; it follows the lead's rows
 * when st has one (sf_stab_follow). */
static int sparse_solver(sf_stab *st, sf_error *err)
{
    if (!st->sp) {
        int m = resolved_method(st->method, st->nq);
        sf_sstab_opts o = {.nev = st->nev, .maxiter = st->arpack_maxiter,
                           .attempts = st->arpack_attempts,
                           .effort = m == SF_EIG_INERTIA ? SF_SSTAB_EIG_BOUNDED
                                                         : SF_SSTAB_EIG_FULL};
        int rc = sf_sstab_create(&st->sp, st->nq, st->ncon, &o, err);
        if (rc) return rc;
    }
    sf_sstab_follow_rows(st->sp, st->lead ? st->lead->sp : NULL);
    return SF_OK;
}

int sf_stab_init(sf_stab *st, const sf_equil *q, int method, int nev, sf_error *err)
{
    memset(st, 0, sizeof *st);
    st->nq = q->nq;
    st->ncon = q->ncon;
    st->nev = nev < 1 ? 1 : nev;
    st->method = method;
    size_t nq = (size_t)q->nq, nc = (size_t)q->ncon, N = nq + nc;
    /* scratch for the method that will run; the dense one (also the
     * fallback of ARPACK) grows it when it needs more (dense_work) */
    int dense = resolved_method(method, q->nq) == SF_EIG_DENSE;
    /* face poses above the dense size: the sparse blocks go to sstab.h
     * directly (sf_peq_kkt_csc), nothing of size nq^2 */
    st->sparse_kkt = q->pz && !dense;
    if (st->sparse_kkt) nq = nc = 0;
    st->nwork = dense ? dense_work(q->nq, q->ncon) : nq * nq + nc * nq + 64;
    st->HL = calloc(nq * nq + 1, sizeof(double));
    st->C = calloc(nc * nq + 1, sizeof(double));
    st->work = calloc(st->nwork, sizeof(double));
    st->iwork = calloc(2 * N + 2 + nq * nq + nc * nq + 2 * nq + 4, sizeof(int));
    st->res.eig = calloc((size_t)st->nev, sizeof(double));
    if (!st->HL || !st->C || !st->work || !st->iwork || !st->res.eig) {
        sf_stab_free(st);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    return SF_OK;
}

void sf_stab_free(sf_stab *st)
{
    sf_sstab_free(st->sp);
    sf_ldlt_free(st->jl);
    free(st->jrow);
    free(st->jcol);
    free(st->jsrc);
    free(st->jval);
    free(st->jfp);
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

/* Dense: Z from the SVD of C^T, H_c = Z^T HL Z, all eigenvalues. */
static int eval_dense(sf_stab *st, int at_gap, sf_error *err)
{
    int nq = st->nq, nc = st->ncon, info = 0;
    sf_stab_result *R = &st->res;
    size_t need = dense_work(nq, nc);
    if (st->nwork < need) {
        double *w2 = realloc(st->work, sizeof(double) * need);
        if (!w2) return sf_fail(err, SF_ENOMEM, "out of memory");
        st->work = w2;
        st->nwork = need;
    }
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
        if (at_gap && S[0] > 0) {
            /* rounding of the SVD: about eps times the size times S[0] */
            double floor = DBL_EPSILON * (nq > nc ? nq : nc) * S[0], wide = RANK_GAP;
            int at = 0;
            for (int i = 0; i < mn; i++) {
                if (!(S[i] <= RANK_WEAK * S[0]) || !(S[i] > floor)) continue;
                double g = S[i] / fmax(i + 1 < mn ? S[i + 1] : 0.0, floor);
                if (g >= wide) { wide = g; at = i + 1; }
            }
            if (at > rank) rank = at;   /* never fewer rows than RANK_TOL keeps */
        }
        Z = U + (size_t)rank * nq;
    } else {
        memset(U, 0, sizeof(double) * nq * nq);
        for (int i = 0; i < nq; i++) U[(size_t)i * nq + i] = 1.0;
        Z = U;
    }
    int d = nq - rank;
    R->method = SF_EIG_DENSE;
    R->morse_unknown = 0;
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
    /* eigenvalues within ZERO_EIG of zero (a located limit or branch
     * point) are zero: neither counted in the Morse index nor stable, so
     * that rounding does not decide the verdict there */
    double zt = ZERO_EIG * fmax(fabs(ev[0]), fabs(ev[d - 1]));
    R->morse = 0;
    for (int i = 0; i < d; i++)
        if (ev[i] < -zt) R->morse++;
    R->stable = R->morse == 0 && ev[0] > zt;
    R->neig = d < st->nev ? d : st->nev;
    memcpy(R->eig, ev, sizeof(double) * R->neig);
    return SF_OK;
}

/* Dense blocks to CSC: HL's lower triangle, C's nonzeros. */
static void dense_to_csc(const double *A, int nrow, int ncol, int lower, int *cp, int *ri,
                         double *v)
{
    int t = 0;
    for (int j = 0; j < ncol; j++) {
        cp[j] = t;
        for (int i = lower ? j : 0; i < nrow; i++) {
            double a = A[(size_t)i * ncol + j]; /* row-major */
            if (a != 0.0 || i == j) {
                ri[t] = i;
                v[t++] = a;
            }
        }
    }
    cp[ncol] = t;
}

/* The sparse solver's verdict as this point's result. */
static void take_sparse_result(sf_stab_result *R, const sf_sstab_result *S, int method)
{
    R->certified = 0;
    R->cert_mu = R->cert_eig = 0.0;
    R->method = method;
    R->rank = S->rank;
    R->dim = S->dim;
    R->morse = S->morse < 0 ? 0 : S->morse;
    R->morse_unknown = S->morse < 0;
    R->stable = S->stable;
    R->neig = S->neig;
    memcpy(R->eig, S->eig, sizeof(double) * (size_t)S->neig);
    R->iters = S->iters;
    R->nop = S->nop;
    R->status = S->status;
    R->attempts = S->attempts;
    snprintf(R->reason, sizeof R->reason, "%s", S->reason);
}

/* ARPACK in shift-invert on the MUMPS factors of the KKT matrix (sstab.h).
 * Returns -1 when the tangent space is too small for ARPACK (the caller
 * goes dense). */
static int eval_arpack(sf_stab *st, sf_error *err)
{
    int nq = st->nq, nc = st->ncon;
    sf_stab_result *R = &st->res;
    int rc = sparse_solver(st, err);
    if (rc) return rc;
    int *cp = st->iwork, *ri = cp + nq + 1;
    double *v = st->work;
    dense_to_csc(st->HL, nq, nq, 1, cp, ri, v);
    int nh = cp[nq];
    int *cp2 = ri + nh, *ri2 = cp2 + nq + 1;
    double *v2 = v + nh;
    dense_to_csc(st->C, nc, nq, 0, cp2, ri2, v2);
    sf_csc H = {nq, nq, cp, ri, v}, C = {nc, nq, cp2, ri2, v2};
    rc = sf_sstab_eval(st->sp, &H, nc > 0 ? &C : NULL, err);
    if (rc) return rc;
    const sf_sstab_result *S = sf_sstab_get(st->sp);
    /* a tangent space too small for ARPACK, or an inertia that could not
     * be trusted (constraint rows near the rank cut, e.g. just off the
     * flat state): the dense method (SVD) decides */
    int method = resolved_method(st->method, nq);
    if (S->neig == 0 && S->dim > 0 && S->dim < st->nev + 3 && method == SF_EIG_ARPACK) return -1;
    if (S->status == SF_SSTAB_UNKNOWN && S->morse < 0) return -1;
    take_sparse_result(R, S, method);
    return SF_OK;
}

/* The certificate of the inertia method (docs/guides/stability.md, "Stable by
 * the corrector's matrix").  The corrector's Jacobian at the point is
 * Jy = [HL C^T; C -E], every constraint row kept and E > 0 the diagonal
 * regularisation of the multipliers.  By the Haynsworth inertia formula
 * (Schur complement on -E) neg(Jy) = m + neg(Q), m rows, Q = HL + C^T E^-1 C;
 * Q restricted to null C is H_c, so (Cauchy interlacing) H_c has at most
 * neg(Q) negative eigenvalues, and H_c is positive definite when Q is.
 * So one LDL^T of Jy with exactly m negative pivots and none null proves
 * the point stable with Morse index 0, whatever the rank of C and however
 * nearly dependent its rows: no QR, no choice of rows.  The converse does
 * not hold (Q can have a negative direction that a constraint removes, a
 * weak row's), so any other inertia leaves the verdict to sstab.h.
 * On the path the inertia is the engine's (sf_stab_give_inertia: the LDL^T
 * it made of this Jacobian at this point, cont_set_point_inertia); where
 * there is none it is factorised here.
 * Not at the flat state (every fold coordinate zero): there the multipliers
 * vanish and HL's pose block is zero, and MUMPS's analysis (which pairs
 * unknowns into 2 x 2 pivots from the values it is given) made for that
 * matrix suits the path's matrices badly (Miura 12x12: 2.5 M entries in
 * the factors and 13,600 delayed pivots later on the path, against 0.84 M
 * and 6,100 with the analysis made at the first point off the flat state;
 * and null pivots where the latter finds none).  The analysis is made at
 * the first point certified and kept (the pattern is the study's).
 * *ok = 1 when certified.  SF_OK, or an error (memory, non-finite). */
static int corrector_certificate(sf_stab *st, sf_equil *q, const double *y, double p, int *ok,
                                 sf_error *err)
{
    *ok = 0;
    if (st->given) {
        /* the engine's own LDL^T of this Jacobian at this point */
        st->given = 0;
        *ok = st->given_null == 0 && st->given_neg == q->ncon;
        return SF_OK;
    }
    double amax = 0.0;
    for (int j = 0; j < q->m->nq; j++) amax = fmax(amax, fabs(y[j]));
    if (amax == 0.0) return SF_OK;
    const long *cp;
    const int *ri;
    const double *v;
    if (!st->jfp && !(st->jfp = malloc(sizeof(double) * (size_t)q->n)))
        return sf_fail(err, SF_ENOMEM, "out of memory");
    if (sf_peq_jacobian_csc(q, y, p, &cp, &ri, &v, st->jfp))
        return sf_fail(err, SF_ENUMERIC, "stability: non-finite Jacobian at p = %g", p);
    int n = q->n;
    if (!st->jl) {
        /* the pattern is the study's (sf_peq_jacobian_csc): its lower
         * triangle once */
        long nl = 0;
        for (int j = 0; j < n; j++)
            for (long k = cp[j]; k < cp[j + 1]; k++) nl += ri[k] >= j;
        st->jrow = malloc(sizeof(int) * (size_t)(nl + 1));
        st->jcol = malloc(sizeof(int) * (size_t)(nl + 1));
        st->jsrc = malloc(sizeof(long) * (size_t)(nl + 1));
        st->jval = malloc(sizeof(double) * (size_t)(nl + 1));
        if (!st->jrow || !st->jcol || !st->jsrc || !st->jval)
            return sf_fail(err, SF_ENOMEM, "out of memory");
        nl = 0;
        for (int j = 0; j < n; j++)
            for (long k = cp[j]; k < cp[j + 1]; k++)
                if (ri[k] >= j) {
                    st->jrow[nl] = ri[k];
                    st->jcol[nl] = j;
                    st->jsrc[nl++] = k;
                }
        st->jnnz = nl;
        int rc = sf_ldlt_create(&st->jl, 0.0, err);
        if (rc) return rc;
    }
    for (long k = 0; k < st->jnnz; k++) st->jval[k] = v[st->jsrc[k]];
    int rc = sf_ldlt_factor(st->jl, n, st->jnnz, st->jrow, st->jcol, st->jval, err);
    if (rc) return rc;
    sf_ldlt_info I;
    sf_ldlt_get_info(st->jl, &I);
    *ok = I.nnull == 0 && I.neg == q->ncon;
    return SF_OK;
}

/* Face poses: the sparse KKT blocks straight to sstab.h; no dense
 * fallback (a tangent space too small for ARPACK leaves the eigenvalues
 * unknown, with the reason). */
static int eval_sparse_kkt(sf_stab *st, sf_equil *q, const double *y, double p, sf_error *err)
{
    sf_stab_result *R = &st->res;
    int method = resolved_method(st->method, st->nq);
    if (method == SF_EIG_INERTIA && q->ncon > 0) {
        int ok, rc = corrector_certificate(st, q, y, p, &ok, err);
        if (rc) return rc;
        if (ok) {
            /* stable, index 0, no eigenvalues (they are asked for with
             * analysis.eigensolver = "arpack"); rank and dimension of the
             * tangent space not computed */
            st->ncert++;
            R->certified = 0;
            R->cert_mu = R->cert_eig = 0.0;
            R->method = method;
            R->rank = R->dim = -1;
            R->morse = 0;
            R->morse_unknown = 0;
            R->stable = 1;
            R->neig = 0;
            R->iters = R->nop = 0;
            R->status = SF_SSTAB_OK;
            R->attempts = 0;
            R->reason[0] = '\0';
            return SF_OK;
        }
    }
    sf_csc H, C;
    int rc = sf_peq_kkt_csc(q, y, p, &H, &C);
    if (rc == SF_ENOMEM) return sf_fail(err, SF_ENOMEM, "out of memory");
    if (rc) return sf_fail(err, SF_ENUMERIC, "stability: non-finite Hessian at p = %g", p);
    if ((rc = sparse_solver(st, err))) return rc;
    if ((rc = sf_sstab_eval(st->sp, &H, st->ncon > 0 ? &C : NULL, err))) return rc;
    const sf_sstab_result *S = sf_sstab_get(st->sp);
    take_sparse_result(R, S, method);
    if (S->neig == 0 && S->dim > 0 && R->reason[0] == '\0' && method == SF_EIG_ARPACK)
        snprintf(R->reason, sizeof R->reason, "tangent space of dimension %d too small for "
                 "ARPACK (%d eigenvalues wanted)", S->dim, st->nev);
    return SF_OK;
}

int sf_stab_wants_inertia(const sf_stab *st, const sf_equil *q)
{
    return st->sparse_kkt && q->pz && resolved_method(st->method, st->nq) == SF_EIG_INERTIA;
}

void sf_stab_give_inertia(sf_stab *st, long neg, long nnull)
{
    st->given = 1;
    st->given_neg = neg;
    st->given_null = nnull;
}

int sf_stab_eval(sf_stab *st, sf_equil *q, const double *y, double p, sf_error *err)
{
    st->nevals++;
    if (st->sparse_kkt) {
        int rc = eval_sparse_kkt(st, q, y, p, err);
        st->given = 0;
        return rc;
    }
    st->given = 0;
    if (sf_equil_kkt(q, y, p, st->HL, st->C))
        return sf_fail(err, SF_ENUMERIC, "stability: non-finite Hessian at p = %g", p);
    int method = resolved_method(st->method, st->nq);
    if (method == SF_EIG_ARPACK || method == SF_EIG_INERTIA) {
        int rc = eval_arpack(st, err);
        if (rc >= 0) return rc;
        /* too small a tangent space for ARPACK, or a singular KKT matrix
         * at every shift tried: the dense method decides */
    }
    st->res.certified = 0;
    st->res.cert_mu = st->res.cert_eig = 0.0;
    int rc = eval_dense(st, q->pz != NULL, err);
    st->res.status = SF_SSTAB_OK;
    st->res.attempts = 0;
    st->res.reason[0] = '\0';
    if (rc == SF_OK) rc = sf_stab_certify(st, q, y, p, err);
    return rc;
}
