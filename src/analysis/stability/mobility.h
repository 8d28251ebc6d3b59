/* mobility.h - how much motion the loop constraints leave the sheet
 * (MODEL.md 4): degrees of freedom of the whole sheet and of each interior
 * vertex under its own six loop rows, at a state that closes the loops
 * (the flat sheet by default).  Used by `smoothfold check` and by `run`
 * when the start of an exact path fails (SF_ELOCKED, naming the vertices).
 *
 * Method, for the whole sheet (all coordinates, all loop rows) and for
 * each vertex (its folds' coordinates, its six rows), about q0:
 *  - First order: the rank of the loop-row Jacobian J at q0 (rows scaled:
 *    rotation rows as they are, translation rows divided by the mean fold
 *    width; LAPACK dgesvd, rank relative to the largest singular value).
 *    At the flat state that count is too generous: the rotation about the
 *    normal and the translations of every loop are of second order there,
 *    their rows are zero.
 *  - Second order, proof of locking: the combinations of rows in the left
 *    null space of J (self-stresses) and their Hessians G_s.  If some
 *    combination sum nu_s G_s is positive definite on the first-order
 *    motions Z, no motion survives to second order (prestress stability;
 *    Connelly and Whiteley, SIAM J. Discrete Math. 9, 1996): locked.  Found
 *    by maximising the smallest eigenvalue over |nu| <= 1 (concave: a
 *    semidefinite program, DSDP through lmi.h, checked with LAPACK
 *    dsyev).
 *  - Motion: every analytic motion from q0 leaves along a ray of the
 *    second-order cone (Z v with v^T Z^T G_s Z v = 0 for all s).  The rays
 *    nearest to the first-order motions closest to each coordinate
 *    direction, +-Z^T Z e_j (Gauss-Newton on the forms; these depend on
 *    the null space alone, not on the basis Z that rounding rotates), and
 *    the second-order motion the study's own driving selects (the limit
 *    problem of flatstart.h), start Gauss-Newton with minimum-norm steps
 *    (dgelss) on [g(q); (|q - q0|^2 - r^2) / (2 r)] on the sphere
 *    |q - q0| = r (r = 0.02 rad); then the first-order motions
 *    themselves.  Each state found (scaled residual <= 1e-10) lies on a
 *    branch of dimension nq - rank J, the rank taken as the largest at
 *    the state and at the states a step r/2 away along each null vector
 *    of J there, back on the set (where branches cross, e.g. one straight
 *    line folded alone, the rows are redundant and the rank drops); the
 *    degrees of freedom are the largest branch's among the states found
 *    (the first two): a lower bound where the set has branches of several
 *    dimensions, as a whole sheet with K >= 1 may.
 *    At a degree-4 vertex the rays are sought from more starts (also
 *    Z^T Z (e_i +- e_j)) until two folding modes are found, each kept by
 *    its fold angles (distinct directions up to sign); there are at most
 *    two, the fold angles lying on the rigid vertex's cone (two lines),
 *    and they are those (tests/test_paths.c).  At higher degree the modes
 *    come in families and are not counted.
 *  - No ray and no prestress: second-order rigidity, if the forms have no
 *    common real zero, shown by a sum of squares (mobility_sos.c, up to
 *    SF_MOBILITY_SOS_MAX first-order motions): locked.  Second-order
 *    rigidity implies rigidity (Connelly and Whiteley 1996); it holds
 *    where no prestress exists, e.g. at a degree-3 vertex with K = 1.
 *  - None of these: undecided (dof = -1; locking, if any, of higher
 *    order, or a motion the probe did not find), with the smallest
 *    residual found.
 * Scale: each vertex's rows are evaluated locally (sf_constraints_vertex:
 * its own columns, no ncon x nq array) from the folding maps of its own
 * folds alone (sf_kin_eval_folds), so each vertex's analysis costs the
 * same on any size of sheet and all of them together grow linearly with
 * the folds (fold_evals below counts the work); the
 * whole sheet's second-order probe is dense in nq and runs up to
 * SF_MOBILITY_DENSE_MAX coordinates, above which the whole sheet gets its
 * first-order count from the sparse rank (mobility_sparse.c) only.
 * A finite-width vertex with K = 0 and no two folds on one line has as many
 * fold angles as its degree against six loop equations: below degree 7 it
 * is locked in general (tests/studies/deg4.cfg); K >= 1 adds coordinates.
 */
#ifndef SF_MOBILITY_H
#define SF_MOBILITY_H

/* What proves a set locked: a prestress (lambda_min of a stress matrix
 * on the first-order motions) or second-order rigidity (gamma of a sum of
 * squares, sum_s Q_s(v)^2 >= gamma |v|^4 relative to its largest
 * eigenvalue; mobility_sos.c). */
#define SF_CERT_PRESTRESS 1
#define SF_CERT_SECOND_ORDER 2
/* folding modes recorded per vertex */
#define SF_MOBILITY_MODES_MAX 8
/* the sum of squares runs up to this many first-order motions */
#define SF_MOBILITY_SOS_MAX 8
#define SF_MOBILITY_SOS_RHO 10.0

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
    double certificate; /* locked: the certificate's value (> 0), by cert_kind */
    int cert_kind;      /* SF_CERT_PRESTRESS or SF_CERT_SECOND_ORDER; 0: none */
    int modes;          /* mobile, of degree 4: its folding modes found, the
                           distinct fold-angle directions (up to sign) of
                           the second-order cone's rays; 0 otherwise */
    int nfolds;         /* its distinct folds (the order of sf_ivertex.folds,
                           first occurrence) */
    double *mode;       /* modes x nfolds: each mode's unit fold-angle
                           direction, its largest angle positive (NULL
                           unless of degree 4) */
} sf_mobility_vertex;

typedef struct sf_mobility {
    int nq, ncon;
    double radius;      /* r [rad] of the probe sphere */
    int first_order;    /* nq - rank J(q0) */
    int dof;            /* degrees of freedom of the whole sheet; 0: locked,
                           -1: undecided */
    double gap;         /* no motion found: smallest scaled residual at |q - q0| = r */
    double certificate; /* locked: the certificate's value (> 0), by cert_kind */
    int cert_kind;      /* SF_CERT_PRESTRESS or SF_CERT_SECOND_ORDER; 0: none */
    int nvertices;
    sf_mobility_vertex *v;
    int nlocked;        /* vertices whose own rows lock their folds */
    int probed;         /* 1: the whole sheet's second-order probe ran (up to
                           SF_MOBILITY_DENSE_MAX coordinates); 0: first order
                           only (sparse rank), dof = -1 */
    int nstates;        /* the whole sheet's probe: closed states found at
                           |q - q0| = radius, the first along the study's
                           driving where it has one (nstates x nq) */
    double *states;
    long fold_evals;    /* folding maps evaluated by the analysis (each one
                           quadrature of the fold's section; the sparse
                           first-order count adds one evaluation of every
                           fold): grows linearly with the folds */
} sf_mobility;

/* The whole sheet's second-order probe (dense in nq) runs up to this many
 * coordinates; above, its first-order count comes from the sparse rank
 * (sf_mobility_first_order) and its dof stays undecided.  Each vertex
 * alone is analysed at every size, locally (sf_constraints_vertex). */
#define SF_MOBILITY_DENSE_MAX 100

/* nq - rank of the scaled loop rows at q (NULL: the flat sheet), with no
 * array of size nq^2: the rows assembled sparse vertex by vertex
 * (sf_constraints_vertex), the rank from SuiteSparseQR of J^T with Heath's
 * rank detection at 1e-8 times the longest row (the dense analysis: SVD,
 * 1e-8 times the largest singular value).  SF_ENOMEM, SF_ENUMERIC. */
int sf_mobility_first_order(const sf_model *m, const double *q, int *first, sf_error *err);

/* Analyse the loop constraints of m about q0 (nq values; NULL: the flat
 * sheet), which must close the loops.  Fails with SF_EINPUT when q0 does
 * not, SF_ENOMEM, SF_ENUMERIC when LAPACK fails. */
int sf_mobility_analyse(const sf_model *m, const double *q0, sf_mobility *mb, sf_error *err);
void sf_mobility_free(sf_mobility *mb);

/* The same analysis about the flat sheet, for the start's census
 * (start.h): the whole sheet's probe seeks up to want closed states
 * (mb->states) and does not measure their branches, so mb->dof is only
 * 0 (locked), -1 (undecided) or > 0 (mobile, an upper bound). */
int sf_mobility_states(const sf_model *m, int want, sf_mobility *mb, sf_error *err);

/* Is the whole sheet, or any vertex, without motion? */
int sf_mobility_locked(const sf_mobility *mb);

/* The count that keeps a sheet of folds with one shape mode from closing:
 * each interior vertex closes with 6 rows (*rows in all), a fold with K
 * shape modes has K + 1 coordinates (*coords), so a sheet of degree-4
 * vertices with K = 1 (about 2 folds a vertex) has 6 rows for 4
 * coordinates a vertex and closes only where its rows happen to be
 * dependent; *coords2 counts the coordinates with every fold given K >= 2,
 * *k1 the folds with K <= 1.  Returns 1 when the rows outnumber the
 * coordinates and some fold has K <= 1 (docs/guides/importing-patterns.md,
 * "shape modes"), else 0. */
int sf_mobility_overcounted(const sf_model *m, int *rows, int *coords, int *coords2, int *k1);

/* One line (no newline) naming what is locked, e.g. "the loop constraints
 * leave the sheet no motion at the flat state: vertex v7 (degree 4, 4
 * coordinates for 6 loop equations) locks its folds"; "" when nothing is. */
void sf_mobility_describe(const sf_model *m, const sf_mobility *mb, char *buf, size_t size);

/* Second-order rigidity of nn first-order motions under n2 forms G
 * (n2 x nn x nn, row-major): the largest gamma found with sum_s (v^T G_s
 * v)^2 >= gamma emax |v|^4 by a checked sum-of-squares certificate
 * (> 0: no second-order motion; emax the largest eigenvalue of the
 * forms' Gram matrix).  -INFINITY when nn exceeds SF_MOBILITY_SOS_MAX.
 * *status: 0 ran, 1 the SDP failed, -1 out of memory. */
double sf_mobility_sos(int nn, int n2, const double *G, int *status);

#endif
