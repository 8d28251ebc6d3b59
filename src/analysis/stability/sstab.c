/* sstab.c - stability from sparse KKT blocks: MUMPS inertia and ARPACK in
 * shift-invert on the MUMPS factors (see sstab.h). */
#include "sstab.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <arpack/arpack.h>

#include "ldlt.h"
#include "sstab_rows.h"

#define ZERO_ROW 1e-13     /* rows shorter than this times the longest: zero */
#define NULL_TOL 1e-12     /* MUMPS null pivot threshold (CNTL(3)) */
#define SHIFT_REL 1e-6     /* sigma0 = -SHIFT_REL * max |diag HL| */
#define EXTRA 6            /* eigenvalues computed beyond those wanted */
#define BOUNDED_ITERS 10   /* ARPACK restarts of the one attempt with SF_SSTAB_EIG_BOUNDED */
#define BOUNDED_BELOW 8    /* factorisations of the search for a shift below the spectrum, bounded */
#define BOUNDED_FULL 400   /* bounded: a tangent space up to this dimension gets a Krylov
                              subspace as large as itself (ncv = dim), which resolves the
                              eigenvalue clusters of flat sheets in a few restarts */
#define WEAK_ROW 1e-8      /* a kept row closer than this to the span of the others (unit rows):
                              its pivot pair in K, about -dist^2 / h, can be lost to round-off */
#define WEAK_MAX 1e-7      /* when K's count is inconsistent, the weakest rows up to this are
                              taken out too, 1, 2, 4, ... of them until K_w's count holds */

struct sf_sstab {
    int n, m;
    sf_sstab *lead;        /* sf_sstab_follow_rows: its independent rows, analyses, workspace */
    int adopted;           /* this evaluation took lead's rows */
    sf_ldlt *kf;           /* the factorisation of K in use: f, or lead's f */
    char *weak_last;       /* [m] the weak rows of the last K_w (kw_last of them; 0: none) */
    int kw_last;
    sf_sstab_opts o;
    int whole;             /* bounded with its own restart cap: small tangent spaces whole */
    sf_ldlt *f;
    sf_ldlt *fw;           /* K_w: K with the weak rows taken out (take_out_weak) */
    sf_ldlt *cur;          /* the factorisation in use: f, or fw when rows were taken out */
    long nextra;           /* triplets after the -sigma diagonal (K_w: the multiplier diagonal) */
    int rank_k, dim_k;     /* rows in the K in use, n - rank_k */
    /* triplets of K (lower triangle) */
    long cap;
    int *ti, *tj;
    double *tv;
    long ndiag_at;         /* index of the first -sigma diagonal triplet */
    /* rows of C: scale (0 = dropped), new index */
    double *rs;
    int *rnew;
    int mk;                /* rows kept: independent rows of C */
    int mnz;               /* nonzero rows */
    int spqr_failed;       /* the last rank decision failed */
    sf_rowbasis *rows;     /* the independent rows, reused while they span (sstab_rows.h) */
    double *b;             /* n + m */
    double scale, gersh;
    double below;          /* a shift below every eigenvalue of H_c (unstable points) */
    sf_sstab_result res;
};

/* Append to the result's reason (truncated when long). */
static void add_reason(sf_sstab_result *R, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void add_reason(sf_sstab_result *R, const char *fmt, ...)
{
    size_t len = strlen(R->reason);
    if (len >= sizeof R->reason - 1) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(R->reason + len, sizeof R->reason - len, fmt, ap);
    va_end(ap);
}

int sf_sstab_create(sf_sstab **out, int n, int m, const sf_sstab_opts *opts, sf_error *err)
{
    *out = NULL;
    if (n < 1 || m < 0)
        return sf_fail(err, SF_EINTERNAL, "sparse stability: bad size (n = %d, m = %d)", n, m);
    sf_sstab *s = calloc(1, sizeof *s);
    if (!s) return sf_fail(err, SF_ENOMEM, "out of memory");
    s->n = n;
    s->m = m;
    if (opts) s->o = *opts;
    if (s->o.nev < 1) s->o.nev = 1;
    if (s->o.maxiter < 1) s->o.maxiter = 1000;
    if (s->o.attempts < 1) s->o.attempts = 4;
    if (!(s->o.tol > 0)) s->o.tol = 1e-10;
    if (s->o.effort == SF_SSTAB_EIG_BOUNDED) {
        /* one attempt, a few restarts: eigenvalues only when they come cheap */
        s->o.attempts = 1;
        if (!opts || opts->maxiter < 1) {
            s->o.maxiter = BOUNDED_ITERS;
            s->whole = 1; /* with a cap of the caller's, ARPACK as the caller set it up */
        }
    }
    s->rs = calloc((size_t)m + 1, sizeof(double));
    s->rnew = calloc((size_t)m + 1, sizeof(int));
    s->b = calloc((size_t)(n + m) + 1, sizeof(double));
    s->res.eig = calloc((size_t)s->o.nev, sizeof(double));
    s->weak_last = calloc((size_t)m + 1, 1);
    if (!s->rs || !s->rnew || !s->b || !s->res.eig || !s->weak_last) {
        sf_sstab_free(s);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    int rc = sf_ldlt_create(&s->f, NULL_TOL, err);
    if (rc) {
        sf_sstab_free(s);
        return rc;
    }
    rc = sf_rowbasis_create(&s->rows, n, m, err);
    if (rc) {
        sf_sstab_free(s);
        return rc;
    }
    *out = s;
    return SF_OK;
}

void sf_sstab_free(sf_sstab *s)
{
    if (!s) return;
    sf_rowbasis_free(s->rows);
    sf_ldlt_free(s->f);
    sf_ldlt_free(s->fw);
    free(s->ti);
    free(s->tj);
    free(s->tv);
    free(s->rs);
    free(s->rnew);
    free(s->b);
    free(s->res.eig);
    free(s->weak_last);
    free(s);
}

void sf_sstab_follow_rows(sf_sstab *s, sf_sstab *lead)
{
    s->lead = lead && lead != s && lead->n == s->n && lead->m == s->m ? lead : NULL;
}

const sf_sstab_result *sf_sstab_get(const sf_sstab *s)
{
    return &s->res;
}

static int check_csc(const sf_csc *A, int nrow, int ncol, const char *name, sf_error *err)
{
    if (A->nrow != nrow || A->ncol != ncol || !A->colptr || A->colptr[0] != 0)
        return sf_fail(err, SF_EINTERNAL, "sparse stability: %s is %d x %d, expected %d x %d", name,
                       A->nrow, A->ncol, nrow, ncol);
    for (int j = 0; j < ncol; j++) {
        if (A->colptr[j + 1] < A->colptr[j])
            return sf_fail(err, SF_EINTERNAL, "sparse stability: %s column %d: bad colptr", name, j);
        for (int k = A->colptr[j]; k < A->colptr[j + 1]; k++) {
            if (A->rowind[k] < 0 || A->rowind[k] >= nrow)
                return sf_fail(err, SF_EINTERNAL, "sparse stability: %s column %d: row %d out of "
                               "range", name, j, A->rowind[k]);
            if (!isfinite(A->val[k]))
                return sf_fail(err, SF_ENUMERIC, "sparse stability: %s (%d, %d) is not finite",
                               name, A->rowind[k], j);
        }
    }
    return SF_OK;
}

/* Triplets of K(0) = [HL, Cs^T; Cs, 0] (lower triangle, scaled kept rows
 * of C), then n diagonal triplets that carry -sigma.  Also the scale of
 * HL and a Gershgorin lower bound of its spectrum. */
static int assemble(sf_sstab *s, const sf_csc *HL, const sf_csc *C, sf_error *err)
{
    int n = s->n, m = C ? s->m : 0;
    /* row lengths of C */
    for (int i = 0; i < m; i++) s->rs[i] = 0.0;
    for (int j = 0; j < n && m > 0; j++)
        for (int k = C->colptr[j]; k < C->colptr[j + 1]; k++)
            s->rs[C->rowind[k]] += C->val[k] * C->val[k];
    double big = 0.0;
    for (int i = 0; i < m; i++) big = fmax(big, s->rs[i] = sqrt(s->rs[i]));
    s->mnz = 0;
    for (int i = 0; i < m; i++) {
        int keep = s->rs[i] > ZERO_ROW * big && s->rs[i] > 0.0;
        s->rnew[i] = keep ? s->mnz++ : -1;
        s->rs[i] = keep ? 1.0 / s->rs[i] : 0.0;
    }
    int rc = SF_OK;
    s->adopted = s->lead && sf_rowbasis_adopt(s->rows, s->lead->rows, s->rs, s->rnew, &s->mk);
    if (s->adopted)
        s->spqr_failed = 0; /* the leader's rows (sf_sstab_follow_rows) */
    else
        rc = sf_rowbasis_select(s->rows, C, s->rs, s->rnew, s->mnz, &s->mk, &s->spqr_failed, err);
    if (rc) return rc;
    sf_rowbasis_counts(s->rows, &s->res.rank_qr, &s->res.rank_reused, &s->res.rank_checks);
    long need = (long)HL->colptr[n] + (m > 0 ? (long)C->colptr[n] : 0) + n + m;
    if (need > s->cap) {
        int *ti = realloc(s->ti, sizeof(int) * (size_t)need);
        if (ti) s->ti = ti;
        int *tj = realloc(s->tj, sizeof(int) * (size_t)need);
        if (tj) s->tj = tj;
        double *tv = realloc(s->tv, sizeof(double) * (size_t)need);
        if (tv) s->tv = tv;
        if (!ti || !tj || !tv) return sf_fail(err, SF_ENOMEM, "out of memory");
        s->cap = need;
    }
    /* Gershgorin: diagonal and off-diagonal row sums from the lower triangle */
    double *diag = s->b; /* b has n + m >= n entries */
    double *offs = calloc((size_t)n, sizeof(double));
    if (!offs) return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int i = 0; i < n; i++) diag[i] = 0.0;
    long t = 0;
    for (int j = 0; j < n; j++)
        for (int k = HL->colptr[j]; k < HL->colptr[j + 1]; k++) {
            int i = HL->rowind[k];
            if (i < j) continue;
            double v = HL->val[k];
            if (i == j) diag[i] += v;
            else {
                offs[i] += fabs(v);
                offs[j] += fabs(v);
            }
            s->ti[t] = i;
            s->tj[t] = j;
            s->tv[t++] = v;
        }
    s->scale = 0.0;
    s->gersh = INFINITY;
    for (int i = 0; i < n; i++) {
        s->scale = fmax(s->scale, fabs(diag[i]));
        s->gersh = fmin(s->gersh, diag[i] - offs[i]);
    }
    free(offs);
    if (!(s->scale > 0)) s->scale = 1.0;
    for (int j = 0; j < n && m > 0; j++)
        for (int k = C->colptr[j]; k < C->colptr[j + 1]; k++) {
            int r = s->rnew[C->rowind[k]];
            if (r < 0) continue;
            s->ti[t] = n + r;
            s->tj[t] = j;
            s->tv[t++] = C->val[k] * s->rs[C->rowind[k]];
        }
    s->ndiag_at = t;
    for (int i = 0; i < n; i++) {
        s->ti[t] = s->tj[t] = i;
        s->tv[t++] = 0.0;
    }
    return SF_OK;
}

/* Factorise K(sigma); fills neg and nnull.  Returns SF_OK, or the error. */
static int factor_at(sf_sstab *s, double sigma, int *neg, int *nnull, sf_error *err)
{
    long nt = s->ndiag_at + s->n;
    for (long t = s->ndiag_at; t < nt; t++) s->tv[t] = -sigma;
    if (s->lead && (s->cur == s->f || s->cur == s->fw)) {
        /* an instance of its own: the workspace relaxation the lead's
         * factorisations of the same matrix (K or K_w at a point h away)
         * needed; a new instance of MUMPS starts at 20 % and repeated its
         * first factorisations two or three times with twice as much
         * (ldlt.c) */
        const sf_ldlt *lf = s->cur == s->fw ? s->lead->fw : s->lead->f;
        if (lf && sf_ldlt_relaxation(lf) > sf_ldlt_relaxation(s->cur))
            sf_ldlt_set_relaxation(s->cur, sf_ldlt_relaxation(lf));
    }
    int rc = sf_ldlt_factor(s->cur, s->n + s->mk, nt + s->nextra, s->ti, s->tj, s->tv, err);
    if (rc) return rc;
    sf_ldlt_info in;
    sf_ldlt_get_info(s->cur, &in);
    *neg = in.neg;
    *nnull = in.nnull;
    s->res.analyses = in.analyses;
    return SF_OK;
}

/* x -> u with K(sigma) [u; nu] = [x; 0] */
static int apply_op(sf_sstab *s, const double *x, double *u, sf_error *err)
{
    int n = s->n;
    memcpy(s->b, x, sizeof(double) * (size_t)n);
    memset(s->b + n, 0, sizeof(double) * (size_t)s->mk);
    int rc = sf_ldlt_solve(s->cur, s->b, err);
    if (rc) return rc;
    memcpy(u, s->b, sizeof(double) * (size_t)n);
    return SF_OK;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* y = P x, P = I - Y Y^T (Y: n x nY, orthonormal columns) */
static void deflate(int n, const double *Y, int nY, double *y)
{
    for (int c = 0; c < nY; c++) {
        const double *yc = Y + (size_t)c * n;
        double d = 0.0;
        for (int i = 0; i < n; i++) d += yc[i] * y[i];
        for (int i = 0; i < n; i++) y[i] -= d * yc[i];
    }
}

/* One ARPACK run on P Op P (the current factors, shift sigma; P deflates
 * the eigenvectors Y already found): *conv = eigenvalues converged;
 * eigenvalues of H_c in eig[nev], eigenvectors in Z (n x nev).  Returns
 * the dsaupd info, 10000 + the dseupd info, or below -1000 a MUMPS solve
 * failure / lack of memory (err says which). */
static int arpack_run(sf_sstab *s, double sigma, int nev, int ncv, unsigned long seed,
                      const double *Y, int nY, double *eig, double *Z, int *conv, int *iters,
                      sf_error *err)
{
    int n = s->n;
    size_t lworkl = (size_t)ncv * (ncv + 8);
    double *V = malloc(sizeof(double) * ((size_t)n * ncv + 3 * (size_t)n + lworkl + n + 1));
    a_int *sel = calloc((size_t)ncv, sizeof(a_int));
    if (!V || !sel) {
        free(V);
        free(sel);
        *conv = 0;
        return sf_fail(err, SF_ENOMEM, "out of memory"), -2000;
    }
    double *workd = V + (size_t)n * ncv, *workl = workd + 3 * (size_t)n, *resid = workl + lworkl;
    /* start: a fixed pseudo-random vector mapped into null(C) */
    unsigned long x = 88172645463325252UL ^ (seed * 0x9E3779B97F4A7C15UL);
    for (int i = 0; i < n; i++) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        workd[i] = (double)(x % 2000001UL) / 1000000.0 - 1.0;
    }
    int info = -1001;
    if (apply_op(s, workd, resid, err)) goto out;
    deflate(n, Y, nY, resid);
    a_int ido = 0, ainfo = 1, iparam[11] = {0}, ipntr[14] = {0};
    iparam[0] = 1;
    iparam[2] = s->o.maxiter;
    iparam[6] = 1;
    for (;;) {
        dsaupd_c(&ido, "I", n, "LM", nev, s->o.tol, resid, ncv, V, n, iparam, ipntr, workd, workl,
                 (a_int)lworkl, &ainfo);
        if (ido != -1 && ido != 1) break;
        double *xin = workd + ipntr[0] - 1, *yout = workd + ipntr[1] - 1;
        deflate(n, Y, nY, xin);
        if (apply_op(s, xin, yout, err)) goto out;
        deflate(n, Y, nY, yout);
        s->res.nop++;
    }
    *conv = (int)iparam[4];
    *iters = (int)iparam[2];
    info = (int)ainfo;
    if (ainfo != 0) goto out;
    dseupd_c(1, "A", sel, eig, Z, n, sigma, "I", n, "LM", nev, s->o.tol, resid, ncv, V, n, iparam,
             ipntr, workd, workl, (a_int)lworkl, &ainfo);
    info = ainfo == 0 ? 0 : 10000 + (int)ainfo;
    if (ainfo == 0)
        for (int i = 0; i < nev; i++) eig[i] = sigma + 1.0 / eig[i];
out:
    free(V);
    free(sel);
    return info;
}

/* Sylvester check of the computed eigenvalues ev[0..nev-1] (ascending):
 * at a cut t in the first clear gap after the wanted ones, the number of
 * eigenvalues of H_c below t, neg(K(t)) - rank, must equal the number
 * computed below t (Lanczos can miss copies of a multiple eigenvalue).
 * Returns how many were missed (0 also when no clear gap exists or the
 * count is ambiguous), or -1 on lack of memory.  Leaves the factors of
 * K(t). */
static int sturm_check(sf_sstab *s, const double *ev, int nev, int rank, int nnull0,
                       sf_error *err)
{
    int k = s->o.nev < nev ? s->o.nev : nev;
    double gap = 1e-6 * fmax(fabs(ev[0]), fabs(ev[nev - 1])) + 1e-14 * s->scale;
    int j = k;
    while (j < nev && ev[j] - ev[j - 1] <= gap) j++;
    if (j >= nev) return 0;
    double t = 0.5 * (ev[j - 1] + ev[j]);
    int neg, nnull;
    sf_error e;
    sf_error_clear(&e);
    if (factor_at(s, t, &neg, &nnull, &e)) {
        if (e.code == SF_ENOMEM) return sf_fail(err, SF_ENOMEM, "%s", e.msg), -1;
        return 0;
    }
    if (nnull != nnull0) return 0;
    int below = neg - rank;
    return below > j ? below - j : 0;
}

/* The shift of attempt a (0-based) and its subspace size. */
static void attempt_plan(const sf_sstab *s, int a, int morse, double sigma0, int nev, int dim,
                         double *sigma, int *ncv)
{
    int base = 2 * nev + 1 > 20 ? 2 * nev + 1 : 20;
    int c = base << (a < 3 ? a : 3);
    /* bounded (one attempt, BOUNDED_ITERS restarts): a small tangent space
     * whole, as its eigenvalue cluster at a flat sheet needs (docs/guides/stability.md,
     * "Cost of the inertia method") */
    if (s->whole && dim <= BOUNDED_FULL) c = dim;
    if (c > dim) c = dim;     /* the operator's rank (Krylov space beyond: zeros) */
    if (c < nev + 1) c = nev + 1;
    *ncv = c > s->n ? s->n : c;
    double below = s->below, d = fabs(below - sigma0);
    if (morse == 0) *sigma = a < 2 ? sigma0 : sigma0 - 1e-3 * (double)(a - 1) * s->scale;
    else *sigma = a < 2 ? below : below - 0.5 * (double)(a - 1) * d;
}

typedef struct found {
    int nf, cap;
    double *val;   /* [cap] eigenvalues of H_c, in the order found */
    double *Y;     /* n x cap eigenvectors */
    double *sorted;
} found;

/* The ARPACK attempts of sf_sstab_eval (shift plan, deflation of what was
 * found when the Sturm count shows missed copies, reasons).  Sets *done
 * when the eigenvalues are complete; R->eig, neig, morse, attempts. */
static int eigen_attempts(sf_sstab *s, double sigma0, int morse0, int *done, sf_error *err)
{
    sf_sstab_result *R = &s->res;
    int n = s->n, want = s->o.nev + EXTRA < s->dim_k ? s->o.nev + EXTRA : s->dim_k;
    *done = 0;
    if (want < 1) {
        add_reason(R, "tangent space of dimension %d too small for ARPACK", s->dim_k);
        return SF_OK;
    }
    sf_error e2;
    sf_error_clear(&e2);
    found F = {0, 4 * want + 2 * EXTRA, NULL, NULL, NULL};
    if (F.cap > s->dim_k) F.cap = s->dim_k;
    F.val = malloc(sizeof(double) * (size_t)F.cap * 2);
    F.Y = malloc(sizeof(double) * (size_t)F.cap * (size_t)n);
    double *ev = malloc(sizeof(double) * (size_t)F.cap);
    double *Z = malloc(sizeof(double) * (size_t)F.cap * (size_t)n);
    int rc = SF_OK;
    if (!F.val || !F.Y || !ev || !Z) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto out;
    }
    F.sorted = F.val + F.cap;
    double fs = sigma0; /* shift of the current factors */
    if (morse0 > 0) {
        /* a shift just below the spectrum, from the inertia: steps growing
         * 4 times from sigma0 until no eigenvalue is left below (Gershgorin
         * bounds the search) */
        double step = SHIFT_REL * s->scale, t = sigma0;
        int ng = 0, nn = 0, cnt = morse0;
        int bounded = s->o.effort == SF_SSTAB_EIG_BOUNDED;
        int maxit = bounded ? BOUNDED_BELOW : 60;
        double grow = bounded ? 8.0 : 4.0; /* bounded: 8 steps reach 2 max|diag HL| */
        for (int it = 0; it < maxit && cnt > 0; it++, step *= grow) {
            t = sigma0 - step;
            if (t < s->gersh) {
                t = s->gersh - 1e-3 * s->scale;
                cnt = 0; /* below the Gershgorin bound: below every eigenvalue */
                break;
            }
            if (factor_at(s, t, &ng, &nn, &e2)) {
                if (e2.code == SF_ENOMEM) {
                    rc = sf_fail(err, SF_ENOMEM, "%s", e2.msg);
                    goto out;
                }
                sf_error_clear(&e2);
                continue;
            }
            cnt = nn == 0 ? ng - s->rank_k : 1;
        }
        if (cnt > 0 && s->o.effort == SF_SSTAB_EIG_BOUNDED) {
            add_reason(R, "no shift below the spectrum within %d factorisations", maxit);
            goto out;
        }
        s->below = t;
        fs = NAN;
    }
    int nev = want;
    for (int a = 0; a < s->o.attempts && !*done; a++) {
        double sigma;
        int ncv, conv = 0, iters = 0, nn = 0, ng = 0;
        int room = s->dim_k - F.nf;
        if (nev > room) nev = room;
        if (nev > n - 1) nev = n - 1;
        if (nev > F.cap - F.nf) nev = F.cap - F.nf;
        if (nev < 1) {
            add_reason(R, "attempt %d: no room left to deflate; ", a + 1);
            break;
        }
        attempt_plan(s, a, morse0, sigma0, nev, room, &sigma, &ncv);
        R->attempts++;
        if (sigma != fs && factor_at(s, sigma, &ng, &nn, &e2)) {
            if (e2.code == SF_ENOMEM) {
                rc = sf_fail(err, SF_ENOMEM, "%s", e2.msg);
                goto out;
            }
            add_reason(R, "attempt %d: factorisation at the shift failed; ", a + 1);
            sf_error_clear(&e2);
            fs = NAN;
            continue;
        }
        fs = sigma; /* the factors are now those of K(sigma) */
        int info = arpack_run(s, sigma, nev, ncv, (unsigned long)a, F.Y, F.nf, ev, Z, &conv,
                              &iters, &e2);
        if (info <= -1000) {
            if (e2.code == SF_ENOMEM) {
                rc = sf_fail(err, SF_ENOMEM, "%s", e2.msg);
                goto out;
            }
            add_reason(R, "attempt %d: solve failed; ", a + 1);
            sf_error_clear(&e2);
            continue;
        }
        if (info != 0) {
            add_reason(R, "attempt %d: ARPACK %s info %d (%d of %d converged, ncv %d, shift "
                       "%.3g); ", a + 1, info >= 10000 ? "dseupd" : "dsaupd",
                       info >= 10000 ? info - 10000 : info, conv, nev, ncv, sigma);
            continue;
        }
        /* keep what was found (eigenvectors of H_c, whatever the shift) */
        memcpy(F.val + F.nf, ev, sizeof(double) * (size_t)nev);
        memcpy(F.Y + (size_t)F.nf * n, Z, sizeof(double) * (size_t)nev * n);
        F.nf += nev;
        memcpy(F.sorted, F.val, sizeof(double) * (size_t)F.nf);
        qsort(F.sorted, (size_t)F.nf, sizeof(double), cmp_double);
        R->iters = iters;
        int missed = sturm_check(s, F.sorted, F.nf, s->rank_k, R->null_pivots, &e2);
        fs = NAN;
        if (missed < 0) {
            rc = sf_fail(err, SF_ENOMEM, "%s", e2.msg);
            goto out;
        }
        if (missed > 0) {
            add_reason(R, "attempt %d: %d eigenvalue(s) missed (Sturm count, ncv %d), deflated; ",
                       a + 1, missed, ncv);
            nev = missed + EXTRA;
            continue;
        }
        *done = 1;
    }
    if (*done) {
        R->neig = F.nf < s->o.nev ? F.nf : s->o.nev;
        memcpy(R->eig, F.sorted, sizeof(double) * (size_t)R->neig);
        int c = 0;
        for (int i = 0; i < F.nf; i++) c += F.sorted[i] < 0.0;
        R->morse = c < F.nf ? c : (c > morse0 ? c : morse0);
    }
out:
    free(F.val);
    free(F.Y);
    free(ev);
    free(Z);
    return rc;
}

typedef struct weak_rank {
    double res;
    int row; /* index among the kept rows */
} weak_rank;

static int cmp_weak(const void *a, const void *b)
{
    double x = ((const weak_rank *)a)->res, y = ((const weak_rank *)b)->res;
    return (x > y) - (x < y);
}

/* The weak rows of K (docs/guides/stability.md, "Weak rows"): the kept rows at
 * null pivots of the last factorisation of K, and the `want` kept rows of
 * smallest Heath residual among those below WEAK_MAX.  Marks them in
 * weak[mk]; returns their number, or -1 on lack of memory.  *ncand: the
 * rows below WEAK_MAX (how far want can grow). */
static int mark_weak(sf_sstab *s, char *weak, int want, int *ncand)
{
    const double *res = sf_rowbasis_resid(s->rows);
    int k = 0, nc = 0;
    memset(weak, 0, (size_t)s->mk + 1);
    weak_rank *wr = malloc(sizeof(weak_rank) * ((size_t)s->mk + 1));
    if (!wr) return -1;
    for (int i = 0; i < s->m; i++)
        if (s->rnew[i] >= 0 && res[i] < WEAK_MAX) wr[nc++] = (weak_rank){res[i], s->rnew[i]};
    qsort(wr, (size_t)nc, sizeof *wr, cmp_weak);
    for (int t = 0; t < nc && t < want; t++) weak[wr[t].row] = 1;
    free(wr);
    *ncand = nc;
    sf_ldlt_info in;
    sf_ldlt_get_info(s->kf, &in);
    if (in.nnull > 0) {
        int *list = malloc(sizeof(int) * (size_t)in.nnull);
        if (!list) return -1;
        int q = sf_ldlt_null_rows(s->kf, list, in.nnull);
        for (int t = 0; t < q && t < in.nnull; t++)
            if (list[t] >= s->n && list[t] < s->n + s->mk) weak[list[t] - s->n] = 1;
        free(list);
    }
    for (int r = 0; r < s->mk; r++) k += weak[r];
    return k;
}

/* Switch to K_w: K with the weak rows taken out (their entries set to 0
 * and a unit diagonal on their multipliers, which adds one positive
 * pivot each; the pattern is that of K plus the multiplier diagonal,
 * factorised by fw, analysed afresh by the caller).  Returns SF_OK or the
 * error. */
static int take_out_weak(sf_sstab *s, const char *weak, int kw, sf_error *err)
{
    int n = s->n, mk = s->mk;
    for (long t = 0; t < s->ndiag_at; t++)
        if (s->ti[t] >= n && weak[s->ti[t] - n]) s->tv[t] = 0.0;
    long at = s->ndiag_at + n;
    for (int r = 0; r < mk; r++) {
        s->ti[at + r] = s->tj[at + r] = n + r;
        s->tv[at + r] = weak[r] ? 1.0 : 0.0;
    }
    if (!s->fw) {
        int rc = sf_ldlt_create(&s->fw, NULL_TOL, err);
        if (rc) return rc;
    }
    s->cur = s->fw;
    s->nextra = mk;
    s->rank_k = mk - kw;
    s->dim_k = n - s->rank_k;
    return SF_OK;
}

static int eval_point(sf_sstab *s, const sf_csc *HL, const sf_csc *C, sf_error *err);

int sf_sstab_eval(sf_sstab *s, const sf_csc *HL, const sf_csc *C, sf_error *err)
{
    /* a follower may factorise with the lead's MUMPS instances (their
     * analyses, sf_sstab_follow_rows); the lead's workspace relaxation is
     * restored afterwards, so that its own next factorisations are made as
     * they would have been */
    sf_sstab *L = s->lead;
    int rf = L ? sf_ldlt_relaxation(L->f) : 0, rfw = L && L->fw ? sf_ldlt_relaxation(L->fw) : 0;
    int rc = eval_point(s, HL, C, err);
    if (L) sf_ldlt_set_relaxation(L->f, rf);
    if (L && L->fw && rfw) sf_ldlt_set_relaxation(L->fw, rfw);
    return rc;
}

static int eval_point(sf_sstab *s, const sf_csc *HL, const sf_csc *C, sf_error *err)
{
    int n = s->n, rc;
    sf_sstab_result *R = &s->res;
    int analyses = R->analyses;
    double *eigsave = R->eig;
    memset(R, 0, sizeof *R);
    R->eig = eigsave;
    R->analyses = analyses;
    R->stable = -1;
    R->morse = -1;
    if ((rc = check_csc(HL, n, n, "HL", err))) return rc;
    if (C && s->m > 0 && (rc = check_csc(C, s->m, n, "C", err))) return rc;
    s->kw_last = 0;
    if ((rc = assemble(s, HL, C, err))) return rc;
    /* a follower with the lead's rows factorises K with the lead's instance
     * and its analysis (the same pattern, values h away): no analysis of
     * its own.  The lead's analysis stays as it was (sf_ldlt_factor
     * analyses only a new pattern; a stale one is not renewed on the lead's
     * instance, below) */
    s->kf = s->adopted && sf_ldlt_has_analysis(s->lead->f, n + s->mk, s->ndiag_at + n, s->ti, s->tj)
                ? s->lead->f : s->f;
    s->cur = s->kf;
    s->nextra = 0;
    if (s->spqr_failed) {
        R->status = SF_SSTAB_UNKNOWN;
        snprintf(R->reason, sizeof R->reason, "the rank of the constraint rows could not be "
                 "decided (SuiteSparseQR)");
        return SF_OK;
    }
    if (s->mk >= n) { /* no motion left: H_c is empty, nothing can be unstable */
        R->rank = s->mk;
        R->dim = 0;
        R->morse = 0;
        R->stable = 1;
        R->status = SF_SSTAB_OK;
        return SF_OK;
    }
    /* inertia at 0 (the index counts eigenvalues < 0, as the dense method);
     * a null pivot (Cr is independent, so it means an eigenvalue of H_c at
     * the shift: a mechanism) moves the shift just below zero */
    const double shifts[3] = {0.0, -SHIFT_REL * s->scale, -3.0 * SHIFT_REL * s->scale};
    double sigma0 = 0.0;
    int neg = 0, nnull = 0;
    sf_error e2;
    sf_error_clear(&e2);
    for (int i = 0; i < 3; i++) {
        sigma0 = shifts[i];
        sf_ldlt_info before;
        sf_ldlt_get_info(s->kf, &before);
        rc = factor_at(s, sigma0, &neg, &nnull, &e2);
        sf_ldlt_info after;
        sf_ldlt_get_info(s->kf, &after);
        if (!rc && i == 0 && nnull > 0 && after.analyses == before.analyses) {
            /* null pivots with an analysis made at an earlier point: MUMPS's
             * analysis depends on the values, and a stale one can report
             * null pivots a fresh one does not (docs/guides/stability.md).  A
             * follower analyses afresh on its own instance, not the lead's */
            s->kf = s->cur = s->f;
            sf_ldlt_forget_analysis(s->f);
            rc = factor_at(s, sigma0, &neg, &nnull, &e2);
        }
        if (!rc && i == 0) {
            sf_ldlt_info in;
            sf_ldlt_get_info(s->kf, &in);
            R->det_sign = in.det_sign;
            R->null_at_zero = nnull;
        }
        if (rc || nnull == 0) break;
    }
    if (rc == SF_ENOMEM) return sf_fail(err, rc, "%s", e2.msg);
    if (rc) {
        R->status = SF_SSTAB_UNKNOWN;
        snprintf(R->reason, sizeof R->reason, "%.190s", e2.msg);
        return SF_OK;
    }
    R->null_pivots = nnull;
    R->rank = s->mk;
    R->dim = n - R->rank;
    R->morse = neg - R->rank;
    s->rank_k = s->mk;
    s->dim_k = R->dim;
    /* Weak rows (docs/guides/stability.md, "Weak rows"): a kept row within
     * WEAK_ROW of the span of the others pairs in K with the direction only
     * it constrains, [h, d; d, 0], whose small eigenvalue -d^2/h can be at
     * round-off: its pivot may come out null or of either sign.  The index
     * mw of K_w (those rows taken out) bounds the true one: adding kw rows
     * lowers a Morse index by at most kw (Cauchy interlacing), so it lies
     * in [mw - kw, mw]: 0 when mw = 0, positive when mw > kw. */
    char *weak = malloc((size_t)s->mk + 1);
    if (!weak) return sf_fail(err, SF_ENOMEM, "out of memory");
    const double *res = sf_rowbasis_resid(s->rows);
    int want = 0, ncand = 0, kw = 0, negw = 0, nw = 0;
    for (int i = 0; i < s->m; i++) want += s->rnew[i] >= 0 && res[i] < WEAK_ROW;
    if (want == 0 && (R->morse < 0 || nnull > 0)) want = 1;
    for (;;) {
        kw = mark_weak(s, weak, want, &ncand);
        if (kw <= 0) break;
        /* K_w gets an analysis of its own each time: MUMPS's analysis
         * depends on the values it sees (sym = 2: scaling, matching, the
         * pairs of its ordering), and those of K_w change in kind with the
         * rows taken out; reused from another set of weak rows it flagged
         * null pivots that a fresh one does not (docs/guides/stability.md).  The
         * MUMPS instance stays: a new one started from the default
         * workspace and repeated most K_w factorisations with more
         * (ICNTL(14), ldlt.c; 116 of 300 factorisations on the 12 x 12
         * Miura path); branch.tsv stays the same to the byte */
        if (s->fw) sf_ldlt_forget_analysis(s->fw);
        s->cur = s->kf;
        rc = take_out_weak(s, weak, kw, &e2);
        /* a follower whose weak rows are those of the lead's last K_w (the
         * same rows and residuals, K's null pivots alike) factorises K_w
         * with the lead's instance and that analysis, made h away: the
         * lead analyses its next K_w afresh anyway */
        if (!rc && s->adopted && s->lead->fw && s->lead->kw_last == kw &&
            memcmp(weak, s->lead->weak_last, (size_t)s->mk) == 0 &&
            sf_ldlt_has_analysis(s->lead->fw, n + s->mk, s->ndiag_at + n + s->mk, s->ti, s->tj))
            s->cur = s->lead->fw;
        for (int i = 0; i < 3 && !rc; i++) {
            sigma0 = shifts[i];
            rc = factor_at(s, sigma0, &negw, &nw, &e2);
            if (!rc && i == 0) R->null_at_zero = nw;
            if (!rc && nw == 0) break;
        }
        if (rc || (nw == 0 && negw >= s->rank_k) || want >= ncand) break;
        want *= 2; /* K_w's count fails too: take out more of the weakest rows */
    }
    if (!rc && kw > 0) { /* what the analysis of fw was made for (a follower's) */
        memcpy(s->weak_last, weak, (size_t)s->mk);
        s->kw_last = kw;
    }
    free(weak);
    if (kw < 0) return sf_fail(err, SF_ENOMEM, "out of memory");
    if (kw > 0) {
        if (rc == SF_ENOMEM) return sf_fail(err, rc, "%s", e2.msg);
        int mw = negw - s->rank_k;
        R->null_pivots = nw;
        R->status = SF_SSTAB_UNKNOWN;
        R->morse = -1;
        if (rc || nw > 0 || mw < 0) {
            snprintf(R->reason, sizeof R->reason, "inertia ambiguous: %d constraint row(s) nearly "
                     "dependent (Heath residual below %.0e or a null KKT pivot), and without them "
                     "%s", kw, WEAK_MAX, rc ? "the factorisation failed"
                     : nw > 0 ? "null pivots remain" : "the count is inconsistent");
            return SF_OK;
        }
        if (mw > 0) {
            snprintf(R->reason, sizeof R->reason, "inertia ambiguous: Morse index between %d and "
                     "%d (%d constraint row(s) nearly dependent: Heath residual below %.0e or a "
                     "null KKT pivot)", mw > kw ? mw - kw : 0, mw, kw, WEAK_MAX);
            R->stable = mw > kw ? 0 : -1;
            return SF_OK;
        }
        /* mw = 0: the index is 0; the eigenvalues are those of K_w, lower
         * bounds of those of H_c (interlacing) */
        R->status = SF_SSTAB_OK;
        R->morse = 0;
        add_reason(R, "Morse index 0 and eigenvalues with %d nearly dependent constraint row(s) "
                   "left out (eigenvalues: lower bounds); ", kw);
    } else if (nnull > 0) {
        /* a null pivot at every shift is no eigenvalue of H_c: the count is
         * ambiguous */
        R->status = SF_SSTAB_UNKNOWN;
        snprintf(R->reason, sizeof R->reason, "inertia ambiguous: %d null pivot(s) of K at every "
                 "shift down to %.3g, %d negative pivots for constraint rank %d", nnull, sigma0, neg,
                 R->rank);
        R->morse = -1;
        return SF_OK;
    }
    if (R->morse < 0) {
        R->status = SF_SSTAB_UNKNOWN;
        snprintf(R->reason, sizeof R->reason, "inertia inconsistent: %d negative pivots for "
                 "constraint rank %d", neg, R->rank);
        R->morse = -1;
        return SF_OK;
    }
    int morse0 = R->morse;
    int done = 0;
    if ((rc = eigen_attempts(s, sigma0, morse0, &done, err))) return rc;
    size_t len = strlen(R->reason);
    while (len > 0 && (R->reason[len - 1] == ' ' || R->reason[len - 1] == ';'))
        R->reason[--len] = '\0';
    /* The level below which an eigenvalue of H_c is zero as far as the
     * inertia can tell: MUMPS calls a pivot null when it is below CNTL(3) =
     * NULL_TOL times the norm of the (scaled) matrix, so an eigenvalue up to
     * about NULL_TOL max|diag HL| can show as a null pivot; a computed one
     * carries ARPACK's error tol |lambda - sigma0| besides (Bauer-Fike). */
    int bounded = s->o.effort == SF_SSTAB_EIG_BOUNDED;
    if (bounded && !done) {
        R->neig = 0;
        R->morse = morse0;
    }
    double zero_eig = NULL_TOL * s->scale;
    int clear = done && R->neig > 0 &&
                R->eig[0] - s->o.tol * fabs(R->eig[0] - sigma0) > zero_eig;
    /* Rows left out (kw > 0, mw = 0): the index is 0 (eigenvalues of K_w in
     * [sigma0, 0) count as zero, those of H_c lie above them), and the
     * eigenvalues are lower bounds: a null pivot of K_w at 0, or a bound at
     * or below zero, says nothing about the sign of those of H_c. */
    if (kw > 0 && (bounded || done)) R->morse = 0;
    if (bounded) {
        /* the inertia decides, the eigenvalues when it cannot (null pivots at 0) */
        R->status = SF_SSTAB_OK;
        R->stable = R->morse == 0 && (R->null_at_zero == 0 || clear);
        if (R->stable && R->null_at_zero > 0)
            add_reason(R, "%s%d null pivot(s) at 0, but eig1 = %.3g lies above the null-pivot level "
                       "%.2g", R->reason[0] ? "; " : "", R->null_at_zero, R->eig[0], zero_eig);
        if (!R->stable && kw > 0) {
            R->status = SF_SSTAB_UNKNOWN;
            R->stable = -1;
            if (!done)
                snprintf(R->reason, sizeof R->reason, "%d null pivot(s) at 0 with %d nearly "
                         "dependent row(s) left out, and no eigenvalues (bounded ARPACK attempt): "
                         "raise analysis.arpack_maxiter", R->null_at_zero, kw);
            else
                snprintf(R->reason, sizeof R->reason, "%d null pivot(s) at 0 with %d nearly "
                         "dependent row(s) left out, and eig1 = %.3g (a lower bound) not above "
                         "%.2g: analysis.eigensolver = \"dense\" decides", R->null_at_zero, kw,
                         R->eig[0], zero_eig);
        }
    } else if (done && kw > 0 && !clear) {
        R->status = SF_SSTAB_UNKNOWN;
        R->stable = -1;
        snprintf(R->reason, sizeof R->reason, "eig1 = %.3g with %d nearly dependent row(s) left out "
                 "is a lower bound only: analysis.eigensolver = \"dense\" decides", R->eig[0], kw);
    } else if (done) {
        R->status = R->attempts > 1 ? SF_SSTAB_RETRIED : SF_SSTAB_OK;
        R->stable = R->morse == 0 && R->eig[0] > 0.0;
    } else {
        R->status = SF_SSTAB_UNKNOWN;
        R->stable = R->morse > 0 ? 0 : -1;
    }
    return SF_OK;
}
