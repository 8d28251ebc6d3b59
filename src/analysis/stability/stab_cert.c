/* stab_cert.c - a second-order certificate of stability where the
 * constraint rows are redundant (stability.h, sf_stab_certify).
 *
 * With redundant rows (rank r < ncon) the multipliers lambda of a point
 * are fixed only up to a self-stress mu in null(C^T), and where the rows do
 * not keep a constant rank around the point (a sheet's loop rows along a
 * symmetric path: the 2x2 waterbomb tessellation driven on both groups)
 * the reduced Hessian Z^T HL(lambda + mu) Z depends on mu: the term
 * sum mu_k Z^T hess(u_k . g) Z is not zero on null(C).  The directions
 * where it is not zero are first-order motions that the rows block at
 * second order (u_k . g grows like t^2 along them), so a negative
 * eigenvalue for one choice of mu proves nothing; the fold formulation
 * inherits a huge self-stress from the flat start (3.9e6 on that sheet)
 * and reported Morse index 1 there.  The second-order sufficient
 * condition holds with ANY valid multiplier: if Z^T HL(lambda + mu) Z is
 * positive definite for some mu in null(C^T), the point is a strict local
 * minimum of the energy on the constraint set.  This file looks for such a
 * mu over the k = ncon - r self-stresses (k <= CERT_MAXK) when the dense
 * method found a negative eigenvalue at a point with redundant rows: a
 * local ascent on the smallest eigenvalue, then, where it stalls, the
 * semidefinite program that maximises it over a ball of self-stresses
 * (DSDP; the smallest eigenvalue is concave in mu, so that is the global
 * maximum), every mu checked with LAPACK; it reports the point stable
 * (Morse index 0, no eigenvalues: they depend on mu) when one is found;
 * otherwise unknown (stable -1, with the reason), since the dense index
 * at the point's own multipliers is then no proof of instability.  Where the rows keep their rank the extra term is
 * zero to round-off and nothing changes.  Fold formulation, dense method
 * only (face poses start their multipliers from zero and small). */
#include "stability.h"

#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "lmi.h"

extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, double *a,
                    const int *lda, double *s, double *u, const int *ldu, double *vt,
                    const int *ldvt, double *work, const int *lwork, int *info);
extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

#define RANK_TOL 1e-9   /* as stability.c */
#define ZERO_ROW 1e-13  /* as stability.c */
#define CERT_MAXK 64    /* self-stresses tried at most */
#define CERT_ITERS 60   /* ascent steps */
/* The bound of the semidefinite program: |mu| <= CERT_RHO emax / amax
 * (2-norm of the self-stress in unit-row scaling; emax the largest
 * |eigenvalue| of H0, amax the largest Frobenius norm of the A_k).  emax /
 * amax is the self-stress that moves the eigenvalues by as much as H0's
 * largest, so the bound does not depend on units or on the scale of the
 * rows; without one the program is unbounded wherever some combination of
 * the A_k is positive definite.  Large self-stresses block the directions
 * that the rows block at second order and leave H0 on the others, so the
 * bound must be generous: on the 2x2 waterbomb tessellation CERT_RHO =
 * 1e4 left 3 of its 37 points uncertified, 3e4 two and 1e5 none
 * (docs/guides/stability.md); 1e6 keeps a factor 10 in reserve.
 * Round-off grows with the self-stress: a certificate must clear the
 * margin plus a bound on LAPACK's error at its mu (cert_roundoff, 1e-6 at
 * the largest self-stress of that path, against an eigenvalue of 0.0145). */
#define CERT_RHO 1e6

typedef struct {
    int nq, nc, d, k;
    double *Z;    /* nq x d (column j at Z + j nq) */
    double *H0;   /* d x d, Z^T HL Z at the point's multipliers */
    double *A;    /* k blocks d x d: Z^T hess(u_k . g) Z */
    double *H, *ev, *wk;
    int lwk;
} cert;

/* Smallest eigenvalue of H0 + sum mu_k A_k; eigenvectors in c->H when vec. */
static int eig_at(cert *c, const double *mu, int vec)
{
    size_t dd = (size_t)c->d * c->d;
    memcpy(c->H, c->H0, sizeof(double) * dd);
    for (int k = 0; k < c->k; k++)
        for (size_t i = 0; i < dd; i++) c->H[i] += mu[k] * c->A[(size_t)k * dd + i];
    int info = 0;
    dsyev_(vec ? "V" : "N", "U", &c->d, c->H, &c->d, c->ev, c->wk, &c->lwk, &info);
    return info;
}

/* The Frobenius norm of the n entries of M. */
static double frob(const double *M, size_t n)
{
    double f = 0.0;
    for (size_t i = 0; i < n; i++) f += M[i] * M[i];
    return sqrt(f);
}

/* A bound on the error of the smallest eigenvalue that eig_at computes at
 * mu: forming H0 + sum mu_k A_k costs (k + 1) eps of the summed norms, and
 * dsyev is backward stable (an error of order d eps |M|); both estimated,
 * generously, by 10 (d + k + 1) eps (|H0|_F + sum |mu_k| |A_k|_F): about
 * 1e-13 of |H0|_F for the small self-stresses of the ascent, far below the
 * margin (1e-8). */
static double cert_roundoff(const cert *c, const double *mu)
{
    size_t dd = (size_t)c->d * c->d;
    double s = frob(c->H0, dd);
    for (int q = 0; q < c->k; q++) s += fabs(mu[q]) * frob(c->A + (size_t)q * dd, dd);
    return 10.0 * (double)(c->d + c->k + 1) * 2.220446049250313e-16 * s;
}

/* Z^T M Z into out (d x d), M nq x nq. */
static void project(const cert *c, const double *M, double *tmp, double *out)
{
    int nq = c->nq, d = c->d;
    for (int b = 0; b < d; b++)
        for (int i = 0; i < nq; i++) {
            double s = 0.0;
            for (int j = 0; j < nq; j++) s += M[(size_t)i * nq + j] * c->Z[(size_t)b * nq + j];
            tmp[(size_t)b * nq + i] = s;
        }
    for (int a = 0; a < d; a++)
        for (int b = 0; b < d; b++) {
            double s = 0.0;
            for (int i = 0; i < nq; i++) s += c->Z[(size_t)a * nq + i] * tmp[(size_t)b * nq + i];
            out[(size_t)a * d + b] = s;
        }
}

/* The ascent: raise the eigenvalues below tau to tau by the minimum-norm
 * first-order step in mu, halved until the smallest eigenvalue grows.
 * Returns 1 with mu when the smallest eigenvalue exceeds margin. */
static int ascend(cert *c, double *mu, double tau, double margin, double *G, double *rhs,
                  double *trial)
{
    int d = c->d, k = c->k;
    size_t dd = (size_t)d * d;
    if (eig_at(c, mu, 1)) return 0;
    double lmin = c->ev[0];
    for (int it = 0; it < CERT_ITERS && !(lmin > margin); it++) {
        int m = 0;
        for (int j = 0; j < d && m < k; j++) {
            if (!(c->ev[j] < tau)) break;
            const double *w = c->H + (size_t)j * d;
            for (int q = 0; q < k; q++) {
                G[(size_t)m * k + q] = sf_quad_form(d, c->A + (size_t)q * dd, w);
            }
            rhs[m++] = tau - c->ev[j];
        }
        if (m == 0) break;
        /* minimum-norm solution of G dmu = rhs: dmu = G^T (G G^T)^-1 rhs,
         * by the normal equations with a tiny ridge (m <= k small) */
        double *GG = trial + k;
        for (int a = 0; a < m; a++)
            for (int b = 0; b < m; b++) {
                double s = 0.0;
                for (int q = 0; q < k; q++) s += G[(size_t)a * k + q] * G[(size_t)b * k + q];
                GG[(size_t)a * m + b] = s + (a == b ? 1e-12 * (s + 1e-300) : 0.0);
            }
        /* Cholesky-free: Gauss elimination with partial pivoting */
        double *x = GG + (size_t)m * m;
        memcpy(x, rhs, sizeof(double) * m);
        int singular = 0;
        for (int col = 0; col < m && !singular; col++) {
            int piv = col;
            for (int r = col + 1; r < m; r++)
                if (fabs(GG[(size_t)r * m + col]) > fabs(GG[(size_t)piv * m + col])) piv = r;
            if (!(fabs(GG[(size_t)piv * m + col]) > 0.0)) { singular = 1; break; }
            if (piv != col) {
                for (int b = 0; b < m; b++) {
                    double t = GG[(size_t)col * m + b];
                    GG[(size_t)col * m + b] = GG[(size_t)piv * m + b];
                    GG[(size_t)piv * m + b] = t;
                }
                double t = x[col]; x[col] = x[piv]; x[piv] = t;
            }
            for (int r = col + 1; r < m; r++) {
                double f = GG[(size_t)r * m + col] / GG[(size_t)col * m + col];
                for (int b = col; b < m; b++) GG[(size_t)r * m + b] -= f * GG[(size_t)col * m + b];
                x[r] -= f * x[col];
            }
        }
        if (singular) break;
        for (int r = m - 1; r >= 0; r--) {
            double s = x[r];
            for (int b = r + 1; b < m; b++) s -= GG[(size_t)r * m + b] * x[b];
            x[r] = s / GG[(size_t)r * m + r];
        }
        double *dmu = rhs + m;
        for (int q = 0; q < k; q++) {
            double s = 0.0;
            for (int a = 0; a < m; a++) s += G[(size_t)a * k + q] * x[a];
            dmu[q] = s;
        }
        int better = 0;
        for (double al = 1.0; al > 1e-4 && !better; al *= 0.5) {
            for (int q = 0; q < k; q++) trial[q] = mu[q] + al * dmu[q];
            if (eig_at(c, trial, 0)) return 0;
            if (c->ev[0] > lmin) {
                better = 1;
                memcpy(mu, trial, sizeof(double) * k);
            }
        }
        if (!better) break;
        if (eig_at(c, mu, 1)) return 0;
        lmin = c->ev[0];
    }
    return lmin > margin;
}


int sf_stab_cert_search(int d, int k, const double *H0, const double *A, double *mu,
                        sf_cert_search *o)
{
    size_t D = (size_t)d, K = (size_t)k, dd = D * D;
    memset(o, 0, sizeof *o);
    o->t_lo = -INFINITY;
    o->t_up = INFINITY;
    if (d <= 0 || k <= 0) return -1;
    double *blk = malloc(sizeof(double) * (2 * dd + 4 * D + 8));
    double *wrk = calloc(4 * K + 3 * K * K + 16, sizeof(double));
    if (!blk || !wrk) {
        free(blk); free(wrk);
        return -1;
    }
    cert c = {0, 0, d, k, NULL, (double *)H0, (double *)A, blk, blk + dd, blk + dd + D + 1,
              (int)(dd + 3 * D)};
    int rc = 0;
    for (int q = 0; q < k; q++) mu[q] = 0.0;
    if (eig_at(&c, mu, 0)) {
        rc = -1;
        goto out;
    }
    /* tau: the smallest positive eigenvalue at mu = 0 (the stiffness scale
     * of the free motions); margin: 1e-8 of the largest */
    double tau = 0.0, emax = 0.0;
    for (int j = 0; j < d; j++) {
        emax = fmax(emax, fabs(c.ev[j]));
        if (tau == 0.0 && c.ev[j] > 0.0) tau = c.ev[j];
    }
    if (!(tau > 0.0)) tau = 1e-6 * emax;
    o->margin = 1e-8 * emax;
    double amax = 0.0;
    for (int q = 0; q < k; q++) amax = fmax(amax, frob(A + (size_t)q * dd, dd));
    o->bound = amax > 0.0 && emax > 0.0 ? CERT_RHO * emax / amax : 0.0;
    double *G = wrk, *rhs = G + K * K, *trial = rhs + 2 * K + 2;
    if (ascend(&c, mu, tau, o->margin, G, rhs, trial)) {
        if (eig_at(&c, mu, 0)) {
            rc = -1;
            goto out;
        }
        o->lmin = c.ev[0];
        o->roundoff = cert_roundoff(&c, mu);
        o->found = o->lmin > o->margin + o->roundoff ? SF_CERT_ASCENT : SF_CERT_NONE;
        if (o->found) goto out;
    }
    /* the local ascent found none: the global search.  lambda_min of an
     * affine matrix function is concave in mu, so the bounded program's
     * optimum is THE largest smallest eigenvalue over the ball */
    if (!(amax > 0.0 && emax > 0.0)) goto out;
    double *mus = malloc(sizeof(double) * (K + 1));
    if (!mus) {
        rc = -1;
        goto out;
    }
    int sr = sf_lmi_max_min_eig(c.d, c.H0, c.k, c.A, emax, amax, CERT_RHO, mus, &o->t_lo, &o->t_up);
    if (sr == 0) {
        o->sdp_ran = 1;
        /* DSDP's mu checked with LAPACK: its accuracy cannot certify */
        if (eig_at(&c, mus, 0)) {
            free(mus);
            rc = -1;
            goto out;
        }
        o->lmin = c.ev[0];
        o->roundoff = cert_roundoff(&c, mus);
        memcpy(mu, mus, sizeof(double) * K);
        if (o->lmin > o->margin + o->roundoff) o->found = SF_CERT_SDP;
    } else {
        o->sdp_err = sr;
        /* the ascent's mu stays; its eigenvalue */
        if (!eig_at(&c, mu, 0)) o->lmin = c.ev[0];
        o->t_lo = -INFINITY;
        o->t_up = INFINITY;
    }
    free(mus);
out:
    free(blk); free(wrk);
    return rc;
}

int sf_stab_certify(sf_stab *st, sf_equil *q, const double *y, double p, sf_error *err)
{
    sf_stab_result *R = &st->res;
    int nq = st->nq, nc = st->ncon;
    if (q->pz || R->method != SF_EIG_DENSE || R->morse == 0 || nc == 0 || R->dim == 0 ||
        R->rank >= nc || nc - R->rank > CERT_MAXK)
        return SF_OK;
    int k = nc - R->rank, d = R->dim, mn = nq < nc ? nq : nc, info = 0, dense_morse = R->morse;
    size_t NQ = (size_t)nq, NC = (size_t)nc, D = (size_t)d, K = (size_t)k;
    double *A = malloc(sizeof(double) * (NQ * NC + NQ * NQ + NC * NC + NQ + NC + 8));
    double *HL0 = malloc(sizeof(double) * (2 * NQ * NQ + NC * NQ + 2));
    double *blk = malloc(sizeof(double) * (K * D * D + 3 * D * D + NQ * D + 4 * D + 8));
    double *yk = malloc(sizeof(double) * ((size_t)q->n + 1));
    double *mu = calloc(4 * K + 2 * K * K + K * K + 16, sizeof(double));
    int rc = SF_OK;
    if (!A || !HL0 || !blk || !yk || !mu) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto done;
    }
    double *U = A + NQ * NC, *Vt = U + NQ * NQ, *S = Vt + NC * NC;
    double *HLk = HL0 + NQ * NQ, *Ck = HLk + NQ * NQ;
    /* the rows scaled to unit length (stability.c), C^T column-major */
    double big = 0.0;
    for (int r = 0; r < nc; r++) {
        double s = 0.0;
        for (int j = 0; j < nq; j++) s += st->C[(size_t)r * nq + j] * st->C[(size_t)r * nq + j];
        big = fmax(big, sqrt(s));
    }
    double *rowlen = malloc(sizeof(double) * (NC + 1));
    if (!rowlen) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto done;
    }
    for (int r = 0; r < nc; r++) {
        double s = 0.0;
        for (int j = 0; j < nq; j++) s += st->C[(size_t)r * nq + j] * st->C[(size_t)r * nq + j];
        s = sqrt(s);
        rowlen[r] = (s > ZERO_ROW * big && s > 0.0) ? s : big;
        double f = (s > ZERO_ROW * big && s > 0.0) ? 1.0 / s : 0.0;
        for (int j = 0; j < nq; j++) A[(size_t)r * nq + j] = f * st->C[(size_t)r * nq + j];
    }
    memcpy(HL0, st->HL, sizeof(double) * NQ * NQ);
    {
        int lw = -1;
        double wq;
        dgesvd_("A", "A", &nq, &nc, A, &nq, S, U, &nq, Vt, &nc, &wq, &lw, &info);
        lw = (int)wq + 1;
        double *W = malloc(sizeof(double) * (size_t)lw);
        if (!W) {
            free(rowlen);
            rc = sf_fail(err, SF_ENOMEM, "out of memory");
            goto done;
        }
        dgesvd_("A", "A", &nq, &nc, A, &nq, S, U, &nq, Vt, &nc, W, &lw, &info);
        free(W);
    }
    int rank = 0;
    for (int i = 0; i < mn; i++)
        if (S[i] > RANK_TOL * S[0] && S[0] > 0) rank++;
    if (info != 0 || rank != R->rank) {
        free(rowlen);
        goto done; /* not the dense method's split: leave its result */
    }
    cert c = {nq, nc, d, k, NULL, NULL, NULL, NULL, NULL, NULL, 0};
    c.Z = U + (size_t)rank * nq;
    c.H0 = blk;
    c.A = c.H0 + D * D;
    c.H = c.A + K * D * D;
    c.ev = c.H + D * D;
    double *tmp = c.ev + D + 1;
    c.wk = tmp + NQ * D;
    c.lwk = (int)(D * D + 3 * D); /* the rest of blk (>= 3 d) */
    project(&c, HL0, tmp, c.H0);
    /* A_k: the change of Z^T HL Z per unit self-stress u_k (a right
     * singular vector of the scaled rows, in null(C^T)), HL being affine
     * in the multipliers; the rows' scales turn it into multipliers */
    double amax = 0.0, *HLz = tmp; /* the energy's Hessian alone (zero multipliers) */
    memcpy(yk, y, sizeof(double) * (size_t)q->n);
    for (int r = 0; r < nc; r++) yk[nq + r] = 0.0;
    double *HLe = malloc(sizeof(double) * (NQ * NQ + 1));
    if (!HLe || sf_equil_kkt(q, yk, p, HLe, Ck)) {
        free(HLe);
        free(rowlen);
        goto done;
    }
    (void)HLz;
    for (int kk = 0; kk < k; kk++) {
        for (int r = 0; r < nc; r++) yk[nq + r] = Vt[(size_t)r * nc + rank + kk] / rowlen[r];
        if (sf_equil_kkt(q, yk, p, HLk, Ck)) {
            free(HLe);
            free(rowlen);
            goto done;
        }
        for (size_t i = 0; i < NQ * NQ; i++) HLk[i] -= HLe[i];
        double *Ak = c.A + (size_t)kk * D * D;
        project(&c, HLk, tmp, Ak);
        for (size_t i = 0; i < D * D; i++) amax = fmax(amax, fabs(Ak[i]));
    }
    free(HLe);
    free(rowlen);
    double hmax = 0.0;
    for (size_t i = 0; i < D * D; i++) hmax = fmax(hmax, fabs(c.H0[i]));
    /* where the rows keep their rank the A_k vanish to round-off */
    if (!(amax > 1e-12 * fmax(hmax, 1.0))) goto done;
    sf_cert_search o;
    if (sf_stab_cert_search(d, k, c.H0, c.A, mu, &o)) goto done;
    if (!o.found) {
        /* no self-stress found that makes the reduced Hessian positive
         * definite, and a negative eigenvalue at the point's own
         * multipliers proves nothing here (above): the verdict is unknown,
         * not unstable.  The SDP's bound t_up on the largest smallest
         * eigenvalue within |mu| <= bound is computed from DSDP's X here
         * and holds whatever DSDP's accuracy; lmin is the eigenvalue at
         * its mu (LAPACK), a lower bound */
        R->morse = 0;
        R->morse_unknown = 1;
        R->stable = -1;
        R->neig = 0;
        R->status = SF_SSTAB_UNKNOWN;
        int n = snprintf(R->reason, sizeof R->reason,
                         "redundant constraint rows that change rank: Morse index %d at the "
                         "path's multipliers, ", dense_morse);
        size_t at = n > 0 && (size_t)n < sizeof R->reason ? (size_t)n : sizeof R->reason - 1;
        char *r = R->reason + at;
        size_t left = sizeof R->reason - at;
        if (!o.sdp_ran)
            snprintf(r, left, "and no self-stress found that makes the point stable (local "
                     "ascent: the semidefinite program failed, DSDP error %d)", o.sdp_err);
        else if (o.t_up <= 0.0)
            snprintf(r, left, "and no self-stress of norm <= %.3g makes the reduced Hessian "
                     "positive definite (SDP: its largest smallest eigenvalue is in [%.4g, "
                     "%.4g])", o.bound, o.lmin, o.t_up);
        else if (o.t_up <= o.margin)
            snprintf(r, left, "and no self-stress of norm <= %.3g raises the reduced Hessian's "
                     "smallest eigenvalue above the margin %.3g (SDP: its largest is in [%.4g, "
                     "%.4g])", o.bound, o.margin, o.lmin, o.t_up);
        else
            snprintf(r, left, "and no self-stress found that makes the point stable (SDP "
                     "inconclusive: the largest smallest eigenvalue for norm <= %.3g is in "
                     "[%.4g, %.4g])", o.bound, o.lmin, o.t_up);
        goto done;
    }
    R->morse = 0;
    R->morse_unknown = 0;
    R->stable = 1;
    R->certified = o.found;
    double mnorm = 0.0;
    for (int kk = 0; kk < k; kk++) mnorm = fmax(mnorm, fabs(mu[kk]));
    R->cert_mu = mnorm;
    /* no eigenvalues: the certificate's depend on the self-stress chosen
     * (on the blocked directions) and jump from point to point, which the
     * step bound would read as crossings; the eig columns stay empty, as
     * for the inertia method without eigenvalues */
    R->neig = 0;
    R->cert_eig = o.lmin;
done:
    free(A); free(HL0); free(blk); free(yk); free(mu);
    return rc;
}
