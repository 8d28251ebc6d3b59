/* lmi.c - the largest smallest eigenvalue of an affine family of
 * symmetric matrices, H0 + sum_k mu_k A_k over a ball of mu, by the
 * semidefinite program that states it (DSDP; lmi.h).  The smallest
 * eigenvalue is concave in mu, so the program's optimum is the global one;
 * callers check the mu it returns with LAPACK. */
#include "lmi.h"

#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <dsdp5.h>

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

double sf_quad_form(int d, const double *M, const double *v)
{
    double s = 0.0;
    for (int a = 0; a < d; a++) {
        double t = 0.0;
        for (int b = 0; b < d; b++) t += M[(size_t)a * d + b] * v[b];
        s += v[a] * t;
    }
    return s;
}

/* DSDP prints the trace of a failed solve with printf, onto the run's
 * progress lines; the caller reports the failure itself, so stdout goes
 * to /dev/null while DSDP solves.  Returns the saved descriptor (-1: not
 * redirected). */
static int stdout_off(void)
{
    fflush(stdout);
    int saved = dup(STDOUT_FILENO), nul = open("/dev/null", O_WRONLY);
    if (saved >= 0 && nul >= 0 && dup2(nul, STDOUT_FILENO) < 0) {
        close(saved);
        saved = -1;
    }
    if (nul >= 0) close(nul);
    return saved;
}

static void stdout_on(int saved)
{
    if (saved < 0) return;
    fflush(stdout);
    dup2(saved, STDOUT_FILENO);
    close(saved);
}

/* The SDP, scaled: Hs = H0 / emax, As_k = A_k / amax, mu = y_k emax /
 * amax, t = y_{k+1} emax.  DSDP's dual form, max b^T y with C - sum y_i A_i
 * PSD: block 0 (d) C = Hs, A_i = -As_i, A_{k+1} = I; block 1 (k + 1)
 * C = rho I, A_i = -(e_i e_{k+1}^T + e_{k+1} e_i^T), which is PSD iff
 * |y_{1..k}| <= rho (Schur complement).  b = e_{k+1}.  On success (DSDP
 * ran, whatever its stop reason): mu from its y, t_lo its dual objective
 * times emax, and t_up, an upper bound of max lambda_min over the ball
 * that holds for ANY PSD X of trace 1 (lambda_min(M) <= <M, X>, and
 * <sum mu_k A_k, X> <= |mu| |(<A_k, X>)_k|): DSDP's block-0 X with its
 * negative eigenvalues cut and its trace scaled to 1 (t_up stays INFINITY
 * when DSDP gives no X).  Returns 0 when DSDP ran, else the error code of
 * the DSDP call that failed (-1: out of memory). */
int sf_lmi_max_min_eig(int d, const double *H0, int k, const double *A, double emax, double amax,
                       double rho, double *mu, double *t_lo, double *t_up)
{
    int m = k + 1, rc = 0;
    size_t dd = (size_t)d * d, np = (size_t)d * (d + 1) / 2;
    double R = rho * emax / amax, tu = INFINITY;
    if (!t_up) t_up = &tu;
    double *pk = malloc(sizeof(double) * (np * (size_t)(k + 1) + (size_t)m + 2 * dd + 4 * (size_t)d +
                                          2 * (size_t)k + 8));
    int *ind = malloc(sizeof(int) * ((size_t)k + 1));
    if (!pk || !ind) {
        free(pk); free(ind);
        return -1;
    }
    /* y (m), X (d x d), W (dsyev's work, d x d + 3 d), xe (d), g (k), val (k) */
    double *y = pk + np * (size_t)(k + 1), *X = y + m, *W = X + dd, *xe = W + dd + 3 * (size_t)d,
           *g = xe + d, *val = g + k;
    for (int a = 0; a < d; a++)
        for (int b = 0; b <= a; b++) {
            size_t at = (size_t)a * (a + 1) / 2 + b;
            pk[at] = H0 ? H0[(size_t)a * d + b] / emax : 0.0;
            for (int q = 0; q < k; q++)
                pk[np * (size_t)(q + 1) + at] = A[(size_t)q * dd + (size_t)a * d + b] / amax;
        }
    for (int q = 0; q < k; q++) {
        ind[q] = k * (k + 1) / 2 + q; /* row k, column q of block 1, packed */
        val[q] = -1.0;
    }
    DSDP dsdp = NULL;
    SDPCone cone = NULL;
    *t_up = INFINITY;
    *t_lo = -INFINITY;
#define DS(call) do { rc = (call); if (rc) goto out; } while (0)
    DS(DSDPCreate(m, &dsdp));
    DS(DSDPCreateSDPCone(dsdp, 2, &cone));
    DS(SDPConeSetBlockSize(cone, 0, d));
    DS(SDPConeSetBlockSize(cone, 1, m));
    DS(SDPConeSetADenseVecMat(cone, 0, 0, d, 1.0, pk, (int)np));
    for (int q = 0; q < k; q++) {
        DS(SDPConeSetADenseVecMat(cone, 0, q + 1, d, -1.0, pk + np * (size_t)(q + 1), (int)np));
        DS(SDPConeSetASparseVecMat(cone, 1, q + 1, m, 1.0, 0, ind + q, val + q, 1));
    }
    DS(SDPConeSetIdentity(cone, 0, m, d, 1.0));
    DS(SDPConeSetIdentity(cone, 1, 0, m, rho));
    DS(DSDPSetDualObjective(dsdp, m, 1.0));
    /* every y is bounded by the ball (mu) and by |t| <= 1 + sqrt(k) rho:
     * DSDP's own box only needs to stay out of the way */
    DS(DSDPSetYBounds(dsdp, -10.0 * (1.0 + sqrt((double)m) * rho), 10.0 * (1.0 + sqrt((double)m) * rho)));
    DS(DSDPSetGapTolerance(dsdp, 1e-8));
    DS(DSDPSetup(dsdp));
    int saved = stdout_off();
    rc = DSDPSolve(dsdp);
    stdout_on(saved);
    if (rc) goto out;
    DS(DSDPGetY(dsdp, y, m));
    for (int q = 0; q < k; q++) mu[q] = y[q] * emax / amax;
    double dobj = 0.0;
    DS(DSDPGetDObjective(dsdp, &dobj));
    *t_lo = dobj * emax;
    /* whatever DSDP's stop reason, its y is checked by the caller with
     * LAPACK, and the bound from X below holds for any X */
    {
        double *xx = NULL;
        int nx = 0;
        if (DSDPComputeX(dsdp) == 0 && SDPConeGetXArray(cone, 0, &xx, &nx) == 0 && xx &&
            (size_t)nx >= np) {
            for (int a = 0; a < d; a++)
                for (int b = 0; b <= a; b++)
                    X[(size_t)a * d + b] = X[(size_t)b * d + a] = xx[(size_t)a * (a + 1) / 2 + b];
            int info = 0, lw = (int)(dd + 3 * (size_t)d);
            dsyev_("V", "U", &d, X, &d, xe, W, &lw, &info);
            double tr = 0.0;
            for (int j = 0; j < d; j++) tr += fmax(xe[j], 0.0);
            if (info == 0 && tr > 0.0) {
                /* Xp = sum_j max(xe_j, 0) v_j v_j^T / tr; <M, Xp> = sum_j w_j v_j^T M v_j */
                double h = 0.0, gn = 0.0;
                for (int q = -1; q < k; q++) {
                    const double *M = q < 0 ? H0 : A + (size_t)q * dd;
                    if (!M) continue;
                    double s = 0.0;
                    for (int j = 0; j < d; j++) {
                        double wj = fmax(xe[j], 0.0) / tr;
                        if (wj == 0.0) continue;
                        s += wj * sf_quad_form(d, M, X + (size_t)j * d);
                    }
                    if (q < 0) h = s;
                    else { g[q] = s; gn += s * s; }
                }
                *t_up = h + R * sqrt(gn);
            }
        }
    }
out:
#undef DS
    if (dsdp) DSDPDestroy(dsdp);
    free(pk); free(ind);
    return rc;
}
