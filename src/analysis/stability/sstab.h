/* sstab.h - stability of an equilibrium from sparse matrices: the entry
 * point for formulations that assemble their KKT blocks sparse (the face
 * poses of MODEL.md 9) and the ARPACK method of stability.h.
 *
 * Input, in compressed sparse column form (sf_csc, 0-based):
 *   HL (n x n) the Hessian of the Lagrangian, hess Pi + sum_c lambda_c hess g_c.
 *      Symmetric; give the full matrix or only its lower triangle: entries
 *      above the diagonal (row < col) are ignored.
 *   C  (m x n) the constraint rows (m may be 0; C may then be NULL).
 * Output: the Morse index of H_c = Z^T HL Z (Z a basis of null(C)), the
 * nev smallest eigenvalues of H_c, and a status with its reason.
 *
 * Method (see docs/guides/stability.md):
 *  - rows of C are scaled to unit length; rows shorter than 1e-13 times the
 *    longest are dropped (zero to round-off, e.g. second-order loop rows
 *    at the flat state);
 *  - the rank r of C and r independent rows Cr: SuiteSparseQR of C^T with
 *    Heath's rank detection (tolerance 1e-9 on the unit rows, as the dense
 *    method's SVD cut).  Rank condition: rows whose smallest singular
 *    value lies near 1e-9 are ambiguous for either method.  The rows of
 *    the last QR are reused while a check shows they still span C
 *    (sstab_rows.h);
 *  - K(sigma) = [HL - sigma I, Cr^T; Cr, 0] factorised by MUMPS (ldlt.h).
 *    Sylvester: neg(K) = neg(H_c - sigma) + r, so the Morse index is
 *    neg(K(0)) - r (when H_c is singular, at sigma0 = -1e-6 max|diag HL|,
 *    an eigenvalue in [sigma0, 0) then counted from its computed value);
 *  - weak rows (kept rows with a Heath residual below 1e-8, or at a null
 *    pivot of K; when K_w's count still fails, the weakest up to 1e-7):
 *    their pivot pairs in K are at round-off.  They are taken out (K_w)
 *    and its index mw bounds the true one to [mw - kw, mw] (interlacing):
 *    0 when mw = 0 (the eigenvalues then those of K_w, lower bounds),
 *    else unknown with the range in the reason ("inertia ambiguous"),
 *    unstable when mw > kw;
 *    for an unstable point the ARPACK shift is placed just below the
 *    spectrum by the same counts;
 *  - ARPACK (dsaupd/dseupd) in shift-invert on the pencil (K(0), diag(I,
 *    0)); each operator application is one MUMPS solve.  Every result is
 *    checked by a Sturm count (inertia of K at a cut after the wanted
 *    eigenvalues); missed copies of a multiple eigenvalue are found by
 *    deflating the eigenvectors found.  A non-converged run is retried
 *    with twice the subspace (ncv), then with a shift moved down, up to
 *    opts.attempts; every retry is counted and explained in the result.
 *
 * Stability: unstable when the Morse index is positive (from the
 * inertia alone, so also when ARPACK failed); stable when it is 0 and the
 * smallest eigenvalue is positive; unknown when the eigenvalues could not
 * be computed and the index is 0, or when the factorisation failed.
 * With SF_SSTAB_EIG_BOUNDED the inertia decides: stable when the Morse
 * index is 0 and K(0) has no null pivot (H_c positive definite), unstable
 * when the index is positive.  A null pivot at 0 (an eigenvalue 0 to
 * round-off is not stable) is settled by the eigenvalues when they came:
 * stable when eig1 lies above the null-pivot level (about 1e-12 max|diag
 * HL|, MUMPS's CNTL(3)); otherwise not stable, or, with weak rows left
 * out (whose eigenvalues are lower bounds only), unknown.  With weak rows
 * left out and the full effort, a lower bound at or below that level is
 * unknown too.  An
 * unknown stability is not an error: sf_sstab_eval returns SF_OK with
 * res.status = SF_SSTAB_UNKNOWN and the reason.  Errors (a non-zero
 * return) are bad arguments, non-finite entries and lack of memory.
 */
#ifndef SF_SSTAB_H
#define SF_SSTAB_H

#include "sf_error.h"

/* A compressed sparse column matrix (0-based, colptr[ncol] entries). */
typedef struct sf_csc {
    int nrow, ncol;
    const int *colptr;   /* [ncol + 1] */
    const int *rowind;   /* [colptr[ncol]] */
    const double *val;   /* [colptr[ncol]] */
} sf_csc;

enum { SF_SSTAB_OK = 0, SF_SSTAB_RETRIED = 1, SF_SSTAB_UNKNOWN = 2 };

/* How hard to try for the eigenvalues (sf_sstab_opts.effort). */
enum {
    SF_SSTAB_EIG_FULL = 0,    /* ARPACK attempts (retries, deflation) until found or spent */
    SF_SSTAB_EIG_BOUNDED = 1  /* stability and Morse index from the inertia alone; the
                                 eigenvalues only when ONE ARPACK attempt of at most
                                 maxiter restarts (0: 10, and then a tangent space of at
                                 most 400 dimensions whole, ncv = its dimension) converges
                                 and passes the Sturm check, else none (neig = 0, status
                                 still OK) */
};

typedef struct sf_sstab_opts {
    int nev;        /* smallest eigenvalues wanted (>= 1) */
    int maxiter;    /* ARPACK restarts per attempt (0: 1000) */
    int attempts;   /* ARPACK attempts in all (0: 4) */
    double tol;     /* ARPACK relative tolerance (0: 1e-10; eigenvalue errors are at most
                       tol times their distance to the shift, Bauer-Fike) */
    int effort;     /* SF_SSTAB_EIG_FULL (0) or SF_SSTAB_EIG_BOUNDED */
} sf_sstab_opts;

typedef struct sf_sstab_result {
    int status;        /* SF_SSTAB_OK, _RETRIED (known after retries), _UNKNOWN */
    char reason[200];  /* for RETRIED and UNKNOWN: what failed ("" for OK) */
    int stable;        /* 1 stable, 0 unstable, -1 unknown */
    int morse;         /* negative eigenvalues of H_c; -1 if the factorisation failed */
    int rank;          /* rank of C */
    int dim;           /* n - rank */
    int null_pivots;   /* null pivots of K(sigma0) (0 unless sigma0 hits an eigenvalue) */
    int null_at_zero;  /* null pivots of K(0): H_c has an eigenvalue 0 to round-off */
    int det_sign;      /* sign of det K(0), K(0) = [HL, Cr^T; Cr, 0], from the same LDL^T:
                          (-1)^neg(K(0)) = (-1)^(morse + rank); 0 when K(0) is singular */
    int neig;          /* eigenvalues in eig (0 when ARPACK failed) */
    double *eig;       /* [nev] smallest eigenvalues of H_c, ascending */
    int attempts;      /* ARPACK attempts made (1 = first try converged) */
    int iters;         /* ARPACK restarts of the attempt that converged */
    int nop;           /* operator applications (MUMPS solves), all attempts */
    int analyses;      /* MUMPS symbolic analyses so far (pattern changes) */
    int rank_qr;       /* rank-revealing QRs of C so far (sstab_rows.h) */
    int rank_reused;   /* evaluations so far that reused the independent rows of the last QR */
    int rank_checks;   /* checks so far whether those rows still span C (sstab_rows.h) */
} sf_sstab_result;

typedef struct sf_sstab sf_sstab;

/* For problems with n coordinates and m constraint rows. */
int sf_sstab_create(sf_sstab **out, int n, int m, const sf_sstab_opts *opts, sf_error *err);
void sf_sstab_free(sf_sstab *s);

/* Stability at one point.  The pattern of the KKT matrix is analysed once
 * and reused while HL and C keep their patterns.  The result stays valid
 * until the next call. */
int sf_sstab_eval(sf_sstab *s, const sf_csc *HL, const sf_csc *C, sf_error *err);
const sf_sstab_result *sf_sstab_get(const sf_sstab *s);

/* The next evaluations of s follow lead's last evaluation: they take its
 * independent constraint rows (same n and m; its Heath residuals too)
 * instead of deciding them with a check or QR of their own (sstab_rows.h),
 * factorise K with lead's MUMPS instance and its analysis (the same
 * pattern), K_w too when its weak rows are those of lead's last K_w, and
 * otherwise start their own instances at the workspace relaxation lead's
 * needed (ldlt.h).  NULL: s decides itself again.  For the step bound's
 * second evaluation, h = 1e-6 along the tangent from the point lead has
 * just evaluated (bifurcation.h): the same constraint set and pivot order
 * at both, so the eigenvalues compared are of the same problem.  A lead
 * without a set, or a row of its set zero at the new point: s decides
 * itself.  lead's results and its next evaluations do not change: its
 * factors are overwritten (they are not used after its evaluation), its
 * analyses and workspace relaxation are kept (a stale analysis is renewed
 * on s's own instance, lead analyses every K_w afresh). */
void sf_sstab_follow_rows(sf_sstab *s, sf_sstab *lead);

#endif
