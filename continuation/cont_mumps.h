/* cont_mumps.h - MUMPS (sequential, unsymmetric multifrontal LU, or LDL^T
 * of a symmetric matrix) as a SUNLinearSolver for a square CSC
 * SUNSparseMatrix: the sparse solver of the engine's bordered systems
 * [Jy Fp; c^T] (CONT_LINSOL_MUMPS, cont.h), and of a symmetric Jy alone for
 * their block elimination (cont_blockelim.c).
 *
 * Setup analyses the pattern (METIS ordering) only when
 * cont_mumps_new_pattern was called since the last analysis (the engine
 * tracks pattern changes, cont_bordered.c), then factorises; the
 * determinant is computed with the factors (MUMPS ICNTL(33)).  When the
 * workspace the analysis predicted is too small (INFO(1) = -8 or -9, e.g.
 * after delayed pivots), the factorisation is retried with twice the
 * relaxation ICNTL(14), up to 1600 %.  A singular matrix fails setup with
 * SUNLS_LUFACT_FAIL; the MUMPS code is available from SUNLinSolLastFlag.
 * The solver never prints.  Creating one (or an ldlt.h solver) sets
 * glibc's mmap and trim thresholds to 1 GB for the process, so that
 * MUMPS's workspace is reused on the heap instead of mapped and faulted
 * in at every factorisation (continuation/README.md, "Where the path's
 * time goes with stability"). */
#ifndef CONT_MUMPS_H
#define CONT_MUMPS_H

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

#include "cont.h"

/* A solver for the m x m CSC matrix A (m = length of y).  NULL on failure
 * (wrong matrix type, out of memory, MUMPS initialisation failed). */
SUNLinearSolver cont_mumps(N_Vector y, SUNMatrix A, SUNContext ctx);

/* The same for a symmetric matrix given by its lower triangle L (entries
 * i >= j only): MUMPS's LDL^T with 1x1 and 2x2 pivots (SYM = 2), null
 * pivots detected (ICNTL(24) = 1) and counted by cont_mumps_null_pivots;
 * the determinant is that of the whole symmetric matrix. */
SUNLinearSolver cont_mumps_sym(N_Vector y, SUNMatrix L, SUNContext ctx);

/* After a setup of a cont_mumps_sym solver: the null pivots MUMPS found
 * (INFOG(28); their rows were not factorised as they are), else 0. */
long cont_mumps_null_pivots(SUNLinearSolver S);

/* The next setup re-analyses the pattern. */
void cont_mumps_new_pattern(SUNLinearSolver S);

/* After a successful setup: sign (+1/-1) and natural log of |det A|.
 * Returns 0, or -1 without factors. */
int cont_mumps_det(SUNLinearSolver S, int *sign, double *logabs);

/* glibc's mmap and trim thresholds set to 1 GB for the process (once;
 * nothing elsewhere): MUMPS's workspace is then reused on the heap.
 * Called by the two solvers above and by src/analysis/linalg/ldlt.c. */
void cont_mumps_keep_heap(void);

/* SCOTCH, MUMPS's ordering of large matrices in a build without METIS,
 * held to one thread for the process (SCOTCH_PTHREAD_NUMBER = 1; once):
 * its threaded orderings differ from run to run, and with them the
 * rounding of every factorisation.  Called where cont_mumps_keep_heap is. */
void cont_mumps_single_thread(void);

/* The last factorisation's figures (cont.h, cont_factor_stats; ldlt is
 * left as it is); zeros without factors. */
void cont_mumps_factor_stats(SUNLinearSolver S, cont_factor_stats *fs);

/* After a setup of a cont_mumps_sym solver: the negative pivots
 * (INFOG(12)) and the null ones (INFOG(28)); -1 each without factors. */
void cont_mumps_inertia(SUNLinearSolver S, long *neg, long *nnull);

/* Counters since creation: analyses, factorisations, workspace relaxations;
 * MUMPS's own timings are not used (none of these may be NULL). */
void cont_mumps_counts(SUNLinearSolver S, long *analyses, long *factors, long *relax);

#endif
