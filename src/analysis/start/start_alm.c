/* start_alm.c - the closed state of a given amount of folding with the
 * least energy, by the method of multipliers (start_impl.h, start.h).
 *
 * The problem: minimise Pi(x; pm) subject to the constraint rows g(x) = 0
 * and one linear "control" l . x = target (the amount of folding), with
 * x the coordinates of the formulation.  Its multiplier mu is, for the
 * driving's own control, the change of the path parameter (l = dF/dp at
 * the flat state, so that the stationarity condition at p = p0 + mu is
 * the equilibrium itself), and for a pinned fold the moment that holds it.
 *
 * The method of multipliers (Hestenes 1969, Powell 1969; Nocedal and
 * Wright, Numerical Optimization, ch. 17) minimises the augmented
 * Lagrangian
 *     Phi(x) = Pi(x) + lam_a . g + sum_r g_r^2 / (2 eps w_r)
 * on the control's hyperplane, then moves the anchor lam_a to the new
 * multipliers lam = lam_a + g / (eps w) and repeats, stiffening eps by 10
 * when the residual did not fall by 4.  Its first step, from the flat
 * sheet with lam_a = 0, is the sheet with compliant loops; each later step
 * makes the loops closer to rigid.  The inner minimisation is Newton's
 * method on the stationarity conditions
 *     F(x, lam; p) = 0  with the rows  g - eps w (lam - lam_a) = 0,
 *     l . x = target,
 * which are the equilibrium problem's own residual with its proximal
 * anchor (equilibrium.h), so the matrix is its Jacobian, regular for any
 * eps > 0 even where rows are redundant.  Each Newton matrix is checked
 * for the inertia of a minimum (m + 1 negative pivots: one per
 * constraint row and one for the control) and shifted on its coordinate
 * block until it has it (Wachter and Biegler 2006, the inertia correction
 * of IPOPT), which makes the step a descent direction of Phi; a
 * backtracking line search on Phi (Armijo) keeps it one.  Where the
 * minimisation ends at a stationary point that is not a minimum (a
 * symmetric driving holding the sheet on a saddle), the direction of
 * negative curvature is found by inverse iteration on the shifted factors
 * and taken with a sign fixed by the sheet's fold order, not by
 * round-off.  The curvature decides, not the pivot count: where inverse
 * iteration finds none negative, the point is a minimum whatever the
 * count (with rows 1/eps times stiffer than the folds, round-off can turn
 * a pivot's sign). */
#include "start_impl.h"
#include "start.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SHIFT_FIRST 1e-4     /* first inertia correction (scaled units) */
#define SHIFT_MAX 1e12
#define INNER_MAX 60         /* Newton iterations per minimisation */
#define NEWTON_MAX 600       /* in all */
#define EPS_FIRST 1e-3        /* the first proximal weight: loops 1000 times stiffer than folds */
#define EPS_MIN 1e-13
#define ARMIJO 1e-4
#define INVIT 40             /* inverse iterations for negative curvature */

static double maxabs(const double *v, int n)
{
    double m = 0.0;
    for (int i = 0; i < n; i++) m = fmax(m, fabs(v[i]));
    return m;
}

/* The path parameter at which the equations are evaluated. */
static double eval_p(const fs_control *c, double mu)
{
    return c->kind == FS_PARAM ? c->p0 + mu : c->p0;
}

/* The control's value at y: row . x for a pinned fold; for the driving
 * the work function Psi(x) = Pi(x; p0 + 1) - Pi(x; p0), whose gradient
 * is dF/dp (forces affine in p: loads within a stage, rest angles), so
 * that the stationarity of Phi + mu (Psi - target) is the equilibrium at
 * p0 + mu exactly. */
static double control_value(fs_kkt *k, const fs_control *c, const double *y)
{
    if (c->kind == FS_FIXED) return 0.0;
    if (c->kind == FS_PIN) {
        double r = 0.0;
        for (int i = 0; i < k->nx; i++) r += c->row[i] * y[i];
        return r;
    }
    double a, b, rr, rt;
    sf_equil_report(k->q, y, c->p0 + 1.0, &a, &rr, &rt);
    sf_equil_report(k->q, y, c->p0, &b, &rr, &rt);
    return a - b;
}

/* Residual of the inner problem in scaled units: R (n values) and the
 * control's row (returned).  y physical, with q's anchor set. */
static int residual(fs_kkt *k, const fs_control *c, const double *y, double mu, double *R,
                    double *rrow, double *rnorm)
{
    sf_equil *q = k->q;
    if (sf_equil_residual(y, eval_p(c, mu), R, q)) return SF_ENUMERIC;
    if (c->kind == FS_PIN)
        for (int i = 0; i < k->nx; i++) R[i] += mu * c->row[i];
    double r = control_value(k, c, y) - c->target;
    /* the size of the residual as the equilibrium's Newton test measures it */
    double rn = 0.0;
    for (int i = 0; i < k->n; i++) {
        rn = fmax(rn, fabs(R[i] * q->fscale[i]));
        R[i] *= k->S[i];
    }
    *rnorm = rn;
    *rrow = r;
    return SF_OK;
}

/* The constraint rows g at x (physical): from the residual at lam = lam_a. */
static int rows_at(fs_kkt *k, const fs_control *c, const double *y, double mu, double *ya,
                   double *F)
{
    sf_equil *q = k->q;
    memcpy(ya, y, sizeof(double) * (size_t)k->nx);
    memcpy(ya + k->nx, q->lam_anchor, sizeof(double) * (size_t)k->m);
    return sf_equil_residual(ya, eval_p(c, mu), F, q) ? SF_ENUMERIC : SF_OK;
}

/* The merit Phi at x and, when grad is not NULL, its gradient (nx). */
static int merit(fs_kkt *k, const fs_control *c, const double *y, double mu, double *ya,
                 double *F, double *phi, double *grad)
{
    sf_equil *q = k->q;
    int nx = k->nx, m = k->m;
    double pm = c->p0, Pi, rr, rt;
    if (rows_at(k, c, y, mu, ya, F)) return SF_ENUMERIC;
    double eps = q->eps_anchor, v = 0.0;
    for (int r = 0; r < m; r++) {
        double g = F[nx + r], w = sf_equil_row_eps(q, 1.0, r) * q->yscale[nx + r] / q->fscale[nx + r];
        v += q->lam_anchor[r] * g + g * g / (2.0 * eps * w);
        ya[nx + r] = q->lam_anchor[r] + g / (eps * w);   /* the multipliers Phi implies */
    }
    sf_equil_report(q, ya, pm, &Pi, &rr, &rt);
    *phi = Pi + v;
    if (!grad) return SF_OK;
    /* grad Phi = grad Pi + C^T (lam_a + g / (eps w)): the coordinate rows of
     * F at those multipliers (the anchor terms touch only the other rows) */
    if (sf_equil_residual(ya, pm, F, q)) return SF_ENUMERIC;
    memcpy(grad, F, sizeof(double) * (size_t)nx);
    (void)mu;
    return SF_OK;
}

/* Solve the bordered system [K0 lh; lh^T 0] [dy; dnu] = [b; rb] with the
 * factors of K0 (b overwritten by dy, scaled).  a: scratch (n) holding
 * K0^-1 lh on return; *dnu the border's unknown; *schur = -lh . a. */
static int bordered_solve(fs_kkt *k, const double *lh, double *a, double *b, double rb,
                          double *dnu, double *schur, sf_error *err)
{
    int n = k->n;
    memset(a, 0, sizeof(double) * (size_t)n);
    memcpy(a, lh, sizeof(double) * (size_t)k->nx);
    if (fs_kkt_solve(k, a, err) || fs_kkt_solve(k, b, err)) return err->code ? err->code : SF_ENUMERIC;
    double la = 0.0, lb = 0.0;
    for (int i = 0; i < k->nx; i++) {
        la += lh[i] * a[i];
        lb += lh[i] * b[i];
    }
    *schur = -la;
    if (la == 0.0 || !isfinite(la)) return SF_ENUMERIC;
    *dnu = (lb - rb) / la;
    for (int i = 0; i < n; i++) b[i] -= a[i] * *dnu;
    return SF_OK;
}

/* Factorise with the smallest shift (0 or SHIFT_FIRST * 8^j) that gives
 * the inertia of a minimum; *shift in and out (the last one used, as a
 * hint).  a: scratch for the Schur complement test. */
static int factor_inertia(fs_kkt *k, const fs_control *c, const double *lh, double *a,
                          double *b, double *shift, int *shifted, sf_error *err)
{
    int target = k->m + (c->kind == FS_FIXED ? 0 : 1);
    double s = 0.0, hint = *shift;
    for (int tries = 0; tries < 60; tries++) {
        int rc = fs_kkt_factor(k, s, err);
        if (rc == SF_ENOMEM) return rc;
        int neg = k->neg;
        if (rc == SF_OK && c->kind != FS_FIXED) {
            double dnu, schur;
            memset(b, 0, sizeof(double) * (size_t)k->n);
            rc = bordered_solve(k, lh, a, b, 0.0, &dnu, &schur, err);
            if (rc == SF_ENOMEM) return rc;
            if (rc == SF_OK) neg += schur < 0.0;
        }
        if (rc == SF_OK && neg == target) {
            *shift = s;
            *shifted = s > 0.0;
            return SF_OK;
        }
        s = s == 0.0 ? (hint > 0.0 ? hint / 3.0 : SHIFT_FIRST) : s * 8.0;
        if (s > SHIFT_MAX) break;
    }
    return sf_fail(err, SF_ENUMERIC, "flat start: no inertia correction up to %g makes the "
                   "Newton matrix that of a minimum", SHIFT_MAX);
}

/* The sign that the sheet's fold order gives to a direction v (scaled,
 * nx coordinates): + when the first fold coordinate of magnitude at least
 * 1e-2 of the largest is positive. */
static double canonical_sign(const fs_kkt *k, const double *v)
{
    const sf_model *m = k->q->m;
    double big = 0.0;
    for (int f = 0; f < m->nfolds; f++) big = fmax(big, fabs(v[m->qoff[f]] * k->S[m->qoff[f]]));
    for (int f = 0; f < m->nfolds; f++) {
        double x = v[m->qoff[f]] * k->S[m->qoff[f]];
        if (fabs(x) >= 1e-2 * big && big > 0.0) return x > 0.0 ? 1.0 : -1.0;
    }
    return 1.0;
}

/* Direction of negative curvature at a saddle of Phi on the hyperplane,
 * by inverse iteration on the shifted factors (which hold the matrix
 * shifted by -sigma, sigma = -shift, below the lowest eigenvalue of the
 * pencil (K0, diag(I, 0)) restricted to the hyperplane).  v receives the
 * scaled direction (n values, coordinates normalised to max 1); returns
 * its Rayleigh quotient, +inf on failure.  The start vector is a fixed
 * sequence, so the result does not depend on the run. */
static double negative_curvature(fs_kkt *k, const double *lh, double *a, double *v, double *w,
                                 sf_error *err)
{
    int n = k->n, nx = k->nx;
    for (int i = 0; i < n; i++) v[i] = i < nx ? 1.0 + 0.5 * sin(1.0 + 1.7 * i) : 0.0;
    double rq = INFINITY;
    for (int it = 0; it < INVIT; it++) {
        memset(w, 0, sizeof(double) * (size_t)n);
        memcpy(w, v, sizeof(double) * (size_t)nx);
        double dnu, schur;
        if (bordered_solve(k, lh, a, w, 0.0, &dnu, &schur, err)) return INFINITY;
        double mx = maxabs(w, nx);
        if (!(mx > 0.0)) return INFINITY;
        for (int i = 0; i < n; i++) v[i] = w[i] / mx;
    }
    /* Rayleigh quotient with the unshifted matrix, coordinates only */
    fs_kkt_matvec(k, v, w);
    double num = 0.0, den = 0.0;
    for (int i = 0; i < n; i++) num += v[i] * w[i];
    for (int i = 0; i < nx; i++) den += v[i] * v[i];
    rq = den > 0.0 ? num / den : INFINITY;
    return rq;
}

int fs_alm(fs_kkt *k, const fs_control *c, double *y, double *mu, int branch, double tol,
           fs_alm_result *res, sf_error *err)
{
    sf_equil *q = k->q;
    int n = k->n, nx = k->nx, m = k->m;
    memset(res, 0, sizeof *res);
    double *R = malloc(sizeof(double) * ((size_t)n + 1));
    double *F = malloc(sizeof(double) * ((size_t)n + 1));
    double *ya = malloc(sizeof(double) * ((size_t)n + 1));
    double *yt = malloc(sizeof(double) * ((size_t)n + 1));
    double *a = malloc(sizeof(double) * ((size_t)n + 1));
    double *d = malloc(sizeof(double) * ((size_t)n + 1));
    double *grad = malloc(sizeof(double) * ((size_t)nx + 1));
    double *lh = malloc(sizeof(double) * ((size_t)nx + 1));
    if (!q->lam_anchor) q->lam_anchor = calloc((size_t)m + 1, sizeof(double));
    int rc = SF_OK;
    if (!R || !F || !ya || !yt || !a || !d || !grad || !lh || !q->lam_anchor) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto done;
    }
    /* the control's row in scaled coordinates, normalised */
    double beta = 0.0;
    for (int i = 0; c->row && i < nx; i++) beta = fmax(beta, fabs(c->row[i] * k->S[i]));
    if (!(beta > 0.0)) beta = 1.0;
    for (int i = 0; i < nx; i++) lh[i] = c->row ? c->row[i] * k->S[i] / beta : 0.0;
    memcpy(q->lam_anchor, y + nx, sizeof(double) * (size_t)m);
    double eps = c->eps0 > 0.0 ? c->eps0 : EPS_FIRST, gprev = INFINITY, shift = 0.0;
    int saddles = 0, stall = 0, stuck = 0;
    for (int outer = 0; rc == SF_OK; outer++) {
        q->eps_anchor = eps;
        res->outer = outer + 1;
        int conv = 0;
        for (int it = 0; it < INNER_MAX && res->newton < NEWTON_MAX; it++) {
            double rrow, rn;
            /* equations that cannot be evaluated at the iterate (a pose
             * turned beyond the rotation chart): blocked too */
            if (residual(k, c, y, *mu, R, &rrow, &rn)) { stuck = 1; break; }
            if (c->kind != FS_FIXED) rn = fmax(rn, fabs(rrow) / beta);
            /* inner tolerance: loose while the rows are far from closed */
            double itol = fmax(tol, fmin(1e-6, 1e-2 * gprev));
            if ((rc = fs_kkt_eval(k, y, eval_p(c, *mu), err))) break;
            if (c->kind == FS_PARAM)   /* the gradient of Psi at x */
                for (int i = 0; i < nx; i++) lh[i] = k->Fp[i] * k->S[i] / beta;
            int shifted = 0;
            if ((rc = factor_inertia(k, c, lh, a, d, &shift, &shifted, err))) {
                /* no shift makes the subproblem convex here: the
                 * constraints' curvature, weighted by multipliers that grow
                 * like 1 / eps where the rows cannot close, exceeds any
                 * shift (the crane at K = 2: Hessian entries of 1e13).  The
                 * minimisation is blocked, as when eps reaches its floor. */
                if (rc == SF_ENUMERIC) {
                    sf_error_clear(err);
                    rc = SF_OK;
                    stuck = 1;
                }
                break;
            }
            if (rn <= itol) {
                if (!shifted) { conv = 1; break; }
                /* a saddle: leave it along negative curvature */
                double rq = negative_curvature(k, lh, a, d, yt, err);
                /* no negative curvature: a minimum whose pivots' signs the
                 * round-off of rows 1/eps times stiffer than the folds
                 * miscounted (the 2x2 waterbomb in poses at eps = 1e-12:
                 * a shift of 1e-4 asked for, lowest curvature +0.0071) */
                if (isfinite(rq) && rq >= 0.0) { conv = 1; break; }
                if (!(rq < 0.0) || ++saddles > 4) {
                    rc = sf_fail(err, SF_ENUMERIC, "flat start: a stationary point that is not "
                                 "a minimum, and no direction of negative curvature found");
                    break;
                }
                res->saddle = 1;
                double sg = canonical_sign(k, d) * (branch == 2 ? -1.0 : 1.0);
                double amp = 0.0, vmax = 0.0;
                for (int f = 0; f < q->m->nfolds; f++) {
                    int i = q->m->qoff[f];
                    amp = fmax(amp, fabs(y[i]));
                    vmax = fmax(vmax, fabs(d[i] * k->S[i]));
                }
                double t = 0.5 * fmax(amp, 1e-3) / vmax;
                for (int i = 0; i < nx; i++) y[i] += sg * t * d[i] * k->S[i];
                continue;
            }
            /* Newton step on the bordered system, scaled */
            for (int i = 0; i < n; i++) d[i] = -R[i];
            double dnu = 0.0, schur;
            if (c->kind == FS_FIXED) rc = fs_kkt_solve(k, d, err);
            else rc = bordered_solve(k, lh, a, d, -rrow / beta, &dnu, &schur, err);
            if (rc) break;
            res->newton++;
            /* Armijo on Phi + rho |row . x - target| (an exact penalty for the
             * control, rho above its multiplier) along the step */
            double phi0;
            if ((rc = merit(k, c, y, *mu, ya, F, &phi0, grad))) break;
            double rho = c->kind == FS_FIXED ? 0.0 : 1.5 * fabs(*mu + dnu / beta) + 1e-12;
            double slope = -rho * fabs(rrow);
            for (int i = 0; i < nx; i++) slope += grad[i] * d[i] * k->S[i];
            if (!(slope < 0.0)) slope = 0.0;
            phi0 += rho * fabs(rrow);
            double t = 1.0, phi = phi0;
            for (int ls = 0; ls < 40; ls++, t *= 0.5) {
                for (int i = 0; i < n; i++) yt[i] = y[i] + t * d[i] * k->S[i];
                double rt = control_value(k, c, yt) - c->target;
                int okm = merit(k, c, yt, *mu + t * dnu / beta, ya, F, &phi, NULL) == SF_OK;
                if (okm && phi + rho * fabs(rt) <= phi0 + ARMIJO * t * slope) break;
                /* near the solution Phi's decrease drowns in its round-off
                 * (its terms g^2 / eps grow as eps falls): a step that
                 * halves the residual is taken too (the matrix already has
                 * the inertia of a minimum) */
                double rrt, rnt;
                if (okm && residual(k, c, yt, *mu + t * dnu / beta, R, &rrt, &rnt) == SF_OK &&
                    fmax(rnt, c->kind == FS_FIXED ? 0.0 : fabs(rrt) / beta) <= 0.5 * rn)
                    break;
            }
            memcpy(y, yt, sizeof(double) * (size_t)n);
            *mu += t * dnu / beta;
        }
        if (rc) break;
        /* the constraint residual (scaled rows), with the anchor moved */
        if (rows_at(k, c, y, *mu, ya, F)) {
            res->gres = INFINITY;
            res->blocked = 1;
            break;
        }
        double gres = 0.0;
        for (int r = 0; r < m; r++) gres = fmax(gres, fabs(F[nx + r] * q->fscale[nx + r]));
        res->gres = gres;
        res->eps = eps;
        memcpy(q->lam_anchor, y + nx, sizeof(double) * (size_t)m);
        if (stuck) { res->blocked = 1; break; }
        /* closed to half the Newton tolerance: the engine takes the point
         * as it is (where rows are nearly dependent its corrector does not
         * close them further from ten times the tolerance, measured on the
         * 3x3 Miura in poses) */
        if (conv && gres <= 0.5 * tol) { res->closed = 1; break; }
        /* a floor of round-off: the residual stays put, small, with the loops
         * already much stiffer than the folds */
        stall = conv && gres <= 1e-6 && gres > 0.5 * gprev && eps <= 1e-8 ? stall + 1 : 0;
        if (stall >= 3) { res->closed = 1; break; }
        if (res->newton >= NEWTON_MAX) break;
        if (!conv || gres > 0.25 * gprev) eps *= 0.1;
        gprev = fmin(gprev, gres);
        if (eps < EPS_MIN) { res->blocked = 1; break; }
    }
done:
    q->eps_anchor = 0.0;
    free(R); free(F); free(ya); free(yt); free(a); free(d); free(grad); free(lh);
    return rc;
}
