/* flatstart_sparse.h - a scalable start of an exact path at the flat state
 * in the face-pose formulation (analysis.flat_start = "sparse", see the
 * comment at the top of flatstart_sparse.c and docs/flatstart.md).  No
 * dense array: one sparse LDL^T (MUMPS, ldlt.h) of the KKT matrix at the
 * flat state, then the continuation engine's own corrector. */
#ifndef SF_FLATSTART_SPARSE_H
#define SF_FLATSTART_SPARSE_H

#include "equilibrium.h"
#include "flatstart.h"

struct cont_solver;

/* The driving's direction at the flat state y0 (q->n values, the flat sheet
 * lifted to poses) and p0: u = -Jy^-1 Fp (q->n values: fold coordinates,
 * poses, multipliers), the response of the bending energy to the driving
 * projected on the first-order kernel of the fold rows (the -eps D block of
 * the Jacobian regularises the rows that are redundant there).  nnull (may
 * be NULL) receives MUMPS's null pivots.  SF_OK, SF_ENUMERIC (the
 * factorisation failed or u is not finite), SF_ENOMEM. */
int sf_flat_direction(sf_equil *q, const double *y0, double p0, double *u, int *nnull,
                      sf_error *err);

/* Start the solver cs (created for q, face poses, exact) off the flat
 * state y0 (the flat sheet, lifted), which solves the problem at p0: a
 * finite step along the driving's direction u (sf_flat_direction), signed
 * by dir, of angle rad on the largest fold angle (its p-step capped at
 * max_dp when > 0), with the declared imperfection of the mode amplitudes,
 * solved at that p by Newton with an inertia correction, then cont_start
 * there (steps 2-5 at the top of flatstart_sparse.c); on failure the step
 * is halved up to 4 times.  Folds whose angle the driving leaves at zero
 * to first order take the sign of their declared assignment
 * (folds[].assignment) when there is one; info->note says what was done.
 * y (q->n) receives the start point (y may be y0).  tol: the Newton
 * tolerance (scaled residual).  On failure SF_ENUMERIC with a diagnosis
 * naming what to try. */
int sf_equil_poses_start_sparse(sf_equil *q, struct cont_solver *cs, const double *y0, double p0,
                                double max_dp, int dir, double angle, double tol, double *y,
                                sf_flatstart_info *info, sf_error *err);

#endif
