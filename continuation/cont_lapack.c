/* cont_lapack.c - dense LU SUNLinearSolver on LAPACK (cont_lapack.h). */
#include "cont_lapack.h"

#include <math.h>
#include <stdlib.h>

#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

extern void dgetrf_(const int *m, const int *n, double *a, const int *lda, int *ipiv, int *info);
extern void dgetrs_(const char *trans, const int *n, const int *nrhs, const double *a,
                    const int *lda, const int *ipiv, double *b, const int *ldb, int *info);

typedef struct lapack_content {
    int n;
    int *ipiv;
    int factored;
    sunindextype last_flag;
} lapack_content;

#define CONTENT(S) ((lapack_content *)(S)->content)

static SUNLinearSolver_Type ls_type(SUNLinearSolver S)
{
    (void)S;
    return SUNLINEARSOLVER_DIRECT;
}

static SUNLinearSolver_ID ls_id(SUNLinearSolver S)
{
    (void)S;
    return SUNLINEARSOLVER_CUSTOM;
}

static int ls_initialize(SUNLinearSolver S)
{
    CONTENT(S)->last_flag = SUNLS_SUCCESS;
    return SUNLS_SUCCESS;
}

static int ls_setup(SUNLinearSolver S, SUNMatrix A)
{
    lapack_content *c = CONTENT(S);
    c->factored = 0;
    if (!A || SUNMatGetID(A) != SUNMATRIX_DENSE || SUNDenseMatrix_Rows(A) != c->n ||
        SUNDenseMatrix_Columns(A) != c->n) {
        c->last_flag = SUNLS_ILL_INPUT;
        return SUNLS_ILL_INPUT;
    }
    int n = c->n, info = 0;
    dgetrf_(&n, &n, SUNDenseMatrix_Data(A), &n, c->ipiv, &info);
    c->last_flag = info;
    if (info < 0) return SUNLS_PACKAGE_FAIL_UNREC;
    if (info > 0) return SUNLS_LUFACT_FAIL;
    c->factored = 1;
    return SUNLS_SUCCESS;
}

static int ls_solve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, realtype tol)
{
    (void)tol;
    lapack_content *c = CONTENT(S);
    if (!c->factored) {
        c->last_flag = SUNLS_ILL_INPUT;
        return SUNLS_ILL_INPUT;
    }
    N_VScale(1.0, b, x);
    int n = c->n, one = 1, info = 0;
    dgetrs_("N", &n, &one, SUNDenseMatrix_Data(A), &n, c->ipiv, N_VGetArrayPointer(x), &n, &info);
    c->last_flag = info;
    return info == 0 ? SUNLS_SUCCESS : SUNLS_PACKAGE_FAIL_UNREC;
}

static sunindextype ls_lastflag(SUNLinearSolver S)
{
    return CONTENT(S)->last_flag;
}

static int ls_space(SUNLinearSolver S, long *lrw, long *liw)
{
    *lrw = 0;
    *liw = 2 + CONTENT(S)->n;
    return SUNLS_SUCCESS;
}

static int ls_free(SUNLinearSolver S)
{
    if (!S) return SUNLS_SUCCESS;
    if (S->content) {
        free(CONTENT(S)->ipiv);
        free(S->content);
        S->content = NULL;
    }
    SUNLinSolFreeEmpty(S);
    return SUNLS_SUCCESS;
}

SUNLinearSolver cont_lapack_dense(N_Vector y, SUNMatrix A, SUNContext ctx)
{
    if (!A || SUNMatGetID(A) != SUNMATRIX_DENSE || SUNDenseMatrix_Rows(A) != SUNDenseMatrix_Columns(A))
        return NULL;
    if (y && N_VGetLength(y) != SUNDenseMatrix_Rows(A)) return NULL;
    SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
    if (!S) return NULL;
    S->ops->gettype = ls_type;
    S->ops->getid = ls_id;
    S->ops->initialize = ls_initialize;
    S->ops->setup = ls_setup;
    S->ops->solve = ls_solve;
    S->ops->lastflag = ls_lastflag;
    S->ops->space = ls_space;
    S->ops->free = ls_free;
    lapack_content *c = calloc(1, sizeof *c);
    if (!c) {
        SUNLinSolFreeEmpty(S);
        return NULL;
    }
    S->content = c;
    c->n = (int)SUNDenseMatrix_Rows(A);
    c->ipiv = calloc((size_t)c->n + 1, sizeof(int));
    if (!c->ipiv) {
        ls_free(S);
        return NULL;
    }
    return S;
}

const int *cont_lapack_pivots(SUNLinearSolver S)
{
    return (S && S->content && CONTENT(S)->factored) ? CONTENT(S)->ipiv : NULL;
}
