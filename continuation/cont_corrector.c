/* cont_corrector.c - the corrector (cont.h, ALGORITHM): KINSOL's Newton
 * on F(y, p) = 0 bordered by c.(x - xa) = sig, with the Jacobian of the
 * bordered system, or the engine's own reusing Newton; with a problem's
 * regularisation (cont_regularise_fn) on its regularised equations, the
 * point accepted by the plain ones; Newton at fixed p (cont_solve_fixed). */
#include "cont_impl.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define REFINE_MAX 10      /* refinements of a solve with reused factors */
#define REFINE_TOL 1e-10   /* their relative accuracy */
#define REFINE_FLOOR 1e-7  /* accepted when they stall there (rounding) */

int ci_kin_sys(N_Vector uv, N_Vector fv, void *data)
{
    cont_solver *s = data;
    long n = s->n;
    double *u = N_VGetArrayPointer(uv), *f = N_VGetArrayPointer(fv);
    if (!ci_all_finite(u, n + 1)) {
        ci_why(s, "Newton iterate became non-finite");
        s->last_fnorm = NAN;
        return -1;
    }
    if (ci_call_residual(s, u, u[n], f) != 0) return -1;
    double g = -s->bsig;
    for (long i = 0; i <= n; i++) g += s->bc[i] * (u[i] - s->bxa[i]);
    f[n] = g;
    s->kin_fs = ci_fscaled_max(s, f, n);
    if (s->att_track) s->att_fsmin = fmin(s->att_fsmin, s->kin_fs);
    return 0;
}

int ci_kin_jac(N_Vector uv, N_Vector fv, SUNMatrix J, void *data,
               N_Vector t1, N_Vector t2)
{
    (void)fv; (void)t1; (void)t2;
    cont_solver *s = data;
    double *u = N_VGetArrayPointer(uv);
    if (s->ulast) memcpy(s->ulast, u, (size_t)s->m * sizeof(double));
    if (ci_call_jacobian(s, u, u[s->n]) != 0) return -1;
    if (J != s->bk.A) return -1;
    if (ci_bm_build(s, &s->bk, s->bc) != 0) return -1;
    s->stp.nfactor++;      /* KINSOL factorises after every Jacobian */
    return 0;
}

void ci_kin_err(int code, const char *module, const char *function,
                char *msg, void *data)
{
    (void)code;
    cont_solver *s = data;
    snprintf(s->kin_msg, sizeof s->kin_msg, "%s/%s: %s", module, function, msg);
}

/* max_i |fscale_i f_i| over the first len rows: the residual test of the
 * corrector (KINSOL's own scaled max norm). */
double ci_fscaled_max(const cont_solver *s, const double *f, long len)
{
    double fs = 0.0;
    for (long i = 0; i < len; i++) fs = fmax(fs, fabs(f[i] * NV_Ith_S(s->fscale, i)));
    return fs;
}

static double scaled_norm2(const cont_solver *s, const double *v)
{
    double r = 0.0;
    for (long i = 0; i < s->m; i++) {
        double a = v[i] * NV_Ith_S(s->uscale, i);
        r += a * a;
    }
    return sqrt(r);
}

/* The norm of the Newton step test: KINSOL's scaled 2-norm, restricted by
 * the norm weights when cont_set_weights gave them (a component left out
 * of the arclength, e.g. a multiplier of a nearly redundant constraint, is
 * then not required to settle to xtol: it is slaved to the others). */
static double step_norm2(const cont_solver *s, const double *v)
{
    if (!s->wy) return scaled_norm2(s, v);
    double r = 0.0;
    for (long i = 0; i < s->m; i++) {
        double a = v[i] * NV_Ith_S(s->uscale, i);
        r += a * a * (i < s->n ? s->wy[i] : 1.0);
    }
    return sqrt(r);
}

/* Further exact Newton iterations on the corrector system (border s->bc,
 * s->bxa, s->bsig) at u, with the engine's own bordered factorisation,
 * until the scaled step is <= xtol (1 + |u|).  0 ok, -1 failed. */
static int polish(cont_solver *s, double *u, int *iters)
{
    long n = s->n, m = s->m;
    for (int k = 0; k < 5; k++) {
        double *b = N_VGetArrayPointer(s->vb);
        if (ci_call_residual(s, u, u[n], b) != 0) return -1;
        double g = -s->bsig;
        for (long i = 0; i <= n; i++) g += s->bc[i] * (u[i] - s->bxa[i]);
        b[n] = g;
        for (long i = 0; i < m; i++) b[i] = -b[i];
        if (ci_call_jacobian(s, u, u[n]) != 0 || ci_bm_build(s, &s->bt, s->bc) != 0 ||
            ci_bm_factor(s, &s->bt, NULL, NULL) != 0 || ci_bm_solve(s, &s->bt, s->vx, s->vb) != 0)
            return -1;
        double *d = N_VGetArrayPointer(s->vx);
        for (long i = 0; i < m; i++) u[i] += d[i];
        (*iters)++;
        s->stp.newton_iters++;
        if (step_norm2(s, d) <= s->xtol * (1.0 + step_norm2(s, u))) return 0;
    }
    ci_why(s, "Newton converges too slowly (near a singular point?): the step is still "
        "above xtol = %.3g after 5 extra iterations", s->xtol);
    return -1;
}

/* KINSOL's Newton on F(x) = 0, c.(x - xa) = sig from the guess x
 * (overwritten with the solution on success).  0 ok, -1 failed (reason in
 * s->why). */
static int kin_correct(cont_solver *s, double *x, const double *c, const double *xa,
                       double sig, int maxit, int strategy, int *nit, double *fnorm)
{
    long m = s->m;
    int track = s->att_track;   /* a step attempt's plain Newton (ci_correct_step) */
    s->att_track = 0;
    s->rgen = -1;
    memcpy(s->bc, c, (size_t)m * sizeof(double));
    memcpy(s->bxa, xa, (size_t)m * sizeof(double));
    s->bsig = sig;
    memcpy(N_VGetArrayPointer(s->u), x, (size_t)m * sizeof(double));
    s->why[0] = '\0';
    s->kin_msg[0] = '\0';
    s->kin_fs = s->fail_fs = NAN;
    KINSetNumMaxIters(s->kmem, maxit);
    KINSetFuncNormTol(s->kmem, s->ftol);
    KINSetScaledStepTol(s->kmem, 1e-15);
    s->att_track = track;
    int flag = KINSol(s->kmem, s->u, strategy, s->uscale, s->fscale);
    s->att_track = 0;
    long nni = 0;
    KINGetNumNonlinSolvIters(s->kmem, &nni);
    s->stp.newton_iters += nni;
    s->stp.nlinsolve += nni;
    if (nit) *nit = (int)nni;
    double *u = N_VGetArrayPointer(s->u);
    /* KIN_LINESEARCH_NONCONV: the line search found no decrease; next to a
     * singular point that happens at a residual already at the tolerance,
     * so it is judged by the final check below like a stagnation */
    int ok = (flag >= 0 || flag == KIN_LINESEARCH_NONCONV) && ci_all_finite(u, m);
    if (ok && nni >= 1 && s->xtol > 0) {
        /* a small residual is not enough where F is flat (near singular
         * points): also require a small last Newton step */
        double sl = 0.0;
        if (s->wy && s->ulast) {
            for (long i = 0; i < m; i++) s->w1[i] = u[i] - s->ulast[i];
            sl = step_norm2(s, s->w1);
        } else {
            KINGetStepLength(s->kmem, &sl);
        }
        if (sl > s->xtol * (1.0 + step_norm2(s, u))) {
            int extra = 0;
            if (polish(s, u, &extra) != 0) ok = 0;
            if (nit) *nit += extra;
        }
    }
    if (ok) {
        /* the residual at the returned point, unscaled, and a final check */
        if (ci_call_residual(s, u, u[s->n], s->w1) != 0) ok = 0;
        else {
            double fs = 0.0;
            for (long i = 0; i < s->n; i++) {
                double a = fabs(s->w1[i] * NV_Ith_S(s->fscale, i));
                if (a > fs) fs = a;
            }
            /* KIN_STEP_LT_STPTOL: stagnation; accept only near the tolerance */
            double lim = flag == KIN_STEP_LT_STPTOL ? 100.0 * s->ftol : 10.0 * s->ftol;
            if (flag == KIN_LINESEARCH_NONCONV && fs > lim) {
                char *name = KINGetReturnFlagName(flag);
                ci_why(s, "KINSOL %s after %ld iterations, scaled residual %.3g > %.3g",
                    name ? name : "failure", nni, fs, lim);
                free(name);
                ok = 0;
            } else if (fs > lim) {
                ci_why(s, "Newton stagnated with scaled residual %.3g > %.3g", fs, lim);
                ok = 0;
            }
            if (!ok) s->fail_fs = fs;
        }
    } else if (s->why[0] == '\0') {
        char *name = KINGetReturnFlagName(flag);
        ci_why(s, "KINSOL %s after %ld iterations, residual norm %.3g%s%s",
            name ? name : "failure", nni, s->last_fnorm,
            s->kin_msg[0] ? ": " : "", s->kin_msg);
        free(name);
        s->fail_fs = s->kin_fs;
    }
    if (fnorm) *fnorm = s->last_fnorm;
    if (!ok) return -1;
    memcpy(x, u, (size_t)m * sizeof(double));
    return 0;
}

static int refine_solve(cont_solver *s, const double *c, const double *rhs, double *x,
                        double tol);

static int reuse_newton(cont_solver *s, double *x, const double *c, const double *xa,
                        double sig, int maxit, int monotone, int have, int *nit, double *fnorm);

/* One step attempt's Newton: the reusing corrector (from the factors of
 * the last iterate where s->reg_have says they fit), then KINSOL's from
 * the same guess. */
static int step_newton(cont_solver *s, double *x, const double *c, const double *xa, double sig,
                       int maxit, int strategy, int *nit, double *fnorm)
{
    if (strategy == KIN_NONE) {
        s->att_track = 1;
        int r = reuse_newton(s, x, c, xa, sig, maxit, 0, s->reg_have, nit, fnorm);
        s->att_track = 0;
        if (r == 0) return 0;
    }
    s->att_track = 1;
    int r = kin_correct(s, x, c, xa, sig, maxit, strategy, nit, fnorm);
    s->att_track = 0;
    return r;
}

/* Newton at fixed p from a guess: the reusing corrector first (the
 * symmetric block elimination where Jy is symmetric): from a good guess,
 * such as the flat start's first point, it converges in a few iterations,
 * while KINSOL's linear solver factorises the bordered matrix by
 * unsymmetric LU, whose delayed pivots make it grow as about n^3 on the
 * pose formulation (Miura 20x20: 46 s); KINSOL with the start's strategy,
 * from the unchanged guess, when it does not converge.  c = e_p, xa = the
 * guess. */
static int fixed_newton(cont_solver *s, double *x, const double *c, const double *xa, double sig,
                        int maxit, int strategy, int *nit, double *fnorm)
{
    (void)strategy;
    return reuse_newton(s, x, c, xa, sig, maxit, s->init_strategy != KIN_NONE, s->reg_have, nit,
                        fnorm) == 0
               ? 0
               : kin_correct(s, x, c, xa, sig, maxit, s->init_strategy, nit, fnorm);
}

typedef int (*newton_fn)(cont_solver *s, double *x, const double *c, const double *xa,
                         double sig, int maxit, int strategy, int *nit, double *fnorm);

/* The corrector with the problem's regularisation (cont_regularise_fn):
 * the regularisation from the base point xa, Newton on F_delta, then
 * multiplier updates (anchored at the point, Newton again from it with
 * the same factors) while they lower the plain residual by half, at most
 * CONT_REG_UPDATES, and the point accepted where the plain residual meets
 * ftol; otherwise a smaller regularisation and the same again from there,
 * up to CONT_REG_ROUNDS times.  *nit counts the Newton iterations before the
 * updates (the measure of a step's difficulty; the updates' iterations
 * are in the statistics).  Without a regularisation, newton alone.  0 ok
 * (x the point), -1 failed (x as given, reason in s->why). */
static int regularised(cont_solver *s, newton_fn newton, double *x, const double *c,
                       const double *xa, double sig, int maxit, int strategy, int *nit,
                       double *fnorm)
{
    long n = s->n, m = s->m;
    s->reg_fs = NAN;
    s->reg_changed = 0;
    if (!s->prob.regularise) return newton(s, x, c, xa, sig, maxit, strategy, nit, fnorm);
    void *u = s->prob.user;
    double *x0 = malloc((size_t)m * sizeof(double)), *xu = malloc((size_t)m * sizeof(double));
    /* xu: the point before the last multiplier update */
    double *f = malloc((size_t)n * sizeof(double));
    if (!x0 || !xu || !f) {
        free(x0);
        free(xu);
        free(f);
        ci_why(s, "out of memory");
        return -1;
    }
    memcpy(x0, x, (size_t)m * sizeof(double));
    int total = 0, r = s->prob.regularise(xa, xa[n], s->ftol, CONT_REG_SET, NULL, u) ? -1 : 0;
    if (r) ci_why(s, "the problem's regularisation failed at the base point");
    for (int round = 0; r == 0; round++) {
        int k = 0;
        r = newton(s, x, c, xa, sig, maxit, strategy, &k, fnorm);
        total += k;
        if (r && round == 0) {
            /* the penalty's multipliers g / delta are far from the guess's
             * where the guess leaves nearly dependent rows open: the
             * method of multipliers from the guess's multipliers instead */
            memcpy(x, x0, (size_t)m * sizeof(double));
            if (s->prob.regularise(x, x[n], s->ftol, CONT_REG_ANCHOR, NULL, u) == 0) {
                r = newton(s, x, c, xa, sig, maxit, strategy, &k, fnorm);
                total += k;
            }
        }
        if (r) break;
        /* multiplier updates, while they contract (each removes the
         * penalty's bias where the problem resolves the constraints, and
         * a share of the rest), at most CONT_REG_UPDATES; a failed one
         * keeps the point before */
        double fs = INFINITY;
        for (int up = 0;; up++) {
            if (s->prob.regularise(x, x[n], s->ftol, CONT_REG_PLAIN, f, u) != 0) {
                ci_why(s, "the plain residual could not be evaluated at the corrected point");
                r = -1;
                break;
            }
            double fu = ci_fscaled_max(s, f, n);
            if (up > 0 && !(fu < 0.5 * fs)) {   /* no longer contracting: the point before */
                memcpy(x, xu, (size_t)m * sizeof(double));
                break;
            }
            fs = fu;
            /* on while they contract, below ftol too: where the problem
             * resolves the constraints they close to round-off */
            if (fs <= 1e-3 * s->ftol || up == CONT_REG_UPDATES) break;
            memcpy(xu, x, (size_t)m * sizeof(double));
            int have = s->rgen == s->bt.gen && s->rgen >= 0;   /* the last iterate's factors */
            if (s->prob.regularise(x, x[n], s->ftol, CONT_REG_ANCHOR, NULL, u) != 0) break;
            s->reg_have = have;   /* the Jacobian does not depend on the anchor */
            int ok = newton(s, x, c, xa, sig, maxit, strategy, &k, NULL) == 0;
            s->reg_have = 0;
            if (!ok) {
                memcpy(x, xu, (size_t)m * sizeof(double));
                break;
            }
        }
        if (r) break;
        if (fs <= s->ftol) break;
        s->reg_fs = fs;
        if (round == CONT_REG_ROUNDS ||
            s->prob.regularise(x, x[n], s->ftol, CONT_REG_TIGHTEN, NULL, u) != 0) {
            /* nothing to tighten at the first round: the plain Newton's own acceptance
             * (kin_correct: ten times the tolerance where it stagnates)
             * stands, as without a regularisation */
            if (round == 0 && fs <= 10.0 * s->ftol) break;
            ci_why(s, "the regularised equations were solved, the plain ones not: scaled "
                   "residual %.3g > %.3g after %d smaller regularisations", fs, s->ftol, round);
            s->fail_fs = fs;
            r = -1;
        } else {
            s->reg_changed = 1;
        }
    }
    if (nit) *nit = total;
    if (r) memcpy(x, x0, (size_t)m * sizeof(double));
    free(x0);
    free(xu);
    free(f);
    return r;
}

int ci_correct(cont_solver *s, double *x, const double *c, const double *xa, double sig,
               int maxit, int strategy, int *nit, double *fnorm)
{
    return regularised(s, kin_correct, x, c, xa, sig, maxit, strategy, nit, fnorm);
}

int ci_correct_step(cont_solver *s, double *x, const double *c, const double *xa, double sig,
                    int *nit, double *fnorm)
{
    s->att_fsmin = INFINITY;
    s->fail_fs = NAN;   /* not a stale value where a later check rejects the point */
    return regularised(s, step_newton, x, c, xa, sig, s->max_newton, s->strategy, nit, fnorm);
}

/* The corrector of CONT_CORRECTOR_REUSE (cont.h, ALGORITHM): Newton's
 * iteration on the corrector system with the engine's own bordered
 * factorisation (s->bt), one per iteration as with KINSOL, converged as
 * ci_correct: max|fscale F| <= ftol and the last step <= xtol (1 + |u|).
 * The factors of the last iterate stay in s->bt, marked (border c) for
 * ci_tangent_reuse.  monotone: every full step must lower max|fscale F|
 * (border row included) until it is at the tolerance, else the iteration
 * gives up (the caller's line search takes over from the unchanged guess).
 * 0: converged, x holds the point; 1: not used (option) or not converged,
 * x unchanged (the caller runs ci_correct). */
int ci_correct_reuse(cont_solver *s, double *x, const double *c, const double *xa,
                     double sig, int maxit, int monotone, int *nit, double *fnorm)
{
    return reuse_newton(s, x, c, xa, sig, maxit, monotone, 0, nit, fnorm);
}

/* ci_correct_reuse; have: start with the factors in s->bt (made for the
 * border c), refined against each iterate's matrix, instead of a new
 * factorisation at the first iterate */
static int reuse_newton(cont_solver *s, double *x, const double *c, const double *xa,
                        double sig, int maxit, int monotone, int have, int *nit, double *fnorm)
{
    long n = s->n, m = s->m;
    s->rgen = -1;
    if (s->corrector != CONT_CORRECTOR_REUSE) return 1;
    double *u = N_VGetArrayPointer(s->u), *b = N_VGetArrayPointer(s->vb);
    double *d = N_VGetArrayPointer(s->vx);
    memcpy(u, x, (size_t)m * sizeof(double));
    double dlast = HUGE_VAL, fsprev = HUGE_VAL;
    for (int k = 0;; k++) {
        if (ci_call_residual(s, u, u[n], b) != 0) return 1;
        double g = -sig;
        for (long i = 0; i <= n; i++) g += c[i] * (u[i] - xa[i]);
        b[n] = g;
        double fs = ci_fscaled_max(s, b, m);
        if (s->att_track) s->att_fsmin = fmin(s->att_fsmin, fs);
        if (monotone && fs > s->ftol && !(fs < fsprev)) return 1;
        fsprev = fs;
        if (k > 0 && fs <= s->ftol && dlast <= s->xtol * (1.0 + step_norm2(s, u))) {
            memcpy(s->rc, c, (size_t)m * sizeof(double));
            s->rgen = s->bt.gen;
            if (nit) *nit = k;
            if (fnorm) *fnorm = s->last_fnorm;
            memcpy(x, u, (size_t)m * sizeof(double));
            return 0;
        }
        if (k == maxit) return 1;
        if (ci_call_jacobian(s, u, u[n]) != 0) return 1;
        for (long i = 0; i < m; i++) b[i] = -b[i];
        /* the Newton step with the factors of an earlier iterate, refined,
         * or with a factorisation here */
        double *rhs = s->rw, *dr = s->rw + m;
        memcpy(rhs, b, (size_t)m * sizeof(double));
        if (have && refine_solve(s, c, rhs, dr, REFINE_TOL) == 0) {
            memcpy(d, dr, (size_t)m * sizeof(double));
        } else {
            if (ci_bm_build(s, &s->bt, c) != 0 || ci_bm_factor(s, &s->bt, NULL, NULL) != 0)
                return 1;
            have = 1;
            memcpy(b, rhs, (size_t)m * sizeof(double));
            if (ci_bm_solve(s, &s->bt, s->vx, s->vb) != 0) return 1;
        }
        dlast = step_norm2(s, d);
        for (long i = 0; i < m; i++) u[i] += d[i];
        s->stp.newton_iters++;
    }
}

/* x = A^{-1} rhs for the exact bordered matrix A = [Jy Fp; c^T] (Jy, Fp as
 * last evaluated) with the factors B in s->bt of a nearby matrix, by
 * iterative refinement: x <- x + B^{-1} (rhs - A x).  Each correction must
 * be at most half the one before (the iteration contracts: the spectral
 * radius of E = I - B^{-1} A is below one, hence det(B^{-1} A) = det(I - E)
 * > 0, real eigenvalues of I - E positive and complex ones in conjugate
 * pairs, and det A has the sign of det B); done when the correction is
 * REFINE_TOL of |x|, or when it stalls below REFINE_FLOOR of |x| (rounding)
 * after contracting.  The solves with B are not refined on their own (block
 * elimination, cont_blockelim.c, is refined here against A instead).
 * 0, or -1 (factorise afresh). */
static int refine_solve(cont_solver *s, const double *c, const double *rhs, double *x,
                        double tol)
{
    long m = s->m;
    double *r = N_VGetArrayPointer(s->vb), *dx = N_VGetArrayPointer(s->vx);
    memcpy(r, rhs, (size_t)m * sizeof(double));
    if (ci_bm_solve_as(s, &s->bt, s->vx, s->vb, 1) != 0) return -1;
    memcpy(x, dx, (size_t)m * sizeof(double));
    double prev = HUGE_VAL;
    for (int it = 0; it < REFINE_MAX; it++) {
        ci_bm_apply(s, c, x, r);
        for (long i = 0; i < m; i++) r[i] = rhs[i] - r[i];
        if (ci_bm_solve_as(s, &s->bt, s->vx, s->vb, 1) != 0) return -1;
        double nd = scaled_norm2(s, dx);
        for (long i = 0; i < m; i++) x[i] += dx[i];
        double nx = scaled_norm2(s, x);
        if (nd <= tol * nx || (nd > 0.5 * prev && it >= 2 && nd <= REFINE_FLOOR * nx))
            return 0;
        if (!(nd <= 0.5 * prev)) return -1;
        prev = nd;
    }
    return -1;
}

/* The tangent solve [Jy Fp; c^T] v = e_n at a corrected point (Jy, Fp
 * evaluated there) with the factors ci_correct_reuse left in s->bt (same
 * border c, made at an iterate near the point), by refine_solve; log|det
 * A| is taken as log|det B| (they differ by log det(I - E), about -tr E).
 * v in s->vx; 0, or -1 (factorise afresh).  One use: the mark is cleared. */
int ci_tangent_reuse(cont_solver *s, const double *c, int *sign, double *logdet)
{
    long n = s->n, m = s->m;
    int ok = s->rgen == s->bt.gen && s->rgen >= 0 &&
             memcmp(s->rc, c, (size_t)m * sizeof(double)) == 0;
    s->rgen = -1;
    if (!ok) return -1;
    double *rhs = s->rw, *v = s->rw + m;
    for (long i = 0; i < m; i++) rhs[i] = 0.0;
    rhs[n] = 1.0;
    if (refine_solve(s, c, rhs, v, REFINE_TOL) != 0) return -1;
    memcpy(N_VGetArrayPointer(s->vx), v, (size_t)m * sizeof(double));
    return ci_bm_det(s, &s->bt, sign, logdet);
}

int ci_solve_fixed(cont_solver *s, double *x, int *nit, double *fnorm)
{
    long n = s->n, m = s->m;
    for (long i = 0; i < m; i++) s->cw[i] = 0.0;
    s->cw[n] = 1.0;
    /* the border c = e_p: only the p component of xa matters */
    double *xa = malloc((size_t)m * sizeof(double));
    if (!xa) return ci_fail(s, CONT_ENOMEM, "out of memory");
    memcpy(xa, x, (size_t)m * sizeof(double));
    int r = regularised(s, fixed_newton, x, s->cw, xa, 0.0, s->init_maxit, s->init_strategy,
                        nit, fnorm);
    free(xa);
    return r;
}

int cont_solve_fixed(cont_solver *s, double *y, double p)
{
    NEED(s);
    if (!y || !isfinite(p)) return ci_fail(s, CONT_EINPUT, "cont_solve_fixed: bad arguments");
    if (!ci_all_finite(y, s->n)) return ci_fail(s, CONT_EINPUT, "cont_solve_fixed: y0 is not finite");
    double t0 = ci_now_sec();
    double *x = malloc((size_t)s->m * sizeof(double));
    if (!x) return ci_fail(s, CONT_ENOMEM, "out of memory");
    memcpy(x, y, (size_t)s->n * sizeof(double));
    x[s->n] = p;
    int nit;
    double fn;
    int r = ci_solve_fixed(s, x, &nit, &fn);
    if (r == 0) memcpy(y, x, (size_t)s->n * sizeof(double));
    free(x);
    if (s->state != ST_RUN) ci_flush_stats(s, t0, 0);
    if (r != 0)
        return ci_fail(s, CONT_ENUMERIC, "Newton at fixed p = %.10g failed: %s", p, s->why);
    return CONT_OK;
}
