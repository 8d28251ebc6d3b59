/* cont.c - pseudo-arclength continuation engine (see cont.h for the
 * algorithm and references).
 *
 * Layout of this file
 *   1. solver structure, small helpers, errors, timing
 *   2. user callbacks wrapped: counting, non-finite checks, pattern checks
 *   3. bordered matrices: assembly, factorisation, determinant, solves
 *   4. KINSOL corrector
 *   5. points: allocation, evaluation (tangent, test functions)
 *   6. special-point location
 *   7. life cycle, options
 *   8. start, step, run
 *   9. branch switching
 */
#include "cont.h"
#include "cont_lapack.h"

#include <kinsol/kinsol.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sundials/sundials_context.h>

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* LAPACK (Fortran interface, LP64) */
extern void dgesvd_(const char *jobu, const char *jobvt, const int *m,
                    const int *n, double *a, const int *lda, double *s,
                    double *u, const int *ldu, double *vt, const int *ldvt,
                    double *work, const int *lwork, int *info);

/* Constants documented in cont.h */
#define SKIP_START_RATIO 1e-4   /* negligible test value at a start point */
#define BP_NULL_TOL 1e-6        /* null-space check in cont_branch_direction */
#define LOC_MAXIT 100
#define GUARD_ANGLE 0.05       /* rad, branch-jump guard in locate() */
#define MERGE_FRAC 1e-3        /* LP and BP this close (fraction of the step) are one BP */

enum { TEST_LP = -1, TEST_BP = -2, TEST_PB = -3 };  /* >= 0: user test k */
enum { ST_IDLE = 0, ST_RUN, ST_DONE, ST_FAIL };

/* ===================================================================== */
/* 1. structure and helpers                                               */
/* ===================================================================== */

typedef struct cont_bmat {
    long m;                   /* order */
    int sparse;
    SUNMatrix A;
    SUNLinearSolver LS;
    sunindextype *pat_ptr, *pat_idx;  /* last pattern given to KLU */
    sunindextype pat_cap;
    int pat_valid;
} cont_bmat;

typedef struct cpt {
    cont_point pub;
    double *x;       /* n+1: y, p */
    double *t;       /* n+1: ty, tp */
    double *test;    /* ntest */
    int det_valid;
    double h;        /* arclength offset from the step base */
    int terminal;
    int stop_reason;
} cpt;

struct cont_solver {
    cont_problem prob;
    long n, m;
    int linsol;
    double *yscale_copy, *fscale_copy;
    double *wy;              /* norm weights of y (cont_set_weights), NULL: all 1 */
    double *ulast;           /* with wy: the Newton iterate at the last Jacobian, m */
    char (*labels)[16];

    /* options */
    double ds0, ds_min, ds_max, grow, shrink, max_angle;
    double p_min, p_max, s_max, theta, ftol, xtol, loc_tol;
    long max_steps;
    int max_newton, strategy, fast_iters, init_maxit, init_strategy;
    unsigned detect;
    int store;
    cont_point_fn cb;
    void *cb_data;

    /* SUNDIALS objects */
    SUNContext ctx;
    SUNMatrix Jy;
    double *Fp;
    N_Vector u, uscale, fscale, vx, vb;
    void *kmem;
    cont_bmat bk, bt;        /* KINSOL's matrix; tangent/determinant matrix */

    /* corrector border: c.(x - xa) - sig = 0 */
    double *bc, *bxa, bsig;
    double *cw, *w1;         /* work, m each */
    char *mark;              /* permutation parity work, m+1 */
    long *stamp;             /* duplicate check of sparse Jy, n */

    /* run state */
    int state, stop_reason, first_step;
    cpt *base;               /* last regular point: the next step starts here */
    double s_arc, ds;
    long steps, index;
    cpt *queue[64];
    int nq, q0;
    cpt *cur;                /* last delivered point */
    int cur_owned;           /* cur not in hist: free it when replaced */
    cpt **hist;
    long nhist, hcap;
    cpt **spec;
    long nspec, scap;
    cpt *lw[3];              /* location scratch */
    struct timespec t_start;

    cont_stats stp, last, total;
    double last_fnorm;       /* residual norm at the last residual call */
    char why[400];           /* reason the last attempt failed */
    char kin_msg[256];       /* last message from KINSOL */
    char msg[512];           /* first error */
    int err;
};

static double now_sec(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double since(const struct timespec *t0)
{
    return now_sec() - ((double)t0->tv_sec + 1e-9 * (double)t0->tv_nsec);
}

/* Record the first error. */
static int fail(cont_solver *s, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static int fail(cont_solver *s, int code, const char *fmt, ...)
{
    if (s->msg[0] == '\0') {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(s->msg, sizeof s->msg, fmt, ap);
        va_end(ap);
        s->err = code;
    }
    return code;
}

/* Reason of the current failed attempt (overwrites). */
static void why(cont_solver *s, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
static void why(cont_solver *s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(s->why, sizeof s->why, fmt, ap);
    va_end(ap);
}

static double dotw(const cont_solver *s, const double *a, const double *b)
{
    double d = 0.0;
    if (s->wy)
        for (long i = 0; i < s->n; i++) d += s->wy[i] * a[i] * b[i];
    else
        for (long i = 0; i < s->n; i++) d += a[i] * b[i];
    return d + s->theta * s->theta * a[s->n] * b[s->n];
}

/* c = W t */
static void weigh(const cont_solver *s, const double *t, double *c)
{
    for (long i = 0; i < s->n; i++) c[i] = s->wy ? s->wy[i] * t[i] : t[i];
    c[s->n] = s->theta * s->theta * t[s->n];
}

static int all_finite(const double *v, long len)
{
    for (long i = 0; i < len; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

static double norm_inf(const double *v, long len)
{
    double r = 0.0;
    for (long i = 0; i < len; i++) {
        double a = fabs(v[i]);
        if (!(a <= r)) r = a;   /* propagates NaN */
    }
    return r;
}

/* ===================================================================== */
/* 2. user callbacks                                                      */
/* ===================================================================== */

/* F at (y, p) into F (n values).  0 ok, -1 failed (reason in s->why). */
static int call_residual(cont_solver *s, const double *y, double p, double *F)
{
    s->stp.nres++;
    int r = s->prob.residual(y, p, F, s->prob.user);
    if (r != 0) {
        s->last_fnorm = NAN;
        why(s, "residual function returned %d at p = %.10g", r, p);
        return -1;
    }
    s->last_fnorm = norm_inf(F, s->n);
    if (!isfinite(s->last_fnorm)) {
        long i = 0;
        while (i < s->n && isfinite(F[i])) i++;
        why(s, "residual function produced a non-finite value (F[%ld] = %g) "
            "at p = %.10g", i, i < s->n ? F[i] : 0.0, p);
        return -1;
    }
    return 0;
}

static int check_sparse_jy(cont_solver *s, double p)
{
    SUNMatrix J = s->Jy;
    long n = s->n;
    sunindextype *ptr = SM_INDEXPTRS_S(J), *idx = SM_INDEXVALS_S(J);
    if (SM_SPARSETYPE_S(J) != CSC_MAT || SM_ROWS_S(J) != n || SM_COLUMNS_S(J) != n) {
        why(s, "Jacobian matrix was replaced by one of the wrong type or size");
        return -1;
    }
    if (ptr[0] != 0) {
        why(s, "sparse Jacobian at p = %.10g: column pointer 0 is %ld, "
            "not 0", p, (long)ptr[0]);
        return -1;
    }
    for (long j = 0; j < n; j++)
        if (ptr[j + 1] < ptr[j]) {
            why(s, "sparse Jacobian at p = %.10g: column pointers decrease "
                "at column %ld", p, j);
            return -1;
        }
    if (ptr[n] > SM_NNZ_S(J)) {
        why(s, "sparse Jacobian at p = %.10g: %ld entries exceed the "
            "capacity %ld (use SUNSparseMatrix_Reallocate)", p, (long)ptr[n],
            (long)SM_NNZ_S(J));
        return -1;
    }
    for (long i = 0; i < n; i++) s->stamp[i] = -1;
    for (long j = 0; j < n; j++)
        for (sunindextype k = ptr[j]; k < ptr[j + 1]; k++) {
            if (idx[k] < 0 || idx[k] >= n) {
                why(s, "sparse Jacobian at p = %.10g: row index %ld out of range "
                    "(column %ld, entry %ld)", p, (long)idx[k], j, (long)k);
                return -1;
            }
            if (s->stamp[idx[k]] == j) {
                why(s, "sparse Jacobian at p = %.10g: duplicate entry (%ld, %ld)",
                    p, (long)idx[k], j);
                return -1;
            }
            s->stamp[idx[k]] = j;
        }
    if (!all_finite(SM_DATA_S(J), (long)ptr[n])) {
        why(s, "sparse Jacobian at p = %.10g has a non-finite entry", p);
        return -1;
    }
    return 0;
}

/* Jy, Fp at (y, p).  0 ok, -1 failed (reason in s->why). */
static int call_jacobian(cont_solver *s, const double *y, double p)
{
    long n = s->n;
    s->stp.njac++;
    SUNMatZero(s->Jy);
    memset(s->Fp, 0, (size_t)n * sizeof(double));
    int r = s->prob.jacobian(y, p, s->Jy, s->Fp, s->prob.user);
    if (r != 0) {
        why(s, "Jacobian function returned %d at p = %.10g", r, p);
        return -1;
    }
    if (!all_finite(s->Fp, n)) {
        why(s, "Jacobian function produced a non-finite dF/dp at p = %.10g", p);
        return -1;
    }
    if (s->prob.jac_matrix == CONT_MATRIX_SPARSE) return check_sparse_jy(s, p);
    if (!all_finite(SM_DATA_D(s->Jy), n * n)) {
        why(s, "Jacobian function produced a non-finite dF/dy at p = %.10g", p);
        return -1;
    }
    return 0;
}

/* ===================================================================== */
/* 3. bordered matrices                                                   */
/* ===================================================================== */

static int bm_init(cont_solver *s, cont_bmat *bm, long m, int sparse,
                   sunindextype nnz, N_Vector tmpl)
{
    memset(bm, 0, sizeof *bm);
    bm->m = m;
    bm->sparse = sparse;
    if (sparse) {
        bm->A = SUNSparseMatrix(m, m, nnz, CSC_MAT, s->ctx);
        if (!bm->A) return CONT_ENOMEM;
        bm->LS = SUNLinSol_KLU(tmpl, bm->A, s->ctx);
    } else {
        bm->A = SUNDenseMatrix(m, m, s->ctx);
        if (!bm->A) return CONT_ENOMEM;
        bm->LS = cont_lapack_dense(tmpl, bm->A, s->ctx);   /* LAPACK LU (cont_lapack.h) */
    }
    if (!bm->LS) return CONT_ENOMEM;
    if (SUNLinSolInitialize(bm->LS) != 0) return CONT_ENOMEM;
    return CONT_OK;
}

static void bm_free(cont_bmat *bm)
{
    if (bm->LS) SUNLinSolFree(bm->LS);
    if (bm->A) SUNMatDestroy(bm->A);
    free(bm->pat_ptr);
    free(bm->pat_idx);
    memset(bm, 0, sizeof *bm);
}

/* Number of stored entries of Jy (sparse: actual; dense: n^2). */
static sunindextype jy_nnz(const cont_solver *s)
{
    if (s->prob.jac_matrix == CONT_MATRIX_SPARSE) return SM_INDEXPTRS_S(s->Jy)[s->n];
    return (sunindextype)s->n * s->n;
}

/* After filling a sparse bordered matrix: tell KLU to re-analyse when the
 * pattern differs from the one it has factorised before. */
static int bm_pattern_check(cont_bmat *bm)
{
    sunindextype *ptr = SM_INDEXPTRS_S(bm->A), *idx = SM_INDEXVALS_S(bm->A);
    sunindextype nnz = ptr[bm->m];
    int same = bm->pat_valid;
    if (same) {
        same = memcmp(ptr, bm->pat_ptr, (size_t)(bm->m + 1) * sizeof *ptr) == 0 &&
               memcmp(idx, bm->pat_idx, (size_t)nnz * sizeof *idx) == 0;
    }
    if (same) return 0;
    if (bm->pat_cap < nnz || !bm->pat_ptr) {
        sunindextype *np = realloc(bm->pat_ptr, (size_t)(bm->m + 1) * sizeof *np);
        if (!np) return -1;
        bm->pat_ptr = np;
        sunindextype *ni = realloc(bm->pat_idx, (size_t)(nnz > 0 ? nnz : 1) * sizeof *ni);
        if (!ni) return -1;
        bm->pat_idx = ni;
        bm->pat_cap = nnz;
    }
    memcpy(bm->pat_ptr, ptr, (size_t)(bm->m + 1) * sizeof *ptr);
    memcpy(bm->pat_idx, idx, (size_t)nnz * sizeof *idx);
    if (bm->pat_valid)
        SUNLinSol_KLUReInit(bm->LS, bm->A, SM_NNZ_S(bm->A), SUNKLU_REINIT_PARTIAL);
    bm->pat_valid = 1;
    return 0;
}

/* Assemble [Jy Fp; c^T] ((n+1) x (n+1)) from s->Jy, s->Fp. */
static int bm_build(cont_solver *s, cont_bmat *bm, const double *c)
{
    long n = s->n, m = n + 1;
    int jsp = s->prob.jac_matrix == CONT_MATRIX_SPARSE;
    if (!bm->sparse) {
        SUNMatZero(bm->A);
        if (jsp) {
            sunindextype *ptr = SM_INDEXPTRS_S(s->Jy), *idx = SM_INDEXVALS_S(s->Jy);
            double *val = SM_DATA_S(s->Jy);
            for (long j = 0; j < n; j++) {
                double *col = SM_COLUMN_D(bm->A, j);
                for (sunindextype k = ptr[j]; k < ptr[j + 1]; k++) col[idx[k]] += val[k];
            }
        } else {
            for (long j = 0; j < n; j++)
                memcpy(SM_COLUMN_D(bm->A, j), SM_COLUMN_D(s->Jy, j), (size_t)n * sizeof(double));
        }
        for (long j = 0; j < n; j++) SM_ELEMENT_D(bm->A, n, j) = c[j];
        double *col = SM_COLUMN_D(bm->A, n);
        memcpy(col, s->Fp, (size_t)n * sizeof(double));
        col[n] = c[n];
        return 0;
    }
    sunindextype need = jy_nnz(s) + 2 * (sunindextype)n + 1;
    if (SM_NNZ_S(bm->A) < need) {
        if (SUNSparseMatrix_Reallocate(bm->A, need) != 0) {
            why(s, "out of memory enlarging the bordered matrix");
            return -1;
        }
    }
    sunindextype *bp = SM_INDEXPTRS_S(bm->A), *bi = SM_INDEXVALS_S(bm->A);
    double *bx = SM_DATA_S(bm->A);
    sunindextype k = 0;
    for (long j = 0; j < n; j++) {
        bp[j] = k;
        if (jsp) {
            sunindextype *ptr = SM_INDEXPTRS_S(s->Jy), *idx = SM_INDEXVALS_S(s->Jy);
            double *val = SM_DATA_S(s->Jy);
            for (sunindextype q = ptr[j]; q < ptr[j + 1]; q++) {
                bi[k] = idx[q];
                bx[k++] = val[q];
            }
        } else {
            double *col = SM_COLUMN_D(s->Jy, j);
            for (long i = 0; i < n; i++) {
                bi[k] = i;
                bx[k++] = col[i];
            }
        }
        bi[k] = n;
        bx[k++] = c[j];
    }
    bp[n] = k;
    for (long i = 0; i < n; i++) {
        bi[k] = i;
        bx[k++] = s->Fp[i];
    }
    bi[k] = n;
    bx[k++] = c[n];
    bp[m] = k;
    (void)m;
    if (bm_pattern_check(bm) != 0) {
        why(s, "out of memory saving the sparsity pattern");
        return -1;
    }
    return 0;
}

/* Parity (+1/-1) of a permutation given as perm[k] = image of k. */
static int perm_parity(const sunindextype *perm, long m, char *mark)
{
    int par = 1;
    memset(mark, 0, (size_t)m);
    for (long i = 0; i < m; i++) {
        if (mark[i]) continue;
        long len = 0, j = i;
        while (!mark[j]) {
            mark[j] = 1;
            j = (long)perm[j];
            len++;
        }
        if (len % 2 == 0) par = -par;
    }
    return par;
}

/* LU-factorise bm; sign and log|.| of its determinant.  0 ok, -1 singular
 * or failed (reason in s->why). */
static int bm_factor(cont_solver *s, cont_bmat *bm, int *sign, double *logdet)
{
    long m = bm->m;
    s->stp.nfactor++;
    int r = SUNLinSolSetup(bm->LS, bm->A);
    if (r != 0) {
        if (bm->sparse)
            why(s, "KLU could not factorise the bordered matrix (flag %d, "
                "singular or not finite)", r);
        else
            why(s, "the bordered matrix is singular (zero pivot in column %ld)",
                (long)SUNLinSolLastFlag(bm->LS) - 1);
        return -1;
    }
    int sg = 1;
    double ld = 0.0;
    if (!bm->sparse) {
        const int *piv = cont_lapack_pivots(bm->LS);
        if (!piv) {
            why(s, "no LU factors of the bordered matrix");
            return -1;
        }
        for (long k = 0; k < m; k++) {
            double d = SM_ELEMENT_D(bm->A, k, k);
            if (d < 0) sg = -sg;
            else if (d == 0) sg = 0;
            ld += log(fabs(d));
            if (piv[k] - 1 != k) sg = -sg;
        }
    } else {
        sun_klu_numeric *num = SUNLinSol_KLUGetNumeric(bm->LS);
        sun_klu_symbolic *sym = SUNLinSol_KLUGetSymbolic(bm->LS);
        if (!num || !sym) {
            why(s, "KLU factorisation not available");
            return -1;
        }
        const double *ud = (const double *)num->Udiag;
        for (long k = 0; k < m; k++) {
            if (ud[k] < 0) sg = -sg;
            else if (ud[k] == 0) sg = 0;
            ld += log(fabs(ud[k]));
            if (num->Rs) ld += log(num->Rs[k]);   /* rows were divided by Rs > 0 */
        }
        sg *= perm_parity((const sunindextype *)num->Pnum, m, s->mark);
        sg *= perm_parity((const sunindextype *)sym->Q, m, s->mark);
    }
    if (sign) *sign = sg;
    if (logdet) *logdet = ld;
    if (sg == 0) {
        why(s, "the bordered matrix is singular");
        return -1;
    }
    return 0;
}

/* Solve with the factors of bm: x = A^{-1} b (vectors of length bm->m). */
static int bm_solve(cont_solver *s, cont_bmat *bm, N_Vector x, N_Vector b)
{
    s->stp.nlinsolve++;
    int r = SUNLinSolSolve(bm->LS, bm->A, x, b, 0.0);
    if (r != 0 || !all_finite(N_VGetArrayPointer(x), bm->m)) {
        why(s, "linear solve with the bordered matrix failed (flag %d)", r);
        return -1;
    }
    return 0;
}

/* ===================================================================== */
/* 4. KINSOL corrector                                                    */
/* ===================================================================== */

static int kin_sys(N_Vector uv, N_Vector fv, void *data)
{
    cont_solver *s = data;
    long n = s->n;
    double *u = N_VGetArrayPointer(uv), *f = N_VGetArrayPointer(fv);
    if (!all_finite(u, n + 1)) {
        why(s, "Newton iterate became non-finite");
        s->last_fnorm = NAN;
        return -1;
    }
    if (call_residual(s, u, u[n], f) != 0) return -1;
    double g = -s->bsig;
    for (long i = 0; i <= n; i++) g += s->bc[i] * (u[i] - s->bxa[i]);
    f[n] = g;
    return 0;
}

static int kin_jac(N_Vector uv, N_Vector fv, SUNMatrix J, void *data,
                   N_Vector t1, N_Vector t2)
{
    (void)fv; (void)t1; (void)t2;
    cont_solver *s = data;
    double *u = N_VGetArrayPointer(uv);
    if (s->ulast) memcpy(s->ulast, u, (size_t)s->m * sizeof(double));
    if (call_jacobian(s, u, u[s->n]) != 0) return -1;
    if (J != s->bk.A) return -1;
    if (bm_build(s, &s->bk, s->bc) != 0) return -1;
    s->stp.nfactor++;      /* KINSOL factorises after every Jacobian */
    return 0;
}

static void kin_err(int code, const char *module, const char *function,
                    char *msg, void *data)
{
    (void)code;
    cont_solver *s = data;
    snprintf(s->kin_msg, sizeof s->kin_msg, "%s/%s: %s", module, function, msg);
}

static double scaled_norm2(const cont_solver *s, const double *v)
{
    double r = 0.0;
    for (long i = 0; i < s->m; i++) {
        double a = v[i] * NV_Ith_S(s->uscale, i);
        r += a * a;
    }
    return sqrt(r);
}

/* The norm of the Newton step test: KINSOL's scaled 2-norm, restricted by
 * the norm weights when cont_set_weights gave them (a component left out
 * of the arclength, e.g. a multiplier of a nearly redundant constraint, is
 * then not required to settle to xtol: it is slaved to the others). */
static double step_norm2(const cont_solver *s, const double *v)
{
    if (!s->wy) return scaled_norm2(s, v);
    double r = 0.0;
    for (long i = 0; i < s->m; i++) {
        double a = v[i] * NV_Ith_S(s->uscale, i);
        r += a * a * (i < s->n ? s->wy[i] : 1.0);
    }
    return sqrt(r);
}

/* Further exact Newton iterations on the corrector system (border s->bc,
 * s->bxa, s->bsig) at u, with the engine's own bordered factorisation,
 * until the scaled step is <= xtol (1 + |u|).  0 ok, -1 failed. */
static int polish(cont_solver *s, double *u, int *iters)
{
    long n = s->n, m = s->m;
    for (int k = 0; k < 5; k++) {
        double *b = N_VGetArrayPointer(s->vb);
        if (call_residual(s, u, u[n], b) != 0) return -1;
        double g = -s->bsig;
        for (long i = 0; i <= n; i++) g += s->bc[i] * (u[i] - s->bxa[i]);
        b[n] = g;
        for (long i = 0; i < m; i++) b[i] = -b[i];
        if (call_jacobian(s, u, u[n]) != 0 || bm_build(s, &s->bt, s->bc) != 0 ||
            bm_factor(s, &s->bt, NULL, NULL) != 0 || bm_solve(s, &s->bt, s->vx, s->vb) != 0)
            return -1;
        double *d = N_VGetArrayPointer(s->vx);
        for (long i = 0; i < m; i++) u[i] += d[i];
        (*iters)++;
        s->stp.newton_iters++;
        if (step_norm2(s, d) <= s->xtol * (1.0 + step_norm2(s, u))) return 0;
    }
    why(s, "Newton converges too slowly (near a singular point?): the step is still "
        "above xtol = %.3g after 5 extra iterations", s->xtol);
    return -1;
}

/* Solve F(x) = 0, c.(x - xa) = sig from the guess x (overwritten with the
 * solution on success).  0 ok, -1 failed (reason in s->why). */
static int correct(cont_solver *s, double *x, const double *c, const double *xa,
                   double sig, int maxit, int strategy, int *nit, double *fnorm)
{
    long m = s->m;
    memcpy(s->bc, c, (size_t)m * sizeof(double));
    memcpy(s->bxa, xa, (size_t)m * sizeof(double));
    s->bsig = sig;
    memcpy(N_VGetArrayPointer(s->u), x, (size_t)m * sizeof(double));
    s->why[0] = '\0';
    s->kin_msg[0] = '\0';
    KINSetNumMaxIters(s->kmem, maxit);
    KINSetFuncNormTol(s->kmem, s->ftol);
    KINSetScaledStepTol(s->kmem, 1e-15);
    int flag = KINSol(s->kmem, s->u, strategy, s->uscale, s->fscale);
    long nni = 0;
    KINGetNumNonlinSolvIters(s->kmem, &nni);
    s->stp.newton_iters += nni;
    s->stp.nlinsolve += nni;
    if (nit) *nit = (int)nni;
    double *u = N_VGetArrayPointer(s->u);
    /* KIN_LINESEARCH_NONCONV: the line search found no decrease; next to a
     * singular point that happens at a residual already at the tolerance,
     * so it is judged by the final check below like a stagnation */
    int ok = (flag >= 0 || flag == KIN_LINESEARCH_NONCONV) && all_finite(u, m);
    if (ok && nni >= 1 && s->xtol > 0) {
        /* a small residual is not enough where F is flat (near singular
         * points): also require a small last Newton step */
        double sl = 0.0;
        if (s->wy && s->ulast) {
            for (long i = 0; i < m; i++) s->w1[i] = u[i] - s->ulast[i];
            sl = step_norm2(s, s->w1);
        } else {
            KINGetStepLength(s->kmem, &sl);
        }
        if (sl > s->xtol * (1.0 + step_norm2(s, u))) {
            int extra = 0;
            if (polish(s, u, &extra) != 0) ok = 0;
            if (nit) *nit += extra;
        }
    }
    if (ok) {
        /* the residual at the returned point, unscaled, and a final check */
        if (call_residual(s, u, u[s->n], s->w1) != 0) ok = 0;
        else {
            double fs = 0.0;
            for (long i = 0; i < s->n; i++) {
                double a = fabs(s->w1[i] * NV_Ith_S(s->fscale, i));
                if (a > fs) fs = a;
            }
            /* KIN_STEP_LT_STPTOL: stagnation; accept only near the tolerance */
            double lim = flag == KIN_STEP_LT_STPTOL ? 100.0 * s->ftol : 10.0 * s->ftol;
            if (flag == KIN_LINESEARCH_NONCONV && fs > lim) {
                char *name = KINGetReturnFlagName(flag);
                why(s, "KINSOL %s after %ld iterations, scaled residual %.3g > %.3g",
                    name ? name : "failure", nni, fs, lim);
                free(name);
                ok = 0;
            } else if (fs > lim) {
                why(s, "Newton stagnated with scaled residual %.3g > %.3g", fs, lim);
                ok = 0;
            }
        }
    } else if (s->why[0] == '\0') {
        char *name = KINGetReturnFlagName(flag);
        why(s, "KINSOL %s after %ld iterations, residual norm %.3g%s%s",
            name ? name : "failure", nni, s->last_fnorm,
            s->kin_msg[0] ? ": " : "", s->kin_msg);
        free(name);
    }
    if (fnorm) *fnorm = s->last_fnorm;
    if (!ok) return -1;
    memcpy(x, u, (size_t)m * sizeof(double));
    return 0;
}

/* ===================================================================== */
/* 5. points                                                              */
/* ===================================================================== */

static cpt *pt_new(cont_solver *s)
{
    long m = s->m;
    int nt = s->prob.ntest;
    cpt *q = calloc(1, sizeof *q);
    if (!q) return NULL;
    q->x = calloc((size_t)(2 * m + nt), sizeof(double));
    if (!q->x) {
        free(q);
        return NULL;
    }
    q->t = q->x + m;
    q->test = nt > 0 ? q->t + m : NULL;
    q->pub.y = q->x;
    q->pub.ty = q->t;
    q->pub.test = q->test;
    return q;
}

static void pt_free(cpt *q)
{
    if (!q) return;
    free(q->x);
    free(q);
}

static void pt_copy(const cont_solver *s, cpt *dst, const cpt *src)
{
    double *x = dst->x, *t = dst->t, *test = dst->test;
    memcpy(x, src->x, (size_t)(2 * s->m + s->prob.ntest) * sizeof(double));
    *dst = *src;
    dst->x = x;
    dst->t = t;
    dst->test = test;
    dst->pub.y = x;
    dst->pub.ty = t;
    dst->pub.test = test;
}

static cpt *pt_dup(cont_solver *s, const cpt *src)
{
    cpt *q = pt_new(s);
    if (q) pt_copy(s, q, src);
    return q;
}

static void pt_sync(const cont_solver *s, cpt *q)
{
    q->pub.p = q->x[s->n];
    q->pub.tp = q->t[s->n];
}

static void set_label(cpt *q, int type, const char *label)
{
    q->pub.type = type;
    snprintf(q->pub.label, sizeof q->pub.label, "%s", label);
}

/* At the corrected point q->x: Jacobian, bordered matrix [Jy Fp; c^T],
 * determinant, tangent (unless keep_t: q->t already holds it and
 * c = W q->t), test functions.
 * Returns 0, -1 (numerical failure: reason in s->why) or CONT_EUSER (a user
 * test function failed: fatal). */
static int eval_point(cont_solver *s, cpt *q, const double *c, int dir, int keep_t)
{
    long n = s->n, m = s->m;
    if (call_jacobian(s, q->x, q->x[n]) != 0) return -1;
    if (bm_build(s, &s->bt, c) != 0) return -1;
    int sg = 0;
    double ld = 0.0;
    int fr = bm_factor(s, &s->bt, &sg, &ld);
    if (keep_t) {
        q->det_valid = fr == 0;
        q->pub.det_sign = fr == 0 ? sg : 0;
        q->pub.log_abs_det = fr == 0 ? ld : -HUGE_VAL;
    } else {
        if (fr != 0) return -1;
        N_VConst(0.0, s->vb);
        NV_Ith_S(s->vb, n) = 1.0;
        if (bm_solve(s, &s->bt, s->vx, s->vb) != 0) return -1;
        double *v = N_VGetArrayPointer(s->vx);
        double nv = sqrt(dotw(s, v, v));
        if (!(nv > 0) || !isfinite(nv)) {
            why(s, "tangent has zero or non-finite norm");
            return -1;
        }
        for (long i = 0; i < m; i++) q->t[i] = dir * v[i] / nv;
        /* det [A; (W t)^T] = dir |v|_W det [A; c^T]  (see cont.h) */
        q->det_valid = 1;
        q->pub.det_sign = dir * sg;
        q->pub.log_abs_det = ld + log(nv);
    }
    pt_sync(s, q);
    if (s->prob.ntest > 0) {
        int r = s->prob.test(q->x, q->x[n], q->t, q->t[n], q->test, s->prob.user);
        if (r != 0)
            return fail(s, CONT_EUSER, "test function returned %d at p = %.10g", r, q->x[n]);
        if (!all_finite(q->test, s->prob.ntest))
            return fail(s, CONT_EUSER, "test function produced a non-finite value at p = %.10g",
                        q->x[n]);
    }
    return 0;
}

/* ===================================================================== */
/* 6. special points                                                      */
/* ===================================================================== */

/* Value of test `id` at q; ref is the log|det| scale for TEST_BP. */
static double test_value(const cont_solver *s, int id, const cpt *q, double ref, double pb)
{
    if (id == TEST_LP) return q->t[s->n];
    if (id == TEST_PB) return q->x[s->n] - pb;
    if (id == TEST_BP) {
        double e = q->pub.log_abs_det - ref;
        if (e > 700) e = 700;
        if (e < -700) e = -700;
        return q->pub.det_sign * exp(e);
    }
    return q->test[id];
}

static int differ(double a, double b) { return signbit(a) != signbit(b); }

/* Locate the zero of test `id` between the step base b (h = 0) and xe
 * (h = he).  *res receives a new point (caller owns).  Returns 0, -1 (no
 * point could be corrected: *res NULL) or CONT_EUSER. */
static int locate(cont_solver *s, int id, const cpt *b, const cpt *xe, double he,
                  double pb, cpt **res)
{
    long n = s->n, m = s->m;
    cpt *lo = s->lw[0], *hi = s->lw[1], *tr = s->lw[2];
    double *c = s->cw;
    weigh(s, b->t, c);
    pt_copy(s, lo, b);
    pt_copy(s, hi, xe);
    lo->h = 0.0;
    hi->h = he;
    double ref = b->pub.log_abs_det;
    double fa = test_value(s, id, lo, ref, pb), fb = test_value(s, id, hi, ref, pb);
    double fa_true = fa, fb_true = fb;
    int side = 0, nit = 0, it;
    double ha = 0.0, hb = he;
    cpt *zero = NULL;
    for (it = 0; it < LOC_MAXIT; it++) {
        double tol = s->loc_tol * (1.0 + s->theta * fabs(hi->x[n]));
        if (hb - ha <= tol) break;
        double h = (fa * hb - fb * ha) / (fa - fb);
        if (!(h > ha && h < hb)) h = 0.5 * (ha + hb);
        int r = -1;
        for (int attempt = 0; attempt < 2 && r != 0; attempt++) {
            if (attempt == 1) h = 0.5 * (ha + hb);
            double w = (h - ha) / (hb - ha);
            for (long i = 0; i < m; i++) tr->x[i] = lo->x[i] + w * (hi->x[i] - lo->x[i]);
            double fn;
            s->stp.nlocate++;
            r = correct(s, tr->x, c, b->x, h, s->max_newton, s->strategy, &nit, &fn);
            if (r == 0) {
                r = eval_point(s, tr, c, +1, 0);
                if (r == CONT_EUSER) return r;
                tr->pub.resnorm = fn;
            }
            if (r == 0) {
                /* Branch guard: near a branch point the hyperplane also cuts
                 * the other branch and Newton may converge there.  Along one
                 * smooth branch the tangent turns by about the angle between
                 * the bracket ends, so a trial tangent turned further away
                 * from either end marks a jump. */
                double lim = acos(fmax(-1.0, fmin(1.0, dotw(s, lo->t, hi->t)))) + GUARD_ANGLE;
                double al = acos(fmax(-1.0, fmin(1.0, dotw(s, tr->t, lo->t))));
                double ah = acos(fmax(-1.0, fmin(1.0, dotw(s, tr->t, hi->t))));
                if (al > lim || ah > lim) {
                    why(s, "locating: trial point jumped to another branch");
                    r = -1;
                }
            }
        }
        if (r != 0) break;          /* give up: keep the best end */
        tr->pub.newton_iters = nit;
        tr->h = h;
        double ft = test_value(s, id, tr, ref, pb);
        if (ft == 0.0) {
            zero = tr;
            break;
        }
        if (!differ(ft, fb_true)) {
            cpt *tmp = hi; hi = tr; tr = tmp;
            hb = h; fb = fb_true = ft;
            if (side == -1) fa *= 0.5;
            side = -1;
        } else {
            cpt *tmp = lo; lo = tr; tr = tmp;
            ha = h; fa = fa_true = ft;
            if (side == +1) fb *= 0.5;
            side = +1;
        }
    }
    /* restore the scratch ring (pointers were swapped) */
    s->lw[0] = lo; s->lw[1] = hi; s->lw[2] = tr;
    const cpt *best = zero ? zero : (fabs(fa_true) <= fabs(fb_true) ? lo : hi);
    cpt *q = pt_dup(s, best);
    if (!q) return fail(s, CONT_ENOMEM, "out of memory");
    q->pub.loc_err = zero ? 0.0 : hb - ha;
    q->pub.ds = q->h;
    q->terminal = 0;
    *res = q;
    return 0;
}

/* ===================================================================== */
/* 7. life cycle, options                                                 */
/* ===================================================================== */

static void clear_run(cont_solver *s)
{
    while (s->nq > 0) {
        pt_free(s->queue[s->q0]);
        s->q0 = (s->q0 + 1) % 64;
        s->nq--;
    }
    s->q0 = 0;
    if (s->cur_owned) pt_free(s->cur);
    s->cur = NULL;
    s->cur_owned = 0;
    for (long i = 0; i < s->nhist; i++) pt_free(s->hist[i]);
    s->nhist = 0;
    for (long i = 0; i < s->nspec; i++) pt_free(s->spec[i]);
    s->nspec = 0;
    s->state = ST_IDLE;
    s->stop_reason = CONT_STOP_NONE;
    s->steps = 0;
    s->index = 0;
    s->s_arc = 0.0;
    memset(&s->stp, 0, sizeof s->stp);
    memset(&s->last, 0, sizeof s->last);
    memset(&s->total, 0, sizeof s->total);
}

void cont_free(cont_solver *s)
{
    if (!s) return;
    clear_run(s);
    free(s->hist);
    free(s->spec);
    for (int i = 0; i < 3; i++) pt_free(s->lw[i]);
    pt_free(s->base);
    if (s->kmem) KINFree(&s->kmem);
    bm_free(&s->bk);
    bm_free(&s->bt);
    if (s->u) N_VDestroy(s->u);
    if (s->uscale) N_VDestroy(s->uscale);
    if (s->fscale) N_VDestroy(s->fscale);
    if (s->vx) N_VDestroy(s->vx);
    if (s->vb) N_VDestroy(s->vb);
    if (s->Jy) SUNMatDestroy(s->Jy);
    free(s->Fp);
    free(s->bc);
    free(s->bxa);
    free(s->cw);
    free(s->w1);
    free(s->mark);
    free(s->stamp);
    free(s->yscale_copy);
    free(s->fscale_copy);
    free(s->wy);
    free(s->ulast);
    free(s->labels);
    if (s->ctx) SUNContext_Free(&s->ctx);
    free(s);
}

int cont_create(const cont_problem *prob, int linsol, cont_solver **out)
{
    if (!out) return CONT_EINPUT;
    *out = NULL;
    cont_solver *s = calloc(1, sizeof *s);
    if (!s) return CONT_ENOMEM;
    *out = s;
    if (!prob) return fail(s, CONT_EINPUT, "cont_create: no problem given");
    s->prob = *prob;
    long n = prob->n;
    if (n < 1) return fail(s, CONT_EINPUT, "cont_create: dimension n = %ld must be >= 1", n);
    if (!prob->residual || !prob->jacobian)
        return fail(s, CONT_EINPUT, "cont_create: residual and jacobian callbacks are required");
    if (prob->jac_matrix != CONT_MATRIX_DENSE && prob->jac_matrix != CONT_MATRIX_SPARSE)
        return fail(s, CONT_EINPUT, "cont_create: jac_matrix must be CONT_MATRIX_DENSE or "
                    "CONT_MATRIX_SPARSE (got %d)", prob->jac_matrix);
    if (prob->ntest < 0 || (prob->ntest > 0 && !prob->test))
        return fail(s, CONT_EINPUT, "cont_create: ntest = %d needs a test callback", prob->ntest);
    if (prob->ntest > 32)
        return fail(s, CONT_EINPUT, "cont_create: at most 32 user test functions (got %d)",
                    prob->ntest);
    if (linsol == CONT_LINSOL_AUTO)
        linsol = (prob->jac_matrix == CONT_MATRIX_SPARSE && n > CONT_AUTO_KLU_N)
                     ? CONT_LINSOL_KLU : CONT_LINSOL_DENSE;
    if (linsol != CONT_LINSOL_DENSE && linsol != CONT_LINSOL_KLU)
        return fail(s, CONT_EINPUT, "cont_create: unknown linear solver %d", linsol);
    s->linsol = linsol;
    s->n = n;
    s->m = n + 1;
    long m = s->m;

    /* defaults */
    s->ds0 = 0.01; s->ds_min = 1e-8; s->ds_max = 0.1;
    s->grow = 1.5; s->shrink = 0.5; s->fast_iters = 3; s->max_angle = 0.5;
    s->p_min = -HUGE_VAL; s->p_max = HUGE_VAL; s->s_max = HUGE_VAL;
    s->max_steps = 1000; s->theta = 1.0;
    s->ftol = 1e-10; s->xtol = 1e-6; s->max_newton = 10; s->strategy = KIN_NONE;
    s->init_maxit = 50; s->init_strategy = KIN_LINESEARCH;
    s->detect = CONT_DETECT_ALL; s->loc_tol = 1e-10;
    s->store = 1;

    /* copies of user arrays */
    if (prob->ntest > 0) {
        s->labels = calloc((size_t)prob->ntest, sizeof *s->labels);
        if (!s->labels) return fail(s, CONT_ENOMEM, "out of memory");
        for (int k = 0; k < prob->ntest; k++) {
            if (prob->test_labels && prob->test_labels[k])
                snprintf(s->labels[k], sizeof s->labels[k], "%s", prob->test_labels[k]);
            else
                snprintf(s->labels[k], sizeof s->labels[k], "USER%d", k + 1);
        }
    }
    s->prob.test_labels = NULL;

    if (SUNContext_Create(NULL, &s->ctx) != 0 || !s->ctx)
        return fail(s, CONT_ENOMEM, "cannot create the SUNDIALS context");
    s->u = N_VNew_Serial(m, s->ctx);
    s->uscale = N_VNew_Serial(m, s->ctx);
    s->fscale = N_VNew_Serial(m, s->ctx);
    s->vx = N_VNew_Serial(m, s->ctx);
    s->vb = N_VNew_Serial(m, s->ctx);
    s->Fp = calloc((size_t)n, sizeof(double));
    s->bc = calloc((size_t)m, sizeof(double));
    s->bxa = calloc((size_t)m, sizeof(double));
    s->cw = calloc((size_t)m, sizeof(double));
    s->w1 = calloc((size_t)m, sizeof(double));
    s->mark = calloc((size_t)m + 2, 1);
    s->stamp = calloc((size_t)n, sizeof(long));
    if (!s->u || !s->uscale || !s->fscale || !s->vx || !s->vb || !s->Fp || !s->bc ||
        !s->bxa || !s->cw || !s->w1 || !s->mark || !s->stamp)
        return fail(s, CONT_ENOMEM, "out of memory (n = %ld)", n);
    N_VConst(1.0, s->uscale);
    N_VConst(1.0, s->fscale);
    for (long i = 0; i < n; i++) {
        if (prob->yscale) {
            if (!(prob->yscale[i] > 0) || !isfinite(prob->yscale[i]))
                return fail(s, CONT_EINPUT, "cont_create: yscale[%ld] = %g must be positive",
                            i, prob->yscale[i]);
            NV_Ith_S(s->uscale, i) = prob->yscale[i];
        }
        if (prob->fscale) {
            if (!(prob->fscale[i] > 0) || !isfinite(prob->fscale[i]))
                return fail(s, CONT_EINPUT, "cont_create: fscale[%ld] = %g must be positive",
                            i, prob->fscale[i]);
            NV_Ith_S(s->fscale, i) = prob->fscale[i];
        }
    }
    if (prob->pscale != 0.0) {
        if (!(prob->pscale > 0) || !isfinite(prob->pscale))
            return fail(s, CONT_EINPUT, "cont_create: pscale = %g must be positive", prob->pscale);
        NV_Ith_S(s->uscale, n) = prob->pscale;
    }
    s->prob.yscale = s->prob.fscale = NULL;   /* copied into the N_Vectors */

    if (prob->jac_matrix == CONT_MATRIX_SPARSE) {
        sunindextype nnz = prob->jac_nnz > 0 ? prob->jac_nnz : 8 * (sunindextype)n;
        s->Jy = SUNSparseMatrix(n, n, nnz, CSC_MAT, s->ctx);
    } else {
        s->Jy = SUNDenseMatrix(n, n, s->ctx);
    }
    if (!s->Jy) return fail(s, CONT_ENOMEM, "out of memory for the Jacobian (n = %ld)", n);

    int sparse = linsol == CONT_LINSOL_KLU;
    sunindextype bnnz = (prob->jac_matrix == CONT_MATRIX_SPARSE ? SM_NNZ_S(s->Jy)
                                                                 : (sunindextype)n * n) +
                        2 * (sunindextype)n + 1;
    if (bm_init(s, &s->bk, m, sparse, bnnz, s->u) != CONT_OK ||
        bm_init(s, &s->bt, m, sparse, bnnz, s->u) != CONT_OK)
        return fail(s, CONT_ENOMEM, "cannot create the %s linear solver (n = %ld)",
                    sparse ? "KLU" : "dense", n);

    s->kmem = KINCreate(s->ctx);
    if (!s->kmem) return fail(s, CONT_ENOMEM, "KINCreate failed");
    KINSetErrHandlerFn(s->kmem, kin_err, s);
    KINSetPrintLevel(s->kmem, 0);
    if (KINInit(s->kmem, kin_sys, s->u) != KIN_SUCCESS ||
        KINSetUserData(s->kmem, s) != KIN_SUCCESS ||
        KINSetLinearSolver(s->kmem, s->bk.LS, s->bk.A) != KIN_SUCCESS ||
        KINSetJacFn(s->kmem, kin_jac) != KIN_SUCCESS ||
        KINSetMaxSetupCalls(s->kmem, 1) != KIN_SUCCESS ||
        KINSetNoResMon(s->kmem, SUNTRUE) != KIN_SUCCESS)
        return fail(s, CONT_ENOMEM, "KINSOL initialisation failed: %s", s->kin_msg);

    s->base = pt_new(s);
    for (int i = 0; i < 3; i++) s->lw[i] = pt_new(s);
    if (!s->base || !s->lw[0] || !s->lw[1] || !s->lw[2])
        return fail(s, CONT_ENOMEM, "out of memory");
    return CONT_OK;
}

#define NEED(s) do { if (!(s)) return CONT_EINPUT; } while (0)

int cont_set_step(cont_solver *s, double ds0, double ds_min, double ds_max)
{
    NEED(s);
    if (!(ds_min > 0 && ds_min <= ds0 && ds0 <= ds_max && isfinite(ds_max)))
        return fail(s, CONT_EINPUT, "cont_set_step: need 0 < ds_min <= ds0 <= ds_max "
                    "(got %g, %g, %g)", ds_min, ds0, ds_max);
    s->ds0 = ds0; s->ds_min = ds_min; s->ds_max = ds_max;
    if (s->state == ST_RUN) s->ds = fmin(fmax(s->ds, ds_min), ds_max);
    return CONT_OK;
}

int cont_set_step_control(cont_solver *s, double grow, double shrink, int fast_iters,
                          double max_angle)
{
    NEED(s);
    if (!(grow >= 1.0 && isfinite(grow)) || !(shrink > 0 && shrink < 1) || fast_iters < 0)
        return fail(s, CONT_EINPUT, "cont_set_step_control: need grow >= 1, 0 < shrink < 1, "
                    "fast_iters >= 0 (got %g, %g, %d)", grow, shrink, fast_iters);
    s->grow = grow; s->shrink = shrink; s->fast_iters = fast_iters; s->max_angle = max_angle;
    return CONT_OK;
}

int cont_set_prange(cont_solver *s, double p_min, double p_max)
{
    NEED(s);
    if (!(p_min < p_max) || isnan(p_min) || isnan(p_max))
        return fail(s, CONT_EINPUT, "cont_set_prange: need p_min < p_max (got %g, %g)",
                    p_min, p_max);
    s->p_min = p_min; s->p_max = p_max;
    return CONT_OK;
}

int cont_set_max_steps(cont_solver *s, long max_steps)
{
    NEED(s);
    s->max_steps = max_steps;
    return CONT_OK;
}

int cont_set_max_arclength(cont_solver *s, double s_max)
{
    NEED(s);
    if (!(s_max > 0))
        return fail(s, CONT_EINPUT, "cont_set_max_arclength: need s_max > 0 (got %g)", s_max);
    s->s_max = s_max;
    return CONT_OK;
}

int cont_set_theta(cont_solver *s, double theta_p)
{
    NEED(s);
    if (!(theta_p > 0) || !isfinite(theta_p))
        return fail(s, CONT_EINPUT, "cont_set_theta: need theta_p > 0 (got %g)", theta_p);
    if (s->state == ST_RUN)
        return fail(s, CONT_ESTATE, "cont_set_theta: cannot change the norm during a run");
    s->theta = theta_p;
    return CONT_OK;
}

int cont_set_weights(cont_solver *s, const double *w)
{
    NEED(s);
    if (s->state == ST_RUN)
        return fail(s, CONT_ESTATE, "cont_set_weights: cannot change the norm during a run");
    if (!w) {
        free(s->wy);
        free(s->ulast);
        s->wy = NULL;
        s->ulast = NULL;
        return CONT_OK;
    }
    double wmax = 0.0;
    for (long i = 0; i < s->n; i++) {
        if (!(w[i] >= 0) || !isfinite(w[i]))
            return fail(s, CONT_EINPUT, "cont_set_weights: weight %ld is %g (need finite >= 0)",
                        i, w[i]);
        wmax = fmax(wmax, w[i]);
    }
    if (!(wmax > 0))
        return fail(s, CONT_EINPUT, "cont_set_weights: all weights are zero");
    if (!s->wy) s->wy = malloc((size_t)s->n * sizeof(double));
    if (!s->ulast) s->ulast = calloc((size_t)s->m, sizeof(double));
    if (!s->wy || !s->ulast) return fail(s, CONT_ENOMEM, "out of memory");
    memcpy(s->wy, w, (size_t)s->n * sizeof(double));
    return CONT_OK;
}

int cont_set_newton(cont_solver *s, double ftol, int max_iters, int strategy)
{
    NEED(s);
    if (!(ftol > 0) || max_iters < 1 || (strategy != KIN_NONE && strategy != KIN_LINESEARCH))
        return fail(s, CONT_EINPUT, "cont_set_newton: need ftol > 0, max_iters >= 1, "
                    "strategy KIN_NONE or KIN_LINESEARCH (got %g, %d, %d)",
                    ftol, max_iters, strategy);
    s->ftol = ftol; s->max_newton = max_iters; s->strategy = strategy;
    return CONT_OK;
}

int cont_set_newton_steptol(cont_solver *s, double xtol)
{
    NEED(s);
    if (!(xtol >= 0) || !isfinite(xtol))
        return fail(s, CONT_EINPUT, "cont_set_newton_steptol: need xtol >= 0 (got %g)", xtol);
    s->xtol = xtol;
    return CONT_OK;
}

int cont_set_newton_init(cont_solver *s, int max_iters, int strategy)
{
    NEED(s);
    if (max_iters < 1 || (strategy != KIN_NONE && strategy != KIN_LINESEARCH))
        return fail(s, CONT_EINPUT, "cont_set_newton_init: need max_iters >= 1 and "
                    "strategy KIN_NONE or KIN_LINESEARCH (got %d, %d)", max_iters, strategy);
    s->init_maxit = max_iters; s->init_strategy = strategy;
    return CONT_OK;
}

int cont_set_detect(cont_solver *s, unsigned mask, double loc_tol)
{
    NEED(s);
    if ((mask & ~(unsigned)CONT_DETECT_ALL) || !(loc_tol > 0))
        return fail(s, CONT_EINPUT, "cont_set_detect: bad mask %u or loc_tol %g", mask, loc_tol);
    s->detect = mask; s->loc_tol = loc_tol;
    return CONT_OK;
}

int cont_set_callback(cont_solver *s, cont_point_fn fn, void *data)
{
    NEED(s);
    s->cb = fn; s->cb_data = data;
    return CONT_OK;
}

int cont_set_store(cont_solver *s, int store_points)
{
    NEED(s);
    if (s->state == ST_RUN)
        return fail(s, CONT_ESTATE, "cont_set_store: cannot change during a run");
    s->store = store_points != 0;
    return CONT_OK;
}

/* ===================================================================== */
/* 8. start, step, run                                                    */
/* ===================================================================== */

static void flush_stats(cont_solver *s, double t0, int is_step)
{
    s->stp.wall = now_sec() - t0;
    if (is_step) s->stp.ds = s->last.ds;
    cont_stats *T = &s->total, *P = &s->stp;
    T->steps += P->steps; T->points += P->points; T->newton_iters += P->newton_iters;
    T->nres += P->nres; T->njac += P->njac; T->nfactor += P->nfactor;
    T->nlinsolve += P->nlinsolve; T->retries += P->retries; T->nlocate += P->nlocate;
    T->wall += P->wall;
    if (is_step) {
        double ds = s->last.ds;
        s->last = *P;
        s->last.ds = ds;
        T->ds = ds;
    }
    memset(P, 0, sizeof *P);
}

static int push_ptr(cpt ***arr, long *len, long *cap, cpt *q)
{
    if (*len == *cap) {
        long nc = *cap ? 2 * *cap : 64;
        cpt **na = realloc(*arr, (size_t)nc * sizeof *na);
        if (!na) return -1;
        *arr = na;
        *cap = nc;
    }
    (*arr)[(*len)++] = q;
    return 0;
}

/* Hand q (owned) to the caller: index, storage, callback.  Returns 1 when
 * the callback asks to stop, 0 otherwise, CONT_ENOMEM on failure. */
static int deliver(cont_solver *s, cpt *q)
{
    q->pub.index = s->index++;
    pt_sync(s, q);
    if (s->cur_owned) pt_free(s->cur);
    s->cur = NULL;
    s->cur_owned = 0;
    if (s->store) {
        if (push_ptr(&s->hist, &s->nhist, &s->hcap, q) != 0) {
            pt_free(q);
            return fail(s, CONT_ENOMEM, "out of memory storing point %ld", s->index - 1);
        }
    } else {
        s->cur_owned = 1;
    }
    s->cur = q;
    if (q->pub.type != CONT_PT_REGULAR) {
        cpt *c = pt_dup(s, q);
        if (!c || push_ptr(&s->spec, &s->nspec, &s->scap, c) != 0) {
            pt_free(c);
            return fail(s, CONT_ENOMEM, "out of memory storing a special point");
        }
    }
    s->stp.points++;
    if (s->cb && s->cb(&q->pub, s->cb_data) != 0) return 1;
    return 0;
}

static void begin_run(cont_solver *s)
{
    clear_run(s);
    s->msg[0] = '\0';
    s->err = 0;
    clock_gettime(CLOCK_MONOTONIC, &s->t_start);
}

static int solve_fixed(cont_solver *s, double *x, int *nit, double *fnorm)
{
    long n = s->n, m = s->m;
    for (long i = 0; i < m; i++) s->cw[i] = 0.0;
    s->cw[n] = 1.0;
    /* anchor xa: only its p component matters, c = e_p */
    double *anchor = malloc((size_t)m * sizeof(double));
    if (!anchor) return fail(s, CONT_ENOMEM, "out of memory");
    memcpy(anchor, x, (size_t)m * sizeof(double));
    int r = correct(s, x, s->cw, anchor, 0.0, s->init_maxit, s->init_strategy, nit, fnorm);
    free(anchor);
    return r;
}

int cont_solve_fixed(cont_solver *s, double *y, double p)
{
    NEED(s);
    if (!y || !isfinite(p)) return fail(s, CONT_EINPUT, "cont_solve_fixed: bad arguments");
    if (!all_finite(y, s->n)) return fail(s, CONT_EINPUT, "cont_solve_fixed: y0 is not finite");
    double t0 = now_sec();
    double *x = malloc((size_t)s->m * sizeof(double));
    if (!x) return fail(s, CONT_ENOMEM, "out of memory");
    memcpy(x, y, (size_t)s->n * sizeof(double));
    x[s->n] = p;
    int nit;
    double fn;
    int r = solve_fixed(s, x, &nit, &fn);
    if (r == 0) memcpy(y, x, (size_t)s->n * sizeof(double));
    free(x);
    if (s->state != ST_RUN) flush_stats(s, t0, 0);
    if (r != 0)
        return fail(s, CONT_ENUMERIC, "Newton at fixed p = %.10g failed: %s", p, s->why);
    return CONT_OK;
}

static int finish_start(cont_solver *s, double t0, int nit, double fn)
{
    cpt *b = s->base;
    b->pub.newton_iters = nit;
    b->pub.resnorm = fn;
    b->pub.s = 0.0;
    b->pub.ds = 0.0;
    b->pub.loc_err = 0.0;
    b->pub.time = since(&s->t_start);
    b->h = 0.0;
    b->terminal = 0;
    set_label(b, CONT_PT_REGULAR, "");
    cpt *q = pt_dup(s, b);
    if (!q) return fail(s, CONT_ENOMEM, "out of memory");
    s->state = ST_RUN;
    s->first_step = 1;
    s->ds = s->ds0;
    s->last.ds = 0.0;
    int r = deliver(s, q);
    flush_stats(s, t0, 0);
    if (r < 0) {
        s->state = ST_FAIL;
        s->stop_reason = CONT_STOP_ERROR;
        return r;
    }
    if (r == 1) {
        s->state = ST_DONE;
        s->stop_reason = CONT_STOP_CALLBACK;
    }
    return CONT_OK;
}

static int start_check(cont_solver *s, const double *y0, double p0)
{
    if (!y0 || !isfinite(p0) || !all_finite(y0, s->n))
        return fail(s, CONT_EINPUT, "start point is missing or not finite");
    if (p0 < s->p_min || p0 > s->p_max)
        return fail(s, CONT_EINPUT, "start parameter p0 = %.10g is outside [%g, %g]",
                    p0, s->p_min, s->p_max);
    return CONT_OK;
}

int cont_start(cont_solver *s, const double *y0, double p0, int dir)
{
    NEED(s);
    begin_run(s);
    double t0 = now_sec();
    if (dir != 1 && dir != -1)
        return fail(s, CONT_EINPUT, "cont_start: dir must be +1 or -1 (got %d)", dir);
    int r = start_check(s, y0, p0);
    if (r != CONT_OK) return r;
    long n = s->n;
    cpt *b = s->base;
    memcpy(b->x, y0, (size_t)n * sizeof(double));
    b->x[n] = p0;
    int nit;
    double fn;
    if (solve_fixed(s, b->x, &nit, &fn) != 0) {
        flush_stats(s, t0, 0);
        return fail(s, CONT_ENUMERIC, "start: Newton at fixed p = %.10g failed: %s", p0, s->why);
    }
    for (long i = 0; i < s->m; i++) s->cw[i] = 0.0;
    s->cw[n] = 1.0;
    r = eval_point(s, b, s->cw, dir, 0);
    if (r != 0) {
        flush_stats(s, t0, 0);
        if (r == CONT_EUSER) return r;
        return fail(s, CONT_ENUMERIC, "start: no tangent at p = %.10g (%s); Jy is singular "
                    "there (a limit or branch point?): give a tangent with "
                    "cont_start_tangent", p0, s->why);
    }
    return finish_start(s, t0, nit, fn);
}

int cont_start_tangent(cont_solver *s, const double *y0, double p0,
                       const double *ty0, double tp0)
{
    NEED(s);
    begin_run(s);
    double t0 = now_sec();
    int r = start_check(s, y0, p0);
    if (r != CONT_OK) return r;
    long n = s->n, m = s->m;
    if (!ty0 || !all_finite(ty0, n) || !isfinite(tp0))
        return fail(s, CONT_EINPUT, "cont_start_tangent: tangent missing or not finite");
    cpt *b = s->base;
    memcpy(b->x, y0, (size_t)n * sizeof(double));
    b->x[n] = p0;
    memcpy(b->t, ty0, (size_t)n * sizeof(double));
    b->t[n] = tp0;
    double nt = sqrt(dotw(s, b->t, b->t));
    if (!(nt > 0)) return fail(s, CONT_EINPUT, "cont_start_tangent: zero tangent");
    for (long i = 0; i < m; i++) b->t[i] /= nt;
    weigh(s, b->t, s->cw);
    /* correct in the hyperplane through x0 orthogonal to t only if needed */
    int nit = 0;
    double fn;
    if (call_residual(s, b->x, p0, s->w1) != 0) {
        flush_stats(s, t0, 0);
        return fail(s, CONT_ENUMERIC, "cont_start_tangent: %s", s->why);
    }
    double fs = 0.0;
    for (long i = 0; i < n; i++) fs = fmax(fs, fabs(s->w1[i] * NV_Ith_S(s->fscale, i)));
    fn = s->last_fnorm;
    if (fs > s->ftol) {
        double *anchor = malloc((size_t)m * sizeof(double));
        if (!anchor) return fail(s, CONT_ENOMEM, "out of memory");
        memcpy(anchor, b->x, (size_t)m * sizeof(double));
        r = correct(s, b->x, s->cw, anchor, 0.0, s->init_maxit, s->init_strategy, &nit, &fn);
        free(anchor);
        if (r != 0) {
            flush_stats(s, t0, 0);
            return fail(s, CONT_ENUMERIC, "cont_start_tangent: the start point (residual "
                        "%.3g) could not be corrected: %s", fs, s->why);
        }
    }
    /* determinant with the given tangent (may be singular at a BP) */
    r = eval_point(s, b, s->cw, +1, 1);
    if (r == CONT_EUSER) {
        flush_stats(s, t0, 0);
        return r;
    }
    if (r != 0) {   /* Jacobian failed here: the first step would fail too */
        flush_stats(s, t0, 0);
        return fail(s, CONT_ENUMERIC, "cont_start_tangent: %s", s->why);
    }
    return finish_start(s, t0, nit, fn);
}

/* Land on p = pb between the base b and x1 (which lies beyond pb).  *res
 * gets the new point.  0, -1 or CONT_EUSER. */
static int land(cont_solver *s, const cpt *b, const cpt *x1, double pb, cpt **res)
{
    long n = s->n, m = s->m;
    *res = NULL;
    cpt *q = pt_new(s);
    if (!q) return fail(s, CONT_ENOMEM, "out of memory");
    double lam = (pb - b->x[n]) / (x1->x[n] - b->x[n]);
    if (!isfinite(lam)) lam = 1.0;
    for (long i = 0; i < m; i++) q->x[i] = b->x[i] + lam * (x1->x[i] - b->x[i]);
    q->x[n] = pb;
    double *c = calloc((size_t)m, sizeof(double));
    double *xa = malloc((size_t)m * sizeof(double));
    if (!c || !xa) {
        free(c); free(xa); pt_free(q);
        return fail(s, CONT_ENOMEM, "out of memory");
    }
    c[n] = 1.0;
    memcpy(xa, q->x, (size_t)m * sizeof(double));
    int nit;
    double fn;
    int r = correct(s, q->x, c, xa, 0.0, s->max_newton, s->strategy, &nit, &fn);
    free(c);
    free(xa);
    if (r == 0) {
        q->x[n] = pb;   /* exactly */
        weigh(s, b->t, s->cw);
        r = eval_point(s, q, s->cw, +1, 0);
        if (r == CONT_EUSER) {
            pt_free(q);
            return r;
        }
    }
    if (r == 0) {
        q->h = dotw(s, b->t, q->x) - dotw(s, b->t, b->x);
        /* the solution at p = pb must lie within the step, not on another
         * part of the solution set */
        if (!(q->h >= -1e-9 * x1->h && q->h <= 2.0 * x1->h)) r = -1;
    }
    if (r == 0) {
        q->pub.newton_iters = nit;
        q->pub.resnorm = fn;
        q->pub.ds = q->h;
        *res = q;
        return 0;
    }
    /* Fallback (Jy singular at pb?): locate p - pb on the branch. */
    pt_free(q);
    r = locate(s, TEST_PB, b, x1, x1->h, pb, res);
    if (r != 0) return r;
    if (fabs((*res)->x[n] - pb) > 1e-8 * (1.0 + fabs(pb))) {
        pt_free(*res);
        *res = NULL;
        return -1;
    }
    return 0;
}

/* Compute one step from s->base and queue the resulting points. */
static int compute_step(cont_solver *s)
{
    long n = s->n, m = s->m;
    cpt *b = s->base;
    double ds = s->ds;
    if (isfinite(s->s_max) && s->s_max - s->s_arc < ds) ds = s->s_max - s->s_arc;
    cpt *x1 = pt_new(s);
    if (!x1) return fail(s, CONT_ENOMEM, "out of memory");
    double *c = calloc((size_t)m, sizeof(double));
    if (!c) {
        pt_free(x1);
        return fail(s, CONT_ENOMEM, "out of memory");
    }
    weigh(s, b->t, c);
    double cosmax = s->max_angle > 0 ? cos(s->max_angle) : -2.0;
    int nit = 0, r;
    double fn = NAN;
    for (;;) {
        if (ds < s->ds_min) {
            free(c);
            pt_free(x1);
            s->stop_reason = CONT_STOP_DSMIN;
            return fail(s, CONT_FAIL, "continuation stopped at step %ld: the step size "
                        "%.3g fell below ds_min = %.3g at p = %.12g (last accepted point, "
                        "s = %.6g, residual norm %.3g); last attempt: %s",
                        s->steps + 1, ds, s->ds_min, b->x[n], s->s_arc, b->pub.resnorm,
                        s->why[0] ? s->why : "no reason recorded");
        }
        for (long i = 0; i < m; i++) x1->x[i] = b->x[i] + ds * b->t[i];
        r = correct(s, x1->x, c, b->x, ds, s->max_newton, s->strategy, &nit, &fn);
        if (r == 0) {
            r = eval_point(s, x1, c, +1, 0);
            if (r == CONT_EUSER) {
                free(c); pt_free(x1);
                s->stop_reason = CONT_STOP_ERROR;
                return r;
            }
            if (r == 0) {
                double ca = dotw(s, x1->t, b->t);
                if (ca < cosmax) {
                    why(s, "the tangent turned by %.3g rad (> max_angle %.3g) over a step "
                        "of %.3g", acos(fmax(-1.0, fmin(1.0, ca))), s->max_angle, ds);
                    r = -1;
                }
            }
        }
        if (r == 0) break;
        s->stp.retries++;
        ds *= s->shrink;
    }
    x1->pub.newton_iters = nit;
    x1->pub.resnorm = fn;
    x1->pub.ds = ds;
    x1->h = ds;
    s->last.ds = ds;
    s->ds = nit <= s->fast_iters ? fmin(ds * s->grow, s->ds_max) : ds;

    cpt *xe = x1;
    int term = 0, reason = CONT_STOP_NONE;
    double p1 = x1->x[n];
    if (p1 > s->p_max || p1 < s->p_min) {
        double pb = p1 > s->p_max ? s->p_max : s->p_min;
        reason = p1 > s->p_max ? CONT_STOP_PMAX : CONT_STOP_PMIN;
        cpt *q = NULL;
        r = land(s, b, x1, pb, &q);
        if (r != 0) {
            free(c); pt_free(x1);
            s->stop_reason = CONT_STOP_ERROR;
            if (r == CONT_EUSER) return r;
            return fail(s, CONT_FAIL, "could not land on the end of the parameter window "
                        "p = %.12g: %s", pb, s->why);
        }
        pt_free(x1);
        xe = q;
        term = 1;
    }
    double he = xe->h;

    /* special points */
    cpt *sp[40];
    int nsp = 0;
    int ids[40], nid = 0;
    if (s->detect & CONT_DETECT_LP) ids[nid++] = TEST_LP;
    if (s->detect & CONT_DETECT_BP) ids[nid++] = TEST_BP;
    if (s->detect & CONT_DETECT_USER)
        for (int k = 0; k < s->prob.ntest; k++) ids[nid++] = k;
    for (int j = 0; j < nid; j++) {
        int id = ids[j];
        double f0, f1;
        if (id == TEST_BP) {
            if (!b->det_valid || !xe->det_valid) continue;
            if (b->pub.det_sign == xe->pub.det_sign) continue;
            if (s->first_step &&
                b->pub.log_abs_det - xe->pub.log_abs_det <= log(SKIP_START_RATIO))
                continue;
        } else {
            f0 = test_value(s, id, b, 0.0, 0.0);
            f1 = test_value(s, id, xe, 0.0, 0.0);
            if (!differ(f0, f1)) continue;
            if (s->first_step && fabs(f0) <= SKIP_START_RATIO * fabs(f1)) continue;
        }
        cpt *q = NULL;
        r = locate(s, id, b, xe, he, 0.0, &q);
        if (r == CONT_EUSER || r == CONT_ENOMEM) {
            free(c);
            pt_free(xe);
            for (int k = 0; k < nsp; k++) pt_free(sp[k]);
            s->stop_reason = CONT_STOP_ERROR;
            return r;
        }
        if (r != 0 || !q) continue;
        if (id == TEST_LP) set_label(q, CONT_PT_LP, "LP");
        else if (id == TEST_BP) set_label(q, CONT_PT_BP, "BP");
        else {
            set_label(q, CONT_PT_USER, s->labels[id]);
            q->pub.user_index = id;
        }
        sp[nsp++] = q;
    }
    /* an LP and a BP at the same place are one BP (pitchfork crossed along
     * its bifurcating branch) */
    for (int i = 0; i < nsp; i++) {
        if (sp[i]->pub.type != CONT_PT_LP) continue;
        for (int j = 0; j < nsp; j++) {
            if (sp[j]->pub.type != CONT_PT_BP) continue;
            double tol = fmax(1e3 * s->loc_tol * (1.0 + s->theta * fabs(sp[j]->x[n])),
                              fmax(MERGE_FRAC * he,
                                   2.0 * (sp[i]->pub.loc_err + sp[j]->pub.loc_err)));
            if (fabs(sp[i]->h - sp[j]->h) <= tol) {
                pt_free(sp[i]);
                sp[i] = sp[--nsp];
                i--;
                break;
            }
        }
    }
    /* order by arclength */
    for (int i = 1; i < nsp; i++)
        for (int j = i; j > 0 && sp[j]->h < sp[j - 1]->h; j--) {
            cpt *tmp = sp[j]; sp[j] = sp[j - 1]; sp[j - 1] = tmp;
        }
    double tnow = since(&s->t_start);
    for (int i = 0; i < nsp; i++) {
        sp[i]->pub.s = s->s_arc + sp[i]->h;
        sp[i]->pub.time = tnow;
        s->queue[(s->q0 + s->nq++) % 64] = sp[i];
    }
    s->steps++;
    s->stp.steps++;
    s->s_arc += he;
    xe->pub.s = s->s_arc;
    xe->pub.time = tnow;
    xe->pub.loc_err = 0.0;
    if (!term && s->max_steps > 0 && s->steps >= s->max_steps) {
        term = 1;
        reason = CONT_STOP_MAXSTEPS;
    }
    if (!term && isfinite(s->s_max) && s->s_arc >= s->s_max * (1.0 - 1e-12)) {
        term = 1;
        reason = CONT_STOP_MAXARC;
    }
    if (!term && isfinite(s->s_max) && s->s_max - s->s_arc < s->ds_min) {
        term = 1;
        reason = CONT_STOP_MAXARC;
    }
    set_label(xe, term ? CONT_PT_EP : CONT_PT_REGULAR, term ? "EP" : "");
    xe->terminal = term;
    xe->stop_reason = reason;
    pt_copy(s, b, xe);
    s->queue[(s->q0 + s->nq++) % 64] = xe;
    s->first_step = 0;
    free(c);
    return CONT_OK;
}

int cont_step(cont_solver *s)
{
    if (!s) return CONT_FAIL;
    if (s->state == ST_DONE) return CONT_DONE;
    if (s->state == ST_FAIL) return CONT_FAIL;
    if (s->state != ST_RUN) {
        fail(s, CONT_ESTATE, "cont_step called before cont_start");
        return CONT_FAIL;
    }
    double t0 = now_sec();
    int computed = 0;
    if (s->nq == 0) {
        int r = compute_step(s);
        computed = 1;
        if (r != CONT_OK) {
            flush_stats(s, t0, 1);
            s->state = ST_FAIL;
            if (s->stop_reason == CONT_STOP_NONE) s->stop_reason = CONT_STOP_ERROR;
            return CONT_FAIL;
        }
    }
    cpt *q = s->queue[s->q0];
    s->q0 = (s->q0 + 1) % 64;
    s->nq--;
    int term = q->terminal, reason = q->stop_reason;
    int r = deliver(s, q);
    if (computed) flush_stats(s, t0, 1);
    else flush_stats(s, t0, 0);
    if (r < 0) {
        s->state = ST_FAIL;
        s->stop_reason = CONT_STOP_ERROR;
        return CONT_FAIL;
    }
    if (r == 1 || term) {
        s->state = ST_DONE;
        s->stop_reason = r == 1 ? CONT_STOP_CALLBACK : reason;
        while (s->nq > 0) {      /* the rest of the step is not delivered */
            pt_free(s->queue[s->q0]);
            s->q0 = (s->q0 + 1) % 64;
            s->nq--;
        }
        return CONT_DONE;
    }
    return CONT_CONTINUE;
}

int cont_run(cont_solver *s)
{
    int st;
    while ((st = cont_step(s)) == CONT_CONTINUE) {}
    return st;
}

/* ---- getters ---- */

const cont_point *cont_get_point(const cont_solver *s)
{
    return s && s->cur ? &s->cur->pub : NULL;
}

long cont_num_points(const cont_solver *s) { return s ? s->nhist : 0; }

const cont_point *cont_point_at(const cont_solver *s, long i)
{
    if (!s || i < 0 || i >= s->nhist) return NULL;
    return &s->hist[i]->pub;
}

long cont_num_special(const cont_solver *s) { return s ? s->nspec : 0; }

const cont_point *cont_special_at(const cont_solver *s, long i)
{
    if (!s || i < 0 || i >= s->nspec) return NULL;
    return &s->spec[i]->pub;
}

int cont_get_stats(const cont_solver *s, cont_stats *last, cont_stats *total)
{
    NEED(s);
    if (last) *last = s->last;
    if (total) *total = s->total;
    return CONT_OK;
}

int cont_stop_reason(const cont_solver *s) { return s ? s->stop_reason : CONT_STOP_NONE; }

const char *cont_stop_name(int reason)
{
    switch (reason) {
    case CONT_STOP_NONE: return "none";
    case CONT_STOP_PMIN: return "p reached p_min";
    case CONT_STOP_PMAX: return "p reached p_max";
    case CONT_STOP_MAXSTEPS: return "maximum number of steps";
    case CONT_STOP_MAXARC: return "maximum arclength";
    case CONT_STOP_CALLBACK: return "stopped by the point callback";
    case CONT_STOP_DSMIN: return "step size below ds_min";
    case CONT_STOP_ERROR: return "error";
    default: return "unknown";
    }
}

const char *cont_errmsg(const cont_solver *s) { return s ? s->msg : "no solver"; }

int cont_get_linsol(const cont_solver *s) { return s ? s->linsol : 0; }

double cont_get_ds(const cont_solver *s) { return s ? s->ds : 0.0; }

const char *cont_reference(void)
{
    return "H. B. Keller, Numerical solution of bifurcation and nonlinear eigenvalue "
           "problems, in: P. Rabinowitz (ed.), Applications of Bifurcation Theory, "
           "Academic Press, 1977, 359-384 (pseudo-arclength continuation, branch switching)\n"
           "E. L. Allgower, K. Georg, Introduction to Numerical Continuation Methods, "
           "SIAM Classics in Applied Mathematics 45, 2003 (tangent orientation, "
           "augmented-Jacobian determinant as bifurcation test, step control)\n"
           "W. J. F. Govaerts, Numerical Methods for Bifurcations of Dynamical Equilibria, "
           "SIAM, 2000 (bordered systems for singular matrices)\n";
}

/* ===================================================================== */
/* 9. branch switching                                                    */
/* ===================================================================== */

/* Dense: SVD of A_s = [Jy, Fp/theta] (scaled coordinates).  t1w is the
 * known tangent weighted by the norm (t1s itself without cont_set_weights). */
static int branch_dense(cont_solver *s, const double *t1s, const double *t1w, double *u,
                        double *sigratio)
{
    long n = s->n, m = s->m;
    int in = (int)n, im = (int)m, one = 1, info = 0, lwork = -1;
    double *A = calloc((size_t)(n * m), sizeof(double));
    double *S = calloc((size_t)n, sizeof(double));
    double *VT = calloc((size_t)(m * m), sizeof(double));
    double wq, udummy = 0.0;
    if (!A || !S || !VT) {
        free(A); free(S); free(VT);
        return fail(s, CONT_ENOMEM, "out of memory");
    }
    if (s->prob.jac_matrix == CONT_MATRIX_SPARSE) {
        sunindextype *ptr = SM_INDEXPTRS_S(s->Jy), *idx = SM_INDEXVALS_S(s->Jy);
        double *val = SM_DATA_S(s->Jy);
        for (long j = 0; j < n; j++)
            for (sunindextype k = ptr[j]; k < ptr[j + 1]; k++) A[j * n + idx[k]] += val[k];
    } else {
        for (long j = 0; j < n; j++)
            memcpy(A + j * n, SM_COLUMN_D(s->Jy, j), (size_t)n * sizeof(double));
    }
    for (long i = 0; i < n; i++) A[n * n + i] = s->Fp[i] / s->theta;
    dgesvd_("N", "A", &in, &im, A, &in, S, &udummy, &one, VT, &im, &wq, &lwork, &info);
    lwork = info == 0 ? (int)wq + 1 : 5 * im + 10;
    double *work = malloc((size_t)lwork * sizeof(double));
    if (!work) {
        free(A); free(S); free(VT);
        return fail(s, CONT_ENOMEM, "out of memory");
    }
    dgesvd_("N", "A", &in, &im, A, &in, S, &udummy, &one, VT, &im, work, &lwork, &info);
    free(work);
    free(A);
    if (info != 0) {
        free(S); free(VT);
        return fail(s, CONT_ENUMERIC, "cont_branch_direction: dgesvd failed (info = %d)", info);
    }
    /* rows n-1 and n of VT (column-major m x m: VT[i + j*m] is row i) */
    double scale = n >= 2 ? S[0] : 1.0;
    double smin = S[n - 1];
    *sigratio = scale > 0 ? smin / scale : 0.0;
    double second = n >= 2 ? S[n - 2] / scale : 1.0;
    double a = 0.0, bb = 0.0, aw = 0.0, bw = 0.0;
    for (long j = 0; j < m; j++) {
        a += VT[(n - 1) + j * m] * t1s[j];
        bb += VT[n + j * m] * t1s[j];
        aw += VT[(n - 1) + j * m] * t1w[j];
        bw += VT[n + j * m] * t1w[j];
    }
    for (long j = 0; j < m; j++) u[j] = bw * VT[(n - 1) + j * m] - aw * VT[n + j * m];
    free(S);
    free(VT);
    if (!(*sigratio <= BP_NULL_TOL))
        return fail(s, CONT_ENUMERIC, "cont_branch_direction: not a branch point: [Jy Fp] "
                    "has full rank (smallest/largest singular value %.3g > %.1e)",
                    *sigratio, BP_NULL_TOL);
    if (n >= 2 && second <= BP_NULL_TOL)
        return fail(s, CONT_ENUMERIC, "cont_branch_direction: the null space of [Jy Fp] has "
                    "dimension > 2 (two singular values below %.1e): not a simple branch "
                    "point", BP_NULL_TOL);
    if (a * a + bb * bb < 0.9)
        return fail(s, CONT_ENUMERIC, "cont_branch_direction: the given tangent is not in the "
                    "null space of [Jy Fp] (component %.3g)", sqrt(a * a + bb * bb));
    return CONT_OK;
}

/* KLU: bordered system [[A_s; t1w^T] bv; cv^T 0] [phi; mu] = [0; 1]. */
static int branch_sparse(cont_solver *s, const double *t1w, double *u, double *resid)
{
    long n = s->n, m = s->m, M = m + 1;
    int rc = CONT_OK;
    double *bv = malloc((size_t)m * sizeof(double)), *cv = malloc((size_t)m * sizeof(double));
    N_Vector x = N_VNew_Serial(M, s->ctx), rhs = N_VNew_Serial(M, s->ctx);
    sunindextype nnz = jy_nnz(s) + 4 * (sunindextype)m + 2;
    SUNMatrix B = SUNSparseMatrix(M, M, nnz, CSC_MAT, s->ctx);
    SUNLinearSolver LS = (B && x) ? SUNLinSol_KLU(x, B, s->ctx) : NULL;
    if (!bv || !cv || !x || !rhs || !B || !LS) {
        rc = fail(s, CONT_ENOMEM, "out of memory");
        goto done;
    }
    /* fixed pseudo-random border vectors, entries in [0.5, 1.5] */
    unsigned long long st = 0x9E3779B97F4A7C15ULL;
    for (long i = 0; i < m; i++) {
        st = st * 6364136223846793005ULL + 1442695040888963407ULL;
        bv[i] = 0.5 + (double)(st >> 11) / 9007199254740992.0;
        st = st * 6364136223846793005ULL + 1442695040888963407ULL;
        cv[i] = 0.5 + (double)(st >> 11) / 9007199254740992.0;
    }
    sunindextype *bp = SM_INDEXPTRS_S(B), *bi = SM_INDEXVALS_S(B);
    double *bx = SM_DATA_S(B);
    sunindextype k = 0;
    int jsp = s->prob.jac_matrix == CONT_MATRIX_SPARSE;
    double anorm2 = 0.0;
    for (long j = 0; j < n; j++) {
        bp[j] = k;
        if (jsp) {
            sunindextype *ptr = SM_INDEXPTRS_S(s->Jy), *idx = SM_INDEXVALS_S(s->Jy);
            double *val = SM_DATA_S(s->Jy);
            for (sunindextype q = ptr[j]; q < ptr[j + 1]; q++) {
                bi[k] = idx[q]; bx[k++] = val[q];
                anorm2 += val[q] * val[q];
            }
        } else {
            for (long i = 0; i < n; i++) {
                double v = SM_ELEMENT_D(s->Jy, i, j);
                bi[k] = i; bx[k++] = v;
                anorm2 += v * v;
            }
        }
        bi[k] = n; bx[k++] = t1w[j];
        bi[k] = m; bx[k++] = cv[j];
    }
    bp[n] = k;
    for (long i = 0; i < n; i++) {
        bi[k] = i; bx[k++] = s->Fp[i] / s->theta;
        anorm2 += s->Fp[i] * s->Fp[i] / (s->theta * s->theta);
    }
    bi[k] = n; bx[k++] = t1w[n];
    bi[k] = m; bx[k++] = cv[n];
    bp[m] = k;
    for (long i = 0; i < m; i++) {
        bi[k] = i; bx[k++] = bv[i];
    }
    bp[M] = k;
    s->stp.nfactor++;
    if (SUNLinSolInitialize(LS) != 0 || SUNLinSolSetup(LS, B) != 0) {
        rc = fail(s, CONT_ENUMERIC, "cont_branch_direction: the bordered system is singular: "
                  "not a simple branch point");
        goto done;
    }
    N_VConst(0.0, rhs);
    NV_Ith_S(rhs, m) = 1.0;
    s->stp.nlinsolve++;
    if (SUNLinSolSolve(LS, B, x, rhs, 0.0) != 0 || !all_finite(N_VGetArrayPointer(x), M)) {
        rc = fail(s, CONT_ENUMERIC, "cont_branch_direction: bordered solve failed");
        goto done;
    }
    double *ph = N_VGetArrayPointer(x);
    double np = 0.0;
    for (long i = 0; i < m; i++) np += ph[i] * ph[i];
    np = sqrt(np);
    if (!(np > 0)) {
        rc = fail(s, CONT_ENUMERIC, "cont_branch_direction: zero null vector");
        goto done;
    }
    for (long i = 0; i < m; i++) u[i] = ph[i] / np;
    /* residual |A_s u| / |A_s|_F */
    double r2 = 0.0;
    for (long i = 0; i < n; i++) s->w1[i] = s->Fp[i] / s->theta * u[n];
    if (jsp) {
        sunindextype *ptr = SM_INDEXPTRS_S(s->Jy), *idx = SM_INDEXVALS_S(s->Jy);
        double *val = SM_DATA_S(s->Jy);
        for (long j = 0; j < n; j++)
            for (sunindextype q = ptr[j]; q < ptr[j + 1]; q++) s->w1[idx[q]] += val[q] * u[j];
    } else {
        for (long j = 0; j < n; j++)
            for (long i = 0; i < n; i++) s->w1[i] += SM_ELEMENT_D(s->Jy, i, j) * u[j];
    }
    for (long i = 0; i < n; i++) r2 += s->w1[i] * s->w1[i];
    /* relative to |A_s|_F, except for n = 1, where [Jy Fp] vanishes as a
     * whole at a branch point (a 1 x 2 matrix with a 2-D null space), so
     * its norm is no scale: absolute, as branch_dense does */
    *resid = (n >= 2 && anorm2 > 0) ? sqrt(r2 / anorm2) : sqrt(r2);
    if (!(*resid <= BP_NULL_TOL))
        rc = fail(s, CONT_ENUMERIC, "cont_branch_direction: not a branch point: no second "
                  "null vector of [Jy Fp] (relative residual %.3g > %.1e)", *resid, BP_NULL_TOL);
done:
    if (LS) SUNLinSolFree(LS);
    if (B) SUNMatDestroy(B);
    if (x) N_VDestroy(x);
    if (rhs) N_VDestroy(rhs);
    free(bv);
    free(cv);
    return rc;
}

int cont_branch_direction(cont_solver *s, const double *y, double p,
                          const double *ty, double tp, double *ty_new, double *tp_new)
{
    NEED(s);
    long n = s->n, m = s->m;
    if (!y || !ty || !ty_new || !tp_new || !isfinite(p) || !all_finite(y, n) ||
        !all_finite(ty, n) || !isfinite(tp))
        return fail(s, CONT_EINPUT, "cont_branch_direction: bad arguments");
    double t0 = now_sec();
    double *t1s = malloc((size_t)m * sizeof(double)), *u = calloc((size_t)m, sizeof(double));
    double *t1w = malloc((size_t)m * sizeof(double));
    if (!t1s || !u || !t1w) {
        free(t1s); free(u); free(t1w);
        return fail(s, CONT_ENOMEM, "out of memory");
    }
    double nrm = 0.0;
    for (long i = 0; i < n; i++) t1s[i] = ty[i];
    t1s[n] = s->theta * tp;
    for (long i = 0; i < m; i++) nrm += t1s[i] * t1s[i];
    nrm = sqrt(nrm);
    int rc = CONT_OK;
    if (!(nrm > 0)) rc = fail(s, CONT_EINPUT, "cont_branch_direction: zero tangent");
    if (rc == CONT_OK) {
        for (long i = 0; i < m; i++) t1s[i] /= nrm;
        /* the norm in the scaled coordinates (y, theta p) is diag(wy, 1) */
        for (long i = 0; i < m; i++) t1w[i] = (s->wy && i < n) ? s->wy[i] * t1s[i] : t1s[i];
        if (call_jacobian(s, y, p) != 0)
            rc = fail(s, CONT_ENUMERIC, "cont_branch_direction: %s", s->why);
    }
    double q;
    if (rc == CONT_OK)
        rc = s->linsol == CONT_LINSOL_KLU ? branch_sparse(s, t1w, u, &q)
                                          : branch_dense(s, t1s, t1w, u, &q);
    if (rc == CONT_OK) {
        /* remove any t1 component, normalise, fix the sign */
        double d = 0.0, tt = 0.0, nu = 0.0;
        for (long i = 0; i < m; i++) {
            d += u[i] * t1w[i];
            tt += t1s[i] * t1w[i];
        }
        if (tt > 0)
            for (long i = 0; i < m; i++) u[i] -= d / tt * t1s[i];
        for (long i = 0; i < m; i++) nu += u[i] * u[i] * ((s->wy && i < n) ? s->wy[i] : 1.0);
        nu = sqrt(nu);
        if (!(nu > 0)) {
            rc = fail(s, CONT_ENUMERIC, "cont_branch_direction: no direction orthogonal to "
                      "the tangent");
        } else {
            long imax = 0;
            for (long i = 0; i < m; i++) {
                u[i] /= nu;
                if (fabs(u[i]) > fabs(u[imax]) * (1.0 + 1e-12)) imax = i;
            }
            double sg = u[imax] < 0 ? -1.0 : 1.0;
            for (long i = 0; i < n; i++) ty_new[i] = sg * u[i];
            *tp_new = sg * u[n] / s->theta;
        }
    }
    free(t1s);
    free(t1w);
    free(u);
    if (s->state != ST_RUN) flush_stats(s, t0, 0);
    return rc;
}
