/* flatswitch.c - every branch at the flat state with exact loop closure
 * (flatswitch.h): the reduced second-order equations on the kernel of the
 * first-order rows solved from many starts, their solutions grouped by
 * symmetry, each started and followed as a branch.
 *
 * The reduction (kernel N of J1, stiffness A = N^T H0 N, driving
 * b = N^T gp, independent forms Q_t) is flatcone.c's (sf_cone_reduce); the
 * back-substitution to the limit problem's (u, mu, nu) and to a state of
 * the exact problem is flatcone.c's and flatstart.c's (sf_cone_to_limit,
 * sf_limit_to_state).  Dense LAPACK throughout: k + r + 1 unknowns. */
#include "flatswitch.h"

#include "flatcone.h"
#include "flatstart.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

extern void dgesv_(const int *n, const int *nrhs, double *a, const int *lda, int *ipiv, double *b,
                   const int *ldb, int *info);
extern void dgelss_(const int *m, const int *n, const int *nrhs, double *a, const int *lda,
                    double *b, const int *ldb, double *s, const double *rcond, int *rank,
                    double *work, const int *lwork, int *info);
extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n,
                    double *a, const int *lda, double *s, double *u, const int *ldu,
                    double *vt, const int *ldvt, double *work, const int *lwork, int *info);
extern void dsygv_(const int *itype, const char *jobz, const char *uplo, const int *n, double *a,
                   const int *lda, double *b, const int *ldb, double *w, double *work,
                   const int *lwork, int *info);

#define NEWTON_MAXIT 80
#define SOL_RTOL 1e-11    /* reduced residual, relative to the stiffness scale */
#define SAME_RTOL 1e-4   /* two solutions are one (x, relative; distinct ones differ by O(1)) */
#define SIG_RTOL 1e-6    /* symmetric images: same p*, energy, sorted |u| */
#define LM_MAXIT 30      /* Levenberg-Marquardt steps per round */
#define LM_ROUNDS 2      /* rounds per start (where Newton's line search stalls) */
#define HOM_MODES 12     /* pencil modes (and their sums, differences) as extra starts */

/* The reduced system: v = (x[k], nu[r], s) with s = p* - p0 when hom. */
typedef struct sys {
    int k, r, hom, n;
    const double *A, *Ap, *b, *Q;
    double scale;         /* largest |A_ij| */
} sys;

static double dot(int n, const double *a, const double *b)
{
    double s = 0.0;
    for (int i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

static void matvec(int k, const double *M, const double *x, double *y)
{
    for (int i = 0; i < k; i++) y[i] = 0.0;
    for (int j = 0; j < k; j++)
        for (int i = 0; i < k; i++) y[i] += M[(size_t)j * k + i] * x[j];
}

static double maxabs(const double *v, int n)
{
    double m = 0.0;
    for (int i = 0; i < n; i++) m = fmax(m, fabs(v[i]));
    return m;
}

/* Residual F (n) and Jacobian Jm (n x n, column-major, or NULL). */
static void sys_eval(const sys *S, const double *v, double *F, double *Jm, double *tmp)
{
    int k = S->k, r = S->r, n = S->n;
    const double *x = v, *nu = v + k;
    double s = S->hom ? v[k + r] : 0.0;
    matvec(k, S->A, x, F);
    if (S->hom) {
        matvec(k, S->Ap, x, tmp);
        for (int i = 0; i < k; i++) F[i] += s * tmp[i];
        F[k + r] = 0.5 * (dot(k, x, x) - 1.0);
        if (Jm) {
            memset(Jm, 0, sizeof(double) * (size_t)n * n);
            for (int i = 0; i < k; i++) {
                Jm[(size_t)(k + r) * n + i] = tmp[i];     /* d/ds */
                Jm[(size_t)i * n + k + r] = x[i];         /* row of |x|^2 / 2 */
            }
        }
    } else {
        for (int i = 0; i < k; i++) F[i] += S->b[i];
        if (Jm) memset(Jm, 0, sizeof(double) * (size_t)n * n);
    }
    if (Jm)
        for (int j = 0; j < k; j++)
            for (int i = 0; i < k; i++)
                Jm[(size_t)j * n + i] = S->A[(size_t)j * k + i] + (S->hom ? s * S->Ap[(size_t)j * k + i] : 0.0);
    sf_cone_forms_add(k, r, S->Q, x, nu, F, Jm, n, tmp);
}

/* Least squares min |a z - b| (a: m x n column-major, destroyed; b: max(m, n)
 * values, the solution in its first n).  0 or -1. */
static int lstsq(int m, int n, double *a, double *b)
{
    int nrhs = 1, ldb = m > n ? m : n, rank, info, lwork = -1;
    double rcond = 1e-12, wq;
    double *sv = malloc(sizeof(double) * ((size_t)(m < n ? m : n) + 1));
    if (!sv) return -1;
    dgelss_(&m, &n, &nrhs, a, &m, b, &ldb, sv, &rcond, &rank, &wq, &lwork, &info);
    lwork = (int)wq + 1;
    double *w = malloc(sizeof(double) * (size_t)lwork);
    if (!w) { free(sv); return -1; }
    dgelss_(&m, &n, &nrhs, a, &m, b, &ldb, sv, &rcond, &rank, w, &lwork, &info);
    free(w);
    free(sv);
    return info == 0 ? 0 : -1;
}

/* Work space of the search */
typedef struct work {
    double *F, *Jm, *J2, *d, *vt, *tmp, *a, *JtJ;
    int *ipiv;
    /* deflation (Farrell, Birkisson & Funke, SIAM J. Sci. Comput. 37, 2015):
     * the solutions found so far, x in the first k of every n values */
    const double *defl;
    int ndefl;
    double dscale;        /* length scale of x (distances relative to it) */
} work;

/* The deflation factor M(x) = prod_j (dscale^2 / |x - x_j|^2 + 1) over
 * the known solutions (and their negatives when hom); g = grad ln M (k
 * values, when not NULL).  Returns ln M. */
static double deflation(const sys *S, const double *x, const work *w, double *g)
{
    int k = S->k, n = S->n;
    double lnM = 0.0, s2 = w->dscale * w->dscale;
    if (g) memset(g, 0, sizeof(double) * (size_t)k);
    for (int j = 0; j < w->ndefl; j++)
        for (int sg = 1; sg >= (S->hom ? -1 : 1); sg -= 2) {
            const double *xj = w->defl + (size_t)j * n;
            double d2 = 0.0;
            for (int i = 0; i < k; i++) d2 += (x[i] - sg * xj[i]) * (x[i] - sg * xj[i]);
            d2 = fmax(d2, 1e-300);
            double m = s2 / d2 + 1.0;
            lnM += log(m);
            if (g)
                for (int i = 0; i < k; i++) g[i] += -2.0 * s2 * (x[i] - sg * xj[i]) / (d2 * d2) / m;
        }
    return lnM;
}

/* Newton with backtracking on the max-norm of the residual; LU steps,
 * minimum-norm ones where LU fails.  0 when converged. */
extern void dposv_(const char *uplo, const int *n, const int *nrhs, double *a, const int *lda,
                   double *b, const int *ldb, int *info);

/* Levenberg-Marquardt on |F|^2 from v (the globalisation where Newton's
 * line search stalls far from a solution): (J^T J + mu I) d = -J^T F, mu
 * divided by 3 after a step that lowers |F|, multiplied by 4 otherwise.
 * Returns when |F|max <= 1e-3 of where it started or after LM_MAXIT
 * steps; 0 when it lowered the residual. */
static int sys_lm(const sys *S, double *v, work *w, double *JtJ)
{
    int n = S->n, one = 1, info;
    sys_eval(S, v, w->F, w->Jm, w->tmp);
    double f2 = dot(n, w->F, w->F), f0 = maxabs(w->F, n), mu = 1e-3 * S->scale * S->scale;
    int improved = 0;
    for (int it = 0; it < LM_MAXIT; it++) {
        for (int j = 0; j < n; j++) {
            w->d[j] = -dot(n, w->Jm + (size_t)j * n, w->F);
            for (int i = 0; i <= j; i++) JtJ[(size_t)j * n + i] = dot(n, w->Jm + (size_t)i * n, w->Jm + (size_t)j * n);
            JtJ[(size_t)j * n + j] += mu;
        }
        dposv_("U", &n, &one, JtJ, &n, w->d, &n, &info);
        if (info != 0) { mu *= 4.0; continue; }
        for (int i = 0; i < n; i++) w->vt[i] = v[i] + w->d[i];
        sys_eval(S, w->vt, w->tmp + n, NULL, w->tmp);
        double g2 = dot(n, w->tmp + n, w->tmp + n);
        if (g2 < f2) {
            memcpy(v, w->vt, sizeof(double) * (size_t)n);
            sys_eval(S, v, w->F, w->Jm, w->tmp);
            f2 = dot(n, w->F, w->F);
            mu /= 3.0;
            improved = 1;
            if (maxabs(w->F, n) <= 1e-3 * f0) break;
        } else {
            mu *= 4.0;
        }
    }
    return improved ? 0 : 1;
}

static int sys_newton(const sys *S, double *v, work *w)
{
    int n = S->n, one = 1, info, nlm = 0;
    double tol = SOL_RTOL * fmax(S->scale, S->hom ? 0.0 : maxabs(S->b, S->k));
    for (int it = 0; it < NEWTON_MAXIT; it++) {
        sys_eval(S, v, w->F, w->Jm, w->tmp);
        double en = maxabs(w->F, n);
        if (!isfinite(en)) return 1;
        if (en <= tol) return 0;
        for (int i = 0; i < n; i++) w->d[i] = -w->F[i];
        memcpy(w->J2, w->Jm, sizeof(double) * (size_t)n * n);
        dgesv_(&n, &one, w->Jm, &n, w->ipiv, w->d, &n, &info);
        if (info != 0 || !isfinite(maxabs(w->d, n))) {
            for (int i = 0; i < n; i++) w->d[i] = -w->F[i];
            if (lstsq(n, n, w->J2, w->d)) return -1;
        }
        if (w->ndefl > 0) {
            /* the deflated Newton step d / (1 - grad ln M . d) (the line
             * search stays on |F|: on M |F| fewer starts converged) */
            double *g = w->J2;
            double gd = 0.0;
            deflation(S, v, w, g);
            for (int i = 0; i < S->k; i++) gd += g[i] * w->d[i];
            if (fabs(1.0 - gd) > 1e-12)
                for (int i = 0; i < n; i++) w->d[i] /= 1.0 - gd;
        }
        double t = 1.0, et = en;
        for (int bt = 0; bt < 30; bt++, t *= 0.5) {
            for (int i = 0; i < n; i++) w->vt[i] = v[i] + t * w->d[i];
            sys_eval(S, w->vt, w->F, NULL, w->tmp);
            et = maxabs(w->F, n);
            if (et < en) break;
        }
        if (!(et < en)) {
            /* stalled: Levenberg-Marquardt steps, then Newton again */
            if (++nlm > LM_ROUNDS || sys_lm(S, v, w, w->JtJ)) return 1;
            continue;
        }
        memcpy(v, w->vt, sizeof(double) * (size_t)n);
    }
    sys_eval(S, v, w->F, NULL, w->tmp);
    return maxabs(w->F, n) <= tol ? 0 : 1;
}

/* The multipliers (and s) of a start x by least squares on the
 * stationarity rows: [Q_t x | Ap x] (nu, s) = -(A x + b). */
static int start_multipliers(const sys *S, double *v, work *w)
{
    int k = S->k, r = S->r, m = r + S->hom;
    if (m == 0) return 0;
    for (int t = 0; t < r; t++) matvec(k, S->Q + (size_t)t * k * k, v, w->a + (size_t)t * k);
    if (S->hom) matvec(k, S->Ap, v, w->a + (size_t)r * k);
    matvec(k, S->A, v, w->d);
    for (int i = 0; i < k; i++) w->d[i] = -(w->d[i] + (S->hom ? 0.0 : S->b[i]));
    if (lstsq(k, m, w->a, w->d)) return -1;
    memcpy(v + k, w->d, sizeof(double) * (size_t)m);
    return 0;
}

/* Smallest over largest singular value of the reduced Jacobian at v: a
 * solution is isolated when it is not small (1e-8). */
static double isolation(const sys *S, const double *v, work *w)
{
    int n = S->n, info, lwork = -1, one = 1;
    double wq, du;
    sys_eval(S, v, w->F, w->Jm, w->tmp);
    double *sv = malloc(sizeof(double) * ((size_t)n + 1));
    if (!sv) return -1.0;
    dgesvd_("N", "N", &n, &n, w->Jm, &n, sv, &du, &one, &du, &one, &wq, &lwork, &info);
    lwork = (int)wq + 1;
    double *wk = malloc(sizeof(double) * (size_t)lwork);
    if (!wk) { free(sv); return -1.0; }
    dgesvd_("N", "N", &n, &n, w->Jm, &n, sv, &du, &one, &du, &one, wk, &lwork, &info);
    double q = info == 0 && sv[0] > 0 ? sv[n - 1] / sv[0] : -1.0;
    free(wk);
    free(sv);
    return q;
}

static double rnd(unsigned long long *st)
{
    *st = *st * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*st >> 11) / (double)(1ULL << 53) * 2.0 - 1.0;
}

/* Homogeneous starts: the modes of the pencil -Ap x = mu A x (A positive
 * definite), lowest critical load first; k of them in X (k x k). */
static int pencil_modes(const sys *S, double *X, double *mu)
{
    int k = S->k, one = 1, info, lwork = -1;
    double *B = malloc(sizeof(double) * ((size_t)k * k + 1)), wq;
    if (!B) return -1;
    for (size_t i = 0; i < (size_t)k * k; i++) {
        X[i] = -S->Ap[i];
        B[i] = S->A[i];
    }
    dsygv_(&one, "V", "U", &k, X, &k, B, &k, mu, &wq, &lwork, &info);
    lwork = (int)wq + 1;
    double *w = malloc(sizeof(double) * (size_t)lwork);
    if (!w) { free(B); return -1; }
    dsygv_(&one, "V", "U", &k, X, &k, B, &k, mu, w, &lwork, &info);
    free(w);
    free(B);
    return info == 0 ? 0 : -1;
}

/* Is v a new solution among the ns in sols (n values each)? Homogeneous:
 * x up to sign, and the same s. */
static int is_new(const sys *S, const double *v, const double *sols, int ns)
{
    int k = S->k, n = S->n;
    double nx = sqrt(dot(k, v, v));
    for (int j = 0; j < ns; j++) {
        const double *o = sols + (size_t)j * n;
        double dm = 0.0, dp = 0.0;
        for (int i = 0; i < k; i++) {
            dm += (v[i] - o[i]) * (v[i] - o[i]);
            dp += (v[i] + o[i]) * (v[i] + o[i]);
        }
        double d = S->hom ? fmin(dm, dp) : dm;
        if (sqrt(d) <= SAME_RTOL * nx &&
            (!S->hom || fabs(v[k + S->r] - o[k + S->r]) <= SAME_RTOL * (1.0 + fabs(o[k + S->r]))))
            return 0;
    }
    return 1;
}

static int cmp_dbl(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

void sf_flatsw_free(sf_flatsw *F)
{
    free(F->pstar);
    free(F->energy);
    free(F->resid);
    free(F->isol);
    free(F->u);
    free(F->cls);
    free(F->sol);
    free(F->y);
    free(F->ty);
    free(F->p);
    free(F->tp);
    memset(F, 0, sizeof *F);
}

/* Newton from the start x = v (first k values): multipliers by least
 * squares, then the (deflated) iteration; a new solution is appended to
 * *sol (n values each, *ns of *cap) and deflated from then on.  0, or -1
 * (out of memory, LAPACK failure). */
static int try_start(const sys *S, double *v, double **solp, int *nsp, int *capp, int *nconv,
                     double a0, work *w)
{
    int k = S->k, n = S->n;
    if (start_multipliers(S, v, w)) return -1;
    int nr = sys_newton(S, v, w);
    if (nr < 0) return -1;
    if (nr) return 0;
    (*nconv)++;
    if (S->hom) {
        /* sign: the largest component positive */
        int im = 0;
        for (int i = 1; i < k; i++) if (fabs(v[i]) > fabs(v[im])) im = i;
        if (v[im] < 0) for (int i = 0; i < k; i++) v[i] = -v[i];
    } else if (!(sqrt(dot(k, v, v)) > 1e-9 * a0)) {
        return 0;
    }
    if (!is_new(S, v, *solp, *nsp)) return 0;
    w->defl = NULL;   /* sol may move */
    if (*nsp == *capp) {
        double *t = realloc(*solp, sizeof(double) * (size_t)(*capp *= 2) * n);
        if (!t) return -1;
        *solp = t;
    }
    memcpy(*solp + (size_t)*nsp * n, v, sizeof(double) * (size_t)n);
    (*nsp)++;
    w->defl = *solp;
    w->ndefl = *nsp;
    return 0;
}

/* The isometries of the crease pattern among the 8 of the square about
 * the vertices' centroid (rotations by multiples of 90 degrees, the
 * reflections): those that map every fold onto a fold.  perm[g * nf + f]:
 * the image of fold f under the g-th found (0: the identity).  Returns
 * their number. */
static int pattern_symmetries(const sf_study *st, int *perm)
{
    int nf = st->nfolds, nv = st->nvertices, ng = 0;
    double c[2] = {0, 0}, size = 0.0;
    for (int i = 0; i < nv; i++) { c[0] += st->vertices[i].x[0] / nv; c[1] += st->vertices[i].x[1] / nv; }
    for (int i = 0; i < nv; i++)
        size = fmax(size, fabs(st->vertices[i].x[0] - c[0]) + fabs(st->vertices[i].x[1] - c[1]));
    double tol = 1e-9 * fmax(size, 1e-300);
    for (int g = 0; g < 8; g++) {
        int ok = 1;
        for (int f = 0; f < nf && ok; f++) {
            double e[2][2];
            for (int end = 0; end < 2; end++) {
                const double *x = st->vertices[end ? st->folds[f].b : st->folds[f].a].x;
                double X = x[0] - c[0], Y = x[1] - c[1];
                if (g >= 4) Y = -Y;
                for (int r = 0; r < g % 4; r++) { double t = X; X = -Y; Y = t; }
                e[end][0] = X + c[0];
                e[end][1] = Y + c[1];
            }
            int found = -1;
            for (int h = 0; h < nf && found < 0; h++) {
                const double *a = st->vertices[st->folds[h].a].x, *b = st->vertices[st->folds[h].b].x;
                double d1 = fabs(a[0] - e[0][0]) + fabs(a[1] - e[0][1]) + fabs(b[0] - e[1][0]) + fabs(b[1] - e[1][1]);
                double d2 = fabs(a[0] - e[1][0]) + fabs(a[1] - e[1][1]) + fabs(b[0] - e[0][0]) + fabs(b[1] - e[0][1]);
                if (d1 <= tol || d2 <= tol) found = h;
            }
            if (found < 0) ok = 0;
            else perm[ng * nf + f] = found;
        }
        if (ok) ng++;
    }
    return ng;
}

/* x' = N^T P u (u = N x) for the fold permutation P (perm: nf values),
 * the shape-mode amplitudes multiplied by msign. */
static void image(const sf_cone_red *R, const sf_model *m, const int *perm, double msign,
                  const double *x, double *v, double *u, double *u2)
{
    int nq = R->nq, k = R->k;
    for (int i = 0; i < nq; i++) u[i] = 0.0;
    for (int c = 0; c < k; c++)
        for (int i = 0; i < nq; i++) u[i] += R->N[(size_t)c * nq + i] * x[c];
    for (int f = 0; f < m->nfolds; f++)
        for (int j = 0; j < m->qn[f]; j++)
            u2[m->qoff[perm[f]] + j] = (j ? msign : 1.0) * u[m->qoff[f] + j];
    for (int c = 0; c < k; c++) v[c] = dot(nq, R->N + (size_t)c * nq, u2);
}

/* Search: solutions v (n values each) into *sols; returns the count. */
/* The crease pattern's symmetries for orbit completion (search). */
typedef struct symm {
    const sf_cone_red *R;
    const sf_model *m;
    int ng, *perm;
    double *u, *u2;       /* nq each */
} symm;

static int search(const sys *S, int nstarts, double p0, double plo, double phi, const symm *sy,
                  double **sols, int *nconv, work *w)
{
    int k = S->k, n = S->n, ns = 0, cap = 16;
    double *sol = malloc(sizeof(double) * (size_t)cap * n);
    double *v = malloc(sizeof(double) * ((size_t)n + 1));
    double *X = malloc(sizeof(double) * ((size_t)k * k + 1));
    double *mu = malloc(sizeof(double) * ((size_t)k + 1)), *H = NULL;
    if (!sol || !v || !X || !mu) { ns = -1; goto done; }
    double a0 = 1.0;
    if (S->hom) {
        if (pencil_modes(S, X, mu)) { ns = -1; goto done; }
    } else {
        /* the driving's response -A^-1 b first, its A-norm for the rest */
        memcpy(X, S->A, sizeof(double) * (size_t)k * k);
        for (int i = 0; i < k; i++) mu[i] = -S->b[i];
        if (lstsq(k, k, X, mu)) { ns = -1; goto done; }
        matvec(k, S->A, mu, w->tmp);
        a0 = sqrt(fmax(dot(k, mu, w->tmp), 1e-300));
    }
    unsigned long long st = 0xf1a75e11ULL;
    *nconv = 0;
    w->dscale = S->hom ? 1.0 : a0;
    /* extra starts: the modes of the pencil, lowest critical load
     * first, and within a multiple eigenvalue (a symmetric sheet) also the
     * sums and differences of neighbouring modes, whose images under the
     * symmetry the single modes need not reach */
    int nh = 0;
    H = S->hom ? malloc(sizeof(double) * ((size_t)3 * HOM_MODES * k + 1)) : NULL;
    if (S->hom && !H) { ns = -1; goto done; }
    for (int s = 0; S->hom && s < HOM_MODES && s < k; s++) {
        int j = k - 1 - s;
        memcpy(H + (size_t)nh++ * k, X + (size_t)j * k, sizeof(double) * (size_t)k);
        if (s > 0 && fabs(mu[j] - mu[j + 1]) <= 1e-6 * fabs(mu[j]))
            for (int sg = -1; sg <= 1; sg += 2, nh++)
                for (int i = 0; i < k; i++)
                    H[(size_t)nh * k + i] = (X[(size_t)j * k + i] + sg * X[(size_t)(j + 1) * k + i]) / M_SQRT2;
    }
    for (int s = 0; s < nstarts + nh; s++) {
        if (S->hom && s < nh) {
            memcpy(v, H + (size_t)s * k, sizeof(double) * (size_t)k);
        } else if (!S->hom && s == 0) {
            memcpy(v, mu, sizeof(double) * (size_t)k);
        } else {
            for (int i = 0; i < k; i++) v[i] = rnd(&st);
        }
        double nv = sqrt(dot(k, v, v));
        if (!(nv > 0)) continue;
        if (S->hom) {
            for (int i = 0; i < k; i++) v[i] /= nv;
        } else if (s > 0) {
            matvec(k, S->A, v, w->tmp);
            double an = sqrt(fmax(dot(k, v, w->tmp), 1e-300));
            for (int i = 0; i < k; i++) v[i] *= a0 / an;
        }
        if (try_start(S, v, &sol, &ns, &cap, nconv, a0, w)) { ns = -1; goto done; }
    }
    /* orbit completion: the images of every solution found under the
     * crease pattern's symmetries (with the shape modes as they are and
     * reversed) as further starts; whatever Newton reaches from them is a
     * solution, an image or not */
    for (int j = 0; j < ns && sy && sy->ng > 1; j++)
        for (int g = 1; g < sy->ng; g++)
            for (int ms = 0; ms < 2; ms++) {
                image(sy->R, sy->m, sy->perm + (size_t)g * sy->m->nfolds, ms ? -1.0 : 1.0,
                      sol + (size_t)j * n, v, sy->u, sy->u2);
                if (try_start(S, v, &sol, &ns, &cap, nconv, a0, w)) { ns = -1; goto done; }
            }
    w->defl = NULL;
    w->ndefl = 0;
    if (S->hom) {
        /* all were deflated; keep those with p* in the range */
        int m = 0;
        for (int j = 0; j < ns; j++) {
            double ps = p0 + sol[(size_t)j * n + k + S->r];
            if (ps < plo - 1e-12 * (1 + fabs(plo)) || ps > phi + 1e-12 * (1 + fabs(phi))) continue;
            memmove(sol + (size_t)m * n, sol + (size_t)j * n, sizeof(double) * (size_t)n);
            m++;
        }
        ns = m;
    }
done:
    free(v);
    free(X);
    free(mu);
    free(H);
    if (ns < 0) { free(sol); sol = NULL; }
    *sols = sol;
    return ns;
}

/* Solutions sorted: homogeneous by p*, driven by energy (insertion). */
static void sort_solutions(const sys *S, double *sol, int ns, double *key, double *tmpv)
{
    int n = S->n, k = S->k;
    for (int j = 0; j < ns; j++) {
        const double *v = sol + (size_t)j * n;
        if (S->hom) key[j] = v[k + S->r];
        else {
            matvec(k, S->A, v, tmpv);
            key[j] = 0.5 * dot(k, v, tmpv) + dot(k, S->b, v);
        }
    }
    for (int i = 1; i < ns; i++)
        for (int j = i; j > 0 && key[j] < key[j - 1]; j--) {
            double t = key[j]; key[j] = key[j - 1]; key[j - 1] = t;
            for (int c = 0; c < n; c++) {
                double *a = sol + (size_t)j * n + c, *b = sol + (size_t)(j - 1) * n + c;
                t = *a; *a = *b; *b = t;
            }
        }
}

/* Classes of symmetric images: same p*, energy and sorted |u|. */
static int classify(sf_flatsw *F)
{
    int nq = F->nq, ncls = 0;
    double *m = malloc(sizeof(double) * ((size_t)F->nsol * nq + 1));
    if (!m) return -1;
    for (int j = 0; j < F->nsol; j++) {
        double *mj = m + (size_t)j * nq;
        for (int i = 0; i < nq; i++) mj[i] = fabs(F->u[(size_t)j * nq + i]);
        qsort(mj, (size_t)nq, sizeof(double), cmp_dbl);
        F->cls[j] = j;
        for (int c = 0; c < j && F->cls[j] == j; c++) {
            if (F->cls[c] != c) continue;
            const double *mc = m + (size_t)c * nq;
            int same = fabs(F->pstar[c] - F->pstar[j]) <= SIG_RTOL * (1.0 + fabs(F->pstar[c])) &&
                       fabs(F->energy[c] - F->energy[j]) <= SIG_RTOL * (1e-12 + fabs(F->energy[c]));
            for (int i = 0; i < nq && same; i++)
                if (fabs(mc[i] - mj[i]) > SIG_RTOL * (1e-3 + mc[nq - 1])) same = 0;
            if (same) F->cls[j] = c;
        }
        if (F->cls[j] == j) ncls++;
    }
    free(m);
    F->ncls = ncls;
    return 0;
}

/* The predicted branches of solution j (v: its reduced values, L: the limit
 * problem at its p*). */
static int predict(sf_flatsw *F, sf_equil *eq, const sf_limit *L, const sf_cone_red *R,
                   const double *v, int j, double p0, double dp, double eps, double *z)
{
    int n = F->n, nq = F->nq;
    if (sf_cone_to_limit(L, R, v, z)) return -1;
    memcpy(F->u + (size_t)j * nq, z, sizeof(double) * (size_t)nq);
    F->resid[j] = sf_limit_residual(L, z);
    int nd = F->homogeneous ? 2 : 1;
    for (int d = 0; d < nd; d++) {
        int i = F->ndir++;
        double sg = d == 0 ? 1.0 : -1.0, a = F->homogeneous ? sg * eps : dp;
        F->sol[i] = j;
        sf_limit_to_state(eq, L, z, a, F->y + (size_t)i * n);
        F->p[i] = F->homogeneous ? F->pstar[j] : p0 + dp;
        /* tangent d/da of (a u, a mu, nu): (u, mu, 0) */
        double *nu = z + nq + L->n1;
        double *keep = malloc(sizeof(double) * ((size_t)L->n2 + 1));
        if (!keep) return -1;
        memcpy(keep, nu, sizeof(double) * (size_t)L->n2);
        memset(nu, 0, sizeof(double) * (size_t)L->n2);
        sf_limit_to_state(eq, L, z, F->homogeneous ? sg : (dp >= 0 ? 1.0 : -1.0), F->ty + (size_t)i * n);
        memcpy(nu, keep, sizeof(double) * (size_t)L->n2);
        free(keep);
        F->tp[i] = F->homogeneous ? 0.0 : (dp >= 0 ? 1.0 : -1.0);
    }
    return 0;
}

int sf_flatsw_find(sf_equil *eq, double p0, double dp, double eps, double plo, double phi,
                   int nstarts, sf_flatsw *F, sf_error *err)
{
    memset(F, 0, sizeof *F);
    const char *path = eq->m->study->path;
    if (eq->pz || eq->nloop == 0 || eq->nsup > 0 || eq->disp_row >= 0)
        return sf_fail(err, SF_EINPUT, "%s: switching at the flat state needs exact loop rows in "
                       "fold coordinates, without supports or a prescribed displacement", path);
    sf_limit L0, L1;
    memset(&L1, 0, sizeof L1);
    if (sf_limit_build(eq, p0, &L0, err)) return err->code;
    sf_cone_red R;
    int rc = SF_OK, ns = 0, nconv = 0;
    double *sol = NULL, *Ap = NULL, *key = NULL, *z = NULL;
    work w;
    memset(&w, 0, sizeof w);
    if (sf_cone_reduce(&L0, &R)) {
        sf_limit_free(&L0);
        return sf_fail(err, SF_ENOMEM, "%s: flat state: out of memory or a LAPACK failure", path);
    }
    int k = R.k, r = R.r, nq = L0.nq;
    sys S = {k, r, 0, k + r, R.A, NULL, R.b, R.Q, 0.0};
    S.scale = maxabs(R.A, k * k);
    F->k = k;
    F->r = r;
    F->n = eq->n;
    F->nq = nq;
    F->nstarts = nstarts;
    if (k == 0) goto done;
    S.hom = !(maxabs(R.b, k) > 1e-12 * S.scale);
    S.n = k + r + S.hom;
    F->homogeneous = S.hom;
    if (S.hom) {
        /* A(p) = A0 + (p - p0) Ap: the stiffness at p0 + 1 on the same kernel */
        if (sf_limit_build(eq, p0 + 1.0, &L1, err)) { rc = err->code; goto done; }
        Ap = calloc((size_t)k * k + 1, sizeof(double));
        double *hc = malloc(sizeof(double) * ((size_t)nq + 1));
        if (!Ap || !hc) { free(hc); rc = sf_fail(err, SF_ENOMEM, "out of memory"); goto done; }
        for (int c = 0; c < k; c++) {
            const double *Nc = R.N + (size_t)c * nq;
            for (int p = 0; p < nq; p++)
                hc[p] = dot(nq, L1.H0 + (size_t)p * nq, Nc) - dot(nq, L0.H0 + (size_t)p * nq, Nc);
            for (int i = 0; i < k; i++) Ap[(size_t)c * k + i] = dot(nq, R.N + (size_t)i * nq, hc);
        }
        free(hc);
        S.Ap = Ap;
        if (!(maxabs(Ap, k * k) > 1e-12 * S.scale)) goto done;   /* p does not act on the flat state */
    }
    int n = S.n, m = 2 * (k + n) + nq + 1;
    w.F = malloc(sizeof(double) * (size_t)m);
    w.Jm = malloc(sizeof(double) * ((size_t)n * n + 1));
    w.J2 = malloc(sizeof(double) * ((size_t)n * n + 1));
    w.d = malloc(sizeof(double) * (size_t)m);
    w.vt = malloc(sizeof(double) * (size_t)m);
    w.tmp = malloc(sizeof(double) * (size_t)m);
    w.a = malloc(sizeof(double) * ((size_t)k * (r + 1) + 1));
    w.ipiv = malloc(sizeof(int) * (size_t)m);
    w.JtJ = malloc(sizeof(double) * ((size_t)n * n + 1));
    if (!w.F || !w.Jm || !w.J2 || !w.d || !w.vt || !w.tmp || !w.a || !w.ipiv || !w.JtJ) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto done;
    }
    symm sy = {&R, eq->m, 0, NULL, NULL, NULL};
    sy.perm = malloc(sizeof(int) * ((size_t)8 * eq->m->nfolds + 1));
    sy.u = malloc(sizeof(double) * ((size_t)nq + 1));
    sy.u2 = malloc(sizeof(double) * ((size_t)nq + 1));
    if (!sy.perm || !sy.u || !sy.u2) {
        free(sy.perm); free(sy.u); free(sy.u2);
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto done;
    }
    sy.ng = pattern_symmetries(eq->m->study, sy.perm);
    F->nsym = sy.ng;
    ns = search(&S, nstarts, p0, plo, phi, &sy, &sol, &nconv, &w);
    free(sy.perm); free(sy.u); free(sy.u2);
    if (ns < 0) { rc = sf_fail(err, SF_ENOMEM, "%s: flat state: out of memory or a LAPACK failure", path); goto done; }
    F->nconv = nconv;
    key = malloc(sizeof(double) * ((size_t)ns + 1));
    z = malloc(sizeof(double) * ((size_t)L0.n + 1));
    int nd = S.hom ? 2 : 1;
    F->pstar = calloc((size_t)ns + 1, sizeof(double));
    F->energy = calloc((size_t)ns + 1, sizeof(double));
    F->resid = calloc((size_t)ns + 1, sizeof(double));
    F->isol = calloc((size_t)ns + 1, sizeof(double));
    F->u = calloc((size_t)ns * nq + 1, sizeof(double));
    F->cls = calloc((size_t)ns + 1, sizeof(int));
    F->sol = calloc((size_t)ns * nd + 1, sizeof(int));
    F->y = calloc((size_t)ns * nd * eq->n + 1, sizeof(double));
    F->ty = calloc((size_t)ns * nd * eq->n + 1, sizeof(double));
    F->p = calloc((size_t)ns * nd + 1, sizeof(double));
    F->tp = calloc((size_t)ns * nd + 1, sizeof(double));
    if (!key || !z || !F->pstar || !F->energy || !F->resid || !F->isol || !F->u || !F->cls || !F->sol || !F->y ||
        !F->ty || !F->p || !F->tp) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto done;
    }
    sort_solutions(&S, sol, ns, key, w.tmp);
    for (int j = 0; j < ns; j++) {
        const double *v = sol + (size_t)j * n;
        F->pstar[j] = S.hom ? p0 + key[j] : p0;
        F->energy[j] = S.hom ? 0.0 : key[j];
        F->isol[j] = isolation(&S, v, &w);
        sf_limit Lj, *Lp = &L0;
        if (S.hom) {
            if (sf_limit_build(eq, F->pstar[j], &Lj, err)) { rc = err->code; goto done; }
            Lp = &Lj;
        }
        int pr = predict(F, eq, Lp, &R, v, j, p0, dp, eps, z);
        if (S.hom) sf_limit_free(&Lj);
        if (pr) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); goto done; }
        F->nsol = j + 1;
    }
    if (classify(F)) rc = sf_fail(err, SF_ENOMEM, "out of memory");
done:
    free(w.F); free(w.Jm); free(w.J2); free(w.d); free(w.vt); free(w.tmp); free(w.a); free(w.ipiv); free(w.JtJ);
    free(sol);
    free(Ap);
    free(key);
    free(z);
    sf_cone_reduce_free(&R);
    sf_limit_free(&L0);
    sf_limit_free(&L1);
    if (rc) sf_flatsw_free(F);
    return rc;
}
