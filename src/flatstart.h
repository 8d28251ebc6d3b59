/* flatstart.h - start of an exact path at the flat state from the limit of
 * the branch (see the comment at the top of flatstart.c). */
#ifndef SF_FLATSTART_H
#define SF_FLATSTART_H

#include "equilibrium.h"

typedef struct sf_flatstart_info {
    int iterations;          /* Newton iterations of the limit problem */
    double residual;         /* its final scaled residual */
    int first_order_rows;    /* loop-row combinations with a gradient at q = 0 */
    int second_order_rows;   /* combinations of zero gradient at q = 0 */
} sf_flatstart_info;

/* Guess y (q->n values) of the exact problem at p1 near the flat state,
 * which solves the problem at p0: y = (dp u, multipliers) with the limit
 * problem's u and multipliers, dp = p1 - p0.  Needs exact loop rows and no
 * support rows (their limit is not set up).  info may be NULL. */
int sf_equil_start_limit(sf_equil *q, double p0, double p1, double *y,
                         sf_flatstart_info *info, sf_error *err);

/* Start the continuation solver cs (created for q) at p1 off the flat
 * state, which solves the problem at p0: cont_start from the limit guess,
 * and if that fails from sf_equil_start_off_flat's penalty homotopy.  y
 * (q->n values) receives the guess used.  SF_OK, or the error with both
 * reasons. */
struct cont_solver;
int sf_equil_start_flat(sf_equil *q, struct cont_solver *cs, double p0, double p1, int dir,
                        double tol, double *y, sf_error *err);

#endif
