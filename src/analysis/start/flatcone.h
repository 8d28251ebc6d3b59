/* flatcone.h - the branches that leave the flat state: the tangent cone of
 * the loop constraints and the driving's choice on it (see flatcone.c). */
#ifndef SF_FLATCONE_H
#define SF_FLATCONE_H

#include "flatstart.h"

/* The stationary rays of the limit problem (flatstart.h) found on the
 * tangent cone of the flat state.  In the kernel of the first-order rows,
 * u = N x (k = dim of the kernel), the second-order rows restricted to it
 * are r independent quadratic forms Q_t (their span; the others depend on
 * them), and the limit problem becomes
 *     (A + sum_t nu_t Q_t) x + b = 0,   x^T Q_t x / 2 = 0,
 * A = N^T H0 N (bending, positive definite), b = N^T gp (the driving).
 * Its solutions are the rays of the cone on which the energy
 * x^T A x / 2 + b . x is stationary: -(b . x)^2 / (2 x^T A x) at the best
 * scale.  A branch is stable when A + sum nu_t Q_t is positive definite on
 * the tangent space of the cone at x. */
typedef struct sf_cone {
    int k, r;            /* kernel dimension, independent quadratic forms */
    int ncone;           /* cone points found (before the driving) */
    double bnorm;        /* max |b|: the driving's first-order work */
    int nb;              /* distinct solutions with b . x < 0, sorted by energy */
    int n;               /* values per solution: the limit problem's n */
    double *z;           /* nb x n: (u, mu, nu) of the limit problem */
    double *energy;      /* nb: x^T A x / 2 + b . x (scaled by kref) */
    int *stable;         /* nb */
    double *resid;       /* nb: max-norm residual of the limit problem */
    /* Degenerate rays (sf_cone_find_rays): rays of the cone on which the
     * driving does work but the limit problem has no solution, because
     * the driving also pushes along a direction that the cone blocks at
     * higher order only (the prestress would grow like 1 / (p - p0)) */
    int ndeg, degcap;
    double *degu;        /* ndeg x nq: u at the ray's best amplitude */
    double *degen;       /* ndeg: its energy -(b . x)^2 / (2 x^T A x) */
} sf_cone;

/* Find the branches: a penalty descent (the second-order conditions as a
 * penalty of weight 1/eps, eps -> 0, Newton steps on the absolute
 * eigenvalues of the Hessian) from the unconstrained response -A^-1 b,
 * continued on both sides of every saddle met on the way (a symmetric
 * state that loses stability), then from nstarts - 1 pseudo-random starts
 * (fixed seed: reproducible); each polished by Newton on the reduced
 * problem.  zextra (L->n values or NULL): a solution of the limit problem
 * found otherwise (flatstart.c's eps homotopy), polished and added.
 * Needs c1 = 0 (no prescribed displacement of first order).  Returns 0,
 * -1 when out of memory or a LAPACK failure. */
int sf_cone_find(const sf_limit *L, int nstarts, const double *zextra, sf_cone *c);
void sf_cone_free(sf_cone *c);

/* The same, with nrays further candidate rays (nq values each: directions
 * of u, e.g. the branches of another driving, which has the same cone):
 * each is taken onto the cone's ray, signed so that the driving does
 * work, and polished; one on which the limit problem has no solution is
 * returned as a degenerate ray (ndeg, degu, degen). */
int sf_cone_find_rays(const sf_limit *L, int nstarts, const double *zextra, const double *rays,
                      int nrays, sf_cone *c);

/* The reduction onto the kernel of the first-order rows (steps 1-2 of
 * flatcone.c): u = N x, A = N^T H0 N, b = N^T gp, r independent unit
 * forms Q'_t spanning the Q_s = N^T G_s N, with nu = W nu'. */
typedef struct sf_cone_red {
    int nq, k, r, n1, n2;
    double *N;   /* nq x k, column-major */
    double *A;   /* k x k */
    double *b;   /* k */
    double *Q;   /* r forms k x k */
    double *W;   /* n2 x r, column-major */
} sf_cone_red;

/* Build it (0, or -1: out of memory or a LAPACK failure); free with
 * sf_cone_reduce_free.  sf_cone_to_limit: the limit problem's
 * z = (u, mu, nu) (L->n values) from v = (x, nu') (k + r), mu by least
 * squares on the stationarity rows with L's H0 and gp; 0 or -1. */
int sf_cone_reduce(const sf_limit *L, sf_cone_red *R);
void sf_cone_reduce_free(sf_cone_red *R);
int sf_cone_to_limit(const sf_limit *L, const sf_cone_red *R, const double *v, double *z);

/* The r second-order rows of a reduced limit problem (forms Q: r blocks
 * of k x k, column-major) added at (x, nu): F[0..k) += sum_t nu_t Q_t x,
 * F[k + t] = x^T Q_t x / 2, and, when Jm is not NULL, their blocks of the
 * n x n column-major Jacobian Jm (n >= k + r).  tmp: k values. */
void sf_cone_forms_add(int k, int r, const double *Q, const double *x, const double *nu,
                       double *F, double *Jm, int n, double *tmp);

/* Residual max-norm of the limit problem at z with eps = 0 (flatstart.c). */
double sf_limit_residual(const sf_limit *L, const double *z);

#endif
