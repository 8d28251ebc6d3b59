/* cont_corrector.c - the corrector (cont.h, ALGORITHM): KINSOL's Newton
 * on F(y, p) = 0 bordered by c.(x - xa) = sig, with the Jacobian of the
 * bordered system; Newton at fixed p (cont_solve_fixed). */
#include "cont_impl.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define REFINE_MAX 10      /* refinements of a solve with reused factors */
#define REFINE_TOL 1e-10   /* their relative accuracy */
#define REFINE_FLOOR 1e-7  /* accepted when they stall there (rounding) */
#define ANCHOR_LEVELS 4    /* levels of the anchored solve (cont_anchor_fn) */
#define ANCHOR_LAST 5      /* ... and the last one, tried after those failed */
#define REANCHORS 2        /* proximal iterations after an anchored solve */

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

/* Newton on the problem's anchored F (cont_anchor_fn) from u = s->u: its
 * Jacobian is the regularised one, so it converges where the plain F
 * stagnates at a floor.  The levels from s->anchor_level (at least 1) to
 * ANCHOR_LAST in turn, each anchored at the best point so far (the lowest
 * plain residual; a smaller weight resolves constraint directions the
 * regularisation hides), until the plain residual meets ftol.  A level
 * that ends at KINSOL's iteration limit still offers its point (the
 * anchored Newton of a small weight can stall at its own rounding floor
 * next to a point that meets the plain tolerance).  s->anchor_level is
 * then the level that did, at most ANCHOR_LEVELS: the last level is only
 * tried after the others failed in this attempt.  0 ok (u updated), -1
 * not (u restored). */
static int anchored_solve(cont_solver *s, int maxit, int strategy, int *nit)
{
    long n = s->n, m = s->m;
    double *u = N_VGetArrayPointer(s->u);
    if (!ci_all_finite(u, m)) return -1;
    memcpy(s->w1, u, (size_t)m * sizeof(double));
    double *f = malloc((size_t)n * sizeof(double));
    double *best = malloc((size_t)m * sizeof(double));
    if (!f || !best) {
        free(f);
        free(best);
        return -1;
    }
    memcpy(best, u, (size_t)m * sizeof(double));
    double fs = INFINITY, fbest = INFINITY;
    int lev = s->anchor_level > 1 ? s->anchor_level : 1;
    for (; lev <= ANCHOR_LAST; lev++) {
        memcpy(u, best, (size_t)m * sizeof(double));
        if (s->prob.anchor(u, u[n], lev, s->prob.user) != 0) break;
        KINSetNumMaxIters(s->kmem, maxit);
        int flag = KINSol(s->kmem, s->u, strategy, s->uscale, s->fscale);
        s->prob.anchor(NULL, 0.0, 0, s->prob.user);
        long nni = 0;
        KINGetNumNonlinSolvIters(s->kmem, &nni);
        s->stp.newton_iters += nni;
        s->stp.nlinsolve += nni;
        if (nit) *nit += (int)nni;
        fs = INFINITY;
        if ((flag >= 0 || flag == KIN_LINESEARCH_NONCONV || flag == KIN_MAXITER_REACHED) &&
            ci_all_finite(u, m) && ci_call_residual(s, u, u[n], f) == 0)
            fs = ci_fscaled_max(s, f, n);
        s->anchor_fs = fmin(s->anchor_fs, fs);
        if (fs <= s->ftol) break;
        if (fs < fbest) {
            fbest = fs;
            memcpy(best, u, (size_t)m * sizeof(double));
        }
    }
    free(f);
    free(best);
    if (fs <= s->ftol) {
        s->anchor_level = lev < ANCHOR_LEVELS ? lev : ANCHOR_LEVELS;
        return 0;
    }
    memcpy(u, s->w1, (size_t)m * sizeof(double));   /* as the plain attempt left it */
    return -1;
}

/* Solve F(x) = 0, c.(x - xa) = sig from the guess x (overwritten with the
 * solution on success).  0 ok, -1 failed (reason in s->why). */
int ci_correct(cont_solver *s, double *x, const double *c, const double *xa,
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
    s->anchor_fs = INFINITY;
    KINSetNumMaxIters(s->kmem, maxit);
    KINSetFuncNormTol(s->kmem, s->ftol);
    KINSetScaledStepTol(s->kmem, 1e-15);
    if (s->prob.anchor && s->anchor_level) {
        /* a residual floor was met earlier on this run: the anchored
         * system first (from the guess, anchored at its multipliers); the
         * plain attempt only if that fails */
        int na = 0;
        if (anchored_solve(s, maxit, strategy, &na) == 0) {
            if (nit) *nit = na;
            if (fnorm) *fnorm = s->last_fnorm;
            memcpy(x, N_VGetArrayPointer(s->u), (size_t)m * sizeof(double));
            return 0;
        }
        s->stp.retries++;
        memcpy(N_VGetArrayPointer(s->u), x, (size_t)m * sizeof(double));
        KINSetNumMaxIters(s->kmem, maxit);
    }
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
        if (s->prob.anchor && s->fail_fs <= 10.0 * s->ftol &&
            anchored_solve(s, maxit, strategy, nit) == 0) {
            ok = 1;
            s->why[0] = '\0';
            s->fail_fs = NAN;
        }
    }
    if (fnorm) *fnorm = s->last_fnorm;
    /* a failed attempt's residual: the lowest plain residual reached,
     * anchored solves included (cont_step.c's floor diagnosis) */
    if (!ok && s->anchor_fs < INFINITY && !(s->fail_fs <= s->anchor_fs)) s->fail_fs = s->anchor_fs;
    if (!ok) return -1;
    memcpy(x, u, (size_t)m * sizeof(double));
    return 0;
}

static int refine_solve(cont_solver *s, const double *c, const double *rhs, double *x,
                        double tol);

static int reuse_newton(cont_solver *s, double *x, const double *c, const double *xa,
                        double sig, int maxit, int monotone, int have, int *nit, double *fnorm);

/* The anchored point of the first level u (plain residual fs) leaves
 * eps D (lambda - lambda_a) on the constraint rows, a bias of the state
 * within the tolerance, or just above it; re-anchored at the point
 * (proximal iterations, each an exact Newton iteration or two from the
 * point with the same factors) it shrinks: on the Miura sheets two bring
 * the fold angles to the plain corrector's points (continuation/README.md,
 * "Larger steps").  Up to REANCHORS of them; one is kept if its plain
 * residual meets ftol or is below the one before, else u is left as it
 * was.  Not counted by the step control (s->polish_iters), counted in the
 * statistics.  Only at the first level: at a residual floor (smaller
 * weights) the proximal iterations drift along the nearly dependent rows
 * instead (continuation/README.md, "Larger steps on large sheets").  Returns the
 * plain residual at u (INFINITY if it cannot be evaluated). */
static double reanchor(cont_solver *s, double *u, const double *c, const double *xa,
                       double sig, int maxit, double fs)
{
    long n = s->n, m = s->m;
    for (int j = 0; j < REANCHORS; j++) {
        memcpy(s->w1, u, (size_t)m * sizeof(double));
        if (s->prob.anchor(u, u[n], 1, s->prob.user) != 0) break;
        int r = reuse_newton(s, u, c, xa, sig, maxit, 0, 1, NULL, NULL);
        s->prob.anchor(NULL, 0.0, 0, s->prob.user);
        double f2 = INFINITY;
        if (r == 0 && ci_call_residual(s, u, u[n], s->rw) == 0) f2 = ci_fscaled_max(s, s->rw, n);
        if (!(f2 <= s->ftol || f2 < fs)) {   /* keep the point before */
            memcpy(u, s->w1, (size_t)m * sizeof(double));
            if (ci_call_residual(s, u, u[n], s->rw) != 0) fs = INFINITY;
            break;
        }
        fs = f2;
    }
    return fs;
}

/* The reusing corrector on the problem's anchored system (cont_anchor_fn)
 * first, for cont_set_anchor_first: from the guess x, anchored at its
 * multipliers, at level max(1, levels reached so far), then at the
 * smaller weights of the next levels, each anchored at the best point so
 * far, while a level converges but leaves the plain residual above ftol
 * (as anchored_solve, with the engine's own Newton and factorisation
 * instead of KINSOL's LU).  The result is kept only where the plain F
 * meets ftol (and the anchored Newton's last step xtol), the acceptance
 * test of every point.  Why (continuation/README.md, "Larger steps"): at
 * the closed states of a sheet the fold rows carry self-stresses that
 * exist only there, and the plain Newton converges only linearly from a
 * long step (the residual is bilinear in the multiplier error along them
 * and the position error); the anchor pins those multipliers.
 * 0: x holds the point, the factors stay marked for ci_tangent_reuse;
 * 1: x unchanged. */
static int correct_reuse_anchored(cont_solver *s, double *x, const double *c, const double *xa,
                                  double sig, int maxit, int *nit, double *fnorm)
{
    long n = s->n, m = s->m;
    if (!s->anchor_first || !s->prob.anchor || s->corrector != CONT_CORRECTOR_REUSE) return 1;
    double *u = malloc((size_t)m * sizeof(double)), *best = malloc((size_t)m * sizeof(double));
    if (!u || !best) {
        free(u);
        free(best);
        return 1;
    }
    memcpy(best, x, (size_t)m * sizeof(double));
    long it0 = s->stp.newton_iters, npx = 0;
    double fbest = INFINITY, fs = INFINITY;
    int lev = s->reuse_level > 1 ? s->reuse_level : 1;
    for (; lev <= ANCHOR_LAST; lev++) {
        memcpy(u, best, (size_t)m * sizeof(double));
        if (s->prob.anchor(u, u[n], lev, s->prob.user) != 0) break;
        s->att_anch = 1;
        int k = 0, r = ci_correct_reuse(s, u, c, xa, sig, maxit, 0, &k, NULL);
        s->att_anch = 0;
        s->prob.anchor(NULL, 0.0, 0, s->prob.user);
        if (r != 0) break;   /* a smaller weight will not converge either */
        if (ci_call_residual(s, u, u[n], s->w1) != 0) break;
        fs = ci_fscaled_max(s, s->w1, n);
        if (lev == 1) {
            /* the bias first: a plain residual just above ftol at the
             * first level is the anchor's own, removed by the proximal
             * iterations, not a floor that needs the smaller weights
             * (and with them the first-order predictor) for the rest of
             * the run */
            long ip = s->stp.newton_iters;
            fs = reanchor(s, u, c, xa, sig, maxit, fs);
            npx += s->stp.newton_iters - ip;
        }
        if (fs <= s->ftol) break;
        if (!(fs < fbest)) break;
        fbest = fs;
        memcpy(best, u, (size_t)m * sizeof(double));
    }
    free(best);
    s->polish_iters = (int)npx;
    if (nit) *nit = (int)(s->stp.newton_iters - it0);
    if (!(fs <= s->ftol)) {
        s->rgen = -1;
        free(u);
        return 1;
    }
    s->reuse_level = lev < ANCHOR_LEVELS ? lev : ANCHOR_LEVELS;
    if (fnorm) *fnorm = s->last_fnorm;
    memcpy(x, u, (size_t)m * sizeof(double));
    free(u);
    return 0;
}

int ci_correct_step(cont_solver *s, double *x, const double *c, const double *xa, double sig,
                    int *nit, double *fnorm)
{
    s->polish_iters = 0;
    s->att_fsmin = INFINITY;
    s->att_afs = INFINITY;
    s->fail_fs = NAN;   /* not a stale value where a later check rejects the point */
    if (s->strategy == KIN_NONE) {
        if (correct_reuse_anchored(s, x, c, xa, sig, s->max_newton, nit, fnorm) == 0) return 0;
        s->att_track = 1;
        int r = ci_correct_reuse(s, x, c, xa, sig, s->max_newton, 0, nit, fnorm);
        s->att_track = 0;
        if (r == 0) {
            s->att_afs = INFINITY;   /* a point: not a failure of the corrector */
            return 0;
        }
    }
    s->att_track = 1;   /* ci_correct's plain KINSOL attempt, not its anchored retry */
    int r = ci_correct(s, x, c, xa, sig, s->max_newton, s->strategy, nit, fnorm);
    s->att_track = 0;
    if (r == 0) s->att_afs = INFINITY;
    return r;
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
static int reuse_newton(cont_solver *s, double *x, const double *c, const double *xa,
                        double sig, int maxit, int monotone, int have, int *nit, double *fnorm);

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
    double dlast = HUGE_VAL, fsprev = HUGE_VAL, fsit = INFINITY;
    for (int k = 0;; k++) {
        if (ci_call_residual(s, u, u[n], b) != 0) return 1;
        double g = -sig;
        for (long i = 0; i <= n; i++) g += c[i] * (u[i] - xa[i]);
        b[n] = g;
        double fs = ci_fscaled_max(s, b, m);
        if (s->att_track) s->att_fsmin = fmin(s->att_fsmin, fs);
        if (k > 0) fsit = fmin(fsit, fs);   /* after a Newton step: not the guess */
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
        if (k == maxit) {
            if (s->att_anch) s->att_afs = fmin(s->att_afs, fsit);
            return 1;
        }
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
    /* anchor xa: only its p component matters, c = e_p */
    double *anchor = malloc((size_t)m * sizeof(double));
    if (!anchor) return ci_fail(s, CONT_ENOMEM, "out of memory");
    memcpy(anchor, x, (size_t)m * sizeof(double));
    /* Newton with the engine's own factorisation first (the symmetric
     * block elimination where Jy is symmetric): from a good guess, such as
     * the flat start's first point, it converges in a few iterations,
     * while KINSOL's linear solver factorises the bordered matrix by
     * unsymmetric LU, whose delayed pivots make it grow as about n^3 on
     * the pose formulation (Miura 20x20: 46 s).  KINSOL with the start's
     * strategy, from the unchanged guess, when it does not converge. */
    int r = ci_correct_reuse(s, x, s->cw, anchor, 0.0, s->init_maxit,
                             s->init_strategy != KIN_NONE, nit, fnorm) == 0
                ? 0
                : ci_correct(s, x, s->cw, anchor, 0.0, s->init_maxit, s->init_strategy, nit, fnorm);
    free(anchor);
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
