/* start_kkt.c - the symmetric KKT matrix of the start and its
 * factorisation with inertia (start_impl.h).
 *
 * The equilibrium Jacobian J = [HL C^T; C -eps D] is symmetric in physical
 * units, but its blocks differ by many orders of magnitude (energies of
 * 1e-2 J, translation rows in metres).  With S = sqrt(fscale / yscale) the
 * matrix S J S is symmetric and of order one in every block: coordinates
 * are scaled by 1 / sqrt(kref), rotation multipliers by sqrt(kref),
 * translation multipliers by sqrt(kref) / lref.  The start solves in those
 * units. */
#include "start_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <sunmatrix/sunmatrix_dense.h>

#include "equilibrium_poses.h"

extern void dsytrf_(const char *uplo, const int *n, double *a, const int *lda, int *ipiv,
                    double *work, const int *lwork, int *info);
extern void dsytrs_(const char *uplo, const int *n, const int *nrhs, const double *a,
                    const int *lda, const int *ipiv, double *b, const int *ldb, int *info);

int fs_kkt_init(fs_kkt *k, sf_equil *q, sf_error *err)
{
    memset(k, 0, sizeof *k);
    k->q = q;
    k->n = q->n;
    k->nx = q->nq;
    k->m = q->ncon;
    /* the fold formulation's Jacobian is dense at every size */
    k->dense = !q->pz || q->n <= FS_DENSE_MAX;
    k->S = malloc(sizeof(double) * ((size_t)k->n + 1));
    k->Fp = calloc((size_t)k->n + 1, sizeof(double));
    if (!k->S || !k->Fp) return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int i = 0; i < k->n; i++) k->S[i] = sqrt(q->fscale[i] / q->yscale[i]);
    if (k->dense) {
        size_t nn = (size_t)k->n * (size_t)k->n;
        k->K = malloc(sizeof(double) * (nn + 1));
        k->LD = malloc(sizeof(double) * (nn + 1));
        k->ipiv = malloc(sizeof(int) * ((size_t)k->n + 1));
        if (!k->K || !k->LD || !k->ipiv) return sf_fail(err, SF_ENOMEM, "out of memory");
        if (!q->pz) {
            if (SUNContext_Create(NULL, &k->ctx) != 0 || !(k->Jd = SUNDenseMatrix(k->n, k->n, k->ctx)))
                return sf_fail(err, SF_ENOMEM, "out of memory");
        }
    } else {
        k->diag = malloc(sizeof(int) * ((size_t)k->n + 1));
        if (!k->diag) return sf_fail(err, SF_ENOMEM, "out of memory");
        if (sf_ldlt_create(&k->ld, 1e-300, err)) return err->code;
    }
    return SF_OK;
}

void fs_kkt_free(fs_kkt *k)
{
    free(k->S);
    free(k->Fp);
    free(k->K);
    free(k->LD);
    free(k->work);
    free(k->ipiv);
    free(k->ti);
    free(k->tj);
    free(k->tv);
    free(k->diag);
    if (k->ld) sf_ldlt_free(k->ld);
    if (k->Jd) SUNMatDestroy(k->Jd);
    if (k->ctx) SUNContext_Free(&k->ctx);
    memset(k, 0, sizeof *k);
}

/* Append triplet (i, j, v) of the lower triangle (i >= j). */
static int push(fs_kkt *k, int i, int j, double v)
{
    if (k->tnnz == k->tcap) {
        long nc = k->tcap ? 2 * k->tcap : 4096;
        int *ti = realloc(k->ti, sizeof(int) * (size_t)nc);
        if (ti) k->ti = ti;
        int *tj = realloc(k->tj, sizeof(int) * (size_t)nc);
        if (tj) k->tj = tj;
        double *tv = realloc(k->tv, sizeof(double) * (size_t)nc);
        if (tv) k->tv = tv;
        if (!ti || !tj || !tv) return -1;
        k->tcap = nc;
    }
    if (i == j) k->diag[i] = (int)k->tnnz;
    k->ti[k->tnnz] = i;
    k->tj[k->tnnz] = j;
    k->tv[k->tnnz++] = v;
    return 0;
}

/* The lower triangle of the scaled CSC matrix (both triangles given) as
 * triplets, every diagonal entry present (the shift goes there). */
static int csc_to_triplets(fs_kkt *k, const long *cp, const int *ri, const double *v)
{
    const double *S = k->S;
    k->tnnz = 0;
    for (int i = 0; i < k->n; i++) k->diag[i] = -1;
    for (int j = 0; j < k->n; j++)
        for (long e = cp[j]; e < cp[j + 1]; e++) {
            int i = ri[e];
            if (i < j) continue;
            if (push(k, i, j, S[i] * v[e] * S[j])) return -1;
        }
    for (int i = 0; i < k->n; i++)
        if (k->diag[i] < 0 && push(k, i, i, 0.0)) return -1;
    return 0;
}

int fs_kkt_eval(fs_kkt *k, const double *y, double p, sf_error *err)
{
    sf_equil *q = k->q;
    int n = k->n;
    k->neval++;
    if (q->pz) {
        const long *cp;
        const int *ri;
        const double *v;
        if (sf_peq_jacobian_csc(q, y, p, &cp, &ri, &v, k->Fp))
            return sf_fail(err, SF_ENUMERIC, "flat start: a non-finite value in the Jacobian");
        if (k->dense) {
            memset(k->K, 0, sizeof(double) * (size_t)n * (size_t)n);
            for (int j = 0; j < n; j++)
                for (long e = cp[j]; e < cp[j + 1]; e++)
                    k->K[(size_t)j * n + ri[e]] = k->S[ri[e]] * v[e] * k->S[j];
        } else if (csc_to_triplets(k, cp, ri, v)) {
            return sf_fail(err, SF_ENOMEM, "out of memory");
        }
        return SF_OK;
    }
    SUNMatZero(k->Jd);
    if (sf_equil_jacobian(y, p, k->Jd, k->Fp, q))
        return sf_fail(err, SF_ENUMERIC, "flat start: a non-finite value in the Jacobian");
    const double *A = SUNDenseMatrix_Data(k->Jd);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) k->K[(size_t)j * n + i] = k->S[i] * A[(size_t)j * n + i] * k->S[j];
    return SF_OK;
}

/* Inertia of the Bunch-Kaufman factors: negative eigenvalues of D. */
static int dense_negatives(const double *LD, const int *ipiv, int n, int *zero)
{
    int neg = 0;
    *zero = 0;
    for (int i = 0; i < n; i++) {
        double a = LD[(size_t)i * n + i];
        if (ipiv[i] > 0) {
            if (a < 0) neg++;
            else if (a == 0) *zero = 1;
            continue;
        }
        /* a 2x2 block (i, i+1) */
        double b = LD[(size_t)i * n + i + 1], c = LD[(size_t)(i + 1) * n + i + 1];
        double det = a * c - b * b;
        if (det < 0) neg += 1;
        else if (det > 0) neg += a < 0 ? 2 : 0;
        else *zero = 1;
        i++;
    }
    return neg;
}

int fs_kkt_factor(fs_kkt *k, double shift, sf_error *err)
{
    int n = k->n;
    k->nfact++;
    if (k->dense) {
        memcpy(k->LD, k->K, sizeof(double) * (size_t)n * (size_t)n);
        for (int i = 0; i < k->nx; i++) k->LD[(size_t)i * n + i] += shift;
        int info, lw = -1;
        if (!k->work) {
            double wq;
            dsytrf_("L", &n, k->LD, &n, k->ipiv, &wq, &lw, &info);
            k->lwork = (int)wq + n;
            if (!(k->work = malloc(sizeof(double) * (size_t)k->lwork)))
                return sf_fail(err, SF_ENOMEM, "out of memory");
        }
        dsytrf_("L", &n, k->LD, &n, k->ipiv, k->work, &k->lwork, &info);
        int zero = 0;
        k->neg = dense_negatives(k->LD, k->ipiv, n, &zero);
        if (info != 0 || zero) return SF_ENUMERIC;
        return SF_OK;
    }
    double *save = malloc(sizeof(double) * ((size_t)k->nx + 1));
    if (!save) return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int i = 0; i < k->nx; i++) {
        save[i] = k->tv[k->diag[i]];
        k->tv[k->diag[i]] += shift;
    }
    sf_error e;
    sf_error_clear(&e);
    int rc = sf_ldlt_factor(k->ld, n, k->tnnz, k->ti, k->tj, k->tv, &e);
    for (int i = 0; i < k->nx; i++) k->tv[k->diag[i]] = save[i];
    free(save);
    if (rc == SF_ENOMEM) return sf_fail(err, rc, "%s", e.msg);
    if (rc) return SF_ENUMERIC;
    sf_ldlt_info in;
    sf_ldlt_get_info(k->ld, &in);
    k->neg = in.neg;
    return in.nnull ? SF_ENUMERIC : SF_OK;
}

int fs_kkt_solve(fs_kkt *k, double *b, sf_error *err)
{
    int n = k->n;
    if (k->dense) {
        int one = 1, info;
        dsytrs_("L", &n, &one, k->LD, &n, k->ipiv, b, &n, &info);
        return info ? sf_fail(err, SF_ENUMERIC, "flat start: dsytrs failed (%d)", info) : SF_OK;
    }
    return sf_ldlt_solve(k->ld, b, err);
}

void fs_kkt_matvec(const fs_kkt *k, const double *v, double *w)
{
    int n = k->n;
    memset(w, 0, sizeof(double) * (size_t)n);
    if (k->dense) {
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) w[i] += k->K[(size_t)j * n + i] * v[j];
        return;
    }
    for (long e = 0; e < k->tnnz; e++) {
        int i = k->ti[e], j = k->tj[e];
        w[i] += k->tv[e] * v[j];
        if (i != j) w[j] += k->tv[e] * v[i];
    }
}
