/* flatstart.h - start of an exact path at the flat state from the limit of
 * the branch (see the comment at the top of flatstart.c). */
#ifndef SF_FLATSTART_H
#define SF_FLATSTART_H

#include "equilibrium.h"

/* The limit problem (flatstart.c):
 *     (H0 + sum_s nu_s G_s) u + J1^T mu + gp = 0,  J1 u + c1 = 0,
 *     u^T G_s u / 2 = 0  (s < n2),
 * unknowns z = (u, mu, nu), n = nq + n1 + n2.  U and cp belong to the
 * equilibrium start (may be NULL otherwise). */
typedef struct sf_limit {
    int nq, ncon, n1, n2, n;
    double *H0, *gp;          /* nq x nq (row-major, symmetric), nq */
    double *cp;               /* ncon: d g / dp of the scaled rows */
    double *U;                /* ncon x ncon left singular vectors of the scaled J(0), column-major */
    double *J1;               /* n1 x nq */
    double *c1;               /* n1 */
    /* Hessians G_s of the second-order combinations, sparse (each is local
     * to the folds of the vertices it combines; a dense n2 x nq x nq array
     * took gigabytes on tessellations): the entries k in [Gp[s], Gp[s+1])
     * are G_s(Gi[k], Gj[k]) = Gx[k]. */
    long *Gp;                 /* n2 + 1 */
    int *Gi, *Gj;
    double *Gx;
} sf_limit;

/* Set L's G_s from n2 dense nq x nq row-major matrices G (the nonzeros
 * are copied); free with sf_limit_free_G.  Returns nonzero when out of
 * memory. */
int sf_limit_set_G_dense(sf_limit *L, const double *G);
void sf_limit_free_G(sf_limit *L);

/* Solve the limit problem by the eps homotopy (flatstart.c), at most maxit
 * Newton iterations in all; z (n values) receives the solution.  Returns
 * the final max-norm of the residual (>= 1 when the homotopy did not reach
 * eps = 0), -1 when out of memory.  iters may be NULL. */
double sf_limit_solve(const sf_limit *L, double *z, int maxit, int *iters);

/* Build the limit problem at the flat state q = 0 and parameter p0 (the
 * exact loop rows of q split into first- and second-order combinations);
 * free with sf_limit_free.  Used by flatstart.c and flatswitch.c. */
int sf_limit_build(sf_equil *q, double p0, sf_limit *L, sf_error *err);
void sf_limit_free(sf_limit *L);

/* The state y (q->n values) of the exact problem at p0 + dp for the limit
 * solution z = (u, mu, nu): coordinates dp u, first-order multipliers
 * dp mu, second-order ones nu (scaled back to the rows). */
void sf_limit_to_state(const sf_equil *q, const sf_limit *L, const double *z, double dp, double *y);

typedef struct sf_flatstart_info {
    int iterations;          /* Newton iterations of the limit problem */
    double residual;         /* its final scaled residual */
    int first_order_rows;    /* loop-row combinations with a gradient at q = 0 */
    int second_order_rows;   /* combinations of zero gradient at q = 0 */
    int cone_dim;            /* first-order motions (kernel of those rows) */
    int cone_forms;          /* independent second-order conditions on them */
    int branches;            /* stable branches found on the tangent cone */
    int ties;                /* of them, sharing the lowest energy */
    int chosen;              /* the one followed (1-based), 0: none */
    int degenerate;          /* 1: the start is on a degenerate ray (flatcone.h) */
    int unstable;            /* 1: branches on the cone, none of them stable */
    int descended;           /* stable states found next to the unstable first
                                point (sf_flat_descend), 0: none tried/found */
    double amplitude;        /* max |fold coordinate| of the guess at p1 */
    char note[1000];         /* what was found and chosen, for the output */
} sf_flatstart_info;

/* Guess y (q->n values) of the exact problem at p1 near the flat state,
 * which solves the problem at p0: y = (dp u, multipliers) with the limit
 * problem's u and multipliers, dp = p1 - p0.  Needs exact loop rows and no
 * support rows (their limit is not set up).  info may be NULL. */
int sf_equil_start_limit(sf_equil *q, double p0, double p1, double *y,
                         sf_flatstart_info *info, sf_error *err);

/* The same, following the branch-th stable branch of the tangent cone by
 * energy (1: lowest; flatcone.h, solver.flat_branch).  Without a branch
 * on the cone (the driving acts at second order only, a prescribed
 * displacement) the eps homotopy of sf_limit_solve.  info->note says
 * what the cone held and what was chosen.  SF_EINPUT when branch exceeds
 * the stable branches found. */
int sf_equil_start_limit_branch(sf_equil *q, double p0, double p1, int branch, double *y,
                                sf_flatstart_info *info, sf_error *err);

/* Start the continuation solver cs (created for q) at p1 off the flat
 * state, which solves the problem at p0: cont_start from the limit guess,
 * and if that fails from sf_equil_start_off_flat's penalty homotopy.  y
 * (q->n values) receives the guess used.  SF_OK, or the error with both
 * reasons.  branch and info (may be NULL) as for
 * sf_equil_start_limit_branch. */
struct cont_solver;
/* On a degenerate ray (info->degenerate) sf_equil_start_flat also sets
 * q->reg_rel = SF_FLAT_REG_REL, q->reg_min = SF_FLAT_REG_MIN for the whole
 * path: the KKT regularisation relative to the squared motion
 * (sf_equil_reg_eps, equilibrium.h); the pose formulation's start
 * (equilibrium_poses.c) the SF_FLAT_REG_*_POSES pair.  Measured on the
 * 2x2 Miura sheet under tip loads of 0.01 to 1 N (docs/flatstart.md). */
#define SF_FLAT_REG_REL 2e-5
#define SF_FLAT_REG_MIN 1e-14
/* The hint of a failed flat start of the fold formulation (flatstart.c):
 * the pose formulation's sparse start, which src/cli/run.c tries by itself
 * where "auto" chose the fold formulation */
#define SF_FLAT_POSES_HINT " (another start to try: solver.formulation = \"poses\", " \
                           "analysis.flat_start = \"sparse\")"
#define SF_FLAT_REG_REL_POSES 2e-7
#define SF_FLAT_REG_MIN_POSES 1e-16
int sf_equil_start_flat(sf_equil *q, struct cont_solver *cs, double p0, double p1, int dir,
                        double tol, double *y, int branch, sf_flatstart_info *info, sf_error *err);

/* The start of sf_equil_start_flat (branch 1) solved to the tolerance tol
 * with a solver of its own: y (q->n values) receives the converged state
 * at p1.  For starting another formulation of the same problem from a
 * converged state (equilibrium_poses.c).  SF_OK or the error. */
int sf_equil_start_flat_solved(sf_equil *q, double p0, double p1, int dir, double tol, double *y,
                               sf_error *err);

/* The stable states next to an unstable first point y at p1 (fold
 * coordinates; flatdescend.c): Newton at fixed p1 with cs (a solver of
 * its own: its current point changes) from y pushed
 * either way along the direction of negative curvature of the reduced
 * Hessian.  At most two, lowest energy first; ties = 1 when their
 * energies are equal to 1e-7 (mirror images: the driving selects neither). */
typedef struct sf_flat_descent {
    int saddle_morse;        /* Morse index at y */
    double saddle_eig;       /* its lowest reduced eigenvalue */
    double saddle_energy;    /* its energy [J] */
    double dist[2];          /* max |fold coordinate - the saddle's| */
    int returned;            /* pushes after which Newton came back to the saddle */
    double push, back;       /* largest push [rad], farthest such return */
    double sv_cut;           /* smallest relative singular value of the rows
                                counted as constraints at the saddle */
    int nfound;              /* stable states found (0..2) */
    int ties;
    double *y;               /* nfound x q->n states (malloc'd) */
    double energy[2], eig[2];   /* energy [J], lowest reduced eigenvalue */
} sf_flat_descent;
int sf_flat_descend(sf_equil *q, struct cont_solver *cs, double p1, const double *y,
                    sf_flat_descent *out);
void sf_flat_descent_free(sf_flat_descent *d);
/* sf_equil_start_flat's last step when every branch of the cone is
 * unstable (info->unstable): cs's current point is unstable; the
 * branch-th stable state next to it by energy (sf_flat_descend) replaces
 * it (y receives it), and info->note says what was found, or why none
 * was (pushes that Newton brings back to the saddle: its negative
 * curvature lies where constraint rows of tiny gradient block it).  None
 * found: the unstable start stands, SF_OK. */
int sf_flat_start_descend(sf_equil *q, struct cont_solver *cs, double p1, int dir, double tol,
                          double *y, int branch, sf_flatstart_info *info, sf_error *err);

#endif
