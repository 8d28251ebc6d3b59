/* flatlimit_sparse.c - the limit problem of the driving's branch at the
 * flat state in face poses, sparse (flatlimit_sparse.h).
 *
 * Unknowns w = (x, mu, z, nu), 2 n values (n = q->n: the coordinates and
 * the constraint rows of the pose problem, twice).  The equations of the
 * header are the stationarity of
 *   L = x^T H0 x / 2 + b . x + mu . J x + nu . (J z + (x^T G x) / 2)
 *       + delta |z|^2 / 2 - eta |nu|^2 / 2,
 * whose Hessian is the symmetric KKT matrix
 *   [ H0 + sum nu_r G_r   J^T    0       [Gx]^T ]   x
 *   [ J                  -reg    0       0      ]   mu
 *   [ 0                   0      delta   J^T    ]   z
 *   [ [Gx]                0      J      -eta    ]   nu
 * ([Gx] the rows x^T G_r).  Every block is local: H0 + sum nu_r G_r, J
 * and J^T are the pose Jacobian at (flat state, multipliers nu)
 * (sf_peq_jacobian_csc, analytic), the rows of [Gx] come from the fold
 * rows' own Hessians (sf_poses_fold_rows with a unit multiplier), so the
 * matrix has about twice the nonzeros of the pose Jacobian and is
 * factorised by MUMPS (ldlt.h), which also gives its inertia.
 *
 * eta is a penalty on the second-order rows (nu = their residual / eta).
 * Newton starts from the first-order response u (the driving's response
 * on the first-order kernel, with the declared imperfection of the mode
 * amplitudes) directly at eta = 1e-8, then 1e-9 and 1e-12 (scaled; from
 * 1e-9, 1e-10, 1e-12 when the first start falls back to the flat state
 * at 1e-8, below): a
 * homotopy from eta = 1e2 down (the sparse counterpart of the penalty
 * descent of flatcone.c) was measured and ends at a locked state on the
 * 3x3 Miura sheet (docs/flatstart.md).  Newton has an inertia
 * correction: while the KKT matrix has more negative pivots than
 * constraint rows (2 per row: mu and nu) the energy is not convex on the
 * constraints' tangent space; the step is then taken with the
 * Gauss-Newton matrix of the penalty (the x block H0 alone, without the
 * curvature sum nu_r G_r of the second-order rows), and only when that
 * is not convex either with a shift on the x block; a converged saddle
 * (inertia of the full matrix) is pushed off by a pseudo-random
 * perturbation (fixed seeds).  delta (tiny) selects the minimum-norm z.
 * The problem has several stable local minima on a tessellation (the 4x4
 * Miura sheet and up): a second start, the rigid-origami motion of the
 * degree-4 vertices (flatrigid.h, warm from the first solution), gives
 * the lower one where the first-order response leads to a higher one;
 * the lower of the two is kept.  A last start, that state with its mode
 * amplitudes negated (its other unknowns kept as the first guess, a small
 * iteration budget), tells a symmetric start (a distinct solution of
 * equal energy) from a selected one.  These two extra starts are left
 * when, after their first stage, they fall back towards the flat state
 * (analysis.flat_collapse): energy 0 there, above any state kept.  The
 * first start is left so too (at FIRST_COLLAPSE of its amplitude) and
 * then made again with every stage's eta ten times smaller (and so are
 * the later starts).  The first start's last stage is run only when its
 * state may be followed: its energy at the stage before bounds the one at
 * the last from below, and a rigid start lower than that bound is
 * followed without it (first_finish).  When the first start's last stage
 * does not converge, its state at the stage before is taken (lw_solve). */
#include "flatlimit_sparse.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "equilibrium_poses.h"
#include "flatrigid.h"
#include "ldlt.h"
#include "poses.h"
#include "study.h"

#define DELTA_S 1e-10    /* delta, scaled */
#define REG_S 1e-12      /* eta of the last stage, scaled */
#define ETA0 1e-8
#define NSTAGES 3
#define MAXIT 250        /* Newton iterations per stage (16x16 Miura: 206, both starts) */
#define MAXIT_RIGID 40   /* the same for the rigid start (stage 1: 16 to 27 where it converged) */
#define MAXIT_MIRROR 30   /* the same for the mirror start (about 10 where it is a solution) */
#define MAXPUSH 6
#define CAP 1.0          /* fold coordinates move by at most CAP |x| per step */
#define SHIFT_DECAY 16.0 /* a shift climb starts at the end of the last one / this */
/* The first start (from eta = 1e-8) is left as falling back to the flat
 * state when its fold amplitude falls below this fraction of its value
 * where the first stage converged, and made again from eta = 1e-9.  The
 * 24x24 and 31x31 Miura sheets: 0.33 and 0.34 there, 0.17 and 0.18 after
 * the first step of the second stage; with the extra starts' 0.25 the
 * 31x31 one then wandered at 0.18 for the second stage's 250 iterations
 * (2 s each) instead of collapsing.  Where the first start converges
 * (5x5 to 20x20 under actuation, 4x4 to 12x12 under load) its amplitude
 * does not fall at all after the first stage. */
#define FIRST_COLLAPSE 0.75
/* The first start's first stage (eta = 1e-8) is also left, and made again
 * from eta = 1e-9, when, once its fold amplitude has settled (moves by at
 * most STALL_MOVE of itself per step), its residual has not fallen below
 * half its lowest value since for this many Newton iterations
 * (analysis.flat_stall, this its default; 0: never).  While the amplitude
 * moves the iterate travels (it halves at the first steps, then grows
 * back) and the residual's climb is no verdict.  On the 31x31 Miura sheet
 * the amplitude settles at 0.29 after 10 iterations (the uniform Miura
 * motion has 0.63) and the residual wanders between 160 and 950 without
 * halving (the penalty-held state that then falls back at eta = 1e-9,
 * above): left after 20 iterations, was 30 with the former count from
 * the stage's start.  Where the first stage leads to a state that is
 * kept, or one left at the next stage as before (24x24), the longest such
 * run measured is 5 (12x12 under gravity and a tip load, 24x24 under
 * actuation), at most 3 elsewhere (4x4 to 20x20 under actuation, 4x4 to
 * 12x12 under load; docs/flatstart.md, "A first stage that makes no
 * progress"). */
#define FIRST_STALL 10
#define STALL_MOVE 0.1
#define PIVOT_U 1e-3     /* MUMPS's CNTL(1) for the limit matrix (lw_init) */

typedef struct lim_ws {
    sf_equil *q;
    sf_poses P;
    int n, nx, nf, ncon;
    long nl, ngx;
    int *r, *c;
    long *src;        /* >= 0 Jacobian entry; -1 diag of x/mu; -2 diag of z/nu; -3 [Gx] */
    double *a, *d, *gx, *qr, *ybuf, *b, *R;
    double *work, *dg, *Hl;
    int *col;
    double *hc;       /* the rows' Hessians at the flat state (gx_rows) */
    double *a1, *a0;  /* the matrix values; a0 with H0 alone in the x block (Gauss-Newton) */
    double *v0;       /* the Jacobian's values at multipliers 0 (H0), once */
    int hc_filled;
    double last_big;     /* the last shift a climb ended at */
    double collapse;     /* analysis.flat_collapse: an extra start is left when its fold
                          * amplitude falls below this fraction of collapse_ref */
    int collapse_on;     /* an extra start: left when it falls back to the flat state */
    double collapse_ref; /* its fold amplitude where the first stage converged (0: not yet) */
    double collapse_frac; /* the fraction of collapse_ref in force: collapse, or for the
                           * first start FIRST_COLLAPSE (0 when collapse is 0) */
    double eta0;         /* the first stage's eta (ETA0, or ETA0 / 10 after a retry) */
    int stall;           /* analysis.flat_stall (0: off) */
    int stall_on;        /* the first start's first stage: left after stall iterations
                          * without progress */
    int stalled;         /* it was */
    int keep_prev;       /* the first start's last stage (first_finish): when it does not
                          * converge, the state of the stage before is taken (lw_solve) */
    sf_ldlt *f;
    const double *y0;
    double p0;
} lim_ws;

static void lw_free(lim_ws *w)
{
    sf_ldlt_free(w->f);
    sf_poses_free(&w->P);
    free(w->r);
    free(w->c);
    free(w->src);
    free(w->a);
    free(w->d);
    free(w->gx);
    free(w->qr);
    free(w->ybuf);
    free(w->b);
    free(w->R);
    free(w->work);
    free(w->dg);
    free(w->Hl);
    free(w->col);
    free(w->hc);
    free(w->a1);
    free(w->a0);
    free(w->v0);
}

/* One constraint row r of gx_rows: its nv local columns (w->col, -1 =
 * not an unknown) from triplet index k, the entries x^T G_r (H: the
 * row's nv x nv Hessian) and x^T G_r x / 2 into qr[r].  Returns the next
 * index. */
static long gx_row(lim_ws *w, const double *x, long k, int record, int row, int nv,
                   const double *H)
{
    double qv = 0.0;
    for (int a = 0; a < nv; a++) {
        if (w->col[a] < 0) continue;
        if (record) {
            w->r[k] = w->n + w->nx + row;
            w->c[k] = w->col[a];
            w->src[k] = -3;
        }
        if (x) {
            double v = 0.0;
            for (int bb = 0; bb < nv; bb++)
                if (w->col[bb] >= 0) v += H[a * nv + bb] * x[w->col[bb]];
            w->gx[k - w->nl] = v;
            qv += 0.5 * v * x[w->col[a]];
        }
        k++;
    }
    if (x) w->qr[row] = qv;
    return k;
}

/* The entries of [Gx] (the rows x^T G_r of the constraint rows r, local
 * columns) from index k of the triplets (record: their positions), and
 * x^T G_r x / 2 into qr.  x NULL: pattern only (returns the end index).
 * The rows' Hessians at the flat state are computed at the first call
 * with x (sf_poses_fold_rows, sf_poses_mpoint with a unit multiplier)
 * and kept (w->hc: nv^2 values per row). */
static long gx_rows(lim_ws *w, const double *x, long k, int record)
{
    sf_equil *q = w->q;
    const sf_model *m = q->m;
    long ho = 0;
    int fill = x && !w->hc_filled;
    if (fill) {
        long tot = 0;
        for (int i = 0; i < m->nfolds; i++) {
            int nv = sf_poses_fold_vars(&w->P, i, w->col);
            tot += 6L * nv * nv;
        }
        for (int s = 0; s < q->nsup; s++) {
            const sf_mpoint *pt = &q->rowpt[s];
            int nv = sf_poses_point_vars(&w->P, pt->face, pt->fold, w->col);
            tot += (long)nv * nv;
        }
        w->hc = malloc(sizeof(double) * (size_t)(tot + 1));
        if (!w->hc) return -1;
    }
    for (int i = 0; i < m->nfolds; i++) {
        int nv = sf_poses_fold_vars(&w->P, i, w->col);
        double g[6];
        for (int cc = 0; cc < 6; cc++) {
            int row = sf_peq_fold_row(q, 6 * i + cc);   /* -1: dropped */
            double lam[6] = {0, 0, 0, 0, 0, 0};
            lam[cc] = 1.0;
            const double *H = w->hc ? w->hc + ho : NULL;
            if (fill) sf_poses_fold_rows(&w->P, w->y0, i, g, w->dg, lam, w->hc + ho, w->work);
            ho += (long)nv * nv;
            if (row < 0) continue;
            k = gx_row(w, x, k, record, row, nv, H);
        }
    }
    for (int s = 0; s < q->nsup; s++) {
        const sf_mpoint *pt = &q->rowpt[s];
        int row = q->nloop + s, cc = q->rowc[s];
        int nv = sf_poses_point_vars(&w->P, pt->face, pt->fold, w->col);
        double xo[3], wt[3] = {0, 0, 0};
        wt[cc] = 1.0;
        const double *H = w->hc ? w->hc + ho : NULL;
        if (fill) sf_poses_mpoint(&w->P, w->y0, pt, xo, w->dg, wt, w->hc + ho, w->work);
        ho += (long)nv * nv;
        k = gx_row(w, x, k, record, row, nv, H);
    }
    if (fill) w->hc_filled = 1;
    return k;
}

static int lw_init(lim_ws *w, sf_equil *q, const double *y0, double p0, sf_error *err)
{
    memset(w, 0, sizeof *w);
    w->q = q;
    w->y0 = y0;
    w->p0 = p0;
    w->n = q->n;
    w->nx = q->nq;
    w->nf = q->m->nq;
    w->ncon = q->ncon;
    int n = w->n;
    if (sf_poses_init(&w->P, q->m, err)) return err->code;
    size_t nv = (size_t)w->P.maxnv;
    w->work = malloc(sizeof(double) * sf_poses_work_size(&w->P));
    w->dg = malloc(sizeof(double) * 6 * nv);
    w->Hl = malloc(sizeof(double) * nv * nv);
    w->col = malloc(sizeof(int) * nv);
    w->d = malloc(sizeof(double) * (size_t)n);
    w->qr = calloc((size_t)w->ncon + 1, sizeof(double));
    w->ybuf = malloc(sizeof(double) * (size_t)n);
    w->b = malloc(sizeof(double) * (size_t)n);
    w->R = malloc(sizeof(double) * 2 * (size_t)n);

    if (!w->work || !w->dg || !w->Hl || !w->col || !w->d || !w->qr || !w->ybuf || !w->b || !w->R)
        return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int i = 0; i < n; i++) w->d[i] = sqrt(q->fscale[i] / q->yscale[i]);
    if (sf_ldlt_create(&w->f, 0.0, err)) return err->code;
    /* MUMPS's pivot threshold 1e-3 instead of its 0.01: the (z, nu) block's
     * diagonals (1e-10, -eta) fail the default test, and about half of
     * its pivots were delayed (docs/flatstart.md, "The pivot threshold of
     * the limit matrix") */
    sf_ldlt_set_pivot_threshold(w->f, PIVOT_U);
    return SF_OK;
}

/* The pattern (first call) and the values of the scaled KKT matrix at
 * w (x, mu, z, nu raw) with eta, no shift (lw_shifted adds it), into
 * L->a1, and the same with H0 alone in the x block into L->a0; the raw
 * residual into w->R. */
static int lw_assemble(lim_ws *L, const double *w, double eta, sf_error *err)
{
    sf_equil *q = L->q;
    int n = L->n, nx = L->nx;
    const long *cp;
    const int *ri;
    const double *v;
    memcpy(L->ybuf, L->y0, sizeof(double) * (size_t)nx);
    if (!L->v0) {   /* H0: the Jacobian at multipliers 0 (its pattern is the study's) */
        memset(L->ybuf + nx, 0, sizeof(double) * (size_t)L->ncon);
        if (sf_peq_jacobian_csc(q, L->ybuf, L->p0, &cp, &ri, &v, L->b))
            return sf_fail(err, SF_ENUMERIC, "%s: a Jacobian at the flat state is not finite",
                           q->m->study->path);
        L->v0 = malloc(sizeof(double) * (size_t)(cp[n] + 1));
        if (!L->v0) return sf_fail(err, SF_ENOMEM, "out of memory");
        memcpy(L->v0, v, sizeof(double) * (size_t)cp[n]);
    }
    memcpy(L->ybuf + nx, w + n + nx, sizeof(double) * (size_t)L->ncon);   /* multipliers nu */
    if (sf_peq_jacobian_csc(q, L->ybuf, L->p0, &cp, &ri, &v, L->b))
        return sf_fail(err, SF_ENUMERIC, "%s: a Jacobian at the flat state is not finite",
                       q->m->study->path);
    if (!L->r) {   /* the pattern, once */
        long nl = 2L * n;
        for (int j = 0; j < n; j++)
            for (long k = cp[j]; k < cp[j + 1]; k++) {
                if (ri[k] >= j) nl++;
                if (j < nx && ri[k] >= nx) nl++;
            }
        L->nl = nl;
        L->ngx = gx_rows(L, NULL, 0, 0);
        long tot = nl + L->ngx;
        L->r = malloc(sizeof(int) * (size_t)tot);
        L->c = malloc(sizeof(int) * (size_t)tot);
        L->src = malloc(sizeof(long) * (size_t)tot);
        L->a = malloc(sizeof(double) * (size_t)tot);
        L->gx = malloc(sizeof(double) * (size_t)L->ngx + 1);
        L->a1 = malloc(sizeof(double) * (size_t)tot);
        L->a0 = malloc(sizeof(double) * (size_t)tot);
        if (!L->r || !L->c || !L->src || !L->a || !L->gx || !L->a1 || !L->a0)
            return sf_fail(err, SF_ENOMEM, "out of memory");
        long k = 0;
        for (int j = 0; j < n; j++) {
            L->r[k] = L->c[k] = j;
            L->src[k++] = -1;
            L->r[k] = L->c[k] = n + j;
            L->src[k++] = -2;
            for (long e = cp[j]; e < cp[j + 1]; e++) {
                if (ri[e] >= j) {
                    L->r[k] = ri[e];
                    L->c[k] = j;
                    L->src[k++] = e;
                }
                if (j < nx && ri[e] >= nx) {   /* J in the (nu, z) block */
                    L->r[k] = n + ri[e];
                    L->c[k] = n + j;
                    L->src[k++] = e;
                }
            }
        }
        gx_rows(L, NULL, k, 1);
    }
    const double *x = w;
    if (gx_rows(L, x, L->nl, 0) < 0) return sf_fail(err, SF_ENOMEM, "out of memory");
    double *d = L->d;
    long tot = L->nl + L->ngx;
    for (long k = 0; k < tot; k++) {
        int i = L->r[k] % n, j = L->c[k] % n;
        double s = d[i] * d[j], val, val0;
        if (L->src[k] >= 0) {
            val = s * v[L->src[k]];
            val0 = L->r[k] < nx && L->c[k] < nx ? s * L->v0[L->src[k]] : val;
        } else {
            if (L->src[k] == -1) val = 0.0;
            else if (L->src[k] == -2) val = i < nx ? DELTA_S : -fmax(eta, REG_S);
            else val = s * L->gx[k - L->nl];
            val0 = val;
        }
        L->a1[k] = val;
        L->a0[k] = val0;
    }
    /* residual (raw) */
    double *R = L->R;
    const double *mu = w + nx, *z = w + n, *nu = w + n + nx;
    for (int i = 0; i < nx; i++) {
        R[i] = L->b[i];
        R[n + i] = DELTA_S / (d[i] * d[i]) * z[i];
    }
    for (int r = 0; r < L->ncon; r++) {
        R[nx + r] = 0.0;
        R[n + nx + r] = L->qr[r] - fmax(eta, REG_S) / (d[nx + r] * d[nx + r]) * nu[r];
    }
    for (int j = 0; j < n; j++)
        for (long e = cp[j]; e < cp[j + 1]; e++) {
            int i = ri[e];
            if (i < nx) {
                R[i] += v[e] * (j < nx ? x[j] : mu[j - nx]);   /* HL x + J^T mu */
                if (j >= nx) R[n + i] += v[e] * nu[j - nx];      /* J^T nu */
            } else if (j < nx) {
                R[i] += v[e] * x[j];                              /* J x */
                R[n + i] += v[e] * z[j];                          /* J z */
            }
        }
    return SF_OK;
}

/* Factorise the assembled matrix (gn: the Gauss-Newton one, H0 alone in
 * the x block) with the shift on the x block; *neg the negative pivots. */
static int lw_shifted(lim_ws *L, int gn, double shift, int *neg, sf_error *err)
{
    long tot = L->nl + L->ngx;
    const double *src = gn ? L->a0 : L->a1;
    for (long k = 0; k < tot; k++)
        L->a[k] = L->src[k] == -1 && L->r[k] < L->nx ? shift : src[k];
    if (sf_ldlt_factor(L->f, 2 * L->n, tot, L->r, L->c, L->a, err)) return err->code;
    sf_ldlt_info li;
    sf_ldlt_get_info(L->f, &li);
    *neg = li.neg;
    return SF_OK;
}

static double lw_resnorm(const lim_ws *L)
{
    double mx = 0.0;
    for (int i = 0; i < 2 * L->n; i++) mx = fmax(mx, fabs(L->R[i] * L->q->fscale[i % L->n]));
    return mx;
}

static double fold_max(const lim_ws *L, const double *x)
{
    double mx = 0.0;
    const sf_model *m = L->q->m;
    for (int i = 0; i < m->nfolds; i++) mx = fmax(mx, fabs(x[m->qoff[i]]));
    return mx;
}

/* Newton with inertia correction at a fixed eta; 0 when converged to a
 * state of the right inertia, 2 when an extra start falls back to the
 * flat state (analysis.flat_collapse), 1 otherwise. */
static int lw_stage(lim_ws *L, double *w, double eta, double tol, int maxit, int *its, int *pushes,
                    double *res, sf_error *err)
{
    int n = L->n, N = 2 * n, target = 2 * L->ncon;
    double best = INFINITY;   /* the stall rule (FIRST_STALL) */
    double amp_prev = 0.0;
    int since = 0;
    int full_ok = 0;   /* the last step's matrix: the full one, of the right inertia */
    for (int it = 0; it < maxit; it++) {
        int neg = 0;
        if (lw_assemble(L, w, eta, err)) return -1;
        *res = lw_resnorm(L);
        /* the stall rule counts the iterations without progress once the
         * fold amplitude has settled (moves by at most STALL_MOVE per
         * step): while it moves, the iterate travels and the residual's
         * climb is no verdict */
        double amp = fold_max(L, w);
        int moving = it > 0 && fabs(amp - amp_prev) > STALL_MOVE * amp_prev;
        amp_prev = amp;
        if (moving || *res < 0.5 * best) {
            best = *res;
            since = 0;
        } else if (L->stall_on && L->stall > 0 && ++since >= L->stall) {
            L->stalled = 1;
            return 2;
        }
        if (*res <= tol) {
            /* the converged state's inertia: that of the last Newton
             * matrix when it was the full one with the right inertia (at
             * the iterate before, whose step converged), else of the full
             * matrix factorised here: one factorisation less per stage
             * (docs/flatstart.md, "The inertia at a converged stage") */
            if (full_ok) return 0;
            if (lw_shifted(L, 0, 0.0, &neg, err)) return -1;
            if (neg <= target) return 0;
            if (++*pushes > MAXPUSH) return 1;
            /* a saddle: pushed off (pseudo-random, fixed seed) */
            unsigned long seed = 2654435761u * (unsigned long)*pushes + 97u;
            double xm = fold_max(L, w);
            for (int i = 0; i < L->nf; i++) {
                seed = seed * 6364136223846793005ul + 1442695040888963407ul;
                w[i] += 1e-2 * xm * ((double)(seed >> 11) / 4503599627370496.0 - 1.0);
            }
            it--;
            continue;
        }
        /* the inertia correction.  The full matrix first; where its
         * inertia is wrong, the Gauss-Newton matrix of the penalty (H0
         * alone in the x block: the curvature sum nu_r G_r of the
         * second-order rows dropped); only when that is wrong too, a
         * shift on its x block, from the end of the last climb /
         * SHIFT_DECAY (at least 1e-6) up by factors of 4.  Far from the
         * cone nu = (second-order residual) / eta is large and sum nu_r G_r
         * indefinite: the shift that repaired it (the former rule: the
         * full matrix shifted, the shift 1 to 4000 in the first stage)
         * damped every direction alike, and the first start crawled (164
         * Newton iterations on the 16x16 Miura sheet, 250 without
         * convergence on the 31x31 one); the Gauss-Newton matrix is
         * convex there and its steps keep their length (16x16: 30).  The
         * converged state's inertia is that of the full matrix (above). */
        if (lw_shifted(L, 0, 0.0, &neg, err)) return -1;
        full_ok = neg <= target;
        if (neg > target) {
            double shift = 0.0;
            for (int k = 0; k < 40; k++) {
                if (lw_shifted(L, 1, shift, &neg, err)) return -1;
                if (neg <= target) break;
                shift = k == 0 ? fmax(1e-6, L->last_big / SHIFT_DECAY) : 4.0 * shift;
            }
            if (shift > 0) L->last_big = shift;   /* a climb: its end */
        }
        (*its)++;
        double *s = malloc(sizeof(double) * (size_t)N);
        if (!s) return sf_fail(err, SF_ENOMEM, "out of memory"), -1;
        for (int i = 0; i < N; i++) s[i] = -L->R[i] * L->d[i % n];
        if (sf_ldlt_solve(L->f, s, err)) {
            free(s);
            return -1;
        }
        double sm = 0.0, xm = fold_max(L, w);
        for (int i = 0; i < N; i++) {
            s[i] *= L->d[i % n];
            if (!isfinite(s[i])) {
                free(s);
                return sf_fail(err, SF_ENUMERIC, "a Newton step of the flat limit problem is not "
                               "finite"), -1;
            }
        }
        for (int i = 0; i < L->nf; i++) sm = fmax(sm, fabs(s[i]));
        double sc = sm > CAP * xm ? CAP * xm / sm : 1.0;
        for (int i = 0; i < N; i++) w[i] += sc * s[i];
        free(s);
        /* an extra start falling back to the flat state after its first
         * stage: the 16x16 Miura sheet's rigid start, whose fold amplitude
         * halved at every step of the last stage, each factorisation
         * there 10 times the cost of one in the first stage (MUMPS near
         * a singular matrix): 40 iterations of about 1.5 s CPU */
        if (L->collapse_ref > 0 && fold_max(L, w) < L->collapse_frac * L->collapse_ref) return 2;
    }
    return 1;
}

/* x^T H0 x / 2 + b . x with H0 at the flat state, multipliers 0. */
static int lw_energy(lim_ws *L, const double *x, double *E, sf_error *err)
{
    int nx = L->nx;
    const long *cp;
    const int *ri;
    const double *v;
    memcpy(L->ybuf, L->y0, sizeof(double) * (size_t)nx);
    memset(L->ybuf + nx, 0, sizeof(double) * (size_t)L->ncon);
    if (sf_peq_jacobian_csc(L->q, L->ybuf, L->p0, &cp, &ri, &v, L->b))
        return sf_fail(err, SF_ENUMERIC, "a Jacobian at the flat state is not finite");
    double e = 0.0;
    for (int j = 0; j < nx; j++) {
        e += L->b[j] * x[j];
        for (long k = cp[j]; k < cp[j + 1]; k++)
            if (ri[k] < nx) e += 0.5 * x[ri[k]] * v[k] * x[j];
    }
    *E = e;
    return SF_OK;
}

/* The penalty stages from .. to - 1 (of NSTAGES) from the state in w;
 * maxit Newton iterations per stage at most. */
static int lw_solve(lim_ws *L, double *w, int from, int to, double tol, int maxit,
                    sf_flatlimit_info *info, sf_error *err)
{
    double eta = L->eta0, res = INFINITY, prev_eta = 0.0;
    double *prev = NULL;
    for (int st = 0; st < from; st++, eta *= 0.1) prev_eta = eta;
    for (int st = from; st < to; st++, eta *= 0.1) {
        int last = st == NSTAGES - 1;
        if (last && L->keep_prev && st > 0) {
            prev = malloc(sizeof(double) * 2 * (size_t)L->n);
            if (!prev) return sf_fail(err, SF_ENOMEM, "out of memory");
            memcpy(prev, w, sizeof(double) * 2 * (size_t)L->n);
        }
        int its0 = info->iterations;
        int stall_on = L->stall_on;
        L->stall_on = stall_on && st == 0;
        int rc = lw_stage(L, w, last ? REG_S : eta, last ? tol : fmax(tol, 1e-7), maxit,
                          &info->iterations, &info->pushes, &res, err);
        L->stall_on = stall_on;
        info->stages = st + 1;
        info->residual = res;
        if (rc > 0 && prev) {
            /* The last stage (eta = 1e-12) does not converge: the 12x12
             * Miura sheet under gravity and a tip load, whose limit state
             * carries a large prestress nu on nearly dependent fold rows;
             * from the previous stage's state (scaled residual 1e-7 at
             * eta = 1e-12) Newton's steps along those rows are of the size
             * of the residual over eta and it wanders for its 250
             * iterations between 1e-6 and 3.  The previous stage's state
             * solves the limit problem to within its penalty (eta = 1e-9)
             * and is only the first guess of the first point, whose Newton
             * solves the full problem: it is taken. */
            memcpy(w, prev, sizeof(double) * 2 * (size_t)L->n);
            free(prev);
            prev = NULL;
            info->prev_stage = 1;
            info->prev_eta = prev_eta;
            info->last_res = res;
            info->last_its = info->iterations - its0;
            break;
        }
        free(prev);
        prev = NULL;
        prev_eta = eta;
        if (rc < 0) return err->code;
        if (rc == 2 && L->stalled) {
            info->collapsed = 1;
            return sf_fail(err, SF_ENUMERIC, "the sparse limit problem's first penalty stage "
                           "makes no progress (scaled residual not halved in %d Newton "
                           "iterations)", L->stall);
        }
        if (rc == 2) {
            info->collapsed = 1;
            return sf_fail(err, SF_ENUMERIC, "the sparse limit problem falls back to the flat "
                           "state at penalty stage %d of %d (fold amplitude below %g of its value "
                           "at stage 1 after %d Newton iterations)", st + 1, NSTAGES, L->collapse_frac,
                           info->iterations);
        }
        if (rc > 0)
            return sf_fail(err, SF_ENUMERIC, "the sparse limit problem of the flat state does not "
                           "converge at penalty stage %d of %d (scaled residual %.3g after %d "
                           "Newton iterations, %d saddles left)", st + 1, NSTAGES, res,
                           info->iterations, info->pushes);
        if (st == 0 && L->collapse_on) L->collapse_ref = fold_max(L, w);
    }
    info->stable = 1;
    return lw_energy(L, w, &info->energy, err);
}

static void imperfect(const sf_model *m, double *x, double rel)
{
    double mx = 0.0;
    for (int i = 0; i < m->nfolds; i++) mx = fmax(mx, fabs(x[m->qoff[i]]));
    for (int i = 0; i < m->nfolds; i++)
        for (int k = 1; k < m->qn[i]; k++) x[m->qoff[i] + k] += rel * mx;
}

/* One candidate: from the start (nstart values of w: x, mu, then z, nu;
 * the others 0) with the mode imperfection rel, at most maxit Newton
 * iterations per stage, the penalty stages before stage to.  0 converged,
 * > 0 not, < 0 error in err. */
static int candidate(lim_ws *L, const double *start, int nstart, double rel, int maxit, int extra,
                     int to, double *w, sf_flatlimit_info *info, sf_error *err)
{
    L->collapse_on = extra;
    L->collapse_ref = 0.0;
    int n = L->n;
    memset(w, 0, sizeof(double) * 2 * (size_t)n);
    memcpy(w, start, sizeof(double) * (size_t)nstart);
    imperfect(L->q->m, w, rel);
    memset(info, 0, sizeof *info);
    int rc = lw_solve(L, w, 0, to, 1e-10, maxit, info, err);
    if (rc && err->code != SF_ENUMERIC) return -1;
    return rc ? 1 : 0;
}

/* The first start's last penalty stage (eta = REG_S), from its state w
 * at the stage before (candidate() with to = NSTAGES - 1), collapse_ref
 * its fold amplitude after its first stage, into info (counts added);
 * when it does not converge, or falls back towards the flat state
 * (analysis.flat_collapse of collapse_ref), the state of the stage before
 * is kept (lw_solve).  Run only when that state may be the one followed
 * (sf_flat_limit_sparse): the last stage costs the most (MUMPS near a
 * singular matrix). */
static int first_finish(lim_ws *L, double *w, double collapse_ref, sf_flatlimit_info *info,
                        sf_error *err)
{
    sf_flatlimit_info fi;
    memset(&fi, 0, sizeof fi);
    L->keep_prev = 1;
    L->collapse_on = 1;
    L->collapse_ref = collapse_ref;
    L->collapse_frac = L->collapse;
    int rc = lw_solve(L, w, NSTAGES - 1, NSTAGES, 1e-10, MAXIT, &fi, err);
    L->keep_prev = 0;
    info->iterations += fi.iterations;
    info->pushes += fi.pushes;
    if (rc) return err->code;
    info->stages = NSTAGES;
    info->residual = fi.residual;
    info->energy = fi.energy;
    info->prev_stage = fi.prev_stage;
    info->prev_eta = fi.prev_eta;
    info->last_res = fi.last_res;
    info->last_its = fi.last_its;
    return SF_OK;
}

/* The start of the limit problem from the rigid modes (2 n values of w),
 * warm from the solution ws of the first start (its scale, its mode
 * amplitudes, multipliers and z): the fold angles of rigid_modes, signed
 * by the driving b (the folds it does not move by u), scaled to ws's
 * largest fold angle; each fold's mode amplitudes those of ws times the
 * ratio of the fold angles (0 where ws leaves the fold near flat or turns
 * it the other way); the poses of that motion; mu, z and nu of ws.  From
 * zero mode amplitudes and multipliers Newton halved the fold angles and
 * ended at a penalty-locked state on the 12x12 Miura sheet
 * (docs/flatstart.md).  0 when there is no such start. */
static int rigid_start(lim_ws *L, const double *u, const double *ws, double *st, double *ybuf)
{
    sf_equil *q = L->q;
    const sf_model *m = q->m;
    int n = L->n, nf = L->nf, nx = L->nx;
    memset(st, 0, sizeof(double) * 2 * (size_t)n);
    double E;
    sf_error e;
    sf_error_clear(&e);
    if (lw_energy(L, st, &E, &e)) return 0;   /* fills L->b, the driving */
    if (!sf_flat_rigid_modes(m, u, L->b, st)) return 0;
    double xs = fold_max(L, ws), xr = fold_max(L, st);
    if (!(xs > 0 && xr > 0)) return 0;
    for (int i = 0; i < m->nfolds; i++) {
        double *t = st + m->qoff[i], ts = ws[m->qoff[i]];
        *t *= xs / xr;
        double ratio = fabs(ts) > 0.1 * xs && *t * ts > 0 ? *t / ts : 0.0;
        for (int k = 1; k < m->qn[i]; k++) t[k] = ratio * ws[m->qoff[i] + k];
    }
    /* the poses of the motion to first order: the derivative of the tree
     * maps' poses along it (a first guess, which Newton corrects: the
     * first-order rows J x = 0 are linear).  The poses of ws instead led
     * back to ws's state. */
    if (sf_equil_poses_lift_dir(q, L->y0, st, ybuf)) return 0;
    for (int i = nf; i < nx; i++) st[i] = ybuf[i];
    memcpy(st + nx, ws + nx, sizeof(double) * (size_t)(2 * n - nx));   /* mu, z, nu */
    return 1;
}

/* A candidate after the first: from st (2n values), counted in info
 * (starts, iterations, pushes, converged) and listed as candidate *k of
 * the given kind, its energy NAN until the caller compares it.  Returns
 * candidate()'s result (< 0: error in err). */
static int extra_candidate(lim_ws *L, const double *st, double imperf, int maxit, int kind,
                           double *wc, sf_flatlimit_info *info, sf_flatlimit_info *ci, int *k,
                           sf_error *err)
{
    sf_error ce;
    sf_error_clear(&ce);
    int r = candidate(L, st, 2 * L->n, imperf, maxit, 1, NSTAGES, wc, ci, &ce);
    info->starts++;
    info->iterations += ci->iterations;
    info->pushes += ci->pushes;
    if (r < 0) {
        *err = ce;
        if (!err->code) err->code = SF_ENUMERIC;
        return r;
    }
    *k = info->ncand++;
    info->cand_kind[*k] = kind;
    info->cand_conv[*k] = !r ? 1 : ci->collapsed ? -1 : 0;
    info->cand_energy[*k] = NAN;
    info->converged += !r;
    return r;
}

int sf_flat_limit_sparse(sf_equil *q, const double *y0, double p0, const double *u, double imperf,
                         int mirror, double *w, sf_flatlimit_info *info, sf_error *err)
{
    lim_ws L;
    int n = q->n, rc = SF_OK;
    size_t wsz = sizeof(double) * 2 * (size_t)n;
    const sf_model *m = q->m;
    memset(info, 0, sizeof *info);
    info->energy_alt = NAN;
    double *st = NULL, *wc = NULL;
    if ((rc = lw_init(&L, q, y0, p0, err))) goto out;
    if ((rc = sf_study_double(m->study, "analysis.flat_collapse", 0.25, &L.collapse, err))) goto out;
    if ((rc = sf_study_int(m->study, "analysis.flat_stall", FIRST_STALL, &L.stall, err)))
        goto out;
    st = malloc(wsz);
    wc = malloc(wsz);
    if (!st || !wc) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto out;
    }
    sf_flatlimit_info ci;
    sf_error ce;
    sf_error_clear(&ce);
    L.eta0 = ETA0;
    L.collapse_frac = L.collapse > 0 ? FIRST_COLLAPSE : 0.0;
    /* the first start up to the stage before the last (first_finish) */
    L.stall_on = 1;
    int r = candidate(&L, u, n, imperf, MAXIT, 1, NSTAGES - 1, w, info, &ce);
    L.stall_on = 0;
    if (r > 0 && info->collapsed) {
        /* the first start falling back to the flat state after its first
         * stage: a state the penalty eta = 1e-8 holds off the cone, which
         * collapses as eta falls (the 24x24 Miura sheet: fold amplitude
         * 0.33 where the first stage converged, 0.17 after the second,
         * 0.07 in the third, each factorisation there ten times the cost
         * of one in the first stage; the uniform Miura motion has 0.63).
         * Again from the first-order response with the stages from eta =
         * 1e-9, and the later starts with them too (24x24: converged at
         * 0.63 in 29 iterations) */
        int its0 = info->iterations, stalled = L.stalled;
        L.stalled = 0;   /* a later fall-back is reported as such */
        L.eta0 = 0.1 * ETA0;
        L.collapse_frac = L.collapse;
        sf_error_clear(&ce);
        r = candidate(&L, u, n, imperf, MAXIT, 1, NSTAGES - 1, w, info, &ce);
        info->iterations += its0;
        info->eta_retry = stalled ? 2 : 1;
    }
    double first_ref = L.collapse_ref;
    L.collapse_frac = L.collapse;
    info->starts = 1;
    if (r) {
        *err = ce;
        rc = ce.code ? ce.code : SF_ENUMERIC;
        goto out;
    }
    info->converged = 1;
    info->stable = 1;
    info->energy_alt = NAN;   /* candidate() cleared info */
    info->ncand = 1;
    info->cand_kind[0] = SF_LIMIT_FIRST;
    info->cand_conv[0] = 1;
    int first_done = 0;
    double e_first = info->energy;   /* at the stage before the last, until first_finish */
    /* the rigid-origami start (rigid_modes): another local minimum of the
     * limit problem where the first-order response leads to a state of
     * higher energy (docs/flatstart.md, the 4x4 Miura sheet).  It is
     * compared with the first start's energy at the stage before the
     * last: the penalty relaxes the second-order rows, so near the state
     * that energy is at most the one at the last stage (the penalised
     * minimum is at most the constrained one), and the last stage is
     * only run (first_finish) when the rigid start is not lower than
     * that bound by more than the tie tolerance */
    if (rigid_start(&L, u, w, st, wc)) {
        int k;
        r = extra_candidate(&L, st, imperf, MAXIT_RIGID, SF_LIMIT_RIGID, wc, info, &ci, &k, err);
        if (r < 0) {
            rc = err->code;
            goto out;
        }
        if (!r) {
            info->cand_energy[k] = ci.energy;
            if (!(ci.energy < e_first - 1e-7 * fabs(e_first))) {
                if ((rc = first_finish(&L, w, first_ref, info, err))) goto out;
                e_first = info->energy;
                first_done = 1;
            }
            /* strictly lower (beyond the tie tolerance): followed */
            if (ci.energy < e_first - 1e-7 * fabs(e_first)) {
                info->energy = ci.energy;
                info->chosen = k;
                memcpy(w, wc, wsz);
            }
        }
    }
    if (!first_done && info->chosen == 0) {
        if ((rc = first_finish(&L, w, first_ref, info, err))) goto out;
        e_first = info->energy;
        first_done = 1;
    }
    info->cand_energy[0] = e_first;
    info->first_bound = !first_done;
    if (mirror) {
        /* the mirror in the modes of the state chosen so far: its mode
         * amplitudes negated, every other unknown (poses, mu, z, nu) kept
         * as a first guess.  Where the mirror is a solution too (a
         * symmetric start) Newton reaches it in about ten iterations;
         * from poses and multipliers set to zero it wandered (132
         * iterations on the 5x5 Miura sheet, 420 without convergence on
         * the 8x8 one) and ended elsewhere.  Hence a small budget: a
         * mirror that does not converge within it is not a tie. */
        memcpy(st, w, wsz);
        for (int i = 0; i < m->nfolds; i++)
            for (int k = 1; k < m->qn[i]; k++) st[m->qoff[i] + k] = -w[m->qoff[i] + k];
        int k;
        r = extra_candidate(&L, st, 0.0, MAXIT_MIRROR, SF_LIMIT_MIRROR, wc, info, &ci, &k, err);
        if (r < 0) {
            rc = err->code;
            goto out;
        }
        if (!r) {
            double dx = 0.0, xm = fold_max(&L, w);
            for (int i = 0; i < m->nq; i++) dx = fmax(dx, fabs(wc[i] - w[i]));
            info->xdiff = xm > 0 ? dx / xm : 0.0;
            /* a distinct state off the flat sheet */
            if (info->xdiff > 1e-6 && fold_max(&L, wc) > 1e-3 * xm) {
                info->cand_energy[k] = ci.energy;
                info->energy_alt = ci.energy;
                info->ties = fabs(ci.energy - info->energy) <= 1e-7 * fabs(info->energy);
                /* the lower energy; of two equal ones, the state chosen
                 * before (the one the declared imperfection leads to) */
                if (!info->ties && ci.energy < info->energy) {
                    info->energy_alt = info->energy;
                    info->energy = ci.energy;
                    info->chosen = k;
                    memcpy(w, wc, wsz);
                }
            }
        }
    }
out:
    if (L.f) {
        sf_ldlt_info fo;
        sf_ldlt_get_info(L.f, &fo);
        info->factorisations = fo.factorisations;
    }
    lw_free(&L);
    free(st);
    free(wc);
    return rc;
}
