/* cont_lapack.h - a dense direct SUNLinearSolver on LAPACK (dgetrf/dgetrs)
 * for the engine's bordered systems.  SUNDIALS' own dense LU
 * (SUNLinSol_Dense) is an unblocked loop: LAPACK's blocked LU is about 9
 * times faster at n = 73 (square4: 2/5 of a whole run was spent in it).
 * Same contract as SUNLinSol_Dense: setup factorises the SUNDenseMatrix in
 * place, solve uses the factors; a zero pivot makes setup return
 * SUNLS_LUFACT_FAIL (recoverable). */
#ifndef CONT_LAPACK_H
#define CONT_LAPACK_H

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

SUNLinearSolver cont_lapack_dense(N_Vector y, SUNMatrix A, SUNContext ctx);

/* Row interchanges of the last factorisation (LAPACK's ipiv, 1-based:
 * row k was swapped with row ipiv[k] - 1), NULL before the first. */
const int *cont_lapack_pivots(SUNLinearSolver S);

#endif
