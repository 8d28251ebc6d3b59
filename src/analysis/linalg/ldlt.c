/* ldlt.c - MUMPS LDL^T with inertia (see ldlt.h). */
#include "ldlt.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <dmumps_c.h>

#include "cont_mumps.h"

/* MUMPS's Fortran communicator value meaning MPI_COMM_WORLD (the
 * sequential build ignores it) */
#define SF_MUMPS_COMM_WORLD (-987654)
#define ICNTL(I) icntl[(I) - 1]
#define CNTL(I) cntl[(I) - 1]
#define INFOG(I) infog[(I) - 1]
#define RINFOG(I) rinfog[(I) - 1]

struct sf_ldlt {
    DMUMPS_STRUC_C id;
    int inited;       /* job = -1 done */
    int n;
    long nnz, cap;
    int *irn, *jcn;   /* 1-based, as MUMPS wants them */
    double *a;
    int analysed;
    int factored;
    double null_tol;
    sf_ldlt_info info;
};

static void mumps_quiet(DMUMPS_STRUC_C *id)
{
    id->ICNTL(1) = -1; /* error messages */
    id->ICNTL(2) = -1; /* diagnostics */
    id->ICNTL(3) = -1; /* global information */
    id->ICNTL(4) = 0;  /* print level */
}

int sf_ldlt_create(sf_ldlt **out, double null_tol, sf_error *err)
{
    *out = NULL;
    cont_mumps_keep_heap();   /* MUMPS's workspace kept on the heap */
    cont_mumps_single_thread();   /* one ordering in every run (SCOTCH) */
    sf_ldlt *f = calloc(1, sizeof *f);
    if (!f) return sf_fail(err, SF_ENOMEM, "out of memory");
    f->null_tol = null_tol > 0 ? null_tol : 1e-12;
    f->id.job = -1;
    f->id.par = 1;
    f->id.sym = 2;
    f->id.comm_fortran = SF_MUMPS_COMM_WORLD;
    dmumps_c(&f->id);
    if (f->id.INFOG(1) < 0) {
        int e = f->id.INFOG(1);
        free(f);
        return sf_fail(err, SF_ENUMERIC, "MUMPS initialisation failed (INFOG(1) = %d)", e);
    }
    f->inited = 1;
    *out = f;
    return SF_OK;
}

void sf_ldlt_free(sf_ldlt *f)
{
    if (!f) return;
    if (f->inited) {
        f->id.job = -2;
        mumps_quiet(&f->id);
        dmumps_c(&f->id);
    }
    free(f->irn);
    free(f->jcn);
    free(f->a);
    free(f);
}

static int same_pattern(const sf_ldlt *f, int n, long nnz, const int *row, const int *col)
{
    if (!f->analysed || n != f->n || nnz != f->nnz) return 0;
    for (long k = 0; k < nnz; k++)
        if (f->irn[k] != row[k] + 1 || f->jcn[k] != col[k] + 1) return 0;
    return 1;
}

static int mumps_fail(const sf_ldlt *f, const char *what, sf_error *err)
{
    int e1 = f->id.INFOG(1), e2 = f->id.INFOG(2);
    if (e1 == -13)
        return sf_fail(err, SF_ENOMEM, "MUMPS %s: out of memory (INFOG(1) = %d, INFOG(2) = %d)",
                       what, e1, e2);
    return sf_fail(err, SF_ENUMERIC, "MUMPS %s failed (INFOG(1) = %d, INFOG(2) = %d)", what, e1,
                   e2);
}

int sf_ldlt_factor(sf_ldlt *f, int n, long nnz, const int *row, const int *col,
                   const double *val, sf_error *err)
{
    if (n < 1 || nnz < 1)
        return sf_fail(err, SF_EINTERNAL, "ldlt: empty matrix (n = %d, nnz = %ld)", n, nnz);
    for (long k = 0; k < nnz; k++) {
        if (row[k] < 0 || row[k] >= n || col[k] < 0 || col[k] >= n)
            return sf_fail(err, SF_EINTERNAL, "ldlt: entry %ld at (%d, %d) outside the %d x %d matrix",
                           k, row[k], col[k], n, n);
        if (!isfinite(val[k]))
            return sf_fail(err, SF_ENUMERIC, "ldlt: non-finite entry at (%d, %d)", row[k], col[k]);
    }
    DMUMPS_STRUC_C *id = &f->id;
    if (!same_pattern(f, n, nnz, row, col)) {
        if (nnz > f->cap) {
            int *ir = realloc(f->irn, sizeof(int) * (size_t)nnz);
            if (ir) f->irn = ir;
            int *jc = realloc(f->jcn, sizeof(int) * (size_t)nnz);
            if (jc) f->jcn = jc;
            double *a = realloc(f->a, sizeof(double) * (size_t)nnz);
            if (a) f->a = a;
            if (!ir || !jc || !a) return sf_fail(err, SF_ENOMEM, "out of memory");
            f->cap = nnz;
        }
        for (long k = 0; k < nnz; k++) {
            f->irn[k] = row[k] + 1;
            f->jcn[k] = col[k] + 1;
        }
        f->n = n;
        f->nnz = nnz;
        f->analysed = 0;
        f->factored = 0;
        id->n = n;
        id->nnz = nnz;
        id->irn = f->irn;
        id->jcn = f->jcn;
        id->a = f->a;
        memcpy(f->a, val, sizeof(double) * (size_t)nnz);
        mumps_quiet(id);
        id->job = 1;
        dmumps_c(id);
        if (id->INFOG(1) < 0) return mumps_fail(f, "analysis", err);
        f->analysed = 1;
        f->info.analyses++;
    } else {
        memcpy(f->a, val, sizeof(double) * (size_t)nnz);
    }
    mumps_quiet(id);
    id->ICNTL(24) = 1;          /* null pivot detection */
    id->CNTL(3) = f->null_tol;  /* its threshold, relative to the matrix norm */
    id->ICNTL(33) = 1;          /* determinant */
    f->factored = 0;
    for (int attempt = 0; attempt < 8; attempt++) {
        id->job = 2;
        dmumps_c(id);
        /* -8, -9: the workspace estimated by the analysis is too small
         * (delayed pivots of the zero block); more relaxation and again */
        if (id->INFOG(1) == -8 || id->INFOG(1) == -9) {
            id->ICNTL(14) = (id->ICNTL(14) > 0 ? id->ICNTL(14) : 20) * 2;
            f->info.relaxations++;
            continue;
        }
        break;
    }
    if (id->INFOG(1) < 0) return mumps_fail(f, "factorisation", err);
    f->factored = 1;
    f->info.factorisations++;
    f->info.n = n;
    f->info.neg = id->INFOG(12);
    f->info.nnull = id->INFOG(28);
    double mant = id->RINFOG(12);
    f->info.det_sign = f->info.nnull > 0 || mant == 0.0 ? 0 : (mant > 0 ? 1 : -1);
    f->info.log2_det = mant != 0.0 ? log2(fabs(mant)) + (double)id->INFOG(34) : -INFINITY;
    return SF_OK;
}

int sf_ldlt_relaxation(const sf_ldlt *f)
{
    return f->id.ICNTL(14) > 0 ? f->id.ICNTL(14) : 20;
}

void sf_ldlt_set_relaxation(sf_ldlt *f, int pct)
{
    if (pct > 0) f->id.ICNTL(14) = pct;
}

int sf_ldlt_has_analysis(const sf_ldlt *f, int n, long nnz, const int *row, const int *col)
{
    return same_pattern(f, n, nnz, row, col);
}

void sf_ldlt_set_pivot_threshold(sf_ldlt *f, double u)
{
    f->id.CNTL(1) = u;
}

void sf_ldlt_forget_analysis(sf_ldlt *f)
{
    f->analysed = 0;
    f->factored = 0;
}

int sf_ldlt_solve(sf_ldlt *f, double *b, sf_error *err)
{
    if (!f->factored) return sf_fail(err, SF_EINTERNAL, "ldlt: solve without factors");
    DMUMPS_STRUC_C *id = &f->id;
    id->rhs = b;
    id->nrhs = 1;
    id->lrhs = f->n;
    id->job = 3;
    mumps_quiet(id);
    dmumps_c(id);
    if (id->INFOG(1) < 0) return mumps_fail(f, "solve", err);
    return SF_OK;
}

void sf_ldlt_get_info(const sf_ldlt *f, sf_ldlt_info *info)
{
    *info = f->info;
}

int sf_ldlt_null_rows(const sf_ldlt *f, int *list, int max)
{
    if (!f->factored) return 0;
    int k = f->info.nnull;
    for (int i = 0; i < k && i < max; i++) list[i] = f->id.pivnul_list[i] - 1;
    return k;
}
