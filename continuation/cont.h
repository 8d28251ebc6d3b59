/* cont.h - generic pseudo-arclength continuation engine (prefix cont_).
 *
 * The engine follows a curve of solutions of F(y, p) = 0, F: R^n x R -> R^n,
 * through limit points, detects and locates special points, and switches
 * branches at simple branch points.  It knows nothing of origami: it sees
 * only a cont_problem (dimension, residual, Jacobian, optional test
 * functions), so it can be checked on textbook problems with known answers.
 *
 * References
 *   H. B. Keller, "Numerical solution of bifurcation and nonlinear eigenvalue
 *     problems", in Applications of Bifurcation Theory (P. Rabinowitz, ed.),
 *     Academic Press, 1977, 359-384  (pseudo-arclength continuation,
 *     branch switching at simple bifurcation points).
 *   E. L. Allgower and K. Georg, "Introduction to Numerical Continuation
 *     Methods", SIAM Classics 45, 2003  (tangent orientation, the augmented
 *     Jacobian and its determinant as a bifurcation test, steplength
 *     adaptation).
 *   W. J. F. Govaerts, "Numerical Methods for Bifurcations of Dynamical
 *     Equilibria", SIAM, 2000  (bordered systems for singular matrices).
 * cont_reference() returns this list as one string.
 *
 * ALGORITHM
 *
 * Unknowns x = (y, p), x in R^(n+1).  A = [Jy Fp] is the n x (n+1) augmented
 * Jacobian (Jy = dF/dy, Fp = dF/dp).
 *
 * Norm.  y and p may have different units, so the arclength s is measured in
 * the weighted norm  |(dy, dp)|_W^2 = dy.dy + theta^2 dp^2  (option theta_p,
 * default 1; W = diag(1, ..., 1, theta^2); cont_set_weights replaces the
 * ones by per-component weights, cont_set_arc_scale scales them by a^2 in
 * the norm alone).  theta > 1 makes p weigh more,
 * i.e. shorter steps in p; theta < 1 lets p move faster.  Tangents are unit
 * vectors in this norm; step sizes ds, ds_min, ds_max and s_max are in it.
 *
 * Tangent.  At a point x with the previous unit tangent t_old, solve the
 * bordered system  [Jy Fp; (W t_old)^T] v = [0; 1]  and set t = v / |v|_W.
 * Because (W t_old).v = 1 > 0 the orientation is kept (t.W t_old > 0), so the
 * branch is never traversed backwards.  The first tangent solves
 * [Jy Fp; e_p^T] v = [0; 1] (direction of increasing p) times the user's
 * sign dir = +1 / -1; this needs Jy regular at the start point.
 *
 * Predictor-corrector step (Keller).  Predictor x_pred = x0 + ds t0
 * (cont_set_predictor 2: plus ds^2 / 2 (t0 - t_prev) / h_prev, the
 * curvature from the tangents of the last step).
 * Corrector: KINSOL (Newton, exact Jacobian refreshed at every iteration) on
 * the (n+1) system
 *        F(y, p) = 0,
 *        (W t0).(x - x0) - ds = 0,
 * whose Jacobian is the bordered matrix [Jy Fp; (W t0)^T], assembled from the
 * user's Jy and Fp, dense (LAPACK LU) or sparse CSC (MUMPS or KLU).
 *
 * With CONT_CORRECTOR_REUSE (the default of the sparse solvers) the
 * corrector is the same full Newton iteration run by the engine, but only
 * its first iteration factorises: the later Newton systems, and the tangent
 * system at the corrected point x (same border), are solved with those
 * factors B by iterative refinement, y <- y + B^{-1} (b - A y) with A the
 * exact bordered matrix of the iterate (one Jacobian evaluation, as
 * before), until the correction is 1e-10 of |y| (or stalls below 1e-7 of
 * |y|, rounding, after contracting); each correction must be at most half
 * the one before, else the iterate is factorised afresh (and its factors
 * serve the rest).  So the iterates are Newton's to 1e-10 and the tests
 * the same.  A contraction means the spectral radius of E = I - B^{-1} A
 * is below one, so det(B^{-1} A) = det(I - E) > 0 and det A has the sign
 * of det B: the branch-point test reads that sign (log|det A| is taken as
 * log|det B|).  Special points are located with fresh factorisations.
 *
 * Step control.  A step is accepted when the corrector converges (max-norm
 * of the scaled residual <= ftol within max_newton iterations, last Newton
 * step <= xtol (1 + |u|), no non-finite value) and the tangent has turned by
 * less than max_angle.  After an accepted step
 * ds grows by `grow` (default 1.5, up to ds_max) if the corrector needed at
 * most fast_iters iterations (default 3).  On failure ds is multiplied by
 * `shrink` (default 0.5) and the step is retried from the same point; when ds
 * drops below ds_min the run stops with CONT_FAIL and a diagnosis (the step
 * size, p, the residual norm of the last point and the reason the last
 * attempt failed).  A residual or Jacobian callback that returns nonzero, or
 * produces NaN/Inf, is an ordinary failed attempt: the step is cut.
 *
 * Stop rules.  (1) p leaves [p_min, p_max]: the engine solves F(y, p_b) = 0
 * at the boundary value p_b itself (Newton at fixed p from the chord
 * interpolation), so the last point lies exactly on p_b; label "EP".  (If
 * that Newton solve fails, e.g. because Jy is singular at p_b, the crossing
 * of p = p_b is located on the branch like a test-function zero instead, and
 * p is then within about loc_tol of p_b.)
 * (2) max_steps accepted steps.  (3) arclength s_max reached (the last step is
 * shortened to land on it).  (4) the point callback asks to stop.  Every
 * terminal point is labelled "EP" (end point, AUTO's convention); the reason
 * is given by cont_stop_reason().
 *
 * Test functions and special points.  After each accepted step the engine
 * evaluates, at the new point,
 *   LP: t_p, the p-component of the unit tangent (changes sign at a limit
 *       point, fold, turning point);
 *   BP: det [Jy Fp; (W t)^T], the determinant of the augmented Jacobian
 *       bordered by the tangent.  Its sign is taken from the LU factors the
 *       tangent solve already computed (product of the signs of U's diagonal
 *       times the parity of the row and column permutations; for KLU also the
 *       positive row scaling; MUMPS computes it with its factors, ICNTL(33)),
 *       and its magnitude as log|det|, so it never overflows.  It keeps its sign through limit points and changes sign
 *       at a simple branch point (Allgower-Georg, sec. 8.1);
 *   USER k: the user's test functions, k = 0..ntest-1.
 * When a test function changes sign between two consecutive points, its
 * zero is located by a safeguarded secant (Illinois regula falsi) on the
 * arclength offset h from the previous point: each trial point is a corrected
 * point on the branch with the arclength equation (W t0).(x - x0) = h.
 * Iteration stops when the bracket in h is narrower than
 * loc_tol (1 + theta |p|) (default loc_tol 1e-10), which bounds the error in p
 * by about loc_tol (1/theta + |p|).  The located point becomes an extra point
 * of the branch, delivered before the step's end point, labelled "LP", "BP" or
 * the user test's label ("USER1", "USER2", ... by default; 1-based).  When the
 * determinant and t_p change sign at the same point (a pitchfork crossed
 * along its bifurcating branch) a single "BP" is reported.
 * On the first step after a start, a test function whose value at the start
 * point is negligible (|f_start| <= 1e-4 |f_1|) is not checked, so that
 * starting at a branch or limit point does not report that point again.
 *
 * Branch switching (cont_branch_direction).  At a simple branch point the
 * null space of A = [Jy Fp] is two-dimensional and contains the known tangent
 * t1.  The new direction is the unit null vector W-orthogonal to t1, found
 *   - dense: from the SVD of A (LAPACK dgesvd; the two right singular vectors
 *     of the smallest singular values), with a check that the null space is
 *     really two-dimensional (sigma_min / sigma_max <= 1e-6);
 *   - KLU or MUMPS: from the bordered (Govaerts) system
 *       [A; (W t1)^T  b; c^T 0] [phi; mu] = [0; 0; 1],
 *     with fixed pseudo-random b, c: it is regular when [A; (W t1)^T] has a
 *     one-dimensional null space, and then mu = 0 and phi spans it, so no
 *     singular matrix is ever factorised.  The residual |A phi| is checked.
 * Continue with cont_start_tangent(y_bp, p_bp, +t2) and (-t2).  The predictor
 * leaves the branch point along t2 and the corrector hyperplane, orthogonal to
 * t2, cuts the second branch transversally (Keller 1977).
 *
 * Linear solver.  CONT_LINSOL_AUTO picks MUMPS when the user's Jy is sparse
 * and n > CONT_AUTO_KLU_N (200), dense otherwise.  Dense LU costs (2/3) n^3
 * flops per Newton iteration: at n = 200 about 5 Mflop (a few ms), where a
 * sparse factorisation's analysis and indirect addressing stop paying off
 * for the block-sparse Jacobians of mechanics problems; from a few hundred
 * unknowns on dense LU dominates the run time.
 * CONT_LINSOL_MUMPS: MUMPS's unsymmetric multifrontal LU of the whole
 * bordered matrix (cont_mumps.h), METIS ordering, symbolic analysis redone
 * only when the pattern of the bordered matrix changes, workspace
 * relaxation doubled and the factorisation retried on INFO -8/-9.  When
 * the problem declares Jy symmetric (cont_problem.jac_symmetric), the
 * corrector's and tangents' bordered systems are instead solved by block
 * elimination on MUMPS's LDL^T of Jy alone (cont_blockelim.c), each solve
 * checked against the bordered matrix, with this LU as the fallback where
 * Jy is singular or the elimination inaccurate (continuation/README.md,
 * "Block elimination"); KINSOL's systems stay LU.
 * CONT_LINSOL_KLU: KLU (COLAMD ordering), kept for comparison and for
 * banded problems, where it is faster than MUMPS (Bratu, n = 400, tests).
 * On saddle-point Jacobians (KKT matrices with a zero multiplier block)
 * KLU's partial pivoting fills in badly: on the 5x5 Miura sheet in the
 * pose formulation (n = 2034, 57k nonzeros) one bordered factorisation takes
 * 0.40 s with KLU and 8.4 ms with MUMPS inside the engine
 * (continuation/README.md).
 * A dense Jy may be used with a sparse solver (all n^2 entries are stored)
 * and a sparse Jy with the dense solver (it is scattered), which is how the
 * paths are compared in the tests.
 *
 * LIFE CYCLE (SUNDIALS style; the caller drives the loop, GSL style)
 *
 *     cont_solver *s;
 *     if (cont_create(&prob, CONT_LINSOL_AUTO, &s) != CONT_OK) {
 *         ... s ? cont_errmsg(s) : "out of memory" ...; cont_free(s);
 *     }
 *     cont_set_step(s, 0.01, 1e-8, 0.2);  cont_set_prange(s, 0.0, 4.0);
 *     if (cont_start(s, y0, p0, +1) != CONT_OK) ... cont_errmsg(s) ...
 *     int st;
 *     while ((st = cont_step(s)) == CONT_CONTINUE) {
 *         const cont_point *pt = cont_get_point(s);   ... use pt ...
 *     }
 *     if (st == CONT_FAIL) ... cont_errmsg(s) ...
 *     cont_free(s);
 *
 * cont_run(s) is that loop.  A point callback (cont_set_callback) sees every
 * delivered point, including the start point and located special points,
 * and may stop the run.  Points are delivered in order of arclength.
 *
 * The library never prints and never exits.  Functions return CONT_OK (0)
 * or a negative CONT_E* code; cont_step returns CONT_CONTINUE, CONT_DONE or
 * CONT_FAIL.  The first error since creation or the last cont_start* call is
 * kept in the solver (cont_errmsg); KINSOL's own messages are captured, never
 * printed.  No global mutable state: several solvers may run in parallel
 * threads provided the user's callbacks allow it.
 */
#ifndef CONT_H
#define CONT_H

#include <stddef.h>
#include <sundials/sundials_matrix.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* ---- status codes -------------------------------------------------- */
enum {
    CONT_OK = 0,
    CONT_CONTINUE = 1,   /* cont_step: a new point is available */
    CONT_DONE = 2,       /* cont_step/cont_run: a stop rule ended the run */
    CONT_FAIL = -1,      /* cont_step/cont_run: the run failed (see cont_errmsg) */
    CONT_EINPUT = -2,    /* bad argument or option */
    CONT_ENOMEM = -3,
    CONT_ENUMERIC = -4,  /* Newton failure, singular matrix, not a branch point */
    CONT_EUSER = -5,     /* a user callback (Jacobian pattern, test fn) failed */
    CONT_ESTATE = -6     /* call out of order (e.g. cont_step before cont_start) */
};

/* Kind of matrix the user's Jacobian callback fills. */
enum { CONT_MATRIX_DENSE = 0, CONT_MATRIX_SPARSE = 1 };

/* Linear solver for the bordered (n+1) systems. */
enum { CONT_LINSOL_AUTO = 0, CONT_LINSOL_DENSE = 1, CONT_LINSOL_KLU = 2,
       CONT_LINSOL_MUMPS = 3 };
#define CONT_AUTO_KLU_N 200   /* AUTO: sparse (MUMPS) above this n */

/* Point types (cont_point.type). */
enum {
    CONT_PT_REGULAR = 0,
    CONT_PT_LP = 1,      /* limit point: t_p = 0 */
    CONT_PT_BP = 2,      /* simple branch point: det [Jy Fp; t^T] = 0 */
    CONT_PT_USER = 3,    /* zero of user test function user_index */
    CONT_PT_EP = 4       /* end point of the run */
};

/* Detection mask (cont_set_detect). */
enum { CONT_DETECT_LP = 1u, CONT_DETECT_BP = 2u, CONT_DETECT_USER = 4u,
       CONT_DETECT_ALL = 7u };

/* Why a run ended (cont_stop_reason). */
enum {
    CONT_STOP_NONE = 0,      /* still running, or not started */
    CONT_STOP_PMIN = 1,
    CONT_STOP_PMAX = 2,
    CONT_STOP_MAXSTEPS = 3,
    CONT_STOP_MAXARC = 4,
    CONT_STOP_CALLBACK = 5,
    CONT_STOP_DSMIN = 6,     /* failure: step size fell below ds_min */
    CONT_STOP_ERROR = 7      /* failure: user callback or internal error */
};

/* ---- problem --------------------------------------------------------- */

/* F = F(y, p), n values.  Return 0 on success, nonzero on failure (the
 * engine then treats the attempt as failed and cuts the step). */
typedef int (*cont_residual_fn)(const double *y, double p, double *F,
                                void *user);

/* Jy = dF/dy (n x n) and Fp = dF/dp (n values).  Jy is a SUNDenseMatrix, or
 * a CSC SUNSparseMatrix, as declared in cont_problem.jac_matrix; the engine
 * zeroes Jy (for sparse: data, row indices and column pointers) and Fp before
 * every call, so the user fills the whole structure each time.  A sparse Jy
 * may be enlarged with SUNSparseMatrix_Reallocate; the pattern may change
 * between calls (the sparse solver then re-analyses).  Row indices within a column may
 * be unsorted; duplicate entries are refused.  Return 0 on success. */
typedef int (*cont_jacobian_fn)(const double *y, double p, SUNMatrix Jy,
                                double *Fp, void *user);

/* Optional proximal anchor, for problems whose Jacobian carries a
 * regularisation -eps D on some unknowns (e.g. the multipliers of nearly
 * dependent constraints) that F itself does not: on = k >= 1 makes F
 * include -eps_k D (y - ya) on those rows, anchored at ya = y (the given
 * state), and the Jacobian carry -eps_k D, so that it is F's exact
 * Jacobian; eps_1 = the problem's eps, each further level a smaller weight
 * (the problem's choice; sf_equil_anchor: 10 times smaller), which
 * resolves constraint directions that eps hides at the price of
 * conditioning.  on = 0 (y NULL) restores the plain F.  The corrector
 * retries an attempt that stagnated at a residual floor near the
 * tolerance with it (levels 1 to 5, each from the best point the earlier
 * ones reached; 5 only after 1 to 4 failed), and once that succeeded,
 * tries it first at every later attempt of the run, from the level that
 * succeeded (at most 4); a result is kept
 * only if the plain F meets the tolerance.  Return 0 on success. */
typedef int (*cont_anchor_fn)(const double *y, double p, int on, void *user);

/* Optional user test functions: out[k], k < ntest, at the point (y, p) with
 * unit tangent (ty, tp).  A zero between consecutive points is located and
 * reported as a special point.  Return 0 on success (nonzero stops the run
 * with CONT_FAIL). */
typedef int (*cont_test_fn)(const double *y, double p, const double *ty,
                            double tp, double *out, void *user);

typedef struct cont_problem {
    long n;                       /* dimension of y (>= 1) */
    cont_residual_fn residual;    /* required */
    cont_jacobian_fn jacobian;    /* required */
    int jac_matrix;               /* CONT_MATRIX_DENSE or CONT_MATRIX_SPARSE */
    long jac_nnz;                 /* initial capacity of a sparse Jy (0: 8 n) */
    int ntest;                    /* number of user test functions (0: none) */
    cont_test_fn test;            /* required if ntest > 0 */
    const char *const *test_labels; /* optional ntest labels (<= 15 chars) */
    /* Optional Newton scaling, passed to KINSOL: yscale[i] and pscale
     * multiply y[i] and p to make them O(1) (KINSOL's uscale); fscale[i]
     * multiplies F[i] (KINSOL's fscale), so ftol applies to fscale*F.
     * NULL / 0 mean 1.  The arrays are copied at cont_create. */
    const double *yscale;
    double pscale;
    const double *fscale;
    cont_anchor_fn anchor;        /* optional (NULL: none) */
    /* nonzero: Jy is symmetric (to round-off) at every (y, p).  With a
     * sparse Jy and MUMPS the tangent/corrector bordered systems are then
     * solved by block elimination on the LDL^T of Jy, falling back to the
     * LU of the whole bordered matrix where that is not accurate
     * (continuation/README.md, "Block elimination"); checked: a Jy that
     * is not symmetric is factorised whole. */
    int jac_symmetric;
    void *user;                   /* passed to every callback */
} cont_problem;

/* ---- points and statistics ------------------------------------------ */

typedef struct cont_point {
    long index;          /* 0 for the start point, then 1, 2, ... */
    const double *y;     /* n values */
    double p;
    const double *ty;    /* unit tangent: a^2 sum w_i ty_i^2 + theta^2 tp^2 = 1
                            (the norm's weights, scale and theta) */
    double tp;
    double s;            /* arclength from the start point (W-norm) */
    double ds;           /* step that produced the point (special points:
                            arclength offset h from the previous point) */
    int newton_iters;    /* corrector iterations for this point */
    double resnorm;      /* max_i |F_i(y, p)|, unscaled */
    int type;            /* CONT_PT_* */
    int user_index;      /* CONT_PT_USER: which test function (0-based) */
    char label[16];      /* "", "LP", "BP", "EP" or the user test label */
    double time;         /* wall-clock seconds since cont_start* */
    double loc_err;      /* special points: final bracket width in h */
    int det_sign;        /* sign of det [Jy Fp; (W t)^T], 0 if unavailable */
    double log_abs_det;  /* log |det [Jy Fp; (W t)^T]| */
    const double *test; /* ntest user test values (NULL when ntest == 0) */
    int jy_inertia;      /* 1: jy_neg and jy_null hold the inertia of Jy at this point
                            (cont_set_point_inertia), 0: not known */
    long jy_neg;         /* negative pivots of the LDL^T of Jy (its negative eigenvalues) */
    long jy_null;        /* pivots MUMPS found null */
} cont_point;

/* Nonzero return value asks the engine to stop (cont_step -> CONT_DONE). */
typedef int (*cont_point_fn)(const cont_point *pt, void *data);

typedef struct cont_stats {
    long steps;          /* accepted continuation steps */
    long points;         /* points delivered (regular, special, start) */
    long newton_iters;   /* KINSOL iterations (corrector, location, landing) */
    long nres;           /* residual evaluations */
    long njac;           /* Jacobian evaluations */
    long nfactor;        /* factorisations of bordered matrices (LU, or block
                            elimination on the LDL^T of a symmetric Jy) */
    long nlinsolve;      /* linear solves with those factors */
    long nfallback;      /* block eliminations (jac_symmetric) given up for the
                            LU of the whole bordered matrix */
    long retries;        /* rejected step attempts (step size cut) */
    long nlocate;        /* corrected trial points while locating zeros */
    double ds;           /* step size of the last accepted step */
    double wall;         /* wall-clock seconds (CLOCK_MONOTONIC) */
} cont_stats;

typedef struct cont_solver cont_solver;

/* ---- life cycle ------------------------------------------------------ */

/* Create a solver for prob with linear solver linsol (CONT_LINSOL_*).
 * Returns CONT_OK, or an error code; *out is NULL only when the solver
 * itself could not be allocated, otherwise it holds the message and must be
 * released with cont_free. */
int cont_create(const cont_problem *prob, int linsol, cont_solver **out);
void cont_free(cont_solver *s);

/* ---- options (each returns CONT_OK or CONT_EINPUT) -------------------- */

/* initial step, smallest and largest step (W-norm); defaults 0.01, 1e-8, 0.1 */
int cont_set_step(cont_solver *s, double ds0, double ds_min, double ds_max);
/* grow factor (>1, default 1.5) applied when the corrector took <= fast_iters
 * iterations (default 3); shrink factor in (0,1) (default 0.5) on failure;
 * largest tangent turn per step in radians (default 0.5; <= 0 disables). */
int cont_set_step_control(cont_solver *s, double grow, double shrink,
                          int fast_iters, double max_angle);
/* parameter window; default (-inf, +inf) */
int cont_set_prange(cont_solver *s, double p_min, double p_max);
/* default 1000 steps; <= 0 means no limit */
int cont_set_max_steps(cont_solver *s, long max_steps);
/* default +inf */
int cont_set_max_arclength(cont_solver *s, double s_max);
/* weight of p in the arclength norm, > 0, default 1 */
int cont_set_theta(cont_solver *s, double theta_p);
/* weights of the components of y in the arclength norm:
 * |(dy, dp)|_W^2 = sum_i w[i] dy_i^2 + theta^2 dp^2, w[i] >= 0 (not all 0);
 * NULL restores w = 1 (the default).  Copied.  A zero weight leaves a
 * component out of the arclength, e.g. Lagrange multipliers, whose rates
 * can dwarf those of the coordinates; the bordered systems stay regular as
 * long as the tangent has a non-zero weighted part.  Branch directions are
 * then W-orthogonal in this norm. */
int cont_set_weights(cont_solver *s, const double *w);
/* |(dy, dp)|_W: the length of a change dy (n) of y and dp of p in the
 * arclength norm (weights, cont_set_arc_scale, theta_p) */
double cont_arc_norm(const cont_solver *s, const double *dy, double dp);
/* the y part of the arclength norm scaled by a > 0 (default 1):
 * |(dy, dp)|^2 = a^2 sum_i w[i] dy_i^2 + theta^2 dp^2, in the steps, the
 * border row and the tangent's normalisation; the corrector's step test
 * (|last Newton step| <= xtol (1 + |u|), weighted by w) keeps w alone.  E.g.
 * a = 1 / sqrt(count of weighted components): an RMS measure of dy whose
 * steps mean the same on a small and a large problem. */
int cont_set_arc_scale(cont_solver *s, double a);
/* on != 0: the reusing corrector (CONT_CORRECTOR_REUSE, no line search)
 * solves the problem's anchored system (cont_anchor_fn) first at every
 * step from the first one, and at the landing on the end of the p
 * window, not only after a residual floor was met: from the predictor,
 * anchored at its multipliers, at the smaller weights of the next levels
 * while a level converges but the plain F stays above ftol; a result is
 * kept only if the plain F meets ftol, else the plain correctors follow
 * as without it.  A point of the first level is then re-anchored at
 * itself twice (proximal iterations with the same factors), which removes
 * most of the anchor's bias eps D (y - ya) from the state, also before the
 * next level is tried where the plain F misses ftol there (a miss by the
 * bias is not a floor: the smaller weights would stay for the rest of the
 * run, and the second-order predictor off); these iterations are not
 * counted by the step control.  For long steps on problems whose Jacobian is singular
 * at the solutions in directions it is not singular in nearby (e.g. self-
 * stresses of constraints that exist only on the solution set), where the
 * plain Newton converges only linearly.  Default 0. */
int cont_set_anchor_first(cont_solver *s, int on);
/* the predictor of a step of length ds from x with tangent t: order 1 (the
 * default) x + ds t; order 2 adds the curvature estimated from the change
 * of the tangent over the last step (length h, tangent t_prev before it):
 * x + ds t + ds^2 / 2 (t - t_prev) / h; its error is O(ds^3) instead of
 * O(ds^2), so a longer step starts as close to the branch.  The first
 * step after a start or a branch switch is of order 1, and so is every
 * step once a residual floor was met (an anchored solve needed a level
 * above 1: the tangents there are fixed only to the floor's accuracy). */
int cont_set_predictor(cont_solver *s, int order);
/* corrector: tolerance on max|fscale F| (default 1e-10), iterations
 * (default 10), strategy KIN_NONE (0, default) or KIN_LINESEARCH (1) */
int cont_set_newton(cont_solver *s, double ftol, int max_iters, int strategy);
/* second convergence test (AUTO-like): the last Newton step, in KINSOL's
 * scaled 2-norm, must be <= xtol (1 + |u|) (default 1e-6; 0 disables).  A
 * residual below ftol alone is not enough where F is flat, e.g. next to a
 * branch point; if KINSOL stopped on the residual with a larger step, up to
 * 5 more exact Newton iterations are made, else the attempt fails. */
int cont_set_newton_steptol(cont_solver *s, double xtol);
/* the corrector of the continuation steps: CONT_CORRECTOR_NEWTON (KINSOL,
 * one factorisation per iteration, then a fresh one at the corrected point
 * for its tangent and determinant) or CONT_CORRECTOR_REUSE (the engine's
 * own Newton, the same iterates and tests, one factorisation per point
 * when the refinements of ALGORITHM contract).  REUSE falls back to
 * NEWTON where it does not apply (line search, no convergence).  Default:
 * REUSE with a sparse bordered solver (KLU, MUMPS), NEWTON with the dense
 * one. */
enum { CONT_CORRECTOR_NEWTON = 0, CONT_CORRECTOR_REUSE = 1 };
int cont_set_corrector(cont_solver *s, int kind);

/* on = 1: every corrected point is evaluated with a factorisation of its
 * own tangent matrix (instead of the corrector's last factors refined),
 * and where that is the LDL^T of a symmetric Jy (cont_problem.jac_symmetric,
 * MUMPS, block elimination) its inertia is delivered with the point
 * (cont_point.jy_inertia, jy_neg, jy_null): one factorisation a point
 * serves the tangent, the determinant sign and a caller's stability test
 * (src/analysis/stability/stability.c).  Default 0. */
int cont_set_point_inertia(cont_solver *s, int on);
int cont_get_corrector(const cont_solver *s);
/* the fixed-p solves of cont_solve_fixed / cont_start: default 50 iterations,
 * KIN_LINESEARCH.  With CONT_CORRECTOR_REUSE they first run the engine's
 * own Newton (full steps; with KIN_LINESEARCH only while each step lowers
 * the scaled residual), then KINSOL with this strategy from the same guess
 * if that does not converge. */
int cont_set_newton_init(cont_solver *s, int max_iters, int strategy);
/* which test functions to monitor (CONT_DETECT_* mask, default ALL) and the
 * location tolerance (default 1e-10) */
int cont_set_detect(cont_solver *s, unsigned mask, double loc_tol);
/* called for every delivered point; NULL removes it */
int cont_set_callback(cont_solver *s, cont_point_fn fn, void *data);
/* keep every delivered point for cont_point_at (default 1); special points
 * are always kept */
int cont_set_store(cont_solver *s, int store_points);

/* ---- running --------------------------------------------------------- */

/* Newton (KINSOL) on F(y, p) = 0 with p fixed; y is the initial guess on
 * entry and the solution on success. */
int cont_solve_fixed(cont_solver *s, double *y, double p);

/* Start a branch at (y0, p0): solve F(y, p0) = 0 from y0 at fixed p0, then
 * take the tangent with sign(t_p) = dir (+1 or -1).  Delivers the start
 * point (index 0).  Discards the points of any previous run. */
int cont_start(cont_solver *s, const double *y0, double p0, int dir);

/* Start at (y0, p0) with the given tangent direction (ty0, tp0) (normalised
 * here; e.g. from cont_branch_direction, or its negative).  The point is
 * corrected in the hyperplane orthogonal to the tangent only if its residual
 * exceeds ftol.  Delivers the start point. */
int cont_start_tangent(cont_solver *s, const double *y0, double p0,
                       const double *ty0, double tp0);

/* One step: delivers the next point (a located special point or the next
 * point of the branch).  Returns CONT_CONTINUE, CONT_DONE (the delivered
 * point was the last one) or CONT_FAIL (no new point; see cont_errmsg). */
int cont_step(cont_solver *s);

/* cont_step until it stops; returns CONT_DONE or CONT_FAIL. */
int cont_run(cont_solver *s);

/* ---- results --------------------------------------------------------- */

/* Last delivered point (NULL before cont_start).  Pointers returned by the
 * getters stay valid until the next cont_step (cont_get_point with
 * store = 0), or until the next cont_start* / cont_free. */
const cont_point *cont_get_point(const cont_solver *s);
long cont_num_points(const cont_solver *s);              /* stored points */
const cont_point *cont_point_at(const cont_solver *s, long i);
long cont_num_special(const cont_solver *s);
const cont_point *cont_special_at(const cont_solver *s, long i);

/* Statistics of the last step (last) and since cont_start* (total);
 * either may be NULL. */
int cont_get_stats(const cont_solver *s, cont_stats *last, cont_stats *total);
int cont_stop_reason(const cont_solver *s);
const char *cont_stop_name(int reason);
/* First error message ("" if none). */
const char *cont_errmsg(const cont_solver *s);
/* The linear solver in use (CONT_LINSOL_DENSE, _KLU or _MUMPS). */
int cont_get_linsol(const cont_solver *s);

/* What the last factorisation of the tangent/corrector matrix cost, as
 * MUMPS reports it: the matrix factorised (n: Jy alone for its LDL^T,
 * ldlt = 1, or the whole bordered matrix for the LU), the entries of its
 * factors (INFOG(29)), its floating-point operations (RINFOG(3)) and the
 * pivots it delayed (INFOG(13)).  0, or -1 when there is none (not
 * factorised yet, or not by MUMPS). */
typedef struct cont_factor_stats {
    long n;
    int ldlt;
    double entries, flops;
    long delayed;
} cont_factor_stats;
int cont_get_factor_stats(const cont_solver *s, cont_factor_stats *fs);
/* Step size the next step will try. */
double cont_get_ds(const cont_solver *s);
/* Set the step size the next step will try (clamped to [ds_min, ds_max]),
 * e.g. from the point callback, which sees each point before the next step
 * is taken, when it predicts special points the engine's tests cannot
 * separate.  Later steps grow from it as usual. */
int cont_set_next_step(cont_solver *s, double ds);

/* ---- branch switching ------------------------------------------------ */

/* At a simple branch point (y, p) with tangent (ty, tp) along the known
 * branch, compute the unit tangent (ty_new, tp_new) of the other branch
 * direction (W-orthogonal to (ty, tp) in the null space of [Jy Fp]).  Its
 * sign is normalised so that its largest component is positive; continue
 * with both +t and -t.  Returns CONT_ENUMERIC if the null space of
 * [Jy Fp] is not two-dimensional at (y, p) (not a simple branch point). */
int cont_branch_direction(cont_solver *s, const double *y, double p,
                          const double *ty, double tp,
                          double *ty_new, double *tp_new);

/* The papers this engine implements, one per line. */
const char *cont_reference(void);

#endif
