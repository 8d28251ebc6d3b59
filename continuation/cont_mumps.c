/* cont_mumps.c - MUMPS unsymmetric LU, or LDL^T of a symmetric matrix, as
 * a SUNLinearSolver (cont_mumps.h). */
#include "cont_mumps.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <dmumps_c.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* MUMPS's Fortran communicator value for MPI_COMM_WORLD (ignored by the
 * sequential build) */
#define MUMPS_COMM_WORLD (-987654)
#define ICNTL(I) icntl[(I) - 1]
#define INFOG(I) infog[(I) - 1]
#define RINFOG(I) rinfog[(I) - 1]
#define RELAX0 100     /* ICNTL(14) to start with, percent (50 gives INFO -9 on the
                          * pose KKT matrices of the Miura sheets) */
#define RELAX_MAX 1600

/* MUMPS allocates its workspace afresh at each factorisation (tens to
 * hundreds of MB on the large sheets).  glibc serves blocks above its mmap
 * threshold (at most 32 MB by default) with a new mapping each time,
 * which the kernel then faults in page by page, and returns freed memory
 * at the top of the heap to the system: on the 16x16 Miura actuation run
 * that was 2.8 s of system time in 34.5 s.  Kept on the heap (both
 * thresholds at 1 GB, set once for the process), the same blocks are
 * reused without faults.  The arithmetic is untouched; peak memory grows
 * by a few percent. */
#define HEAP_KEEP (1 << 30)
void cont_mumps_keep_heap(void)
{
#ifdef __GLIBC__
    static int done;
    if (done) return;
    done = 1;
    mallopt(M_MMAP_THRESHOLD, HEAP_KEEP);
    mallopt(M_TRIM_THRESHOLD, HEAP_KEEP);
#endif
}

/* The sequential MUMPS of Debian 12 (5.5) is built without METIS: an
 * ICNTL(7) of 5 falls back to MUMPS's automatic choice, which is SCOTCH
 * above 10000 rows of a symmetric matrix, 5000 of an unsymmetric one
 * (INFOG(7) = 3; AMF below: the LDL^T of sheets up to 8x8 does not reach
 * it).  SCOTCH 7 orders with one thread per
 * CPU of the affinity mask, and its threaded orderings differ from run to
 * run: 2 of 10 runs of the 12x12 Miura sheet had another permutation of
 * the same matrix (factor entries 518415 and 503680 against 491208), hence
 * other rounding from the first point after the flat start on.  With one
 * thread the ordering is the same in every run (6 of 6).  SCOTCH reads
 * SCOTCH_PTHREAD_NUMBER from the environment when it orders: set here for
 * the process, before the first analysis (once), over any value given,
 * as OpenBLAS's threads are in src/cli/main.c. */
void cont_mumps_single_thread(void)
{
    static int done;
    if (done) return;
    done = 1;
    setenv("SCOTCH_PTHREAD_NUMBER", "1", 1);
}

typedef struct mumps_content {
    DMUMPS_STRUC_C id;
    int inited;          /* job -1 done */
    int m;
    int sym;             /* 2: symmetric (lower triangle given), LDL^T */
    int *irn, *jcn;      /* 1-based coordinates of the analysed pattern */
    long cap;
    int need_analysis;
    int factored;
    long analyses, factors, relax;
    sunindextype last_flag;
} mumps_content;

#define CONTENT(S) ((mumps_content *)(S)->content)

static void quiet(DMUMPS_STRUC_C *id)
{
    id->ICNTL(1) = -1;   /* errors */
    id->ICNTL(2) = -1;   /* diagnostics */
    id->ICNTL(3) = -1;   /* global information */
    id->ICNTL(4) = 0;    /* print level */
}

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

/* The coordinates of A's pattern, 1-based, for a new analysis. */
static int take_pattern(mumps_content *c, SUNMatrix A)
{
    const sunindextype *ptr = SM_INDEXPTRS_S(A), *idx = SM_INDEXVALS_S(A);
    long nnz = (long)ptr[c->m];
    if (nnz > c->cap) {
        int *ir = realloc(c->irn, sizeof(int) * (size_t)nnz);
        if (ir) c->irn = ir;
        int *jc = realloc(c->jcn, sizeof(int) * (size_t)nnz);
        if (jc) c->jcn = jc;
        if (!ir || !jc) return -1;
        c->cap = nnz;
    }
    for (int j = 0; j < c->m; j++)
        for (sunindextype k = ptr[j]; k < ptr[j + 1]; k++) {
            c->irn[k] = (int)idx[k] + 1;
            c->jcn[k] = j + 1;
        }
    c->id.n = c->m;
    c->id.nnz = nnz;
    c->id.irn = c->irn;
    c->id.jcn = c->jcn;
    return 0;
}

static int ls_setup(SUNLinearSolver S, SUNMatrix A)
{
    mumps_content *c = CONTENT(S);
    DMUMPS_STRUC_C *id = &c->id;
    c->factored = 0;
    if (!A || SUNMatGetID(A) != SUNMATRIX_SPARSE || SM_SPARSETYPE_S(A) != CSC_MAT ||
        SM_ROWS_S(A) != c->m || SM_COLUMNS_S(A) != c->m) {
        c->last_flag = SUNLS_ILL_INPUT;
        return SUNLS_ILL_INPUT;
    }
    if (c->need_analysis || id->nnz != (MUMPS_INT8)SM_INDEXPTRS_S(A)[c->m]) {
        if (take_pattern(c, A) != 0) {
            c->last_flag = SUNLS_MEM_FAIL;
            return SUNLS_MEM_FAIL;
        }
        id->a = SM_DATA_S(A);
        quiet(id);
        id->ICNTL(7) = 5;     /* METIS ordering (SCOTCH or AMF where MUMPS
                                 * lacks METIS, cont_mumps_single_thread) */
        id->ICNTL(28) = 1;    /* sequential analysis */
        id->job = 1;
        dmumps_c(id);
        if (id->INFOG(1) < 0) {
            c->last_flag = id->INFOG(1);
            return SUNLS_PACKAGE_FAIL_UNREC;
        }
        c->need_analysis = 0;
        c->analyses++;
    }
    id->a = SM_DATA_S(A);
    quiet(id);
    id->ICNTL(33) = 1;        /* determinant */
    if (c->sym) id->ICNTL(24) = 1;   /* count null pivots (INFOG(28)) */
    for (;;) {
        id->job = 2;
        dmumps_c(id);
        /* -8, -9: the workspace the analysis estimated is too small */
        if ((id->INFOG(1) == -8 || id->INFOG(1) == -9) && id->ICNTL(14) < RELAX_MAX) {
            id->ICNTL(14) *= 2;   /* kept for the later factorisations */
            c->relax++;
            continue;
        }
        break;
    }
    c->last_flag = id->INFOG(1);
    if (id->INFOG(1) < 0) {
        /* -10: numerically singular; anything else is a failure of MUMPS */
        return id->INFOG(1) == -10 ? SUNLS_LUFACT_FAIL : SUNLS_PACKAGE_FAIL_UNREC;
    }
    c->factors++;
    c->factored = 1;
    return SUNLS_SUCCESS;
}

static int ls_solve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, realtype tol)
{
    (void)A; (void)tol;
    mumps_content *c = CONTENT(S);
    DMUMPS_STRUC_C *id = &c->id;
    if (!c->factored) {
        c->last_flag = SUNLS_ILL_INPUT;
        return SUNLS_ILL_INPUT;
    }
    N_VScale(1.0, b, x);
    id->rhs = N_VGetArrayPointer(x);
    id->nrhs = 1;
    id->lrhs = c->m;
    id->ICNTL(20) = 0;        /* dense right-hand side */
    id->ICNTL(21) = 0;        /* centralised solution */
    quiet(id);
    id->job = 3;
    dmumps_c(id);
    c->last_flag = id->INFOG(1);
    return id->INFOG(1) < 0 ? SUNLS_PACKAGE_FAIL_UNREC : SUNLS_SUCCESS;
}

static sunindextype ls_lastflag(SUNLinearSolver S)
{
    return CONTENT(S)->last_flag;
}

static int ls_free(SUNLinearSolver S)
{
    if (!S) return SUNLS_SUCCESS;
    mumps_content *c = S->content;
    if (c) {
        if (c->inited) {
            c->id.job = -2;
            quiet(&c->id);
            dmumps_c(&c->id);
        }
        free(c->irn);
        free(c->jcn);
        free(c);
        S->content = NULL;
    }
    SUNLinSolFreeEmpty(S);
    return SUNLS_SUCCESS;
}

static SUNLinearSolver create(N_Vector y, SUNMatrix A, SUNContext ctx, int sym)
{
    if (!A || SUNMatGetID(A) != SUNMATRIX_SPARSE || SM_SPARSETYPE_S(A) != CSC_MAT ||
        SM_ROWS_S(A) != SM_COLUMNS_S(A))
        return NULL;
    if (y && N_VGetLength(y) != SM_ROWS_S(A)) return NULL;
    cont_mumps_keep_heap();
    cont_mumps_single_thread();
    SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
    if (!S) return NULL;
    S->ops->gettype = ls_type;
    S->ops->getid = ls_id;
    S->ops->initialize = ls_initialize;
    S->ops->setup = ls_setup;
    S->ops->solve = ls_solve;
    S->ops->lastflag = ls_lastflag;
    S->ops->free = ls_free;
    mumps_content *c = calloc(1, sizeof *c);
    if (!c) {
        SUNLinSolFreeEmpty(S);
        return NULL;
    }
    S->content = c;
    c->m = (int)SM_ROWS_S(A);
    c->need_analysis = 1;
    c->id.job = -1;
    c->id.par = 1;
    c->sym = sym;
    c->id.sym = sym;          /* 0: unsymmetric LU; 2: general symmetric LDL^T */
    c->id.comm_fortran = MUMPS_COMM_WORLD;
    dmumps_c(&c->id);
    if (c->id.INFOG(1) < 0) {
        ls_free(S);
        return NULL;
    }
    c->inited = 1;
    quiet(&c->id);
    c->id.ICNTL(14) = RELAX0;
    return S;
}

SUNLinearSolver cont_mumps(N_Vector y, SUNMatrix A, SUNContext ctx)
{
    return create(y, A, ctx, 0);
}

SUNLinearSolver cont_mumps_sym(N_Vector y, SUNMatrix L, SUNContext ctx)
{
    return create(y, L, ctx, 2);
}

long cont_mumps_null_pivots(SUNLinearSolver S)
{
    const mumps_content *c = CONTENT(S);
    return c->factored && c->sym ? (long)c->id.INFOG(28) : 0;
}

void cont_mumps_new_pattern(SUNLinearSolver S)
{
    if (S && S->content) CONTENT(S)->need_analysis = 1;
}

int cont_mumps_det(SUNLinearSolver S, int *sign, double *logabs)
{
    if (!S || !S->content || !CONTENT(S)->factored) return -1;
    const DMUMPS_STRUC_C *id = &CONTENT(S)->id;
    double mant = id->RINFOG(12);   /* det = mant * 2^INFOG(34) */
    *sign = mant > 0 ? 1 : (mant < 0 ? -1 : 0);
    *logabs = mant != 0 ? log(fabs(mant)) + (double)id->INFOG(34) * log(2.0) : -HUGE_VAL;
    return 0;
}

void cont_mumps_factor_stats(SUNLinearSolver S, cont_factor_stats *fs)
{
    const mumps_content *c = CONTENT(S);
    fs->n = c->m;
    fs->entries = c->factored ? (double)c->id.INFOG(29) : 0.0;
    if (fs->entries < 0) fs->entries = -1e6 * fs->entries;   /* MUMPS: negative = millions */
    fs->flops = c->factored ? c->id.RINFOG(3) : 0.0;
    fs->delayed = c->factored ? c->id.INFOG(13) : 0;
}

void cont_mumps_inertia(SUNLinearSolver S, long *neg, long *nnull)
{
    const mumps_content *c = CONTENT(S);
    *neg = c->factored && c->sym ? (long)c->id.INFOG(12) : -1;
    *nnull = c->factored && c->sym ? (long)c->id.INFOG(28) : -1;
}

void cont_mumps_counts(SUNLinearSolver S, long *analyses, long *factors, long *relax)
{
    const mumps_content *c = CONTENT(S);
    *analyses = c->analyses;
    *factors = c->factors;
    *relax = c->relax;
}
