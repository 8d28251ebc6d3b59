/* stability.h - stability of an equilibrium (MODEL.md 6): eigenvalues of
 * the Hessian of the Lagrangian restricted to the constraint tangent space,
 *   H_c = Z^T HL Z,  HL = hess Pi + sum_c lambda_c hess g_c,  Z: basis of null(C),
 * C the constraint rows (loop closure in exact mode, supports, prescribed
 * displacement).  Stable iff every eigenvalue is positive; the number of
 * negative ones is the Morse index.  Eigenvalues are in J per unit of the
 * generalised coordinates (rad for fold angles, 1 for shape amplitudes).
 *
 * Two methods:
 *  - dense (LAPACK): Z from the SVD of the row-normalised C (dgesvd), H_c
 *    formed and diagonalised completely (dsyev).  Exact Morse index, all
 *    eigenvalues; O(nq^3).  For small problems and as the reference.
 *  - ARPACK, shift-invert on the KKT pencil  [HL C^T; C 0] v = mu [I 0; 0 0] v:
 *    the operator x -> u with [HL - sigma I, Cr^T; Cr, 0] [u; nu] = [x; 0]
 *    is symmetric on R^nq, vanishes on range(C^T) and equals
 *    Z (H_c - sigma)^-1 Z^T on null(C), so its largest eigenvalues
 *    1/(mu - sigma) give the eigenvalues mu of H_c nearest sigma, and
 *    constraint directions can never appear as eigenvalues (they map to 0,
 *    the end of the spectrum ARPACK never asks for).  Z is never formed.
 *    Cr are linearly independent constraint rows (QR with column pivoting
 *    of C^T, dgeqp3), so redundant loop rows (e.g. at the flat state) leave
 *    the KKT matrix regular.  The KKT matrix is factorised once per point
 *    (LAPACK dsytrf, symmetric indefinite); its inertia gives the Morse
 *    index exactly (Sylvester: inertia(K) = inertia(H_c - sigma) + (r, r, 0)).
 *    sigma = -1e-6 * scale when the point is stable, so the eigenvalues
 *    nearest sigma are the smallest; otherwise sigma is a Gershgorin lower
 *    bound of HL, below every eigenvalue of H_c.
 *    The corrector's factorisation is not reused: KINSOL factorises the
 *    bordered, unsymmetric (n+1) matrix at the last Newton iterate, with the
 *    multiplier block regularised; the symmetric KKT matrix at the converged
 *    point costs one more factorisation of the same size.
 * SF_EIG_AUTO uses dense up to SF_EIG_DENSE_MAX coordinates, ARPACK
 * above; ARPACK falls back to dense when the tangent space is too small for
 * it (fewer than nev + 2 dimensions).  Measured on square4 with K = 2 (72
 * coordinates, 74 points): ARPACK 0.35 s, dense 0.17 s, no stability
 * 0.14 s, so dense stays the better choice well beyond 64 coordinates.
 */
#ifndef SF_STABILITY_H
#define SF_STABILITY_H

#include "equilibrium.h"
#include "sf_error.h"

enum { SF_EIG_AUTO = 0, SF_EIG_DENSE = 1, SF_EIG_ARPACK = 2 };
#define SF_EIG_DENSE_MAX 200

typedef struct sf_stab_result {
    int method;        /* SF_EIG_DENSE or SF_EIG_ARPACK (the one used) */
    int rank;          /* rank of the constraint rows */
    int dim;           /* dimension of the tangent space, nq - rank */
    int morse;         /* negative eigenvalues of H_c */
    int stable;        /* 1 if all eigenvalues of H_c are positive */
    int neig;          /* eigenvalues in eig (min(nev, dim)) */
    double *eig;       /* [nev] smallest eigenvalues, ascending */
    int iters;         /* ARPACK restarts (0 for dense) */
    int nop;           /* ARPACK operator applications */
} sf_stab_result;

typedef struct sf_stab {
    int nq, ncon, nev, method;
    double *HL, *C;        /* KKT blocks at the point */
    double *work;          /* scratch */
    size_t nwork;
    int *iwork;
    sf_stab_result res;
} sf_stab;

/* nev: how many of the smallest eigenvalues to report (>= 1). */
int sf_stab_init(sf_stab *st, const sf_equil *q, int method, int nev, sf_error *err);
void sf_stab_free(sf_stab *st);

/* Stability of the solved point (y, p) of q; the result is st->res (valid
 * until the next call).  Fails (SF_ENUMERIC) only on non-finite input or a
 * LAPACK/ARPACK failure, with a message. */
int sf_stab_eval(sf_stab *st, sf_equil *q, const double *y, double p, sf_error *err);

const char *sf_stab_method_name(int method);

#endif
