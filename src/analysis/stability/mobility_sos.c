/* mobility_sos.c - second-order rigidity by a sum of squares (mobility.h).
 *
 * A first-order motion v (coordinates in the basis Z of mobility.c) can
 * only start a motion of the loops if every self-stress's form vanishes
 * on it, Q_s(v) = v^T G_s v = 0.  Where no v != 0 does so, the set is
 * second-order rigid, and second-order rigidity implies rigidity
 * (Connelly and Whiteley, SIAM J. Discrete Math. 9, 1996).  The prestress
 * certificate (one combination of the G_s positive definite) is the
 * stronger condition and misses cases such as the degree-3 vertex, whose
 * stresses give a rank-one form and two traceless ones: no combination is
 * definite, yet the forms have no common real zero.
 *
 * Certificate: f(v) = sum_s Q_s(v)^2 >= gamma |v|^4 with gamma > 0, shown
 * by writing f - gamma |v|^4 as m^T X m with X positive semidefinite, m
 * the degree-2 monomials scaled so that m^T m = |v|^4 (v_a^2, and
 * sqrt(2) v_a v_b for a < b).  The Gram matrices of f form the affine set
 * F + sum_j y_j B_j (F = sum_s w_s w_s^T, w_s the coefficients of Q_s in
 * m; B_j the matrices whose form in m is the zero polynomial), so the best
 * gamma is the largest smallest eigenvalue of that set: a linear matrix
 * inequality (lmi.h, DSDP).  The eigenvalue is checked with LAPACK at the
 * y found, so the certificate does not rest on DSDP's accuracy. */
#include "mobility.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lmi.h"

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

/* index of the monomial v_a v_b (a <= b) among the nn (nn + 1) / 2 */
static int mono(int nn, int a, int b)
{
    if (a > b) { int t = a; a = b; b = t; }
    return a * nn - a * (a - 1) / 2 + (b - a);
}

double sf_mobility_sos(int nn, int n2, const double *G, int *status)
{
    *status = 0;
    if (nn <= 0 || n2 <= 0 || nn > SF_MOBILITY_SOS_MAX) return -INFINITY;
    int N = nn * (nn + 1) / 2;
    size_t NN = (size_t)N * N;
    double r2 = sqrt(2.0);
    /* a monomial's scale in m: 1 for v_a^2, sqrt(2) for v_a v_b */
    double *sc = malloc(sizeof(double) * (size_t)N);
    int *pa = malloc(sizeof(int) * (size_t)N), *pb = malloc(sizeof(int) * (size_t)N);
    double *F = calloc(NN, sizeof(double)), *w = malloc(sizeof(double) * (size_t)N);
    /* the null matrices: for each quartic monomial the first pair (p, q)
     * that gives it, and one matrix for every further pair */
    int npair = N * (N + 1) / 2;
    int *first = malloc(sizeof(int) * (size_t)npair * 2);
    double *B = NULL, *S = NULL, *ev = NULL, *work = NULL, *y = NULL;
    double gamma = -INFINITY;
    int nb = 0;
    if (!sc || !pa || !pb || !F || !w || !first) goto oom;
    for (int a = 0; a < nn; a++)
        for (int b = a; b < nn; b++) {
            int p = mono(nn, a, b);
            pa[p] = a;
            pb[p] = b;
            sc[p] = a == b ? 1.0 : r2;
        }
    for (int s = 0; s < n2; s++) {
        const double *Gs = G + (size_t)s * nn * nn;
        for (int p = 0; p < N; p++)
            w[p] = pa[p] == pb[p] ? Gs[(size_t)pa[p] * nn + pa[p]]
                                  : 2.0 * Gs[(size_t)pa[p] * nn + pb[p]] / r2;
        for (int p = 0; p < N; p++)
            for (int q = 0; q < N; q++) F[(size_t)p * N + q] += w[p] * w[q];
    }
    /* quartic monomial of the pair (p, q) as a sorted key of four indices */
    long *key = malloc(sizeof(long) * (size_t)npair);
    if (!key) goto oom;
    int k = 0;
    for (int p = 0; p < N; p++)
        for (int q = p; q < N; q++, k++) {
            int e[4] = {pa[p], pb[p], pa[q], pb[q]};
            for (int i = 1; i < 4; i++)
                for (int j = i; j > 0 && e[j - 1] > e[j]; j--) { int t = e[j]; e[j] = e[j - 1]; e[j - 1] = t; }
            key[k] = ((long)e[0] * nn + e[1]) * nn * nn + (long)e[2] * nn + e[3];
            first[2 * k] = p;
            first[2 * k + 1] = q;
        }
    B = malloc(sizeof(double) * ((size_t)npair * NN + 1));
    if (!B) { free(key); goto oom; }
    /* for each pair, the earliest pair with the same monomial: the zero
     * polynomial Esym(p0, q0) / c0 - Esym(p, q) / c (c = the pair's scale) */
    for (int i = 0; i < npair; i++) {
        int j0 = -1;
        for (int j = 0; j < i; j++)
            if (key[j] == key[i]) { j0 = j; break; }
        if (j0 < 0) continue;
        double *Bj = B + (size_t)nb * NN;
        memset(Bj, 0, sizeof(double) * NN);
        int p0 = first[2 * j0], q0 = first[2 * j0 + 1], p = first[2 * i], q = first[2 * i + 1];
        double c0 = sc[p0] * sc[q0], c = sc[p] * sc[q];
        Bj[(size_t)p0 * N + q0] += 0.5 / c0;
        Bj[(size_t)q0 * N + p0] += 0.5 / c0;
        Bj[(size_t)p * N + q] -= 0.5 / c;
        Bj[(size_t)q * N + p] -= 0.5 / c;
        nb++;
    }
    free(key);
    /* scales for the LMI: F's largest eigenvalue, the B's norms */
    S = malloc(sizeof(double) * (NN + 1));
    ev = malloc(sizeof(double) * ((size_t)N + 1));
    int lw = 3 * N + 1, info;
    work = malloc(sizeof(double) * (size_t)lw);
    y = calloc((size_t)nb + 1, sizeof(double));
    if (!S || !ev || !work || !y) goto oom;
    memcpy(S, F, sizeof(double) * NN);
    dsyev_("N", "L", &N, S, &N, ev, work, &lw, &info);
    if (info) goto fail;
    double emax = fmax(fabs(ev[0]), fabs(ev[N - 1]));
    if (!(emax > 0)) goto done; /* every form zero: every v is a second-order motion */
    double amax = 0.0;
    for (int j = 0; j < nb; j++) {
        double f = 0.0;
        for (size_t i = 0; i < NN; i++) f += B[(size_t)j * NN + i] * B[(size_t)j * NN + i];
        amax = fmax(amax, sqrt(f));
    }
    double tlo = -INFINITY;
    if (nb > 0) {
        int rc = sf_lmi_max_min_eig(N, F, nb, B, emax, amax, SF_MOBILITY_SOS_RHO, y, &tlo, NULL);
        if (rc == -1) goto oom;
        if (rc) goto fail;
    }
    /* the certificate, checked: the smallest eigenvalue of F + sum y B */
    memcpy(S, F, sizeof(double) * NN);
    for (int j = 0; j < nb; j++)
        for (size_t i = 0; i < NN; i++) S[i] += y[j] * B[(size_t)j * NN + i];
    dsyev_("N", "L", &N, S, &N, ev, work, &lw, &info);
    if (info) goto fail;
    gamma = ev[0] / emax;
    goto done;
oom:
    *status = -1;
    goto done;
fail:
    *status = 1;
done:
    free(sc); free(pa); free(pb); free(F); free(w); free(first);
    free(B); free(S); free(ev); free(work); free(y);
    return gamma;
}
