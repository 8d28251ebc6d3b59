/* sstab_rows.c - independent constraint rows: SuiteSparseQR, reused while
 * checked (see sstab_rows.h). */
#include "sstab_rows.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <SuiteSparseQR_C.h>

#include "ldlt.h"

#define RANK_TOL 1e-9   /* SPQR: (unit) columns of C^T left shorter than this are dependent */
#define NULL_TOL 1e-12  /* MUMPS null pivot threshold of P */
#define OUT_TOL 1e-11   /* reuse: |d . u| of every other row at most this */
#define FLOOR_TOL 1e-12 /* reuse: |c . u| of the rows of S (round-off) at most this */
#define DRAWS 6         /* random vectors of the check */
#define SQUARE_SKIP 7   /* after a failed check of a set of n rows, the next 7 go to the QR
                           (15, then 31, after 2 and 3 or more failures in a row) */

struct sf_rowbasis {
    int n, m;
    int ns;              /* rows in S; -1: no set yet */
    int *ins;            /* [m] 1 for a row of S */
    cholmod_common cc;
    sf_ldlt *f;          /* P = [I, Cs^T; Cs, 0] */
    long cap;
    int *ti, *tj;
    double *tv;
    double *w;           /* n + ns: right-hand side and solution */
    double *cu;          /* [m] C u */
    unsigned long long seed;
    int qr, reused, checks;
    double flops;        /* SuiteSparseQR's operation count, all QRs */
    int square_skip;     /* checks of a set of n rows left out (straight to the QR) */
    int skip;            /* checks of any set left out after failures in a row */
    int fails;           /* checks failed in a row */
    double *resid;       /* [m] Heath residual |R(k,k)| of a row of S at the last QR */
};

int sf_rowbasis_create(sf_rowbasis **out, int n, int m, sf_error *err)
{
    *out = NULL;
    sf_rowbasis *b = calloc(1, sizeof *b);
    if (!b) return sf_fail(err, SF_ENOMEM, "out of memory");
    b->n = n;
    b->m = m;
    b->ns = -1;
    b->seed = 0x2545F4914F6CDD1DULL;
    b->ins = calloc((size_t)m + 1, sizeof(int));
    b->w = calloc((size_t)(n + m) + 1, sizeof(double));
    b->cu = calloc((size_t)m + 1, sizeof(double));
    b->resid = calloc((size_t)m + 1, sizeof(double));
    if (!b->ins || !b->w || !b->cu || !b->resid) {
        sf_rowbasis_free(b);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    cholmod_l_start(&b->cc);
    b->cc.print = 0;
    b->cc.error_handler = NULL;
    *out = b;
    return SF_OK;
}

void sf_rowbasis_free(sf_rowbasis *b)
{
    if (!b) return;
    if (b->ins) cholmod_l_finish(&b->cc);
    sf_ldlt_free(b->f);
    free(b->ins);
    free(b->ti);
    free(b->tj);
    free(b->tv);
    free(b->w);
    free(b->cu);
    free(b->resid);
    free(b);
}

const double *sf_rowbasis_resid(const sf_rowbasis *b)
{
    return b->resid;
}

double sf_rowbasis_qr_flops(const sf_rowbasis *b)
{
    return b->flops;
}

void sf_rowbasis_counts(const sf_rowbasis *b, int *qr, int *reused, int *checks)
{
    *qr = b->qr;
    *reused = b->reused;
    *checks = b->checks;
}

/* Rank and independent rows of the scaled nonzero rows of C: sparse QR
 * with Heath's rank detection (SuiteSparseQR) of C^T, whose columns are
 * the rows; the first rank columns of its permutation E are independent
 * (R(0:r, 0:r) upper triangular with nonzero diagonal, checked).  Marks
 * them in ins[] and sets ns; ns = -1 when SPQR failed.
 * SuiteSparseQR_C with no right-hand side, not SuiteSparseQR_C_QR: the
 * latter factorises [C^T, I] to form Q even when Q is not asked for,
 * 5 to 10 times the work on the Miura paths (docs/guides/stability.md, "The
 * QR of C^T alone"). */
static int qr_rows(sf_rowbasis *b, const sf_csc *C, const double *rs, const int *rnew, int mnz,
                   sf_error *err)
{
    int n = b->n, m = b->m;
    b->ns = -1;
    b->qr++;
    long nnz = C->colptr[n];
    cholmod_sparse *A = cholmod_l_allocate_sparse((size_t)n, (size_t)mnz, (size_t)nnz, 1, 1, 0,
                                                  CHOLMOD_REAL, &b->cc);
    if (!A) return sf_fail(err, SF_ENOMEM, "out of memory (CHOLMOD)");
    SuiteSparse_long *Ap = A->p, *Ai = A->i;
    double *Ax = A->x;
    /* column c of A = row of C numbered c among the nonzero rows */
    for (int c = 0; c <= mnz; c++) Ap[c] = 0;
    for (long k = 0; k < nnz; k++) {
        int c = rnew[C->rowind[k]];
        if (c >= 0) Ap[c + 1]++;
    }
    for (int c = 0; c < mnz; c++) Ap[c + 1] += Ap[c];
    SuiteSparse_long *next = malloc(sizeof(SuiteSparse_long) * (size_t)(mnz + 1));
    if (!next) {
        cholmod_l_free_sparse(&A, &b->cc);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    memcpy(next, Ap, sizeof(SuiteSparse_long) * (size_t)mnz);
    for (int j = 0; j < n; j++) /* rows in increasing j: sorted columns */
        for (int k = C->colptr[j]; k < C->colptr[j + 1]; k++) {
            int i = C->rowind[k], c = rnew[i];
            if (c < 0) continue;
            Ai[next[c]] = j;
            Ax[next[c]++] = C->val[k] * rs[i];
        }
    free(next);
    cholmod_sparse *R = NULL;
    SuiteSparse_long *E = NULL;
    SuiteSparse_long r = SuiteSparseQR_C(SPQR_ORDERING_DEFAULT, RANK_TOL, 0, 0, A, NULL, NULL, NULL,
                                         NULL, &R, &E, NULL, NULL, NULL, &b->cc);
    cholmod_l_free_sparse(&A, &b->cc);
    if (r >= 0) b->flops += b->cc.SPQR_flopcount;
    int ok = r >= 0 && R;
    /* check: R(k, k) is the last entry of column k, nonzero, for k < r */
    for (SuiteSparse_long k = 0; ok && k < r; k++) {
        SuiteSparse_long *Rp = R->p, *Ri = R->i;
        double *Rx = R->x;
        SuiteSparse_long last = Rp[k + 1] - 1;
        if (last < Rp[k] || Ri[last] != k || !(fabs(Rx[last]) > RANK_TOL)) ok = 0;
    }
    int *indep = NULL;
    if (ok) indep = calloc((size_t)mnz + 1, sizeof(int));
    if (ok && indep) {
        double *res = malloc(sizeof(double) * ((size_t)mnz + 1));
        if (!res) {
            free(indep);
            indep = NULL;
        } else {
            SuiteSparse_long *Rp = R->p;
            double *Rx = R->x;
            for (SuiteSparse_long k = 0; k < r; k++) {
                indep[E ? E[k] : k] = 1;
                res[E ? E[k] : k] = fabs(Rx[Rp[k + 1] - 1]);
            }
            b->ns = 0;
            for (int i = 0; i < m; i++) {
                b->ins[i] = rnew[i] >= 0 && indep[rnew[i]];
                b->resid[i] = b->ins[i] ? res[rnew[i]] : 0.0;
                b->ns += b->ins[i];
            }
            free(res);
        }
    }
    if (R) cholmod_l_free_sparse(&R, &b->cc);
    if (E) cholmod_l_free(mnz, sizeof(SuiteSparse_long), E, &b->cc);
    if (ok && !indep) return sf_fail(err, SF_ENOMEM, "out of memory");
    free(indep);
    if (!ok && b->cc.status == CHOLMOD_OUT_OF_MEMORY)
        return sf_fail(err, SF_ENOMEM, "out of memory (SuiteSparseQR)");
    return SF_OK;
}

/* A standard normal number (xorshift64*, Box-Muller). */
static double gauss(unsigned long long *x)
{
    double u[2];
    for (int k = 0; k < 2; k++) {
        *x ^= *x >> 12;
        *x ^= *x << 25;
        *x ^= *x >> 27;
        u[k] = ((double)((*x * 0x2545F4914F6CDD1DULL) >> 11) + 0.5) / 9007199254740992.0;
    }
    return sqrt(-2.0 * log(u[0])) * cos(2.0 * M_PI * u[1]);
}

/* Triplets (lower triangle) of [I, Cm^T; Cm, 0] into ti/tj/tv, Cm the
 * unit rows i of C with map[i] >= 0, numbered map[i].  Returns their
 * number, or -1 on lack of memory. */
static long build_p(sf_rowbasis *b, const sf_csc *C, const double *rs, const int *map)
{
    int n = b->n;
    long need = (long)n + C->colptr[n];
    if (need > b->cap) {
        int *ti = realloc(b->ti, sizeof(int) * (size_t)need);
        if (ti) b->ti = ti;
        int *tj = realloc(b->tj, sizeof(int) * (size_t)need);
        if (tj) b->tj = tj;
        double *tv = realloc(b->tv, sizeof(double) * (size_t)need);
        if (tv) b->tv = tv;
        if (!ti || !tj || !tv) return -1;
        b->cap = need;
    }
    long t = 0;
    for (int j = 0; j < n; j++) {
        b->ti[t] = b->tj[t] = j;
        b->tv[t++] = 1.0;
        for (int k = C->colptr[j]; k < C->colptr[j + 1]; k++) {
            int i = C->rowind[k];
            if (map[i] < 0) continue;
            b->ti[t] = n + map[i];
            b->tj[t] = j;
            b->tv[t++] = C->val[k] * rs[i];
        }
    }
    return t;
}

/* Factorise [I, Cm^T; Cm, 0] (build_p) of order n + nm with *f (created
 * on first use).  1 done, 0 failed (the caller falls back to the QR), or
 * minus an error code (lack of memory). */
static int factor_p(sf_rowbasis *b, sf_ldlt **f, const sf_csc *C, const double *rs,
                    const int *map, int nm, sf_error *err)
{
    long t = build_p(b, C, rs, map);
    if (t < 0) return -sf_fail(err, SF_ENOMEM, "out of memory");
    sf_error e2;
    sf_error_clear(&e2);
    int rc = *f ? SF_OK : sf_ldlt_create(f, NULL_TOL, &e2);
    if (!rc) rc = sf_ldlt_factor(*f, b->n + nm, t, b->ti, b->tj, b->tv, &e2);
    if (rc == SF_ENOMEM) return -sf_fail(err, rc, "%s", e2.msg);
    return rc == SF_OK;
}

/* Is S (ins, ns) still a basis of the rows of C (sstab_rows.h)?  1 yes,
 * 0 no, or minus an error code (lack of memory). */
static int still_spans(sf_rowbasis *b, const sf_csc *C, const double *rs, const int *rnew,
                       sf_error *err)
{
    int n = b->n, m = b->m, ns = b->ns;
    for (int i = 0; i < m; i++)
        if (b->ins[i] && rnew[i] < 0) return 0; /* a row of S is now zero */
    int *snew = malloc(sizeof(int) * ((size_t)m + 1));
    if (!snew) return -sf_fail(err, SF_ENOMEM, "out of memory");
    for (int i = 0, t = 0; i < m; i++) snew[i] = b->ins[i] ? t++ : -1;
    int rc = factor_p(b, &b->f, C, rs, snew, ns, err);
    free(snew);
    if (rc <= 0) return rc;
    sf_ldlt_info in;
    sf_ldlt_get_info(b->f, &in);
    if (in.nnull > 0) return 0; /* Cs has lost rank */
    sf_error e2;
    sf_error_clear(&e2);
    for (int d = 0; d < DRAWS; d++) {
        for (int j = 0; j < n; j++) b->w[j] = gauss(&b->seed);
        memset(b->w + n, 0, sizeof(double) * (size_t)ns);
        rc = sf_ldlt_solve(b->f, b->w, &e2);
        if (rc == SF_ENOMEM) return -sf_fail(err, rc, "%s", e2.msg);
        if (rc) return 0;
        memset(b->cu, 0, sizeof(double) * (size_t)m);
        for (int j = 0; j < n; j++)
            for (int k = C->colptr[j]; k < C->colptr[j + 1]; k++)
                b->cu[C->rowind[k]] += C->val[k] * b->w[j];
        for (int i = 0; i < m; i++) {
            double a = fabs(b->cu[i] * rs[i]);
            if (rnew[i] >= 0 && !(a <= (b->ins[i] ? FLOOR_TOL : OUT_TOL))) return 0;
        }
    }
    return 1;
}

int sf_rowbasis_adopt(sf_rowbasis *b, const sf_rowbasis *from, double *rs, int *rnew, int *mk)
{
    if (!from || from->ns <= 0 || from->n != b->n || from->m != b->m) return 0;
    for (int i = 0; i < b->m; i++)
        if (from->ins[i] && rnew[i] < 0) return 0; /* a row of the set is zero here */
    memcpy(b->ins, from->ins, sizeof(int) * (size_t)b->m);
    memcpy(b->resid, from->resid, sizeof(double) * (size_t)b->m);
    b->ns = from->ns;
    int t = 0;
    for (int i = 0; i < b->m; i++) {
        rnew[i] = b->ins[i] ? t++ : -1;
        if (rnew[i] < 0) rs[i] = 0.0;
    }
    *mk = t;
    return 1;
}

int sf_rowbasis_select(sf_rowbasis *b, const sf_csc *C, double *rs, int *rnew, int mnz, int *mk,
                       int *failed, sf_error *err)
{
    int m = b->m;
    *mk = 0;
    *failed = 0;
    if (mnz == 0 || !C) return SF_OK;
    int ok = 0;
    /* Checks that would fail are left out and the QR decides, as it does
     * after a failed check.  S of n rows (no tangent space): Cs square,
     * u = 0 up to its round-off, which on nearly dependent rows exceeds the
     * check's bounds (the 8 x 8 Miura actuation path: 107 failed checks of
     * 107): after a failure the next 7 checks of such sets, after 2 and 3
     * or more failures in a row the next 15 and 31.  Any other S: after f
     * failures in a row the next 2^(f-1) - 1 checks, at most 7 (rows that
     * stay nearly dependent along the path: no check passes on the 8 x 8
     * and 12 x 12 Miura paths); a single failure (the rank changed at a
     * special state) is followed by a check, as before */
    if (b->ns > 0 && b->ns == b->n && b->square_skip > 0) {
        b->square_skip--;
    } else if (b->ns > 0 && b->ns < b->n && b->skip > 0) {
        b->skip--;
    } else if (b->ns > 0) {
        b->checks++;
        ok = still_spans(b, C, rs, rnew, err);
        if (ok < 0) return -ok;
        if (ok) {
            b->reused++;
            b->fails = 0;
        } else if (b->ns == b->n) {
            b->fails++;
            int f = b->fails < 3 ? b->fails : 3;
            b->square_skip = ((SQUARE_SKIP + 1) << (f - 1)) - 1;
        } else {
            b->fails++;
            int f = b->fails < 4 ? b->fails : 4;
            b->skip = (1 << (f - 1)) - 1; /* 0, 1, 3, then 7 */
        }
    }
    if (!ok) {
        int rc = qr_rows(b, C, rs, rnew, mnz, err);
        if (rc) return rc;
        if (b->ns < 0) {
            *failed = 1;
            return SF_OK;
        }
    }
    int t = 0;
    for (int i = 0; i < m; i++) {
        rnew[i] = b->ins[i] ? t++ : -1;
        if (rnew[i] < 0) rs[i] = 0.0;
    }
    *mk = t;
    return SF_OK;
}
