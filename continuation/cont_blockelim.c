/* cont_blockelim.c - the bordered matrix A = [Jy Fp; c^T d] factorised by
 * block elimination on MUMPS's LDL^T of a symmetric Jy (cont.h,
 * cont_problem.jac_symmetric), for the engine's tangent/corrector matrix
 * s->bt when the solver is MUMPS.
 *
 * With z = Jy^{-1} Fp and the border pivot g = d - c_y . z:
 *   det A = det Jy * g,
 *   A^{-1} b: w = Jy^{-1} b_y, x_p = (b_n - c_y . w) / g, x_y = w - x_p z,
 * one solve with Jy per bordered solve (z is computed once per
 * factorisation), none when b_y = 0 (the tangent system's e_n: w = 0).
 * Block elimination is unstable where Jy is nearly singular (limit
 * points in p, branch points, the flat state): the two
 * terms of x_y grow like 1/sigma_min(Jy) and cancel.  Each solve is
 * therefore checked against A itself (componentwise backward error,
 * Oettli-Prager) and refined with the same factors; the caller
 * (cont_bordered.c) falls back to the LU of the whole bordered matrix
 * when
 *   - Jy is not symmetric to BLK_SYM_TOL (the problem's flag is wrong),
 *   - MUMPS fails or finds null pivots in Jy (Jy singular),
 *   - |g| <= BLK_PIVOT_MIN (|d| + sum |c_i z_i|): the border pivot is lost
 *     in the cancellation of its terms,
 *   - a solve does not reach BLK_BERR_TOL within BLK_REFINE_MAX
 *     refinements, or a refinement does not contract.
 * Each fallback is counted (cont_stats.nfallback). */
#include "cont_impl.h"

#include <stdlib.h>
#include <string.h>

#define BLK_SYM_TOL 1e-12    /* |Jy - Jy^T| / max|Jy|: symmetric to round-off */
#define BLK_PIVOT_MIN 1e-8   /* border pivot against its terms */
#define BLK_BERR_TOL 1e-12   /* componentwise backward error of a solve */
#define BLK_REFINE_MAX 3     /* refinements of a solve with the block factors */

struct cont_blk {
    long n;
    SUNMatrix L;              /* lower triangle of Jy (CSC, n x n) */
    SUNLinearSolver LS;       /* MUMPS LDL^T of L (cont_mumps_sym) */
    N_Vector vb, vx;          /* n each: MUMPS right-hand side, solution */
    sunindextype *lsrc;       /* position in the bordered matrix of each entry of L */
    sunindextype *tpos;       /* position of the transpose of each Jy entry, -1: none */
    sunindextype cap;         /* capacity of lsrc and tpos */
    int stale;                /* the bordered pattern changed: recompute the above */
    double *z, *cy;           /* Jy^{-1} Fp, the border row c_y (n each) */
    double *r, *sc, *d;       /* work, m each */
    double g;                 /* border pivot d - c_y . z */
    int sign;
    double logdet;
};

int ci_blk_init(cont_solver *s, cont_bmat *bm)
{
    long n = bm->m - 1;
    struct cont_blk *b = calloc(1, sizeof *b);
    if (!b) return CONT_ENOMEM;
    bm->blk = b;
    b->n = n;
    b->stale = 1;
    b->L = SUNSparseMatrix(n, n, SM_NNZ_S(bm->A) / 2 + n, CSC_MAT, s->ctx);
    b->vb = N_VNew_Serial(n, s->ctx);
    b->vx = N_VNew_Serial(n, s->ctx);
    b->z = calloc((size_t)n, sizeof(double));
    b->cy = calloc((size_t)n, sizeof(double));
    b->r = calloc((size_t)bm->m, sizeof(double));
    b->sc = calloc((size_t)bm->m, sizeof(double));
    b->d = calloc((size_t)bm->m, sizeof(double));
    if (!b->L || !b->vb || !b->vx || !b->z || !b->cy || !b->r || !b->sc || !b->d)
        return CONT_ENOMEM;
    b->LS = cont_mumps_sym(b->vb, b->L, s->ctx);
    if (!b->LS || SUNLinSolInitialize(b->LS) != 0) return CONT_ENOMEM;
    return CONT_OK;
}

void ci_blk_free(cont_bmat *bm)
{
    struct cont_blk *b = bm->blk;
    if (!b) return;
    if (b->LS) SUNLinSolFree(b->LS);
    if (b->L) SUNMatDestroy(b->L);
    if (b->vb) N_VDestroy(b->vb);
    if (b->vx) N_VDestroy(b->vx);
    free(b->lsrc);
    free(b->tpos);
    free(b->z);
    free(b->cy);
    free(b->r);
    free(b->sc);
    free(b->d);
    free(b);
    bm->blk = NULL;
}

void ci_blk_new_pattern(cont_bmat *bm)
{
    if (bm->blk) bm->blk->stale = 1;
}

/* From the bordered matrix's pattern: where each Jy entry's transpose is,
 * and the lower triangle L with the source of each of its entries. */
static int blk_pattern(cont_bmat *bm)
{
    struct cont_blk *b = bm->blk;
    long n = b->n;
    const sunindextype *ap = SM_INDEXPTRS_S(bm->A), *ai = SM_INDEXVALS_S(bm->A);
    sunindextype nnz = ap[bm->m];
    if (nnz > b->cap) {
        sunindextype *l = realloc(b->lsrc, (size_t)nnz * sizeof *l);
        if (l) b->lsrc = l;
        sunindextype *t = realloc(b->tpos, (size_t)nnz * sizeof *t);
        if (t) b->tpos = t;
        if (!l || !t) return -1;
        b->cap = nnz;
    }
    /* the Jy entries row by row (column and position), by counting */
    sunindextype *rp = calloc((size_t)n + 1, sizeof *rp);
    sunindextype *rcol = malloc((size_t)(nnz > 0 ? nnz : 1) * sizeof *rcol);
    sunindextype *rpos = malloc((size_t)(nnz > 0 ? nnz : 1) * sizeof *rpos);
    sunindextype *where = malloc((size_t)n * sizeof *where);
    long *mark = malloc((size_t)n * sizeof *mark);
    int ok = rp && rcol && rpos && where && mark;
    if (ok) {
        for (long j = 0; j < n; j++)
            for (sunindextype k = ap[j]; k < ap[j + 1]; k++)
                if (ai[k] < n) rp[ai[k] + 1]++;
        for (long i = 0; i < n; i++) rp[i + 1] += rp[i];
        for (long j = 0; j < n; j++)
            for (sunindextype k = ap[j]; k < ap[j + 1]; k++)
                if (ai[k] < n) {
                    sunindextype q = rp[ai[k]]++;
                    rcol[q] = j;
                    rpos[q] = k;
                }
        for (long i = n; i > 0; i--) rp[i] = rp[i - 1];
        rp[0] = 0;
        for (long i = 0; i < n; i++) mark[i] = -1;
        for (sunindextype k = 0; k < nnz; k++) b->tpos[k] = -1;
        /* column j holds (i, j) at where[i]; row j lists (j, i), whose
         * transpose is (i, j) */
        for (long j = 0; j < n; j++) {
            for (sunindextype k = ap[j]; k < ap[j + 1]; k++)
                if (ai[k] < n) {
                    where[ai[k]] = k;
                    mark[ai[k]] = j;
                }
            for (sunindextype q = rp[j]; q < rp[j + 1]; q++)
                if (mark[rcol[q]] == j) b->tpos[rpos[q]] = where[rcol[q]];
        }
        sunindextype nl = 0;
        for (long j = 0; j < n; j++)
            for (sunindextype k = ap[j]; k < ap[j + 1]; k++)
                if (ai[k] >= j && ai[k] < n) nl++;
        if (SM_NNZ_S(b->L) < nl && SUNSparseMatrix_Reallocate(b->L, nl) != 0) ok = 0;
    }
    if (ok) {
        sunindextype *lp = SM_INDEXPTRS_S(b->L), *li = SM_INDEXVALS_S(b->L);
        sunindextype nl = 0;
        for (long j = 0; j < n; j++) {
            lp[j] = nl;
            for (sunindextype k = ap[j]; k < ap[j + 1]; k++)
                if (ai[k] >= j && ai[k] < n) {
                    li[nl] = ai[k];
                    b->lsrc[nl++] = k;
                }
        }
        lp[n] = nl;
        cont_mumps_new_pattern(b->LS);
        b->stale = 0;
    }
    free(rp);
    free(rcol);
    free(rpos);
    free(where);
    free(mark);
    return ok ? 0 : -1;
}

/* x = B^{-1} rhs by block elimination with the factors (x, rhs: m values,
 * distinct).  0, or -1 (MUMPS failed). */
static int blk_apply(cont_bmat *bm, const double *rhs, double *x)
{
    struct cont_blk *b = bm->blk;
    long n = b->n;
    long nz = 0;
    while (nz < n && rhs[nz] == 0.0) nz++;
    if (nz == n) {
        /* b_y = 0 (the tangent's e_n): w = 0 exactly, as the solve
         * would give it */
        memset(N_VGetArrayPointer(b->vx), 0, (size_t)n * sizeof(double));
    } else {
        memcpy(N_VGetArrayPointer(b->vb), rhs, (size_t)n * sizeof(double));
        if (SUNLinSolSolve(b->LS, b->L, b->vx, b->vb, 0.0) != 0) return -1;
    }
    const double *w = N_VGetArrayPointer(b->vx);
    double cw = 0.0;
    for (long i = 0; i < n; i++) cw += b->cy[i] * w[i];
    double xp = (rhs[n] - cw) / b->g;
    for (long i = 0; i < n; i++) x[i] = w[i] - xp * b->z[i];
    x[n] = xp;
    return ci_all_finite(x, n + 1) ? 0 : -1;
}

/* The componentwise backward error of x for A x = rhs (A = bm->A, the
 * matrix factorised), max_i |rhs - A x|_i / (|A| |x| + |rhs|)_i; the
 * residual rhs - A x is left in b->r. */
static double backward_error(cont_bmat *bm, const double *x, const double *rhs)
{
    struct cont_blk *b = bm->blk;
    long m = bm->m;
    const sunindextype *ap = SM_INDEXPTRS_S(bm->A), *ai = SM_INDEXVALS_S(bm->A);
    const double *av = SM_DATA_S(bm->A);
    for (long i = 0; i < m; i++) {
        b->r[i] = rhs[i];
        b->sc[i] = fabs(rhs[i]);
    }
    for (long j = 0; j < m; j++)
        for (sunindextype k = ap[j]; k < ap[j + 1]; k++) {
            double v = av[k] * x[j];
            b->r[ai[k]] -= v;
            b->sc[ai[k]] += fabs(v);
        }
    double om = 0.0;
    for (long i = 0; i < m; i++) {
        if (b->r[i] == 0.0) continue;
        om = b->sc[i] > 0 ? fmax(om, fabs(b->r[i]) / b->sc[i]) : INFINITY;
    }
    return om;
}

/* Factorise bm->A (assembled by ci_bm_build) by block elimination.  0 ok;
 * 1: not usable here (the caller factorises the whole matrix instead). */
int ci_blk_factor(cont_solver *s, cont_bmat *bm)
{
    (void)s;
    struct cont_blk *b = bm->blk;
    long n = b->n;
    if (b->stale && blk_pattern(bm) != 0) return 1;
    const sunindextype *ap = SM_INDEXPTRS_S(bm->A), *ai = SM_INDEXVALS_S(bm->A);
    const double *av = SM_DATA_S(bm->A);
    double amax = 0.0, asym = 0.0;
    for (long j = 0; j < n; j++)
        for (sunindextype k = ap[j]; k < ap[j + 1]; k++) {
            if (ai[k] >= n) continue;
            double t = b->tpos[k] >= 0 ? av[b->tpos[k]] : 0.0;
            amax = fmax(amax, fabs(av[k]));
            asym = fmax(asym, fabs(av[k] - t));
        }
    if (!(asym <= BLK_SYM_TOL * amax)) return 1;
    double *lx = SM_DATA_S(b->L);
    for (sunindextype k = 0; k < SM_INDEXPTRS_S(b->L)[n]; k++) lx[k] = av[b->lsrc[k]];
    if (SUNLinSolSetup(b->LS, b->L) != 0 || cont_mumps_null_pivots(b->LS) > 0) return 1;
    /* z = Jy^{-1} Fp and the border row, from the bordered matrix */
    double *fp = N_VGetArrayPointer(b->vb), d = 0.0;
    memset(fp, 0, (size_t)n * sizeof(double));
    memset(b->cy, 0, (size_t)n * sizeof(double));
    for (sunindextype k = ap[n]; k < ap[n + 1]; k++) {
        if (ai[k] < n) fp[ai[k]] = av[k];
        else d = av[k];
    }
    for (long j = 0; j < n; j++)
        for (sunindextype k = ap[j]; k < ap[j + 1]; k++)
            if (ai[k] == n) b->cy[j] = av[k];
    if (SUNLinSolSolve(b->LS, b->L, b->vx, b->vb, 0.0) != 0) return 1;
    memcpy(b->z, N_VGetArrayPointer(b->vx), (size_t)n * sizeof(double));
    double g = d, terms = fabs(d);
    for (long i = 0; i < n; i++) {
        g -= b->cy[i] * b->z[i];
        terms += fabs(b->cy[i] * b->z[i]);
    }
    if (!isfinite(terms) || !(fabs(g) > BLK_PIVOT_MIN * terms)) return 1;
    b->g = g;
    int sg;
    double ld;
    if (cont_mumps_det(b->LS, &sg, &ld) != 0 || sg == 0) return 1;
    b->sign = g > 0 ? sg : -sg;
    b->logdet = ld + log(fabs(g));
    return 0;
}

void ci_blk_factor_stats(const cont_bmat *bm, cont_factor_stats *fs)
{
    cont_mumps_factor_stats(bm->blk->LS, fs);
}

void ci_blk_inertia(const cont_bmat *bm, long *neg, long *nnull)
{
    cont_mumps_inertia(bm->blk->LS, neg, nnull);
}

int ci_blk_det(const cont_bmat *bm, int *sign, double *logdet)
{
    if (sign) *sign = bm->blk->sign;
    if (logdet) *logdet = bm->blk->logdet;
    return 0;
}

/* x = A^{-1} b with the block factors, refined against A to BLK_BERR_TOL.
 * 0 ok; 1: not reached (the caller factorises the whole matrix). */
int ci_blk_solve(cont_solver *s, cont_bmat *bm, double *x, const double *rhs, int raw)
{
    struct cont_blk *b = bm->blk;
    long m = bm->m;
    if (blk_apply(bm, rhs, x) != 0) return 1;
    if (raw) return 0;
    double prev = HUGE_VAL;
    for (int it = 0;; it++) {
        double om = backward_error(bm, x, rhs);
        if (om <= BLK_BERR_TOL) return 0;
        if (it == BLK_REFINE_MAX || !(om <= 0.5 * prev)) return 1;
        prev = om;
        s->stp.nlinsolve++;
        if (blk_apply(bm, b->r, b->d) != 0) return 1;
        for (long i = 0; i < m; i++) x[i] += b->d[i];
    }
}
