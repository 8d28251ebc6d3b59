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
 *    the operator x -> u with [HL - sigma I, C^T; C, 0] [u; nu] = [x; 0]
 *    is symmetric on R^nq, vanishes on range(C^T) and equals
 *    Z (H_c - sigma)^-1 Z^T on null(C), so its largest eigenvalues
 *    1/(mu - sigma) give the eigenvalues mu of H_c nearest sigma, and
 *    constraint directions can never appear as eigenvalues.  Z is never
 *    formed.  The blocks are handed to sstab.h as sparse matrices: the KKT
 *    matrix is factorised by MUMPS, whose inertia gives the Morse index
 *    (redundant constraint rows show as null pivots), ARPACK's operator is
 *    a MUMPS solve, and a non-converged ARPACK run is retried, then
 *    marked unknown (res.status, res.reason) instead of failing.
 *  - inertia (SF_EIG_INERTIA): in face poses first the inertia of one
 *    LDL^T of the corrector's own Jacobian [HL C^T; C -E] at the point,
 *    which proves the point stable (Morse index 0, no eigenvalues) when it
 *    has exactly as many negative pivots as constraint rows and no null
 *    one (stability.c, corrector_certificate; docs/guides/stability.md, "Stable
 *    by the corrector's matrix"); otherwise, and in fold coordinates, the
 *    MUMPS factorisation of K(0) above, stability and Morse index from its
 *    inertia (Sylvester: neg(K(0)) = morse + rank C); the eigenvalues
 *    there only when one short ARPACK attempt converges (sstab.h,
 *    SF_SSTAB_EIG_BOUNDED), else none (empty eig columns).  For large
 *    sheets, whose eigenvalue clusters make ARPACK slow.
 * Fold coordinates, dense: where redundant rows lose rank a negative
 * eigenvalue may come from the self-stress the multipliers carry;
 * sf_stab_certify (stab_cert.c) then looks for a self-stress that makes
 * H_c positive definite (stable, no eigenvalues written).
 * SF_EIG_AUTO uses dense up to SF_EIG_DENSE_MAX coordinates, inertia
 * above; ARPACK falls back to dense when the tangent space is too small for
 * it (fewer than nev + 2 dimensions).  Measured on square4 with K = 2 (72
 * coordinates, 74 points): ARPACK 0.35 s, dense 0.17 s, no stability
 * 0.14 s, so dense stays the better choice well beyond 64 coordinates.
 */
#ifndef SF_STABILITY_H
#define SF_STABILITY_H

#include "equilibrium.h"
#include "sf_error.h"
#include "sstab.h"

enum { SF_EIG_AUTO = 0, SF_EIG_DENSE = 1, SF_EIG_ARPACK = 2, SF_EIG_INERTIA = 3 };
/* Dense up to 200 coordinates, the MUMPS inertia above.  Miura-ori
 * actuation paths in poses with exact closure (docs/guides/stability.md, "Where
 * auto switches"): the dense method costs 2 ms per point at 138
 * coordinates, 50 ms at 330 and 1.6 s at 954, the inertia 5.5 ms at 330
 * and 45 ms at 954, with the same stable and morse columns.  ARPACK is
 * never the automatic choice: the smallest eigenvalue of these sheets is
 * a cluster of hundreds of copies, which Lanczos resolves slowly. */
#define SF_EIG_DENSE_MAX 200

typedef struct sf_stab_result {
    int method;        /* SF_EIG_DENSE or SF_EIG_ARPACK (the one used) */
    int rank;          /* rank of the constraint rows */
    int dim;           /* dimension of the tangent space, nq - rank */
    int morse;         /* negative eigenvalues of H_c */
    int morse_unknown; /* 1: the index could not be decided (an ambiguous KKT inertia, the
                          reason says why and gives its range); morse then holds 0 */
    int stable;        /* 1 if all eigenvalues of H_c are positive, 0 if not,
                          -1 unknown (ARPACK failed and the index is 0) */
    int neig;          /* eigenvalues in eig (min(nev, dim)) */
    double *eig;       /* [nev] smallest eigenvalues, ascending */
    int iters;         /* ARPACK restarts (0 for dense) */
    int nop;           /* ARPACK operator applications */
    int status;        /* SF_SSTAB_OK, SF_SSTAB_RETRIED, SF_SSTAB_UNKNOWN (sstab.h) */
    int attempts;      /* ARPACK attempts (0 for dense, 1 without retry) */
    char reason[320];  /* what was retried or failed ("" when nothing) */
    int certified;     /* stable by a self-stress of redundant rows (stab_cert.c), found by
                          the local ascent (1) or the semidefinite program (2);
                          then neig = 0 (the eigenvalues depend on the self-stress) */
    double cert_mu;    /* the largest self-stress amplitude of the certificate */
    double cert_eig;   /* the certificate's smallest eigenvalue (> 0) */
} sf_stab_result;

struct sf_ldlt;
typedef struct sf_stab {
    int nq, ncon, nev, method;
    double *HL, *C;        /* KKT blocks at the point */
    double *work;          /* scratch */
    size_t nwork;
    int *iwork;
    sf_sstab *sp;          /* the ARPACK method (MUMPS + ARPACK) */
    /* the inertia method's certificate on the corrector's matrix
     * (stability.c, corrector_certificate): its LDL^T, the lower triangle's
     * pattern (0-based) and where each entry sits in the assembly */
    struct sf_ldlt *jl;
    int *jrow, *jcol;
    long *jsrc, jnnz;
    double *jval, *jfp;
    long ncert;            /* points certified stable that way */
    int given;             /* sf_stab_give_inertia: 1 until the next evaluation */
    long given_neg, given_null;
    int sparse_kkt;        /* face poses: sparse blocks to sp, no dense HL, C */
    int arpack_maxiter;    /* 0: sstab.h default; set before the first eval */
    int arpack_attempts;   /* 0: sstab.h default */
    const struct sf_stab *lead; /* sf_stab_follow */
    long nevals;           /* evaluations so far */
    sf_stab_result res;
} sf_stab;

/* nev: how many of the smallest eigenvalues to report (>= 1). */
int sf_stab_init(sf_stab *st, const sf_equil *q, int method, int nev, sf_error *err);

/* The study's analysis.arpack_maxiter and analysis.arpack_attempts into
 * st (before the first eval).  An absent arpack_maxiter stays 0, sstab.h's
 * default: 1000 restarts per ARPACK attempt, and 10 for the one bounded
 * attempt of the inertia method (docs/guides/stability.md). */
int sf_stab_read_keys(sf_stab *st, const sf_study *s, sf_error *err);
void sf_stab_free(sf_stab *st);

/* The sparse methods of st take the independent constraint rows of lead's
 * last evaluation instead of deciding them anew (sf_sstab_follow_rows);
 * lead NULL: st decides again.  The dense method is not affected. */
void sf_stab_follow(sf_stab *st, const sf_stab *lead);

/* Stability of the solved point (y, p) of q; the result is st->res (valid
 * until the next call).  Fails (SF_ENUMERIC) only on non-finite input or a
 * LAPACK/ARPACK failure, with a message. */
int sf_stab_eval(sf_stab *st, sf_equil *q, const double *y, double p, sf_error *err);

/* After a dense evaluation in fold coordinates that found a negative
 * eigenvalue at a point with redundant constraint rows: look for a
 * self-stress mu of the rows (null C^T, at most 64 of them) with
 * Z^T HL(lambda + mu) Z positive definite, the second-order sufficient
 * condition; when found, res says stable, morse 0, certified 1 or 2, no
 * eigenvalues (stab_cert.c; docs/guides/stability.md).  Called by
 * sf_stab_eval. */
int sf_stab_certify(sf_stab *st, sf_equil *q, const double *y, double p, sf_error *err);

/* The search of sf_stab_certify on its own: H0 (d x d) and A (k blocks
 * d x d), symmetric, column-major.  First the local ascent, then, where it
 * fails, the semidefinite program max t s.t. H0 + sum mu_k A_k - t I >= 0,
 * |mu| <= bound (DSDP); every mu is checked with LAPACK before it
 * certifies (its smallest eigenvalue above the margin plus a bound on
 * LAPACK's error there).  Returns 0, or -1 when LAPACK fails or memory
 * runs out (nothing decided).  mu (k) receives the certificate's (or the SDP's) self-stress. */
enum { SF_CERT_NONE = 0, SF_CERT_ASCENT = 1, SF_CERT_SDP = 2 };
typedef struct {
    int found;       /* SF_CERT_ASCENT or SF_CERT_SDP: smallest eigenvalue (LAPACK) > margin at mu */
    int sdp_ran;     /* 1: DSDP solved (primal and dual feasible); 0: not run or failed */
    int sdp_err;     /* DSDP's error code, or its stop reason when not converged; 0 otherwise */
    double margin;   /* 1e-8 of the largest |eigenvalue| of H0 */
    double roundoff; /* a bound on LAPACK's error of lmin at mu; found needs lmin > margin + roundoff */
    double bound;    /* the bound on |mu| (2-norm), same units as mu */
    double lmin;     /* the smallest eigenvalue at mu (LAPACK) */
    double t_lo;     /* DSDP's t at its mu (dual objective; the eigenvalue lmin checks it) */
    double t_up;     /* an upper bound of max { lambda_min(H0 + sum mu_k A_k) : |mu| <= bound }
                        computed here from DSDP's X (PSD part, trace 1); INFINITY if none */
} sf_cert_search;
int sf_stab_cert_search(int d, int k, const double *H0, const double *A, double *mu,
                        sf_cert_search *out);

const char *sf_stab_method_name(int method);

/* 1 when st's evaluations of q's points start from the inertia of the
 * corrector's own Jacobian at the point (the inertia method in face
 * poses): the caller then asks the engine for it (cont_set_point_inertia)
 * and hands it over with sf_stab_give_inertia. */
int sf_stab_wants_inertia(const sf_stab *st, const sf_equil *q);

/* The inertia of the corrector's Jacobian at the point the next
 * sf_stab_eval evaluates (negative and null pivots of its LDL^T, from
 * the engine: cont_point.jy_inertia); used by that evaluation only, in
 * place of a factorisation of its own. */
void sf_stab_give_inertia(sf_stab *st, long neg, long nnull);

#endif
