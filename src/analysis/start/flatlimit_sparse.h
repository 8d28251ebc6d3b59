/* flatlimit_sparse.h - the limit problem of the branch that the driving
 * selects at the flat state, in face poses, with sparse matrices only (see
 * the comment at the top of flatlimit_sparse.c and docs/flatstart.md).
 *
 * A branch leaving the flat state y0 as y = y0 + h x + h^2 z + O(h^3),
 * lambda = nu + h mu + O(h^2) (h = p - p0) solves, order by order,
 *   H0 x + b + J^T mu + sum_r nu_r G_r x = 0,   J^T nu = 0,
 *   J x = 0,                                   J z + (x^T G_r x / 2)_r = 0,
 * (H0 the bending Hessian, b = dF/dp, J and G_r the gradients and
 * Hessians of the constraint rows, all at the flat state): the
 * stationarity of x^T H0 x / 2 + b . x on the tangent cone of the
 * constraints.  The driving's branch is a local minimum of it; Newton
 * (with an inertia correction) reaches one from the first-order response.
 * Newton reaches the nearest one, not necessarily the lowest (the 4x4
 * Miura sheet, docs/flatstart.md): sf_flat_limit_sparse tries a few starts
 * and keeps the lowest state found, which is not a global guarantee. */
#ifndef SF_FLATLIMIT_SPARSE_H
#define SF_FLATLIMIT_SPARSE_H

#include "equilibrium.h"

typedef struct sf_flatlimit_info {
    int iterations;     /* Newton iterations, all stages */
    int stages;         /* penalty stages */
    int pushes;         /* saddles left by a perturbation */
    int stable;         /* 1: the limit problem's inertia says minimum */
    int ties;           /* 1: the mirror start gave another state of equal energy */
    double energy;      /* x^T H0 x / 2 + b . x (J per unit p^2) */
    double energy_alt;  /* the same for the other start (ties test), NAN if none */
    double xdiff;       /* max |x - x_alt| over the fold coordinates, relative */
    double residual;    /* final scaled residual */
    int factorisations;  /* MUMPS LDL^T factorisations, all starts */
    int starts, converged;  /* candidate starts tried, converged */
    int chosen;         /* the candidate followed (index into cand_*) */
    /* the starts tried, in order (SF_LIMIT_FIRST, SF_LIMIT_RIGID,
     * SF_LIMIT_MIRROR): cand_conv 1 when Newton converged within its
     * budget (a stable limit state: the inertia is checked), and then its
     * energy, NAN when the mirror came back to the state it started from */
    int ncand;
    int cand_kind[3], cand_conv[3];   /* cand_conv -1: left, falling back to the flat state */
    int collapsed;      /* the last start was left falling back to the flat state */
    int eta_retry;      /* the first start was made again with the penalty stages from
                         * eta = 1e-9: 1 it fell back to the flat state, 2 its first
                         * stage made no progress (FIRST_STALL iterations) */
    double cand_energy[3];
    int first_bound;    /* 1: the first start's last stage was not run (the rigid start
                         * is lower than its energy at the stage before, a lower bound
                         * of the energy at the last), cand_energy[0] is that bound */
    /* the first start's last stage (eta = 1e-12) did not converge (scaled
     * residual last_res after last_its iterations): the state of the stage
     * before (eta = prev_eta) is taken */
    int prev_stage, last_its;
    double prev_eta, last_res;
} sf_flatlimit_info;

enum { SF_LIMIT_FIRST, SF_LIMIT_RIGID, SF_LIMIT_MIRROR };

/* Solve the limit problem at the flat state y0 (q->n values, poses
 * lifted), p0, from the first-order response u (sf_flat_direction).
 * w receives 2 q->n values: (x, mu) then (z, nu) in the layout of y
 * (coordinates, then constraint rows).  imperf: the declared imperfection
 * of the mode amplitudes (every shape-mode amplitude of the start moved
 * by imperf times the largest fold angle of u; 0 for none).  Starts: u;
 * then, on patterns with degree-4 interior vertices, the rigid-origami
 * motion of their closed-form modes (warm from the first solution, at
 * most 40 Newton iterations per stage), kept when its energy is lower by
 * more than 1e-7 relative (than the first start's energy at the penalty
 * stage before the last, a lower bound of its limit energy, whose last
 * stage is then not run: info->first_bound); when mirror is set, the
 * state kept with its mode amplitudes negated (its other unknowns as the first guess, at most
 * 30 iterations per stage): a distinct solution of equal energy (1e-7)
 * sets info->ties (the state kept before stays), a lower one replaces
 * it.  SF_OK, SF_ENUMERIC (no convergence, with the numbers),
 * SF_ENOMEM. */
int sf_flat_limit_sparse(sf_equil *q, const double *y0, double p0, const double *u, double imperf,
                         int mirror, double *w, sf_flatlimit_info *info, sf_error *err);

#endif
