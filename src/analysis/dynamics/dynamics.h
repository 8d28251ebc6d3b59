/* dynamics.h - quasi-dynamic folding trajectories (MODEL.md section 7),
 * integrated with SUNDIALS IDA.
 *
 * Equations.  With the potential Pi(q; t), the constraint rows g(q; t) of
 * the equilibrium problem (loop closure and supports, equilibrium.h), their
 * Jacobian J and multipliers lambda:
 *   M(q) q'' + C q' + grad Pi + J^T lambda = 0,   g(q) = 0.
 * C is constant and block diagonal: fold i contributes c_i G_i / G_i[0][0]
 * on its coordinates (theta_i, a_i1..a_iK), G_i the Gram matrix of its
 * curvature basis (shape.h), so the fold angle has damping c_i exactly
 * (folds[].damping, else analysis.damping) and the dissipation in the band
 * is that of a viscous band, (c_i / 2) int (kappa')^2 ds / int phi_0^2 ds,
 * which never damps one mode of a fold more than its bending resists it.
 *
 * Stabilised formulation.
 *  Overdamped (M = 0, the default): unknowns y = (q, lambda), q differential,
 *  lambda algebraic,
 *     C q' + grad Pi + J^T lambda = 0,   g(q; t) = 0.
 *  The position constraint itself is an equation of the DAE (index 2,
 *  Hessenberg form): every step solves g = 0 with the corrector, so the
 *  drift does not accumulate; lambda is left out of IDA's error test (it is
 *  the algebraic variable of an index-2 system).  This is what the
 *  Gear-Gupta-Leimkuhler formulation reduces to for a first-order system:
 *  the extra multiplier mu of GGL would enter as C^-1 J^T mu, in the same
 *  directions as lambda, and merges with it.
 *  With inertia (analysis.inertia = true): the Gear-Gupta-Leimkuhler
 *  formulation, unknowns y = (q, lambda, v, mu), q and v differential,
 *      M(q) v' + h(q, v) + C v + grad Pi + J^T lambda = 0,
 *      g(q; t) = 0,
 *      q' - v - Jh^T mu = 0,
 *      Jh v = 0,
 *  with Jh = S J, gh = S g the constraint rows scaled to O(1) (S the row
 *  scales of the equilibrium problem).  Position and velocity constraints
 *  both hold along the solution, where mu = 0; numerically mu absorbs the
 *  drift.  h(q, v) = sum_p m_p dx_p^T (d2x_p[v, v]) are the velocity terms
 *  of the accelerations.
 *
 * Consistent initial conditions.  The trajectory starts at rest (v = 0) in
 * a state with g = 0: the equilibrium at t = 0 (analysis.initial =
 * "equilibrium", found as the continuation finds its start point), or the
 * flat sheet ("flat").  IDACalcIC (IDA_YA_YDP_INIT) then computes q' and
 * lambda (and v', mu) on the index-1 form of the same system, whose
 * constraint rows are differentiated once in time (J q' + g_t = 0 in place
 * of g = 0, J v' = 0 in place of J v + g_t = 0); since g = 0 holds at the
 * start both forms agree there, and IDA is re-initialised with the
 * consistent values on the stabilised form.
 *
 * Mass (inertia only): the kinetic energy is integrated exactly for the
 * rigid faces (each face body split into triangles from its centroid,
 * three edge-midpoint points per triangle: exact for the quadratic
 * integrand) and with a 4 x 2 Gauss rule over each fold band (density
 * times thickness per reference area: bending keeps the band's area).
 * M(q) = sum_p m_p dx_p^T dx_p.
 *
 * Jacobian: analytic and dense (as the equilibrium solver), F_y + cj F_y'.
 * Overdamped it is exact.  With inertia it omits two terms that need
 * third derivatives of the kinematic maps: the q-derivative of h(q, v)
 * beyond the change of dx_p, and the q-derivative of Jh v; both are of
 * order |v| or |v|^2 and IDA's Newton iteration is a modified Newton
 * iteration anyway.
 *
 * Rows are scaled by the equilibrium problem's fscale before IDA sees them
 * (this changes no solution, only the pivoting).  Tolerances: relative
 * analysis.tolerance (rtol); absolute 1e-2 rtol [rad] for the coordinates,
 * rtol / yscale for the multipliers (left out of the error test), rtol per
 * relaxation time [rad/s] for v and mu.
 *
 * Drift.  The constraint rows are equations of the DAE, so their residual
 * is whatever the corrector leaves.  IDA's usual Newton test (on the
 * weighted size of the last update, with a rate estimate kept from earlier
 * steps) may accept an iterate of the modified Newton iteration while g is
 * still at the level of the local error (1e-7 for square4 at rtol 1e-6).
 * The convergence test installed here adds one condition: the scaled
 * constraint rows of the accepted iterate are below solver.tolerance
 * (1e-10 by default: the equilibrium solver's Newton tolerance); otherwise
 * the iteration goes on.  The drift then stays at that level at every
 * step, independently of the length of the trajectory.
 *
 * Time histories (all piecewise linear, constant beyond their ends):
 *   p(t)      analysis.schedule (default: start to end over the duration),
 *             the parameter of analysis.parameter (load factor, actuation
 *             factor of analysis.group, or a prescribed displacement);
 *   load(t)   analysis.load_schedule when p is not the load (default
 *             analysis.load);
 *   group g   actuation[g].schedule: actuation factor of that group,
 *             overriding p for it.
 * The integrator stops at every kink of these histories (IDASetStopTime).
 * The run ends at analysis.duration, or earlier when every history has
 * ended and max |q'| < analysis.settle_tolerance (rad/s).
 */
#ifndef SF_DYNAMICS_H
#define SF_DYNAMICS_H

#include <sundials/sundials_matrix.h>

#include "equilibrium.h"
#include "kinematics.h"
#include "sf_error.h"

/* A piecewise-linear time history. */
typedef struct sf_schedule {
    int n;            /* points; 0 = not given */
    double *t, *v;
} sf_schedule;

/* Value at t (constant before the first and after the last point); the
 * slope (right derivative) in *slope when not NULL. */
double sf_schedule_eval(const sf_schedule *s, double t, double *slope);

typedef struct sf_dyn_stats {
    long steps;         /* IDA steps */
    long nres;          /* residual evaluations (IDA's count, including
                           those of IDACalcIC and of the Jacobian) */
    long njac;          /* Jacobian evaluations */
    long nni;           /* Newton iterations */
    long netf;          /* error test failures */
    long ncfn;          /* Newton convergence failures */
    long ic_nres;       /* residual evaluations of IDACalcIC */
    long nchecks;       /* evaluations of the constraint rows by the
                           Newton convergence test (each one residual) */
    long nextra;        /* Newton iterations the constraint rows added */
    double h;           /* last step size [s] */
    int order;          /* last BDF order */
    double wall;        /* seconds in sf_dyn_start and sf_dyn_step */
} sf_dyn_stats;

struct sf_dyn_ida;

typedef struct sf_dyn {
    const sf_model *m;
    sf_equil eq;          /* potential, constraint rows, scales */
    int inertia;
    int nq, ncon, n;      /* DAE unknowns: n = nq + ncon (+ nq + ncon with inertia) */
    int ov, om;           /* offsets of v and mu (inertia) */
    double *C;            /* nq x nq damping matrix, row-major */
    double cmin_tau;      /* smallest c_i / k_i [s] */
    /* time histories */
    double duration, p_start, p_end, settle_tol, rtol;
    double ctol;          /* constraint rows at every step: max |fscale g| (solver.tolerance) */
    long max_steps;
    int initial_flat;
    sf_schedule psched, lsched, *gsched;   /* gsched[ngroups] */
    double t_hist_end;    /* last point of any history */
    /* mass points (inertia) */
    int nmass;
    sf_mpoint *mpt;
    double *mw;           /* mass of each point [kg] */
    /* state */
    double t;             /* current time */
    double *y, *yp;       /* n values: (q, lambda[, v, mu]) and their rates */
    double p, load;       /* parameter and load factor at the time of the
                             last evaluation (sf_dyn_set_time) */
    double teval, pslope; /* that time, and dp/dt there */
    double load_fixed;    /* analysis.load */
    int done;             /* 1: final time reached; 2: settled */
    int ic_mode;          /* residual in its index-1 (initial condition) form */
    sf_dyn_stats stats;
    long ic_nje, ic_nni;  /* Jacobians and Newton iterations of IDACalcIC */
    struct sf_dyn_ida *ida;
    /* scratch */
    double *Jc, *Hc, *work, *F, *Fp;
    sf_error *err;        /* error of a callback (first wins) */
} sf_dyn;

/* Set up from the study of m (analysis.* keys, folds[].damping,
 * actuation[].schedule): builds the equilibrium problem, damping, masses
 * and histories.  Checks the keys (one-line messages with file and line). */
int sf_dyn_init(sf_dyn *d, const sf_model *m, sf_error *err);
void sf_dyn_free(sf_dyn *d);

/* Initial state, IDA, consistent initial conditions (IDACalcIC). */
int sf_dyn_start(sf_dyn *d, sf_error *err);

/* One IDA step (stopping at the kinks of the histories and at the final
 * time).  Sets d->done when the run is over.  Returns SF_OK or an error. */
int sf_dyn_step(sf_dyn *d, sf_error *err);

/* Quantities of the current state: potential energy Pi [J], kinetic
 * energy [J] (0 when overdamped), constraint drift max |g| over every
 * constraint row (loop rows: rotation entries and translation [m];
 * supports [m]) and the speed max |q'| [rad/s]. */
void sf_dyn_report(sf_dyn *d, double *Pi, double *kinetic, double *drift,
                   double *speed);

/* Rest angles and load factors at time t into d->eq.par (for the caller's
 * own evaluations with the equilibrium functions: after this call,
 * sf_equil_residual(y, d->p, ...) is the static problem at time t). */
void sf_dyn_set_time(sf_dyn *d, double t);

/* The DAE itself, as IDA sees it (rows scaled): residual R(t, y, y') and
 * Jacobian dR/dy + cj dR/dy' into the n x n dense matrix A.  With inertia
 * they need sf_dyn_start first.  Return 0, or 1 where the state is not
 * admissible (non-finite values). */
int sf_dyn_residual(sf_dyn *d, double t, const double *y, const double *yp, double *R);
int sf_dyn_jacobian(sf_dyn *d, double t, double cj, const double *y, const double *yp,
                    SUNMatrix A);

/* The damping matrix, built from the folds (also used by the tests). */
const double *sf_dyn_damping(const sf_dyn *d);

#endif
