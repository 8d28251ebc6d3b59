/* flatstart_sparse.c - starting an exact path at the flat state of a large
 * sheet in the face-pose formulation (analysis.flat_start = "sparse").
 *
 * The flat state is a singular point: the fold rows of the pose
 * formulation have redundant combinations there (rotation about the normal
 * and in-plane translation of each vertex loop are of second order in the
 * fold angles), several branches may meet, and Newton converges only
 * linearly in its neighbourhood.  The dense tangent-cone analysis
 * (flatcone.c) resolves this exactly but works on the first-order kernel
 * as a dense array.  Here, with sparse matrices only:
 *
 * 1. Direction.  The driving selects the branch.  At the flat state the
 *    Jacobian is the KKT matrix [H0 J^T; J -eps D] (H0 the bending Hessian,
 *    J the fold rows, the -eps D regularisation of equilibrium_poses.c),
 *    symmetric; u = -Jy^-1 Fp is the response of the bending energy to the
 *    driving projected on the first-order kernel of J, i.e. the minimiser
 *    of u^T H0 u / 2 + Fp . u subject to J u = 0 (the rows redundant at the
 *    flat state are consistent, their multipliers stay small).  One MUMPS
 *    LDL^T (ldlt.h) of the symmetrically scaled matrix.
 * 2. Sign selection.  Folds whose angle u leaves at zero (relative 1e-8 of
 *    the largest) are not selected by the driving; if they carry a declared
 *    assignment (folds[].assignment, "M" < 0, "V" > 0) that sign is added
 *    to u at 1e-3 of the largest angle, a declared imperfection; otherwise
 *    the note says that the driving leaves them undetermined.
 * 3. Mode amplitudes.  Along the branches of a sheet with shape modes
 *    (K >= 1) the modes' amplitudes are of the order of the fold angles,
 *    but the driving does not move them to first order (u has none): a
 *    state and its mirror in the modes have the same energy.  A declared
 *    imperfection selects one: every mode amplitude starts at -1e-2 times
 *    the largest fold angle.
 * 4. First point.  A finite step along u (the largest fold angle moves by
 *    `angle` rad, e.g. 0.05, not 1e-6: next to the singular point Newton
 *    stalls), poses lifted from the folds, then Newton on the full problem
 *    at the fixed p of the step's end, with an inertia correction: while
 *    the KKT matrix (MUMPS) has more negative pivots than constraint rows,
 *    a shift on the coordinates makes the step descend (away from saddles,
 *    e.g. the symmetric state), and the fold coordinates move by at most a
 *    quarter of the step per iteration.  A converged state whose inertia
 *    says unstable is pushed off again (pseudo-random mode amplitudes,
 *    fixed seeds, 4 times at most).  On the first failure the same step
 *    is taken again with a smaller KKT regularisation (SMALL_REG, for
 *    the start only), then the step is halved (4 times at most), then
 *    the start stops with a diagnosis.
 * 5. Check and hand-over.  cont_start polishes the point at that p and
 *    takes the engine's tangent there (direction dir); a point that came
 *    back to the flat sheet is a failure.
 */
#include "flatstart_sparse.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cont.h"
#include "equilibrium_poses.h"
#include "flatlimit_sparse.h"
#include "ldlt.h"
#include "study.h"

/* the first point's Newton stops when SLOW_SPAN unshifted iterations gain
 * less than a factor 2 (linear convergence: a singular Jacobian) */
#define SLOW_SPAN 10

/* The KKT regularisation of the first point's Newton after a failed
 * attempt (scaled units; the fixed one is 1e-10, equilibrium.c): under
 * gravity and a tip load the first point needs large multipliers on
 * nearly dependent fold rows (the zigzag folds' rows next to the folds
 * that stay flat), and Newton's matrix with -1e-10 D in its multiplier
 * block resolves them only partly per iteration (residual ratio 0.97 at
 * 8x8) or takes steps of 1e280 (2x2 and 3x3 sheets under 5 and 10 times
 * the load).  Measured: 1e-12 and 1e-13 start the 7x7 sheet at the first
 * step, 1e-14 after two halvings, 1e-16 not at all (rounding). */
#define SMALL_REG 1e-13

/* The scaled KKT matrix A = D (Jy + delta P) D of the Newton systems,
 * D = sqrt(fscale / yscale) (the Newton scales of equilibrium_poses.c make
 * A a matrix of O(1) entries, symmetric as Jy is), P the identity on the
 * coordinates: its lower triangle as triplets (pattern of the study's
 * Jacobian plus the diagonal, fixed), factorised by MUMPS. */
typedef struct kkt_ws {
    int n, nx;
    long nl;
    int *r, *c;
    long *src;      /* index in the Jacobian's values, -1: the added diagonal */
    double *a, *d;
    sf_ldlt *f;
} kkt_ws;

static void ws_free(kkt_ws *w)
{
    sf_ldlt_free(w->f);
    free(w->r);
    free(w->c);
    free(w->src);
    free(w->a);
    free(w->d);
}

/* Factorise A at (y, p) with the shift delta; Fp (n values) receives
 * dF/dp; *neg the negative pivots. */
static int ws_factor(kkt_ws *w, sf_equil *q, const double *y, double p, double delta, double *Fp,
                     int *neg, sf_error *err)
{
    int n = q->n;
    const long *cp;
    const int *ri;
    const double *v;
    if (sf_peq_jacobian_csc(q, y, p, &cp, &ri, &v, Fp))
        return sf_fail(err, SF_ENUMERIC, "%s: a Jacobian next to the flat state is not finite",
                       q->m->study->path);
    if (!w->r) {   /* the pattern, once */
        w->n = n;
        w->nx = q->nq;
        long nl = n;
        for (int j = 0; j < n; j++)
            for (long k = cp[j]; k < cp[j + 1]; k++)
                if (ri[k] >= j) nl++;
        w->r = malloc(sizeof(int) * (size_t)nl);
        w->c = malloc(sizeof(int) * (size_t)nl);
        w->src = malloc(sizeof(long) * (size_t)nl);
        w->a = malloc(sizeof(double) * (size_t)nl);
        w->d = malloc(sizeof(double) * (size_t)n);
        if (!w->r || !w->c || !w->src || !w->a || !w->d) return sf_fail(err, SF_ENOMEM, "out of memory");
        if (sf_ldlt_create(&w->f, 0.0, err)) return err->code;
        nl = 0;
        for (int j = 0; j < n; j++) {
            w->d[j] = sqrt(q->fscale[j] / q->yscale[j]);
            w->r[nl] = w->c[nl] = j;
            w->src[nl++] = -1;
            for (long k = cp[j]; k < cp[j + 1]; k++)
                if (ri[k] >= j) {
                    w->r[nl] = ri[k];
                    w->c[nl] = j;
                    w->src[nl++] = k;
                }
        }
        w->nl = nl;
    }
    for (long k = 0; k < w->nl; k++) {
        double dd = w->d[w->r[k]] * w->d[w->c[k]];
        w->a[k] = w->src[k] >= 0 ? dd * v[w->src[k]] : (w->r[k] < w->nx ? delta : 0.0);
    }
    if (sf_ldlt_factor(w->f, n, w->nl, w->r, w->c, w->a, err)) return err->code;
    sf_ldlt_info li;
    sf_ldlt_get_info(w->f, &li);
    *neg = li.neg;
    return SF_OK;
}

/* Solve Jy x = b (b scaled in place to the solution) with the factors. */
static int ws_solve(kkt_ws *w, double *b, sf_error *err)
{
    for (int i = 0; i < w->n; i++) b[i] *= w->d[i];
    if (sf_ldlt_solve(w->f, b, err)) return err->code;
    for (int i = 0; i < w->n; i++) {
        b[i] *= w->d[i];
        if (!isfinite(b[i])) return sf_fail(err, SF_ENUMERIC, "a Newton step next to the flat state is not finite");
    }
    return SF_OK;
}

int sf_flat_direction(sf_equil *q, const double *y0, double p0, double *u, int *nnull,
                      sf_error *err)
{
    kkt_ws w;
    memset(&w, 0, sizeof w);
    int neg, rc = ws_factor(&w, q, y0, p0, 0.0, u, &neg, err);
    if (!rc) {
        for (int i = 0; i < q->n; i++) u[i] = -u[i];
        rc = ws_solve(&w, u, err);
    }
    if (!rc && nnull) {
        sf_ldlt_info li;
        sf_ldlt_get_info(w.f, &li);
        *nnull = li.nnull;
    }
    ws_free(&w);
    return rc;
}

/* Largest |fold angle| in u. */
static double max_angle(const sf_model *m, const double *u)
{
    double mx = 0.0;
    for (int i = 0; i < m->nfolds; i++) mx = fmax(mx, fabs(u[m->qoff[i]]));
    return mx;
}

/* Step 2 of the comment at the top: folds the driving leaves at zero take
 * their declared assignment's sign.  Returns the number of such folds;
 * *declared of them had an assignment. */
static int select_signs(const sf_equil *q, double *u, int *declared)
{
    const sf_model *m = q->m;
    const sf_study *s = m->study;
    double mx = max_angle(m, u);
    int nzero = 0;
    *declared = 0;
    for (int i = 0; i < m->nfolds; i++) {
        double *t = u + m->qoff[i];
        if (fabs(*t) > 1e-8 * mx) continue;
        nzero++;
        double sg = sf_study_fold_sign(s, i);
        if (sg == 0.0) continue;
        *t = sg * 1e-3 * mx;
        (*declared)++;
    }
    return nzero;
}

/* The declared imperfection of the mode amplitudes (the driving leaves
 * their signs open: a state and its mirror in the modes have the same
 * energy): push = 0, every mode amplitude moved by -rel times the largest
 * fold angle of y; push > 0 (a converged saddle pushed off again),
 * pseudo-random signs and sizes, fixed seeds. */
static void perturb_modes(const sf_model *m, double *y, double rel, int push)
{
    double mx = max_angle(m, y);
    unsigned long seed = 12345u + 7919u * (unsigned long)push;
    for (int i = 0; i < m->nfolds; i++)
        for (int k = 1; k < m->qn[i]; k++) {
            seed = seed * 6364136223846793005ul + 1442695040888963407ul;
            double r = (double)(seed >> 11) / 9007199254740992.0;   /* [0, 1) */
            y[m->qoff[i] + k] += rel * mx * (push ? 2.0 * r - 1.0 : -1.0);
        }
}

/* Newton at fixed p from y (updated in place) with an inertia
 * correction: while the KKT matrix has more negative pivots than
 * constraint rows (each row, regularised, gives one), i.e. the Hessian is
 * not positive definite on the constraints' kernel, a shift delta on the
 * coordinates is added, so that the step descends from saddles (a
 * symmetric state losing stability) instead of converging to them; the
 * fold coordinates move by at most `cap` per iteration.  0 when converged
 * (scaled residual <= tol). */
static int descent(sf_equil *q, kkt_ws *w, double *y, double p, double tol, double cap, int maxit,
                   int *iters, double *fres, int *slow, sf_error *err)
{
    int n = q->n, nq = q->m->nq, rc = 1, pushes = 0, unshifted = 0;
    double hist[SLOW_SPAN];   /* the residuals of the last unshifted iterations */
    *slow = 0;
    double *F = malloc(sizeof(double) * (size_t)n), *Fp = malloc(sizeof(double) * (size_t)n);
    if (!F || !Fp) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto out;
    }
    *fres = INFINITY;
    for (*iters = 0; *iters < maxit; (*iters)++) {
        if (sf_equil_residual(y, p, F, q)) break;
        double fs = 0.0;
        for (int i = 0; i < n; i++) fs = fmax(fs, fabs(F[i] * q->fscale[i]));
        *fres = fs;
        /* Newton without shift that gains less than a factor 2 in
         * SLOW_SPAN iterations: linear convergence, a singular Jacobian at
         * the state (the 8x8 Miura sheet under load: 0.97 per iteration
         * near 1e-7, 100 iterations per attempt) */
        if (unshifted >= SLOW_SPAN && fs > 0.5 * hist[(unshifted - SLOW_SPAN) % SLOW_SPAN] &&
            fs < 1e-4) {
            *slow = 1;
            break;
        }
        double delta = 0.0;
        int neg = 0;
        for (int k = 0; k < 40; k++) {
            if (ws_factor(w, q, y, p, delta, Fp, &neg, err)) goto out;
            if (k == 0 && fs <= tol) {
                if (neg <= q->ncon) {   /* converged to a stable state */
                    rc = 0;
                    goto out;
                }
                if (++pushes > 4) goto out;   /* a saddle: pushed off again */
                perturb_modes(q->m, y, 1e-2, pushes);
            }
            if (neg <= q->ncon) break;
            delta = delta > 0 ? 4.0 * delta : 1e-6;
        }
        if (delta > 0) unshifted = 0;
        else hist[unshifted++ % SLOW_SPAN] = fs;
        for (int i = 0; i < n; i++) F[i] = -F[i];
        if (ws_solve(w, F, err)) goto out;
        double mx = 0.0;
        for (int i = 0; i < nq; i++) mx = fmax(mx, fabs(F[i]));
        double sc = mx > cap ? cap / mx : 1.0;
        for (int i = 0; i < n; i++) y[i] += sc * F[i];
    }
    sf_error_clear(err);
out:
    free(F);
    free(Fp);
    return rc;
}

/* One attempt: the step h from the flat state, signed by dir (t = dir h),
 * along the limit solution W (x, mu, z, nu: y = y0 + t x + t^2 z,
 * lambda = nu + t mu) when W is not NULL, else along u with the declared
 * imperfection of the mode amplitudes and poses lifted; solved at
 * p0 + t by descent(), then cont_start there.  0 on success. */
static int attempt_reg(sf_equil *q, struct cont_solver *cs, kkt_ws *w, const double *y0,
                       double p0, int dir, const double *u, const double *W, double h, double tol,
                       double *y, int *iters, double *fres_out, int *slow, sf_error *err)
{
    int n = q->n, nq = q->m->nq, nx = q->nq;
    double t = dir * h;
    memcpy(y, y0, sizeof(double) * (size_t)n);
    if (W) {
        for (int i = 0; i < nx; i++) y[i] += t * W[i] + t * t * W[n + i];
        for (int i = nx; i < n; i++) y[i] = W[n + i] + t * W[i];
    } else {
        for (int i = 0; i < nq; i++) y[i] += t * u[i];
        perturb_modes(q->m, y, 1e-2, 0);
        sf_equil_poses_lift(q, y);
        for (int i = nx; i < n; i++) y[i] = y0[i] + t * u[i];
    }
    double fres = INFINITY;
    /* fold coordinates move by at most a quarter of the step per iteration */
    double cap = 0.25 * h * max_angle(q->m, W ? W : u);
    int rc = descent(q, w, y, p0 + t, fmax(tol, 1e-9), cap, 100, iters, &fres, slow, err);
    *fres_out = fres;
    if (rc) {
        if (!err->code && *slow)
            sf_fail(err, SF_ENUMERIC, "Newton with inertia correction at p = %g converges only "
                    "linearly (scaled residual %.3g after %d iterations, less than a factor 2 in "
                    "the last %d: a singular Jacobian there)", p0 + t, fres, *iters, SLOW_SPAN);
        else if (!err->code)
            sf_fail(err, SF_ENUMERIC, "Newton with inertia correction at p = %g: scaled "
                    "residual %.3g after %d iterations", p0 + t, fres, *iters);
        return 1;
    }
    if (cont_start(cs, y, p0 + t, dir) != CONT_OK)
        return sf_fail(err, SF_ENUMERIC, "%s", cont_errmsg(cs));
    return 0;
}

/* attempt_reg; with small_reg, with the KKT regularisation SMALL_REG
 * instead of the path's (restored afterwards: the corrector of the path
 * keeps its own). */
static int attempt(sf_equil *q, struct cont_solver *cs, kkt_ws *w, const double *y0, double p0,
                   int dir, const double *u, const double *W, double h, double tol, int small_reg,
                   double *y, int *iters, double *fres_out, int *slow, sf_error *err)
{
    double rel = q->reg_rel, mn = q->reg_min;
    if (small_reg) {   /* sf_equil_reg_eps then returns reg_min */
        q->reg_rel = 1e-300;
        q->reg_min = SMALL_REG;
    }
    int rc = attempt_reg(q, cs, w, y0, p0, dir, u, W, h, tol, y, iters, fres_out, slow, err);
    q->reg_rel = rel;
    q->reg_min = mn;
    return rc;
}

int sf_equil_poses_start_sparse(sf_equil *q, struct cont_solver *cs, const double *y0, double p0,
                                double max_dp, int dir, double angle, double tol, double *y,
                                sf_flatstart_info *info, sf_error *err)
{
    const sf_model *m = q->m;
    const char *path = m->study->path;
    int n = q->n, nnull = 0, rc;
    if (!q->pz) return sf_fail(err, SF_EINPUT, "%s: analysis.flat_start = \"sparse\" needs "
                                "solver.formulation = \"poses\"", path);
    if (q->disp_row >= 0)
        return sf_fail(err, SF_EINPUT, "%s: a displacement parameter with exact loop constraints "
                       "cannot start at the flat state; start from p != 0", path);
    kkt_ws w;
    memset(&w, 0, sizeof w);
    double *W = NULL;
    double *u = malloc(sizeof(double) * ((size_t)n + 1));
    double *yf = malloc(sizeof(double) * ((size_t)n + 1));
    if (!u || !yf) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto out;
    }
    memcpy(yf, y0, sizeof(double) * (size_t)n);   /* y may be y0 */
    if ((rc = sf_flat_direction(q, yf, p0, u, &nnull, err))) goto out;
    double um = max_angle(m, u);
    if (!(um > 0)) {
        rc = sf_fail(err, SF_ENUMERIC, "%s: flat start (sparse): the driving does not move any "
                     "fold to first order at the flat state; try analysis.flat_start = \"limit\" "
                     "(second-order start, small sheets) or another driving", path);
        goto out;
    }
    int declared = 0, nzero = select_signs(q, u, &declared);
    /* the limit problem of the driving's branch (flatlimit_sparse.h) */
    W = malloc(sizeof(double) * 2 * (size_t)n);
    if (!W) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto out;
    }
    sf_flatlimit_info li;
    sf_error lerr;
    sf_error_clear(&lerr);
    int lim = !sf_flat_limit_sparse(q, yf, p0, u, -1e-2, 1, W, &li, &lerr);
    if (!lim && lerr.code == SF_ENOMEM) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto out;
    }
    double h = angle / max_angle(m, lim ? W : u);
    if (max_dp > 0 && h > max_dp) h = max_dp;
    char why[SF_MSG_SIZE] = "", why0[600] = "";
    int halvings, its = 0, nslow = 0, small_reg = 0;
    double last_res = NAN;   /* the first point's last scaled residual */
    for (halvings = 0; halvings <= 4; halvings++, h *= 0.5) {
        sf_error aerr;
        sf_error_clear(&aerr);
        int slow = 0;
        if (attempt(q, cs, &w, yf, p0, dir, u, lim ? W : NULL, h, tol, small_reg, y, &its,
                    &last_res, &slow, &aerr)) {
            snprintf(why, sizeof why, "%s", aerr.msg);
            nslow += slow;
            if (!small_reg) {
                /* the same step again with the smaller regularisation
                 * (SMALL_REG), and every later one */
                snprintf(why0, sizeof why0, "%.590s", aerr.msg);
                small_reg = 1;
                halvings--;
                h *= 2.0;
            }
            continue;
        }
        const cont_point *pt = cont_get_point(cs);
        if (max_angle(m, pt->y) > 0.05 * h * um && (pt->p - p0) * dir > 0) break;
        snprintf(why, sizeof why, "the corrector went back to the flat state");
    }
    if (halvings > 4) {
        /* two plain sentences: what failed, what to try; the attempts'
         * own messages only as far as they say where Newton stopped */
        if (lim && nslow >= 3)
            /* Newton converging linearly at most attempts, also with the
             * smaller regularisation: its matrix is nearly singular at the
             * state it approaches (docs/flatstart.md, "The sheet under
             * gravity and a tip load") */
            rc = sf_fail(err, SF_ENUMERIC, "%s: flat start: no folded equilibrium found next to "
                         "the flat sheet: Newton's matrix is nearly singular at the state it "
                         "approaches (nearly dependent fold rows; scaled residual %.2g after 6 "
                         "attempts from %.3g rad). Try the loop penalty (solver.formulation = "
                         "\"folds\", solver.constraints = \"penalty\"), which needs no flat start",
                         path, last_res, angle);
        else
            rc = sf_fail(err, SF_ENUMERIC, "%s: flat start: no folded equilibrium found next to "
                         "the flat sheet along the driving's direction (%s; 6 attempts from %.3g "
                         "rad, the last: %.200s). Try `smoothfold check` (can every vertex "
                         "fold?), a driving that selects a branch (folds[].assignment, a load), "
                         "or the loop penalty (solver.constraints = \"penalty\")",
                         path, lim ? "its second-order solution" : "its first-order response, the "
                         "limit problem failed", angle, why);
        goto out;
    }
    const cont_point *pt = cont_get_point(cs);
    memcpy(y, pt->y, sizeof(double) * (size_t)n);
    if (info) {
        double Pi, rr, rt;
        sf_equil_report(q, pt->y, pt->p, &Pi, &rr, &rt);
        const char *signs = !nzero ? ""
                            : declared == nzero ? "; folds the driving leaves at zero take their "
                                                  "declared assignment's sign"
                                                : "; the driving leaves some folds at zero to "
                                                  "first order and no assignment declares their "
                                                  "sign";
        info->iterations = its;
        info->residual = fmax(rr, rt);
        char lnote[900], cands[300] = "";
        if (lim) {
            /* every limit state found, with its energy (J per unit p^2) */
            static const char *kind[] = {"first-order response", "rigid vertex modes",
                                         "mirror in the modes"};
            size_t o = 0;
            for (int k = 0; k < li.ncand && o < sizeof cands; k++) {
                const char *sep = k ? ", " : "", *nm = kind[li.cand_kind[k]];
                const char *fol = k == li.chosen ? " (followed)" : "";
                /* the first start not carried to the last penalty stage:
                 * its energy at the stage before, at most its limit energy */
                if (k == 0 && li.first_bound && isfinite(li.cand_energy[k]))
                    o += (size_t)snprintf(cands + o, sizeof cands - o, "%s%s >= %.9g", sep, nm,
                                          li.cand_energy[k]);
                else if (isfinite(li.cand_energy[k]))
                    o += (size_t)snprintf(cands + o, sizeof cands - o, "%s%s %.9g%s", sep, nm,
                                          li.cand_energy[k], fol);
                else
                    o += (size_t)snprintf(cands + o, sizeof cands - o, "%s%s: %s", sep, nm,
                                          li.cand_conv[k] > 0 ? "the same state"
                                          : li.cand_conv[k] < 0 ? "left, falling back to the flat "
                                                                  "state after its first stage"
                                                                : "no convergence within its "
                                                                  "budget");
            }
        }
        /* the first start at eta = 1e-8 fell back to the flat state, or
         * its first stage made no progress (flatlimit_sparse.c) */
        const char *retry = !lim || !li.eta_retry ? ""
                            : li.eta_retry == 2 ? "; penalty stages from eta = 1e-9 (from 1e-8 "
                                                  "the first start's first stage made no progress)"
                                                : "; penalty stages from eta = 1e-9 (from 1e-8 "
                                                  "the first start fell back to the flat state)";
        char prevnote[300] = "";
        if (lim && li.prev_stage)
            snprintf(prevnote, sizeof prevnote, "; the first start's last penalty stage (eta = "
                     "1e-12) did not converge (scaled residual %.3g after %d iterations): its "
                     "state at eta = %g taken", li.last_res, li.last_its, li.prev_eta);
        if (lim && li.ties)
            snprintf(lnote, sizeof lnote, "the driving selects no single branch: the lowest "
                     "limit state found and its mirror in the mode amplitudes have equal energy "
                     "%.9g (a symmetric start; limit states found: %s; %d starts, %d Newton "
                     "iterations, %d MUMPS factorisations%s%s); following the first of the two, the "
                     "one the declared imperfection -1e-2 of the mode amplitudes leads to (the "
                     "lowest of the states found, not a global guarantee)", li.energy, cands,
                     li.starts, li.iterations, li.factorisations, retry, prevnote);
        else if (lim)
            snprintf(lnote, sizeof lnote, "the driving's branch from the sparse limit problem "
                     "(%d starts, %d Newton iterations, %d MUMPS factorisations, %d saddles "
                     "left; limit energy %.9g; limit states found: %s%s%s; the lowest of the states "
                     "found, not a global guarantee)", li.starts, li.iterations,
                     li.factorisations, li.pushes, li.energy, cands, retry, prevnote);
        else
            snprintf(lnote, sizeof lnote, "the sparse limit problem failed (%.200s): the "
                     "driving's first-order response with a declared imperfection (every mode "
                     "amplitude -1e-2 times the largest fold angle)", lerr.msg);
        char regnote[400] = "";
        if (small_reg)
            snprintf(regnote, sizeof regnote, "; the first point's Newton with the KKT "
                     "regularisation %g (with the path's: %.200s)", SMALL_REG, why0);
        snprintf(info->note, sizeof info->note,
                 "flat start (sparse): %.700s; a step of %.3g in p, %d Newton iterations, first "
                 "point at p = %.6g, largest fold angle %.4g rad, fold-row residual %.2g, %d step "
                 "halvings%s%s", lnote, h, its, pt->p, max_angle(m, pt->y), fmax(rr, rt),
                 halvings, regnote, signs);
    }
out:
    ws_free(&w);
    free(W);
    free(u);
    free(yf);
    return rc;
}
