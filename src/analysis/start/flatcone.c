/* flatcone.c - the branches that leave the flat state.
 *
 * At the flat state of a foldable crease pattern the loop constraints are
 * singular: some combinations of rows (the rotation about the normal and
 * the in-plane translations of every vertex loop) have no gradient, and
 * the first-order rows J1 leave a kernel of dimension k, the first-order
 * motions (for creased folds: the fold-angle rates of rigid origami that
 * keep every face flat to first order).  A branch leaving the flat state
 * with q = dp u + O(dp^2) needs u in that kernel AND the second-order
 * rows to vanish on u: u^T G_s u = 0.  These quadratic conditions cut the
 * kernel down to a cone, the tangent cone of the constraint set (for a
 * single flat-foldable degree-4 vertex of creases: two lines, the two
 * rigid folding modes; for a tessellation: a union of many).  Which ray
 * of the cone the sheet follows is decided by the driving: the limit
 * problem of flatstart.c is the stationarity of the energy
 * x^T A x / 2 + b . x on the cone, and a branch that the driving can
 * follow is a local minimum of it, i.e. a local maximum of the work
 * (b . x)^2 / (x^T A x) over the rays.  With a perfectly symmetric
 * driving several rays have the same energy: the driving selects none.
 *
 * Method (all dense LAPACK: the kernel, the forms and the reduced problem
 * are small next to the sheet):
 *  1. N: kernel of J1 (dgesvd of J1^T);
 *  2. Q_s = N^T G_s N, and the span of the Q_s (dgesvd of their packed
 *     upper triangles): r unit forms Q'_t and weights W with
 *     sum_s nu_s Q_s = sum_t nu'_t Q'_t for nu = W nu';
 *  3. cone points: from each start x, Gauss-Newton with minimum-norm
 *     steps (dgelss) on x^T Q'_t x / 2 = 0, x renormalised in the A norm;
 *  4. from each cone point, scaled to its best amplitude, Newton (dgelss
 *     steps, backtracking) on the reduced limit problem;
 *  5. distinct solutions, their stability (dsyev of the reduced Hessian on
 *     the cone's tangent space at x), energy; back to (u, mu, nu).
 * Besides the penalty descent from the driving's response (pen_min,
 * descend), cone points come from ASCENT_STARTS pseudo-random rays taken
 * onto the cone (step 3) and raised along it to a stationary ray of the
 * work (cone_ascend: projected gradient in the A metric), and from rays
 * given by the caller (sf_cone_find_rays).  A ray on which step 4 fails
 * while the driving does work on it is degenerate (flatcone.h): kept
 * apart, with its energy.  When nothing else is found, so is the end of
 * the descent from the driving's response if it reached EPS_MIN next to
 * the cone without multipliers (the miura 2x2 sheet under gravity and a
 * tip load: docs/flatstart.md).
 */
#include "flatcone.h"
#include "flatcone_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n,
                    double *a, const int *lda, double *s, double *u, const int *ldu,
                    double *vt, const int *ldvt, double *work, const int *lwork, int *info);
extern void dgelss_(const int *m, const int *n, const int *nrhs, double *a, const int *lda,
                    double *b, const int *ldb, double *s, const double *rcond, int *rank,
                    double *work, const int *lwork, int *info);
extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

#define KER_RTOL 1e-8     /* singular values of J1 below this (relative) span the kernel */
#define FORM_RTOL 1e-9    /* forms below this (relative) depend on the others */
#define NEWTON_MAXIT 60
#define SOL_TOL 1e-12     /* reduced residual, relative to max(1, |b|) */
#define STAB_TOL 1e-9     /* smallest reduced eigenvalue of a stable branch (relative) */


static void red_free(red *R)
{
    free(R->N);
    free(R->A);
    free(R->b);
    free(R->Q);
    free(R->W);
}

/* Singular value decomposition a = U S V^T (m x n column-major, destroyed);
 * u (m x m when jobu 'A', m x min when 'S') and vt (min x n, 'S') may be NULL
 * with job 'N'. */
static int svd(char jobu, char jobvt, int m, int n, double *a, double *s, double *u, double *vt)
{
    int lda = m > 0 ? m : 1, ldu = m > 0 ? m : 1, mn = m < n ? m : n;
    int ldvt = jobvt == 'S' ? (mn > 0 ? mn : 1) : 1, info, lwork = -1;
    double wq, dummy;
    dgesvd_(&jobu, &jobvt, &m, &n, a, &lda, s, u ? u : &dummy, &ldu, vt ? vt : &dummy, &ldvt,
            &wq, &lwork, &info);
    lwork = (int)wq + 1;
    double *w = malloc(sizeof(double) * (size_t)lwork);
    if (!w) return -1;
    dgesvd_(&jobu, &jobvt, &m, &n, a, &lda, s, u ? u : &dummy, &ldu, vt ? vt : &dummy, &ldvt, w,
            &lwork, &info);
    free(w);
    return info;
}

/* Minimum-norm least-squares solution of the m x n system a x = b
 * (column-major, destroyed); b has max(m, n) entries and returns x. */
static int lstsq(int m, int n, double *a, double *b)
{
    int one = 1, rank, info, lwork = -1, lda = m > 0 ? m : 1, ldb = m > n ? m : n;
    double rcond = 1e-12, wq;
    if (ldb < 1) ldb = 1;
    double *s = malloc(sizeof(double) * ((size_t)(m < n ? m : n) + 1));
    if (!s) return -1;
    dgelss_(&m, &n, &one, a, &lda, b, &ldb, s, &rcond, &rank, &wq, &lwork, &info);
    lwork = (int)wq + 1;
    double *w = malloc(sizeof(double) * (size_t)lwork);
    if (!w) { free(s); return -1; }
    dgelss_(&m, &n, &one, a, &lda, b, &ldb, s, &rcond, &rank, w, &lwork, &info);
    free(w);
    free(s);
    return info;
}

static double maxabs(const double *v, int n)
{
    double m = 0.0;
    for (int i = 0; i < n; i++) m = fmax(m, fabs(v[i]));
    return m;
}

/* y = M x for the k x k column-major M */
static void matvec(int k, const double *M, const double *x, double *y)
{
    for (int i = 0; i < k; i++) y[i] = 0.0;
    for (int j = 0; j < k; j++)
        for (int i = 0; i < k; i++) y[i] += M[(size_t)j * k + i] * x[j];
}

static double dot(int k, const double *a, const double *b)
{
    double v = 0.0;
    for (int i = 0; i < k; i++) v += a[i] * b[i];
    return v;
}

/* Steps 1 and 2: the kernel, A, b, the independent forms. */
static int red_build(const sf_limit *L, red *R)
{
    int nq = L->nq, n1 = L->n1, n2 = L->n2, rc = -1;
    memset(R, 0, sizeof *R);
    R->nq = nq;
    R->n1 = n1;
    R->n2 = n2;
    double *a = malloc(sizeof(double) * ((size_t)nq * n1 + 1));
    double *U = malloc(sizeof(double) * ((size_t)nq * nq + 1));
    double *S = calloc((size_t)nq + 1, sizeof(double));
    double *GN = NULL, *Qs = NULL, *M = NULL, *Um = NULL, *Vt = NULL, *Sm = NULL;
    if (!a || !U || !S) goto done;
    /* J1 row-major (n1 x nq) is J1^T column-major (nq x n1) */
    memcpy(a, L->J1, sizeof(double) * (size_t)nq * n1);
    int rank = 0;
    if (n1 > 0) {
        if (svd('A', 'N', nq, n1, a, S, U, NULL)) goto done;
        for (int i = 0; i < (nq < n1 ? nq : n1); i++)
            if (S[i] > KER_RTOL * S[0]) rank++;
    } else {
        for (int i = 0; i < nq; i++)
            for (int j = 0; j < nq; j++) U[(size_t)j * nq + i] = i == j;
    }
    int k = nq - rank;
    R->k = k;
    R->N = malloc(sizeof(double) * ((size_t)nq * k + 1));
    R->A = calloc((size_t)k * k + 1, sizeof(double));
    R->b = calloc((size_t)k + 1, sizeof(double));
    if (!R->N || !R->A || !R->b) goto done;
    memcpy(R->N, U + (size_t)rank * nq, sizeof(double) * (size_t)nq * k);
    const double *N = R->N;
    double *hc = malloc(sizeof(double) * ((size_t)nq + 1));
    if (!hc) goto done;
    for (int c = 0; c < k; c++) {
        for (int p = 0; p < nq; p++)
            hc[p] = dot(nq, L->H0 + (size_t)p * nq, N + (size_t)c * nq);   /* H0 N_c */
        for (int i = 0; i < k; i++) R->A[(size_t)c * k + i] = dot(nq, N + (size_t)i * nq, hc);
        R->b[c] = dot(nq, N + (size_t)c * nq, L->gp);
    }
    free(hc);
    if (n2 == 0 || k == 0) { rc = 0; goto done; }
    /* Q_s = N^T G_s N, packed (upper triangle, off-diagonal times sqrt 2) */
    int mp = k * (k + 1) / 2;
    GN = malloc(sizeof(double) * ((size_t)nq * k + 1));
    Qs = malloc(sizeof(double) * ((size_t)n2 * k * k + 1));
    M = malloc(sizeof(double) * ((size_t)n2 * mp + 1));
    if (!GN || !Qs || !M) goto done;
    for (int s = 0; s < n2; s++) {
        memset(GN, 0, sizeof(double) * (size_t)nq * k);
        for (long e = L->Gp[s]; e < L->Gp[s + 1]; e++)
            for (int c = 0; c < k; c++)
                GN[(size_t)c * nq + L->Gi[e]] += L->Gx[e] * N[(size_t)c * nq + L->Gj[e]];
        double *Q = Qs + (size_t)s * k * k;
        for (int c = 0; c < k; c++)
            for (int i = 0; i < k; i++) Q[(size_t)c * k + i] = dot(nq, N + (size_t)i * nq, GN + (size_t)c * nq);
        int e = 0;
        for (int j = 0; j < k; j++)
            for (int i = 0; i <= j; i++, e++) {
                double v = 0.5 * (Q[(size_t)j * k + i] + Q[(size_t)i * k + j]);
                M[(size_t)e * n2 + s] = i == j ? v : M_SQRT2 * v;
            }
    }
    int mn = n2 < mp ? n2 : mp;
    Um = malloc(sizeof(double) * ((size_t)n2 * mn + 1));
    Vt = malloc(sizeof(double) * ((size_t)mn * mp + 1));
    Sm = calloc((size_t)mn + 1, sizeof(double));
    if (!Um || !Vt || !Sm) goto done;
    if (svd('S', 'S', n2, mp, M, Sm, Um, Vt)) goto done;
    int r = 0;
    for (int t = 0; t < mn; t++)
        if (Sm[t] > FORM_RTOL * Sm[0] && Sm[t] > 1e-300) r++;
    R->r = r;
    R->Q = malloc(sizeof(double) * ((size_t)r * k * k + 1));
    R->W = malloc(sizeof(double) * ((size_t)n2 * r + 1));
    if (!R->Q || !R->W) goto done;
    for (int t = 0; t < r; t++) {
        double *Q = R->Q + (size_t)t * k * k;
        int e = 0;
        for (int j = 0; j < k; j++)
            for (int i = 0; i <= j; i++, e++) {
                double v = Vt[(size_t)e * mn + t];
                if (i != j) v /= M_SQRT2;
                Q[(size_t)j * k + i] = Q[(size_t)i * k + j] = v;
            }
        for (int s = 0; s < n2; s++) R->W[(size_t)t * n2 + s] = Um[(size_t)t * n2 + s] / Sm[t];
    }
    rc = 0;
done:
    free(a);
    free(U);
    free(S);
    free(GN);
    free(Qs);
    free(M);
    free(Um);
    free(Vt);
    free(Sm);
    if (rc) red_free(R);
    return rc;
}

/* h_t = x^T Q_t x / 2 and the rows (Q_t x)^T (r x k, column-major) */
static void cone_eval(const red *R, const double *x, double *h, double *Jh, double *tmp)
{
    int k = R->k, r = R->r;
    for (int t = 0; t < r; t++) {
        matvec(k, R->Q + (size_t)t * k * k, x, tmp);
        h[t] = 0.5 * dot(k, x, tmp);
        if (Jh)
            for (int j = 0; j < k; j++) Jh[(size_t)j * r + t] = tmp[j];
    }
}

static void anormalise(const red *R, double *x, double *tmp)
{
    matvec(R->k, R->A, x, tmp);
    double a = sqrt(fmax(dot(R->k, x, tmp), 1e-300));
    for (int i = 0; i < R->k; i++) x[i] /= a;
}

void sf_cone_forms_add(int k, int r, const double *Q, const double *x, const double *nu,
                       double *F, double *Jm, int n, double *tmp)
{
    for (int t = 0; t < r; t++) {
        const double *Qt = Q + (size_t)t * k * k;
        matvec(k, Qt, x, tmp);
        for (int i = 0; i < k; i++) F[i] += nu[t] * tmp[i];
        F[k + t] = 0.5 * dot(k, x, tmp);
        if (Jm) {
            for (int j = 0; j < k; j++)
                for (int i = 0; i < k; i++) Jm[(size_t)j * n + i] += nu[t] * Qt[(size_t)j * k + i];
            for (int i = 0; i < k; i++) {
                Jm[(size_t)(k + t) * n + i] = tmp[i];
                Jm[(size_t)i * n + k + t] = tmp[i];
            }
        }
    }
}

/* Reduced residual F(x, nu) (k + r) */
static void red_eval(const red *R, const double *v, double *F, double *Jm, double *tmp)
{
    int k = R->k, r = R->r, n = k + r;
    const double *x = v, *nu = v + k;
    matvec(k, R->A, x, F);
    for (int i = 0; i < k; i++) F[i] += R->b[i];
    if (Jm) {
        memset(Jm, 0, sizeof(double) * (size_t)n * n);
        for (int j = 0; j < k; j++)
            for (int i = 0; i < k; i++) Jm[(size_t)j * n + i] = R->A[(size_t)j * k + i];
    }
    sf_cone_forms_add(k, r, R->Q, x, nu, F, Jm, n, tmp);
}

/* Step 4: Newton on the reduced problem from v.  0 when converged. */
static int red_newton(const red *R, double *v, double *F, double *Jm, double *d, double *vt,
                      double *tmp)
{
    int k = R->k, r = R->r, n = k + r;
    double tol = SOL_TOL * fmax(1.0, maxabs(R->b, k));
    for (int it = 0; it < NEWTON_MAXIT; it++) {
        red_eval(R, v, F, Jm, tmp);
        double en = maxabs(F, n);
        if (en <= tol) return 0;
        for (int i = 0; i < n; i++) d[i] = -F[i];
        if (lstsq(n, n, Jm, d)) return -1;
        double t = 1.0, et = en;
        for (int bt = 0; bt < 30; bt++, t *= 0.5) {
            for (int i = 0; i < n; i++) vt[i] = v[i] + t * d[i];
            red_eval(R, vt, F, NULL, tmp);
            et = maxabs(F, n);
            if (et < en) break;
        }
        if (!(et < en)) return 1;
        memcpy(v, vt, sizeof(double) * (size_t)n);
    }
    red_eval(R, v, F, NULL, tmp);
    return maxabs(F, n) <= tol ? 0 : 1;
}

/* Step 5: stable when A + sum nu Q is positive definite on the null space
 * of the rows (Q_t x)^T. */
static int red_stable(const red *R, const double *v)
{
    int k = R->k, r = R->r, rc = 0;
    const double *x = v, *nu = v + k;
    double *Jh = malloc(sizeof(double) * ((size_t)(r > 0 ? r : 1) * k + 1));
    double *Vt = malloc(sizeof(double) * ((size_t)k * k + 1));
    double *S = calloc((size_t)k + 1, sizeof(double));
    double *h = calloc((size_t)r + 1, sizeof(double));
    double *tmp = malloc(sizeof(double) * ((size_t)k + 1));
    double *H = malloc(sizeof(double) * ((size_t)k * k + 1));
    double *Z = NULL, *Hz = NULL, *ev = NULL;
    if (!Jh || !Vt || !S || !h || !tmp || !H) goto done;
    int rank = 0;
    if (r > 0) {
        cone_eval(R, x, h, Jh, tmp);
        /* right singular vectors: dgesvd with jobvt 'A' */
        int info, lwork = -1, ldu = 1, lda = r;
        double wq, du;
        dgesvd_("N", "A", &r, &k, Jh, &lda, S, &du, &ldu, Vt, &k, &wq, &lwork, &info);
        lwork = (int)wq + 1;
        double *w = malloc(sizeof(double) * (size_t)lwork);
        if (!w) goto done;
        dgesvd_("N", "A", &r, &k, Jh, &lda, S, &du, &ldu, Vt, &k, w, &lwork, &info);
        free(w);
        if (info) goto done;
        for (int i = 0; i < (r < k ? r : k); i++)
            if (S[i] > 1e-8 * fmax(S[0], 1e-300)) rank++;
    } else {
        for (int i = 0; i < k; i++)
            for (int j = 0; j < k; j++) Vt[(size_t)j * k + i] = i == j;
    }
    int d = k - rank;
    for (size_t i = 0; i < (size_t)k * k; i++) H[i] = R->A[i];
    for (int t = 0; t < r; t++)
        for (size_t i = 0; i < (size_t)k * k; i++) H[i] += nu[t] * R->Q[(size_t)t * k * k + i];
    Z = malloc(sizeof(double) * ((size_t)k * d + 1));
    Hz = malloc(sizeof(double) * ((size_t)d * d + 1));
    ev = malloc(sizeof(double) * ((size_t)d + 1));
    if (!Z || !Hz || !ev) goto done;
    /* Z columns: rows rank.. of Vt */
    for (int c = 0; c < d; c++)
        for (int i = 0; i < k; i++) Z[(size_t)c * k + i] = Vt[(size_t)i * k + rank + c];
    double scale = 0.0;
    for (int i = 0; i < k; i++) scale = fmax(scale, fabs(R->A[(size_t)i * k + i]));
    for (int c = 0; c < d; c++) {
        matvec(k, H, Z + (size_t)c * k, tmp);
        for (int e = 0; e < d; e++) Hz[(size_t)c * d + e] = dot(k, Z + (size_t)e * k, tmp);
    }
    if (d == 0) { rc = 1; goto done; }
    int info, lwork = -1;
    double wq;
    dsyev_("N", "U", &d, Hz, &d, ev, &wq, &lwork, &info);
    lwork = (int)wq + 1;
    double *w = malloc(sizeof(double) * (size_t)lwork);
    if (!w) goto done;
    dsyev_("N", "U", &d, Hz, &d, ev, w, &lwork, &info);
    free(w);
    rc = info == 0 && ev[0] > STAB_TOL * scale;
done:
    free(Jh); free(Vt); free(S); free(h); free(tmp); free(H); free(Z); free(Hz); free(ev);
    return rc;
}

/* A pseudo-random number in [-1, 1] from the generator state *st */
static double rnd(unsigned long long *st)
{
    *st = *st * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*st >> 11) / (double)(1ULL << 53) * 2.0 - 1.0;
}

/* Back to the limit problem's z = (u, mu, nu) from v = (x, nu'). */
static int to_full(const sf_limit *L, const red *R, const double *v, double *z)
{
    int nq = L->nq, n1 = L->n1, n2 = L->n2, k = R->k, r = R->r;
    memset(z, 0, sizeof(double) * (size_t)L->n);
    double *u = z, *mu = z + nq, *nu = z + nq + n1;
    for (int c = 0; c < k; c++)
        for (int i = 0; i < nq; i++) u[i] += R->N[(size_t)c * nq + i] * v[c];
    for (int s = 0; s < n2; s++)
        for (int t = 0; t < r; t++) nu[s] += R->W[(size_t)t * n2 + s] * v[k + t];
    if (n1 == 0) return 0;
    /* J1^T mu = -(H0 u + gp + sum nu_s G_s u): least squares */
    double *rhs = calloc((size_t)nq + (size_t)n1 + 1, sizeof(double));
    double *a = malloc(sizeof(double) * ((size_t)nq * n1 + 1));
    if (!rhs || !a) { free(rhs); free(a); return -1; }
    for (int i = 0; i < nq; i++) {
        double w = L->gp[i];
        for (int j = 0; j < nq; j++) w += L->H0[(size_t)i * nq + j] * u[j];
        rhs[i] = -w;
    }
    for (int s = 0; s < n2; s++)
        for (long e = L->Gp[s]; e < L->Gp[s + 1]; e++) rhs[L->Gi[e]] -= nu[s] * L->Gx[e] * u[L->Gj[e]];
    memcpy(a, L->J1, sizeof(double) * (size_t)nq * n1);   /* J1^T column-major */
    int rc = lstsq(nq, n1, a, rhs);
    if (!rc) memcpy(mu, rhs, sizeof(double) * (size_t)n1);
    free(rhs);
    free(a);
    return rc ? -1 : 0;
}

void sf_cone_free(sf_cone *c)
{
    free(c->z);
    free(c->energy);
    free(c->stable);
    free(c->resid);
    free(c->degu);
    free(c->degen);
    memset(c, 0, sizeof *c);
}

/* Work space of the penalty descent */
typedef struct dwork {
    double *g, *H, *ev, *d, *xt, *tmp, *h, *work;
    int lwork;
} dwork;

/* P_eps(x) = x^T A x / 2 + b . x + sum_t h_t^2 / (2 eps); gradient g and
 * Hessian H (k x k) when not NULL. */
static double pen_eval(const red *R, const double *x, double eps, dwork *w, double *g, double *H)
{
    int k = R->k;
    double *t = w->tmp;
    matvec(k, R->A, x, t);
    double P = 0.5 * dot(k, x, t) + dot(k, R->b, x);
    if (g)
        for (int i = 0; i < k; i++) g[i] = t[i] + R->b[i];
    if (H) memcpy(H, R->A, sizeof(double) * (size_t)k * k);
    for (int tt = 0; tt < R->r; tt++) {
        const double *Q = R->Q + (size_t)tt * k * k;
        matvec(k, Q, x, t);
        double h = 0.5 * dot(k, x, t);
        P += h * h / (2.0 * eps);
        if (g)
            for (int i = 0; i < k; i++) g[i] += h / eps * t[i];
        if (H)
            for (int j = 0; j < k; j++)
                for (int i = 0; i < k; i++)
                    H[(size_t)j * k + i] += (h * Q[(size_t)j * k + i] + t[i] * t[j]) / eps;
    }
    return P;
}

/* Minimise P_eps from x by Newton steps on |H| (eigenvalues made
 * positive) with backtracking.  At a stationary point whose Hessian has a
 * negative eigenvalue (a saddle, e.g. a symmetric state past the
 * symmetry-breaking eps), the step goes along that eigenvector with the
 * sign *sign (then set to +1); the first saddle met is stored in sx, sv
 * (*saddle set) so that the caller can take the other side.  0 when
 * converged. */
static int pen_min(const red *R, double *x, double eps, int *sign, int *saddle, double *sx,
                   double *sv, dwork *w)
{
    int k = R->k, info;
    double scale = 1.0 + maxabs(R->b, k);
    for (int it = 0; it < 100; it++) {
        double P = pen_eval(R, x, eps, w, w->g, w->H);
        double gn = maxabs(w->g, k);
        dsyev_("V", "U", &k, w->H, &k, w->ev, w->work, &w->lwork, &info);
        if (info) return -1;
        double lmax = fmax(fabs(w->ev[k - 1]), fabs(w->ev[0]));
        int stationary = gn <= 1e-13 * scale * fmax(1.0, lmax * 1e-6);
        if (stationary && w->ev[0] >= -1e-9 * lmax) return 0;
        if (stationary || (w->ev[0] < -1e-9 * lmax && gn <= 1e-9 * scale)) {
            /* a saddle: leave along the eigenvector of the negative eigenvalue */
            const double *v = w->H;   /* column 0 */
            int imax = 0;
            for (int i = 1; i < k; i++)
                if (fabs(v[i]) > fabs(v[imax])) imax = i;
            double sg = (v[imax] > 0 ? 1.0 : -1.0) * *sign;
            if (!*saddle) {
                *saddle = 1;
                memcpy(sx, x, sizeof(double) * (size_t)k);
                for (int i = 0; i < k; i++) sv[i] = (v[imax] > 0 ? 1.0 : -1.0) * v[i];
            }
            *sign = 1;
            matvec(k, R->A, x, w->tmp);
            double xa = sqrt(fmax(dot(k, x, w->tmp), 1e-300));
            for (int i = 0; i < k; i++) w->d[i] = sg * 1e-3 * fmax(xa, 1e-8) * v[i];
        } else {
            for (int i = 0; i < k; i++) w->d[i] = 0.0;
            for (int c = 0; c < k; c++) {
                const double *v = w->H + (size_t)c * k;
                double a = fmax(fabs(w->ev[c]), 1e-12 * lmax);
                double f = -dot(k, v, w->g) / a;
                for (int i = 0; i < k; i++) w->d[i] += f * v[i];
            }
        }
        if (!stationary && w->ev[0] >= -1e-9 * lmax && -dot(k, w->g, w->d) <= 1e-14 * fabs(P))
            return 0;   /* Newton decrement at the rounding of P */
        double t = 1.0, Pt = P;
        for (int bt = 0; bt < 30; bt++, t *= 0.5) {
            for (int i = 0; i < k; i++) w->xt[i] = x[i] + t * w->d[i];
            Pt = pen_eval(R, w->xt, eps, w, NULL, NULL);
            if (Pt < P) break;
        }
        if (!(Pt < P)) {
            /* no decrease within roundoff: a minimum when the Newton
             * decrement is at the level of the rounding of P */
            double dec = -dot(k, w->g, w->d);
            return fabs(dec) <= 1e-12 * (fabs(P) + 1e-300) ? 0 : 1;
        }
        memcpy(x, w->xt, sizeof(double) * (size_t)k);
    }
    return 1;
}

#define EPS_MIN 1e-10
#define DESCENT_DEG_TOL 1e-6  /* |x^T Q x| / 2 (x^T A x = 1) at the end of a descent
                               * kept as a degenerate ray */
#define MAX_RUNS 8
#define ORDER_TIE_RTOL 1e-7   /* energies equal to this (relative): mirror images */
#define ORDER_SAME_RTOL 1e-6  /* coordinates equal to this (relative to the largest) */

/* One descent from x at level eps0 down to EPS_MIN, then the exact
 * reduced Newton; v receives (x, nu).  0 when it reached a solution. */
static int descend(const red *R, double *x, double eps0, int sign, int *saddle, double *sx,
                   double *sv, double *seps, double *v, dwork *w, double *F, double *Jm,
                   double *d, double *vt, int *bottom)
{
    int k = R->k, r = R->r;
    *bottom = 0;
    for (double eps = eps0; eps >= EPS_MIN * 0.999; eps *= 0.1) {
        int had = *saddle;
        int rc = pen_min(R, x, eps, &sign, saddle, sx, sv, w);
        if (*saddle && !had) *seps = eps;
        if (rc < 0) return -1;
        if (rc) break;
        *bottom = eps < EPS_MIN * 1.001;
        if (eps <= 1e-4) {
            /* polish with the exact reduced problem, nu_t = h_t / eps */
            memcpy(v, x, sizeof(double) * (size_t)k);
            for (int t = 0; t < r; t++) {
                matvec(k, R->Q + (size_t)t * k * k, x, w->tmp);
                v[k + t] = 0.5 * dot(k, x, w->tmp) / eps;
            }
            int nr = red_newton(R, v, F, Jm, d, vt, w->tmp);
            if (nr <= 0) return nr;
        }
    }
    return 1;
}

/* Add the solution v = (x, nu') to sols (n = k + r values each, energies
 * in en) unless it is (near) zero, does no work, or is already there.
 * Returns the new count. */
static int add_sol(const red *R, const double *v, double a0, double *sols, double *en, int ns,
                   int nmax, int *ncone, double *d, double *tmp)
{
    int k = R->k, n = R->k + R->r;
    matvec(k, R->A, v, tmp);
    double na = sqrt(fmax(dot(k, v, tmp), 0.0));
    if (!(na > 1e-6 * a0)) return ns;
    (*ncone)++;
    if (!(dot(k, R->b, v) < 0.0)) return ns;
    for (int j = 0; j < ns; j++) {
        for (int i = 0; i < k; i++) d[i] = v[i] - sols[(size_t)j * n + i];
        matvec(k, R->A, d, tmp);
        if (sqrt(fmax(dot(k, d, tmp), 0.0)) <= SAME_TOL * na) return ns;
    }
    if (ns >= nmax) return ns;
    memcpy(sols + (size_t)ns * n, v, sizeof(double) * (size_t)n);
    matvec(k, R->A, v, tmp);
    en[ns] = 0.5 * dot(k, v, tmp) + dot(k, R->b, v);
    return ns + 1;
}

/* Whether branch a comes before branch b (z: full coordinates, en:
 * energies): lower energy first; of equal energies (to ORDER_TIE_RTOL) the
 * one whose first displacement coordinate that differs (by more than
 * ORDER_SAME_RTOL of the largest) is larger. */
static int branch_before(const sf_limit *L, const double *z, const double *en, int a, int b)
{
    double scale = fmax(fabs(en[a]), fabs(en[b]));
    if (fabs(en[a] - en[b]) > ORDER_TIE_RTOL * scale) return en[a] < en[b];
    const double *za = z + (size_t)a * L->n, *zb = z + (size_t)b * L->n;
    double big = fmax(maxabs(za, L->nq), maxabs(zb, L->nq));
    for (int i = 0; i < L->nq; i++)
        if (fabs(za[i] - zb[i]) > ORDER_SAME_RTOL * big) return za[i] > zb[i];
    return 0;
}

int sf_cone_find(const sf_limit *L, int nstarts, const double *zextra, sf_cone *c)
{
    return sf_cone_find_rays(L, nstarts, zextra, NULL, 0, c);
}

int sf_cone_find_rays(const sf_limit *L, int nstarts, const double *zextra, const double *rays,
                      int nrays, sf_cone *c)
{
    memset(c, 0, sizeof *c);
    c->n = L->n;
    red R;
    if (red_build(L, &R)) return -1;
    int k = R.k, r = R.r, n = k + r, rc = -1, nmax = MAX_RUNS + nstarts + ASCENT_STARTS + nrays;
    c->k = k;
    c->r = r;
    c->bnorm = maxabs(R.b, k);
    int m = (r > k ? r : k) + n + L->nq + 1;
    dwork w;
    memset(&w, 0, sizeof w);
    double *x = malloc(sizeof(double) * (size_t)m);
    double *x0 = malloc(sizeof(double) * (size_t)m);
    double *v = malloc(sizeof(double) * (size_t)m);
    double *F = malloc(sizeof(double) * (size_t)m);
    double *Jm = malloc(sizeof(double) * ((size_t)n * n + 1));
    double *d = malloc(sizeof(double) * (size_t)m);
    double *vt = malloc(sizeof(double) * (size_t)m);
    double *sols = malloc(sizeof(double) * ((size_t)nmax * n + 1));
    double *en = malloc(sizeof(double) * ((size_t)nmax + 1));
    double *stx = malloc(sizeof(double) * ((size_t)MAX_RUNS * k + 1));
    double *stv = malloc(sizeof(double) * ((size_t)MAX_RUNS * k + 1));
    double *steps = malloc(sizeof(double) * ((size_t)MAX_RUNS + 1));
    double *xdeg = malloc(sizeof(double) * ((size_t)k + 1));
    w.g = malloc(sizeof(double) * (size_t)m);
    w.H = malloc(sizeof(double) * ((size_t)k * k + 1));
    w.ev = malloc(sizeof(double) * (size_t)m);
    w.d = malloc(sizeof(double) * (size_t)m);
    w.xt = malloc(sizeof(double) * (size_t)m);
    w.tmp = malloc(sizeof(double) * (size_t)m);
    if (!x || !x0 || !v || !F || !Jm || !d || !vt || !sols || !en || !stx || !stv || !steps ||
        !xdeg || !w.g || !w.H || !w.ev || !w.d || !w.xt || !w.tmp)
        goto done;
    int ns = 0;
    if (k == 0 || c->bnorm == 0.0) { rc = 0; goto done; }
    {
        int lw = -1, info;
        double wq;
        dsyev_("V", "U", &k, w.H, &k, w.ev, &wq, &lw, &info);
        w.lwork = (int)wq + 1;
        w.work = malloc(sizeof(double) * (size_t)w.lwork);
        if (!w.work) goto done;
    }
    /* the unconstrained response -A^{-1} b, amplitude for the other starts */
    memcpy(x0, R.b, sizeof(double) * (size_t)k);
    memcpy(Jm, R.A, sizeof(double) * (size_t)k * k);
    if (lstsq(k, k, Jm, x0)) goto done;
    for (int i = 0; i < k; i++) x0[i] = -x0[i];
    matvec(k, R.A, x0, w.tmp);
    double a0 = sqrt(fmax(dot(k, x0, w.tmp), 0.0));
    if (zextra) {
        /* the given solution of the limit problem (the eps homotopy's):
         * its kernel coordinates, nu' by least squares, polished */
        for (int c2 = 0; c2 < k; c2++) v[c2] = dot(L->nq, R.N + (size_t)c2 * L->nq, zextra);
        if (r > 0) {
            for (int t = 0; t < r; t++) {
                matvec(k, R.Q + (size_t)t * k * k, v, w.tmp);
                memcpy(Jm + (size_t)t * k, w.tmp, sizeof(double) * (size_t)k);
            }
            matvec(k, R.A, v, d);
            for (int i = 0; i < k; i++) d[i] = -(d[i] + R.b[i]);
            if (lstsq(k, r, Jm, d)) goto done;
            memcpy(v + k, d, sizeof(double) * (size_t)r);
        }
        int nr = red_newton(&R, v, F, Jm, d, vt, w.tmp);
        if (nr < 0) goto done;
        if (!nr) ns = add_sol(&R, v, a0, sols, en, ns, nmax, &c->ncone, d, w.tmp);
    }
    unsigned long long st = 0x5eedf1a7ULL;
    int havedeg = 0;
    /* runs: from x0 (and the other side of every saddle met), then from
     * nstarts - 1 pseudo-random starts of the same amplitude */
    int nst = 0, runs = 0;
    for (int start = 0; start < nstarts; start++) {
        if (start == 0) memcpy(x, x0, sizeof(double) * (size_t)k);
        else {
            for (int i = 0; i < k; i++) x[i] = rnd(&st);
            anormalise(&R, x, w.tmp);
            for (int i = 0; i < k; i++) x[i] *= a0;
        }
        double eps0 = start == 0 ? 1.0 : 1e-2;
        int sign = 1;
        for (;;) {
            int saddle = 0;
            double seps = eps0;
            double *sx = stx + (size_t)(nst < MAX_RUNS ? nst : MAX_RUNS - 1) * k;
            double *sv = stv + (size_t)(nst < MAX_RUNS ? nst : MAX_RUNS - 1) * k;
            int bottom = 0;
            int dr = descend(&R, x, eps0, sign, &saddle, sx, sv, &seps, v, &w, F, Jm, d, vt,
                             &bottom);
            runs++;
            if (dr < 0) goto done;
            if (dr && bottom && start == 0 && !havedeg) {
                memcpy(xdeg, x, sizeof(double) * (size_t)k);
                havedeg = 1;
            }
            if (saddle && start == 0 && nst < MAX_RUNS) steps[nst++] = seps;
            if (!dr) ns = add_sol(&R, v, a0, sols, en, ns, nmax, &c->ncone, d, w.tmp);
            /* the other side of the saddles met on the way from x0 */
            if (start != 0 || nst == 0 || runs > MAX_RUNS) break;
            nst--;
            memcpy(x, stx + (size_t)nst * k, sizeof(double) * (size_t)k);
            eps0 = steps[nst];
            sign = -1;
        }
    }
    /* random rays of the cone, each raised to a stationary ray of the
     * work: the descent above follows the driving's response and can end
     * at the flat state where the best rays lie far from it (a waterbomb
     * tessellation, whose cone is a union of many-dimensional pieces) */
    c->degcap = (nrays > 0 ? nrays : 0) + ASCENT_STARTS + 1;
    c->degu = calloc((size_t)c->degcap * L->nq + 1, sizeof(double));
    c->degen = calloc((size_t)c->degcap + 1, sizeof(double));
    if (!c->degu || !c->degen) goto done;
    if (sf_fc_rays_add(L, &R, rays, nrays, a0, sols, en, &ns, nmax, c, v, F, Jm, d, vt, w.tmp) < 0)
        goto done;
    /* With a stable branch in hand the rays only look for a lower one, and
     * an ascent that creeps along a corner of the cone is left; without
     * one, their ends are the candidates and degenerate rays the start
     * may follow, and every ascent runs its course (left early, the 2x2
     * waterbomb tessellation in fold coordinates started from another
     * point of a flat valley of the limit energy: docs/flatstart.md). */
    int have_stable = 0;
    for (int i = 0; i < ns && !have_stable; i++) have_stable = red_stable(&R, sols + (size_t)i * n) == 1;
    if (r > 0 &&
        sf_fc_cone_search(&R, a0, sols, en, &ns, nmax, c, v, F, Jm, d, vt, &st, have_stable) < 0)
        goto done;
    if (ns == 0 && c->ndeg == 0 && havedeg && r > 0) {
        /* nothing else: the descent from the driving's response went down
         * to EPS_MIN next to the cone, but the reduced Newton found no
         * multipliers there (they grow as eps falls): a degenerate ray */
        anormalise(&R, xdeg, w.tmp);
        cone_eval(&R, xdeg, F, NULL, w.tmp);
        double wk = dot(k, R.b, xdeg);
        if (maxabs(F, r) <= DESCENT_DEG_TOL && wk < 0.0) {
            c->ncone++;
            sf_fc_deg_add(&R, xdeg, wk, c);
        }
    }
    /* the branches in full coordinates, then ordered by energy; energies
     * equal to ORDER_TIE_RTOL (mirror images of a symmetric sheet, whose
     * computed energies differ only by rounding) by their first coordinate
     * that differs, larger first, so that the order, and the branch the
     * start follows, does not change with the BLAS kernel */
    c->z = calloc((size_t)ns * L->n + 1, sizeof(double));
    c->energy = calloc((size_t)ns + 1, sizeof(double));
    c->stable = calloc((size_t)ns + 1, sizeof(int));
    c->resid = calloc((size_t)ns + 1, sizeof(double));
    double *zs = calloc((size_t)ns * L->n + 1, sizeof(double));
    int *ord = malloc(sizeof(int) * ((size_t)ns + 1));
    if (!c->z || !c->energy || !c->stable || !c->resid || !zs || !ord) {
        free(zs); free(ord);
        goto done;
    }
    for (int i = 0; i < ns; i++) {
        ord[i] = i;
        if (to_full(L, &R, sols + (size_t)i * n, zs + (size_t)i * L->n)) {
            free(zs); free(ord);
            goto done;
        }
    }
    for (int i = 1; i < ns; i++)
        for (int j = i; j > 0 && branch_before(L, zs, en, ord[j], ord[j - 1]); j--) {
            int t = ord[j]; ord[j] = ord[j - 1]; ord[j - 1] = t;
        }
    for (int i = 0; i < ns; i++) {
        const double *s = sols + (size_t)ord[i] * n;
        double *z = c->z + (size_t)i * L->n;
        memcpy(z, zs + (size_t)ord[i] * L->n, sizeof(double) * (size_t)L->n);
        c->energy[i] = en[ord[i]];
        c->stable[i] = red_stable(&R, s);
        c->resid[i] = sf_limit_residual(L, z);
    }
    free(zs);
    c->nb = ns;
    free(ord);
    rc = 0;
done:
    free(x); free(x0); free(v); free(F); free(Jm); free(d); free(vt); free(sols); free(en);
    free(stx); free(stv); free(steps); free(xdeg);
    free(w.g); free(w.H); free(w.ev); free(w.d); free(w.xt); free(w.tmp); free(w.work);
    red_free(&R);
    if (rc) sf_cone_free(c);
    return rc;
}

/* ---- the reduction for other modules (flatcone.h; flatswitch.c) ---- */
int sf_cone_reduce(const sf_limit *L, sf_cone_red *R) { return red_build(L, R); }
void sf_cone_reduce_free(sf_cone_red *R) { red_free(R); }
int sf_cone_to_limit(const sf_limit *L, const sf_cone_red *R, const double *v, double *z)
{
    return to_full(L, R, v, z);
}

/* The helpers of flatcone_rays.c (flatcone_impl.h) */
int sf_fc_lstsq(int m, int n, double *a, double *b) { return lstsq(m, n, a, b); }
double sf_fc_maxabs(const double *v, int n) { return maxabs(v, n); }
void sf_fc_matvec(int k, const double *M, const double *x, double *y) { matvec(k, M, x, y); }
double sf_fc_dot(int k, const double *a, const double *b) { return dot(k, a, b); }
void sf_fc_cone_eval(const red *R, const double *x, double *h, double *Jh, double *tmp)
{
    cone_eval(R, x, h, Jh, tmp);
}
void sf_fc_anormalise(const red *R, double *x, double *tmp) { anormalise(R, x, tmp); }
int sf_fc_red_newton(const red *R, double *v, double *F, double *Jm, double *d, double *vt,
                     double *tmp)
{
    return red_newton(R, v, F, Jm, d, vt, tmp);
}
double sf_fc_rnd(unsigned long long *st) { return rnd(st); }
int sf_fc_add_sol(const red *R, const double *v, double a0, double *sols, double *en, int ns,
                  int nmax, int *ncone, double *d, double *tmp)
{
    return add_sol(R, v, a0, sols, en, ns, nmax, ncone, d, tmp);
}
