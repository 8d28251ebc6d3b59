/* ldlt.h - sparse symmetric indefinite LDL^T factorisation with inertia,
 * a small wrapper around MUMPS (sequential build, libmumps-seq-dev).
 *
 * Life cycle (SuiteSparse KLU style): create; factor (the symbolic
 * analysis is done at the first call and redone only when the pattern
 * changes); solve as often as wanted; read the inertia; free.
 *
 * The matrix is given as triplets (row, col, value), 0-based, of ONE
 * triangle (entries with row < col are mirrored by MUMPS; duplicates are
 * summed).  MUMPS is called with sym = 2 (general symmetric), null pivot
 * detection on (ICNTL(24) = 1, threshold null_tol * ||A||, see
 * sf_ldlt_create) and the determinant on (ICNTL(33) = 1).  Its printing is
 * silenced (ICNTL(1..4)).
 *
 * Inertia: neg = INFOG(12), the number of negative pivots of D (for
 * sym = 2 these are the negative eigenvalues of A by Sylvester's law when
 * A is regular); nnull = INFOG(28), the pivots found null.  The null
 * pivots are not counted in neg.  A solve with null pivots returns the
 * solution with the corresponding unknowns set to zero (MUMPS fixes those
 * pivots to a large value), a consistent system's solution when the
 * null pivots belong to redundant rows.
 *
 * Creating one sets glibc's mmap and trim thresholds to 1 GB for the
 * process (cont_mumps_keep_heap): MUMPS's workspace, allocated at every
 * factorisation, is then reused on the heap instead of mapped and
 * faulted in each time.
 */
#ifndef SF_LDLT_H
#define SF_LDLT_H

#include "sf_error.h"

typedef struct sf_ldlt sf_ldlt;

/* null_tol: a pivot p is null when |p| <= null_tol * (the norm MUMPS uses
 * for the null pivot test); <= 0 chooses 1e-12. */
int sf_ldlt_create(sf_ldlt **out, double null_tol, sf_error *err);
void sf_ldlt_free(sf_ldlt *f);

/* Factorise the n x n symmetric matrix given by nnz triplets of one
 * triangle.  The arrays are copied.  Analyses again when n or the
 * triplet pattern differs from the previous call. */
int sf_ldlt_factor(sf_ldlt *f, int n, long nnz, const int *row, const int *col,
                   const double *val, sf_error *err);

/* Solve A x = b in place (b has n entries) with the last factors. */
int sf_ldlt_solve(sf_ldlt *f, double *b, sf_error *err);
/* The next sf_ldlt_factor analyses its matrix afresh even when the pattern is
 * unchanged (MUMPS's analysis depends on the values it was made with). */
void sf_ldlt_forget_analysis(sf_ldlt *f);
/* MUMPS's workspace relaxation ICNTL(14), percent over the analysis's
 * estimate: its default 20 until a factorisation failed for lack of
 * workspace (INFOG(1) = -8 or -9) and was repeated with twice as much,
 * then the value that succeeded.  Where the workspace is just enough,
 * MUMPS's factors can differ in rounding from those with more (random KKT
 * matrices with zero diagonals and dependent rows, order 1000: at 16 of 30
 * the factors at the smallest relaxation that succeeded differed from
 * those at 2 to 32 times more, which all agreed; the inertia never
 * differed), so a relaxation carried over can change the last digits. */
int sf_ldlt_relaxation(const sf_ldlt *f);
/* Start the next factorisations with pct (e.g. what a factorisation of
 * the same matrix nearby needed: no factorisation repeated to find it
 * again; or the value before another caller used f). */
void sf_ldlt_set_relaxation(sf_ldlt *f, int pct);
/* 1 when f holds an analysis of this n and triplet pattern (the next
 * sf_ldlt_factor with it makes no analysis), else 0. */
int sf_ldlt_has_analysis(const sf_ldlt *f, int n, long nnz, const int *row, const int *col);
/* MUMPS's relative pivot threshold CNTL(1) for the next factorisations
 * (its default 0.01 for a symmetric indefinite matrix). */
void sf_ldlt_set_pivot_threshold(sf_ldlt *f, double u);

typedef struct sf_ldlt_info {
    int n;
    int neg;          /* negative pivots, INFOG(12) */
    int nnull;        /* null pivots, INFOG(28) */
    int det_sign;     /* sign of det A (0 when there are null pivots) */
    double log2_det;  /* log2 |det A| over the non-null pivots */
    int analyses;     /* symbolic analyses so far */
    int factorisations;
    int relaxations;  /* factorisations repeated with more workspace (ICNTL(14)) */
} sf_ldlt_info;

void sf_ldlt_get_info(const sf_ldlt *f, sf_ldlt_info *info);

/* The rows (0-based) of the null pivots of the last factorisation
 * (MUMPS PIVNUL_LIST, INFOG(28) of them): up to max into list; returns
 * their number. */
int sf_ldlt_null_rows(const sf_ldlt *f, int *list, int max);

#endif
