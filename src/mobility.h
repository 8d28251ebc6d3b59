/* mobility.h - how much motion the loop constraints leave the sheet
 * (MODEL.md 4): degrees of freedom of the whole sheet and of each interior
 * vertex under its own six loop rows, at a state that closes the loops
 * (the flat sheet by default).  Used by `smoothfold check` and by `run`
 * when the start of an exact path fails (SF_ELOCKED, naming the vertices).
 *
 * Method.  First order: the rank of the loop-row Jacobian J at the base
 * state (rows scaled: rotation rows as they are, translation rows divided
 * by the mean fold width; SVD, LAPACK dgesvd, rank relative to the largest
 * singular value).  At the flat state that count is too generous: the
 * rotation about the normal and the in-plane translations of every loop
 * are of second order there, so their rows are zero.  Hence the probe: on
 * the sphere |q - q0| = r (r = 0.02 rad) look for a state that closes the
 * loops, by Gauss-Newton with minimum-norm steps (LAPACK dgelss) on
 * [g(q); (|q - q0|^2 - r^2) / (2 r)] from starts along the first-order
 * motions (null vectors of J) and deterministic pseudo-random mixtures of
 * them.  If one converges (scaled residual <= 1e-10) the constraints leave
 * motion, and the degrees of freedom are nq - rank J there (largest rank
 * over up to three such states, so that a singular state, where branches
 * cross, does not count extra freedom); if none does, the sheet (or the
 * vertex) is locked and `gap` is the smallest residual found, e.g. the
 * loop mismatch of a degree-4 vertex with K = 0 and finite widths at
 * |q| = r.  A finite-width vertex with no collinear folds needs at least 7
 * coordinates (6 loop equations plus one motion) unless its rows are
 * redundant; K >= 1 adds coordinates.
 */
#ifndef SF_MOBILITY_H
#define SF_MOBILITY_H

#include <stddef.h>

#include "kinematics.h"
#include "sf_error.h"

typedef struct sf_mobility_vertex {
    int ivertex;        /* interior vertex (topology index) */
    int coords;         /* coordinates of its folds */
    int first_order;    /* coords - rank of its rows at the base state */
    int dof;            /* degrees of freedom under its own rows; 0: locked,
                           -1: undecided */
    double gap;         /* no motion found: smallest scaled loop residual at |q - q0| = r */
    double certificate; /* largest lambda_min of a stress matrix (> 0: locked) */
} sf_mobility_vertex;

typedef struct sf_mobility {
    int nq, ncon;
    double radius;      /* r [rad] of the probe sphere */
    int first_order;    /* nq - rank J(q0) */
    int dof;            /* degrees of freedom of the whole sheet; 0: locked,
                           -1: undecided */
    double gap;         /* no motion found: smallest scaled residual at |q - q0| = r */
    double certificate; /* largest lambda_min of a stress matrix (> 0: locked) */
    int nvertices;
    sf_mobility_vertex *v;
    int nlocked;        /* vertices whose own rows lock their folds */
} sf_mobility;

/* Analyse the loop constraints of m about q0 (nq values; NULL: the flat
 * sheet), which must close the loops.  Fails with SF_EINPUT when q0 does
 * not, SF_ENOMEM, SF_ENUMERIC when LAPACK fails. */
int sf_mobility_analyse(const sf_model *m, const double *q0, sf_mobility *mb, sf_error *err);
void sf_mobility_free(sf_mobility *mb);

/* Is the whole sheet, or any vertex, without motion? */
int sf_mobility_locked(const sf_mobility *mb);

/* One line (no newline) naming what is locked, e.g. "the loop constraints
 * leave the sheet no motion at the flat state: vertex v7 (degree 4, 4
 * coordinates for 6 loop equations) locks its folds"; "" when nothing is. */
void sf_mobility_describe(const sf_model *m, const sf_mobility *mb, char *buf, size_t size);

#endif
