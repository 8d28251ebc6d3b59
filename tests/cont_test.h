/* cont_test.h - checks and helpers shared by the continuation engine's
 * tests (test_cont.c, test_cont_det.c, test_cont_reuse.c).  Include after cmocka.h. */
#ifndef SF_CONT_TEST_H
#define SF_CONT_TEST_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sunmatrix/sunmatrix_sparse.h>

#include "cont.h"

#define CHECK_CLOSE(got, exp, tol)                                            \
    do {                                                                      \
        double g_ = (got), e_ = (exp), t_ = (tol);                            \
        if (!(fabs(g_ - e_) <= t_)) {                                         \
            print_error("%s:%d: %s\n  expected %.17g\n  got      %.17g\n"     \
                        "  |diff| = %.3g > tol %.3g\n",                       \
                        __FILE__, __LINE__, #got, e_, g_, fabs(g_ - e_), t_); \
            fail();                                                           \
        }                                                                     \
    } while (0)

#define CHECK_TRUE(cond, ...)                                                 \
    do {                                                                      \
        if (!(cond)) {                                                        \
            print_error("%s:%d: check failed: %s\n  ", __FILE__, __LINE__,   \
                        #cond);                                               \
            print_error(__VA_ARGS__);                                         \
            print_error("\n");                                                \
            fail();                                                           \
        }                                                                     \
    } while (0)

#define CHECK_OK(call, s)                                                     \
    do {                                                                      \
        int rc_ = (call);                                                     \
        if (rc_ != CONT_OK) {                                                 \
            print_error("%s:%d: %s returned %d, expected CONT_OK: %s\n",      \
                        __FILE__, __LINE__, #call, rc_, cont_errmsg(s));      \
            fail();                                                           \
        }                                                                     \
    } while (0)

static inline cont_solver *make(const cont_problem *prob, int linsol)
{
    cont_solver *s = NULL;
    int rc = cont_create(prob, linsol, &s);
    if (rc != CONT_OK) {
        print_error("cont_create failed (%d): %s\n", rc, s ? cont_errmsg(s) : "no memory");
        cont_free(s);
        fail();
    }
    return s;
}

static inline double norm_inf(const double *v, int n)
{
    double r = 0.0;
    for (int i = 0; i < n; i++) r = fmax(r, fabs(v[i]));
    return r;
}

static inline int count_label(const cont_solver *s, const char *label)
{
    int k = 0;
    for (long i = 0; i < cont_num_special(s); i++)
        if (strcmp(cont_special_at(s, i)->label, label) == 0) k++;
    return k;
}

static inline const cont_point *find_label(const cont_solver *s, const char *label)
{
    for (long i = 0; i < cont_num_special(s); i++)
        if (strcmp(cont_special_at(s, i)->label, label) == 0) return cont_special_at(s, i);
    return NULL;
}

/* Fill a CSC sparse matrix from dense column-major values (|v| > 0 kept,
 * plus the diagonal so the pattern stays fixed). */
static inline void dense_to_csc(SUNMatrix J, long n, const double *a)
{
    sunindextype nnz = 0;
    for (long j = 0; j < n; j++)
        for (long i = 0; i < n; i++)
            if (a[j * n + i] != 0.0 || i == j) nnz++;
    if (SM_NNZ_S(J) < nnz) SUNSparseMatrix_Reallocate(J, nnz);
    sunindextype *ptr = SM_INDEXPTRS_S(J), *idx = SM_INDEXVALS_S(J);
    double *val = SM_DATA_S(J);
    sunindextype k = 0;
    for (long j = 0; j < n; j++) {
        ptr[j] = k;
        for (long i = 0; i < n; i++)
            if (a[j * n + i] != 0.0 || i == j) {
                idx[k] = i;
                val[k++] = a[j * n + i];
            }
    }
    ptr[n] = k;
}

/* Bratu u'' + lam e^u = 0 on (0, 1), u = 0 at both ends, N central
 * differences (user data: a bratu); its sparse Jacobian (3N entries). */
typedef struct bratu {
    long N;
} bratu;

static inline int bratu_res(const double *u, double lam, double *F, void *ud)
{
    long N = ((bratu *)ud)->N;
    double h = 1.0 / (double)(N + 1), h2 = h * h;
    for (long i = 0; i < N; i++) {
        double ul = i > 0 ? u[i - 1] : 0.0, ur = i < N - 1 ? u[i + 1] : 0.0;
        F[i] = ul - 2.0 * u[i] + ur + h2 * lam * exp(u[i]);
    }
    return 0;
}

static inline int bratu_jac_sparse(const double *u, double lam, SUNMatrix J, double *Fp, void *ud)
{
    long N = ((bratu *)ud)->N;
    double h = 1.0 / (double)(N + 1), h2 = h * h;
    if (SM_NNZ_S(J) < 3 * N && SUNSparseMatrix_Reallocate(J, 3 * N) != 0) return -1;
    sunindextype *ptr = SM_INDEXPTRS_S(J), *idx = SM_INDEXVALS_S(J);
    double *val = SM_DATA_S(J);
    sunindextype k = 0;
    for (long j = 0; j < N; j++) {
        ptr[j] = k;
        if (j > 0) { idx[k] = j - 1; val[k++] = 1.0; }
        idx[k] = j; val[k++] = -2.0 + h2 * lam * exp(u[j]);
        if (j < N - 1) { idx[k] = j + 1; val[k++] = 1.0; }
        Fp[j] = h2 * exp(u[j]);
    }
    ptr[N] = k;
    return 0;
}

/* Two paths of n unknowns side by side: the largest differences of their
 * points and of their tangents (relative to 1 + |b's value|) over the
 * points both have, and the largest residual of a's points; the points'
 * determinant signs and types must match. */
typedef struct path_diff {
    double dx, dt, rmax;
} path_diff;

static inline double rel_diff(double a, double b) { return fabs(a - b) / (1.0 + fabs(b)); }

static inline path_diff compare_paths(const cont_solver *a, const cont_solver *b, long n,
                                      int (*res)(const double *, double, double *, void *),
                                      void *user, const char *what)
{
    path_diff d = {0.0, 0.0, 0.0};
    long np = cont_num_points(a) < cont_num_points(b) ? cont_num_points(a) : cont_num_points(b);
    double *F = malloc(sizeof(double) * (size_t)n);
    CHECK_TRUE(F != NULL, "%s: out of memory", what);
    for (long k = 0; k < np; k++) {
        const cont_point *pa = cont_point_at(a, k), *pb = cont_point_at(b, k);
        d.dx = fmax(d.dx, rel_diff(pa->p, pb->p));
        d.dt = fmax(d.dt, rel_diff(pa->tp, pb->tp));
        for (long i = 0; i < n; i++) {
            d.dx = fmax(d.dx, rel_diff(pa->y[i], pb->y[i]));
            d.dt = fmax(d.dt, rel_diff(pa->ty[i], pb->ty[i]));
        }
        CHECK_TRUE(pa->det_sign == pb->det_sign, "%s: point %ld det sign %d against %d", what,
                   k, pa->det_sign, pb->det_sign);
        CHECK_TRUE(pa->type == pb->type, "%s: point %ld type %d against %d", what, k,
                   pa->type, pb->type);
        res(pa->y, pa->p, F, user);
        for (long i = 0; i < n; i++) d.rmax = fmax(d.rmax, fabs(F[i]));
    }
    free(F);
    return d;
}

#endif
