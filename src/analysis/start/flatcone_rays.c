/* flatcone_rays.c - rays of the tangent cone besides the penalty descent
 * of flatcone.c: pseudo-random rays taken onto the cone and raised along
 * it to a stationary ray of the work (a projected gradient in the A
 * metric), and rays given by the caller (sf_cone_find_rays); each is
 * polished by Newton on the reduced problem, and a ray on which that
 * fails while the driving does work on it is kept as a degenerate ray
 * (flatcone.h).  Dense LAPACK, like flatcone.c. */
#include "flatcone.h"
#include "flatcone_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

extern void dgesv_(const int *n, const int *nrhs, double *a, const int *lda, int *ipiv, double *b,
                   const int *ldb, int *info);

/* Work space of the ascent on the cone */
typedef struct awork {
    double *Ainv;    /* k x k: A^-1 */
    double *C, *M, *g, *d, *mu, *xt, *h, *tmp;
} awork;

/* Gauss-Newton with minimum-norm steps on x^T Q_t x / 2 = 0 (x kept at
 * unit A norm).  Returns the final max |h_t|. */
static double cone_project(const red *R, double *x, awork *a)
{
    int k = R->k, r = R->r;
    double hm = 0.0;
    sf_fc_anormalise(R, x, a->tmp);
    for (int it = 0; it < CONE_MAXIT; it++) {
        sf_fc_cone_eval(R, x, a->h, a->C, a->tmp);
        hm = sf_fc_maxabs(a->h, r);
        if (hm <= CONE_TOL) break;
        for (int t = 0; t < r; t++) a->d[t] = -a->h[t];
        if (sf_fc_lstsq(r, k, a->C, a->d)) return INFINITY;
        for (int i = 0; i < k; i++) x[i] += a->d[i];
        sf_fc_anormalise(R, x, a->tmp);
    }
    return hm;
}

/* From x (unit A norm, on the cone), raise the work -b . x along the cone
 * by projected gradient steps in the A metric: d = A^-1 (C^T mu - b) with
 * C = [(Q_t x)^T; (A x)^T] and C d = 0, then back onto the cone.  A step
 * that does not raise the work is halved; the ascent ends where the
 * projected gradient vanishes (a stationary ray, polished by the caller)
 * or no step helps, or (stall_ends) the steps gain almost nothing: a
 * corner of the cone.  Returns 0 at a stationary ray. */
static int cone_ascend(const red *R, double *x, awork *a, int stall_ends)
{
    int k = R->k, r = R->r, m = r + 1;
    double step = 0.05, wpast[ASCENT_STALL_ITS];   /* the work of the last iterations */
    for (int it = 0; it < ASCENT_MAXIT; it++) {
        /* a corner: steps still found, but they gain almost nothing (the
         * cone turns the projected gradient back) */
        double w = sf_fc_dot(k, R->b, x);
        if (stall_ends && it >= ASCENT_STALL_ITS &&
            wpast[it % ASCENT_STALL_ITS] - w <= ASCENT_STALL_GAIN * fabs(w))
            return 1;
        wpast[it % ASCENT_STALL_ITS] = w;
        sf_fc_cone_eval(R, x, a->h, a->C, a->tmp);   /* C rows 0..r-1 (leading dimension r) */
        /* C with leading dimension m: row r is (A x)^T */
        for (int j = k - 1; j >= 0; j--)
            for (int t = r - 1; t >= 0; t--) a->C[(size_t)j * m + t] = a->C[(size_t)j * r + t];
        sf_fc_matvec(k, R->A, x, a->tmp);
        for (int j = 0; j < k; j++) a->C[(size_t)j * m + r] = a->tmp[j];
        /* g = -A^-1 b; M = C A^-1 C^T; mu = sf_fc_lstsq(M, -C g) */
        sf_fc_matvec(k, a->Ainv, R->b, a->g);
        for (int i = 0; i < k; i++) a->g[i] = -a->g[i];
        double *AC = a->xt;   /* k x m: A^-1 C^T (xt has room: see sf_cone_find) */
        for (int t = 0; t < m; t++) {
            for (int j = 0; j < k; j++) a->tmp[j] = a->C[(size_t)j * m + t];
            sf_fc_matvec(k, a->Ainv, a->tmp, AC + (size_t)t * k);
        }
        for (int t = 0; t < m; t++) {
            double v = 0.0;
            for (int j = 0; j < k; j++) v += a->C[(size_t)j * m + t] * a->g[j];
            a->mu[t] = -v;
            for (int u = 0; u < m; u++) {
                double w = 0.0;
                for (int j = 0; j < k; j++) w += a->C[(size_t)j * m + t] * AC[(size_t)u * k + j];
                a->M[(size_t)u * m + t] = w;
            }
        }
        if (sf_fc_lstsq(m, m, a->M, a->mu)) return -1;
        for (int i = 0; i < k; i++) {
            double v = a->g[i];
            for (int t = 0; t < m; t++) v += AC[(size_t)t * k + i] * a->mu[t];
            a->d[i] = v;
        }
        sf_fc_matvec(k, R->A, a->d, a->tmp);
        double dn = sqrt(fmax(sf_fc_dot(k, a->d, a->tmp), 0.0));
        if (dn <= ASCENT_TOL * fmax(1.0, sqrt(fmax(-sf_fc_dot(k, R->b, a->g), 0.0)))) return 0;
        double w0 = sf_fc_dot(k, R->b, x);
        int moved = 0;
        for (int bt = 0; bt < 12 && !moved; bt++, step *= 0.5) {
            double *xn = a->tmp + k;   /* tmp has room for 2k */
            for (int i = 0; i < k; i++) xn[i] = x[i] + step * a->d[i] / dn;
            if (cone_project(R, xn, a) > CONE_TOL * 1e3) continue;
            if (sf_fc_dot(k, R->b, xn) < w0) {
                memcpy(x, xn, sizeof(double) * (size_t)k);
                moved = 1;
            }
        }
        if (!moved) return 1;
        step = fmin(0.2, step * 4.0);
    }
    return 1;
}

/* Polish the ray x (unit A norm, b . x < 0) at its best amplitude by
 * Newton on the reduced problem; v receives (x, nu').  0 when converged. */
static int ray_polish(const red *R, const double *x, double *v, double *F, double *Jm, double *d,
                      double *vt, double *tmp)
{
    int k = R->k, r = R->r;
    double lam = -sf_fc_dot(k, R->b, x);
    for (int i = 0; i < k; i++) v[i] = lam * x[i];
    if (r > 0) {
        for (int t = 0; t < r; t++) sf_fc_matvec(k, R->Q + (size_t)t * k * k, v, Jm + (size_t)t * k);
        sf_fc_matvec(k, R->A, v, d);
        for (int i = 0; i < k; i++) d[i] = -(d[i] + R->b[i]);
        if (sf_fc_lstsq(k, r, Jm, d)) return -1;
        memcpy(v + k, d, sizeof(double) * (size_t)r);
    }
    return sf_fc_red_newton(R, v, F, Jm, d, vt, tmp);
}

/* Keep the ray x (unit A norm, w = b . x < 0) as a degenerate one of c
 * (capacity c->degcap) unless it is there already. */
void sf_fc_deg_add(const red *R, const double *x, double w, sf_cone *c)
{
    int k = R->k, nq = R->nq;
    if (c->ndeg >= c->degcap) return;
    double *u = c->degu + (size_t)c->ndeg * nq, un = 0.0;
    for (int i = 0; i < nq; i++) {
        double vv = 0.0;
        for (int cc = 0; cc < k; cc++) vv += R->N[(size_t)cc * nq + i] * x[cc];
        u[i] = -w * vv;
        un = fmax(un, fabs(u[i]));
    }
    for (int j = 0; j < c->ndeg; j++) {
        const double *o = c->degu + (size_t)j * nq;
        double dm = 0.0;
        for (int i = 0; i < nq; i++) dm = fmax(dm, fabs(o[i] - u[i]));
        if (dm <= SAME_TOL * un) return;
    }
    c->degen[c->ndeg++] = -0.5 * w * w;
}

/* ASCENT_STARTS pseudo-random rays: onto the cone, up the work, polished;
 * the solutions are added to sols.  -1 when out of memory. */
int sf_fc_cone_search(const red *R, double a0, double *sols, double *en, int *ns, int nmax,
                       sf_cone *c, double *v, double *F, double *Jm, double *d, double *vt,
                       unsigned long long *st, int stall_ends)
{
    int k = R->k, r = R->r, m = r + 1, rc = -1, big = (k > m ? k : m) + 1;
    awork a;
    memset(&a, 0, sizeof a);
    a.Ainv = malloc(sizeof(double) * ((size_t)k * k + 1));
    a.C = malloc(sizeof(double) * ((size_t)m * k + 1));
    a.M = malloc(sizeof(double) * ((size_t)m * m + 1));
    a.g = malloc(sizeof(double) * (size_t)big);
    a.d = malloc(sizeof(double) * (size_t)big);
    a.mu = malloc(sizeof(double) * (size_t)big);
    a.xt = malloc(sizeof(double) * ((size_t)k * m + 1));
    a.h = malloc(sizeof(double) * (size_t)big);
    a.tmp = malloc(sizeof(double) * (2 * (size_t)big));
    double *x = malloc(sizeof(double) * (size_t)big);
    int *ipiv = malloc(sizeof(int) * (size_t)big);
    double *Ac = malloc(sizeof(double) * ((size_t)k * k + 1));
    if (!a.Ainv || !a.C || !a.M || !a.g || !a.d || !a.mu || !a.xt || !a.h || !a.tmp || !x || !ipiv || !Ac)
        goto done;
    memcpy(Ac, R->A, sizeof(double) * (size_t)k * k);
    for (int j = 0; j < k; j++)
        for (int i = 0; i < k; i++) a.Ainv[(size_t)j * k + i] = i == j;
    int info;
    dgesv_(&k, &k, Ac, &k, ipiv, a.Ainv, &k, &info);
    if (info) goto done;
    for (int start = 0; start < ASCENT_STARTS; start++) {
        for (int i = 0; i < k; i++) x[i] = sf_fc_rnd(st);
        if (cone_project(R, x, &a) > CONE_TOL) continue;
        if (sf_fc_dot(k, R->b, x) > 0.0)
            for (int i = 0; i < k; i++) x[i] = -x[i];
        int ar = cone_ascend(R, x, &a, stall_ends);
        if (ar < 0) goto done;
        if (!(sf_fc_dot(k, R->b, x) < 0.0)) continue;
        int pr = ray_polish(R, x, v, F, Jm, d, vt, a.tmp);
        if (pr < 0) goto done;
        if (!pr) *ns = sf_fc_add_sol(R, v, a0, sols, en, *ns, nmax, &c->ncone, d, a.tmp);
        else if (ar == 1) {
            /* the ascent ended at a corner of the cone, where the limit
             * problem has no solution: a degenerate ray */
            c->ncone++;
            sf_fc_deg_add(R, x, sf_fc_dot(k, R->b, x), c);
        }
    }
    rc = 0;
done:
    free(a.Ainv); free(a.C); free(a.M); free(a.g); free(a.d); free(a.mu); free(a.xt);
    free(a.h); free(a.tmp); free(x); free(ipiv); free(Ac);
    return rc;
}

/* The rays (nq values each, directions of u) onto the cone, polished at
 * their best amplitude: a solution is added to sols; a ray of the cone on
 * which the reduced problem has no solution (degenerate) is kept in c's
 * deg fields.  -1 when out of memory. */
int sf_fc_rays_add(const sf_limit *L, const red *R, const double *rays, int nrays, double a0,
                    double *sols, double *en, int *ns, int nmax, sf_cone *c, double *v, double *F,
                    double *Jm, double *d, double *vt, double *tmp)
{
    int k = R->k, nq = L->nq;
    if (nrays <= 0) return 0;
    double *x = malloc(sizeof(double) * ((size_t)k + 1));
    if (!x) return -1;
    for (int j = 0; j < nrays; j++) {
        for (int i = 0; i < k; i++) x[i] = sf_fc_dot(nq, R->N + (size_t)i * nq, rays + (size_t)j * nq);
        sf_fc_anormalise(R, x, tmp);
        sf_fc_cone_eval(R, x, F, NULL, tmp);
        if (sf_fc_maxabs(F, R->r) > CONE_TOL * 1e3) continue;   /* not on the cone */
        if (sf_fc_dot(k, R->b, x) > 0.0)
            for (int i = 0; i < k; i++) x[i] = -x[i];
        double w = sf_fc_dot(k, R->b, x);
        if (!(w < 0.0)) continue;
        int pr = ray_polish(R, x, v, F, Jm, d, vt, tmp);
        if (pr < 0) { free(x); return -1; }
        if (!pr) {
            *ns = sf_fc_add_sol(R, v, a0, sols, en, *ns, nmax, &c->ncone, d, tmp);
        } else {
            /* degenerate: the driving pushes along a direction that the
             * cone blocks at higher order; kept at its best amplitude */
            c->ncone++;
            sf_fc_deg_add(R, x, w, c);
        }
    }
    free(x);
    return 0;
}

