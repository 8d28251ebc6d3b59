/* shape.c - smooth-fold cross-sections defined by their curvature.
 *
 * See shape.h for the basis.  Everything here is exact up to the Gauss-
 * Legendre quadrature of the section integrals, except the circular arc
 * (G1, K = 0), whose chord has closed forms.
 */
#include "shape.h"
#include "pattern.h"   /* SF_QUADRATURE_MIN, SF_QUADRATURE_MAX */

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Legendre polynomials P_0..P_nmax at x. */
static void legendre(int nmax, double x, double *P)
{
    P[0] = 1.0;
    if (nmax >= 1) P[1] = x;
    for (int n = 1; n < nmax; n++)
        P[n + 1] = ((2.0 * n + 1.0) * x * P[n] - n * P[n - 1]) / (n + 1.0);
}

/* P_n(z) in *p; returns its derivative P_n'(z) (|z| < 1). */
static double legendre_dp(int n, double z, double *p)
{
    double p0 = 1.0, p1 = z;
    for (int k = 1; k < n; k++) {
        double p2 = ((2.0 * k + 1.0) * z * p1 - k * p0) / (k + 1.0);
        p0 = p1;
        p1 = p2;
    }
    *p = p1;
    return n * (z * p1 - p0) / (z * z - 1.0);
}

/* Gauss-Legendre rule with n points on [0, 1] (Newton on P_n). */
static void gauss_legendre01(int n, double *x, double *w)
{
    for (int i = 0; i < (n + 1) / 2; i++) {
        double z = cos(M_PI * (i + 0.75) / (n + 0.5)), p;
        for (int it = 0; it < 100; it++) {
            double dp = legendre_dp(n, z, &p), dz = p / dp;
            z -= dz;
            if (fabs(dz) < 1e-16) break;
        }
        /* the derivative at the converged node */
        double dp = legendre_dp(n, z, &p);
        double wt = 2.0 / ((1.0 - z * z) * dp * dp);
        /* map from [-1, 1] to [0, 1] */
        x[i] = 0.5 * (1.0 - z);
        x[n - 1 - i] = 0.5 * (1.0 + z);
        w[i] = w[n - 1 - i] = 0.5 * wt;
    }
}

int sf_section_init(sf_section *sec, double w, int continuity, int K,
                    int nquad, sf_error *err)
{
    memset(sec, 0, sizeof *sec);
    if (!(w > 0.0) || !isfinite(w))
        return sf_fail(err, SF_EINPUT, "section width must be positive (got %g)", w);
    if (continuity != 1 && continuity != 2)
        return sf_fail(err, SF_EINPUT, "continuity must be 1 or 2 (got %d)", continuity);
    if (K < 0 || K > 64)
        return sf_fail(err, SF_EINPUT, "number of shape modes must be in 0..64 (got %d)", K);
    if (nquad < SF_QUADRATURE_MIN || nquad > SF_QUADRATURE_MAX)
        return sf_fail(err, SF_EINPUT, "quadrature order must be in %d..%d (got %d)",
                       SF_QUADRATURE_MIN, SF_QUADRATURE_MAX, nquad);
    sec->w = w;
    sec->continuity = continuity;
    sec->K = K;
    sec->nq = K + 1;
    sec->nquad = nquad;
    int nc = K + 3;
    sec->xg = malloc(sizeof(double) * nquad);
    sec->wg = malloc(sizeof(double) * nquad);
    sec->coef = calloc((size_t)sec->nq * nc, sizeof(double));
    sec->gram = calloc((size_t)sec->nq * sec->nq, sizeof(double));
    if (!sec->xg || !sec->wg || !sec->coef || !sec->gram) {
        sf_section_free(sec);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    gauss_legendre01(nquad, sec->xg, sec->wg);
    for (int j = 0; j < sec->nq; j++) {
        sec->coef[j * nc + j] = 1.0;
        if (continuity == 2) sec->coef[j * nc + j + 2] = -1.0;
    }
    /* int_0^1 P_m(2s-1) P_n(2s-1) ds = delta_mn / (2n + 1) */
    for (int i = 0; i < sec->nq; i++)
        for (int j = 0; j < sec->nq; j++) {
            double g = 0.0;
            for (int n = 0; n < nc; n++)
                g += sec->coef[i * nc + n] * sec->coef[j * nc + n] / (2.0 * n + 1.0);
            sec->gram[i * sec->nq + j] = g;
        }
    sec->Phiq = malloc(sizeof(double) * (size_t)nquad * sec->nq);
    if (!sec->Phiq) {
        sf_section_free(sec);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int g = 0; g < nquad; g++) sf_section_basis(sec, sec->xg[g], NULL, sec->Phiq + (size_t)g * sec->nq);
    return SF_OK;
}

void sf_section_free(sf_section *sec)
{
    free(sec->xg);
    free(sec->wg);
    free(sec->coef);
    free(sec->gram);
    free(sec->Phiq);
    memset(sec, 0, sizeof *sec);
}

void sf_section_basis(const sf_section *sec, double shat, double *phi, double *Phi)
{
    int nc = sec->K + 3;
    double P[72];
    double x = 2.0 * shat - 1.0;
    legendre(nc, x, P); /* P_0 .. P_{K+3} */
    for (int j = 0; j < sec->nq; j++) {
        double f = 0.0, F = 0.0;
        for (int n = 0; n < nc; n++) {
            double c = sec->coef[j * nc + n];
            if (c == 0.0) continue;
            f += c * P[n];
            /* int_0^shat P_n(2t - 1) dt */
            double I = n == 0 ? 0.5 * (x + 1.0)
                              : (P[n + 1] - P[n - 1]) / (2.0 * (2.0 * n + 1.0));
            F += c * I;
        }
        if (phi) phi[j] = f;
        if (Phi) Phi[j] = F;
    }
}

double sf_section_psi(const sf_section *sec, const double *q, double shat)
{
    double Phi[65];
    sf_section_basis(sec, shat, NULL, Phi);
    double psi = 0.0;
    for (int j = 0; j < sec->nq; j++) psi += q[j] * Phi[j];
    return psi;
}

double sf_section_kappa(const sf_section *sec, const double *q, double shat)
{
    double phi[65];
    sf_section_basis(sec, shat, phi, NULL);
    double k = 0.0;
    for (int j = 0; j < sec->nq; j++) k += q[j] * phi[j];
    return k / sec->w;
}

/* sin(t)/t and (1 - cos t)/t with two derivatives.  Below |t| < 1 the
 * Taylor series are summed to full precision (the closed forms lose digits
 * to cancellation there, worst in the second derivatives). */
void sf_arc_functions(double t, double f[3], double g[3])
{
    if (fabs(t) < SF_ARC_SERIES) {
        /* f = sum_k a_k t^2k,      a_k = (-1)^k / (2k+1)!
         * g = sum_k b_k t^(2k+1),  b_k = (-1)^k / (2k+2)!
         * With |t| < 1 the terms fall faster than 1/(2k+1)!, so 12 terms
         * reach double precision. */
        double f0 = 0, f1 = 0, f2 = 0, g0 = 0, g1 = 0, g2 = 0;
        double fact = 1.0;      /* (2k+1)! */
        double p2km2 = 0.0;     /* t^(2k-2), k >= 1 */
        double p2k = 1.0;       /* t^(2k) */
        for (int k = 0; k < 13; k++) {
            double a = (k % 2 ? -1.0 : 1.0) / fact;
            double b = a / (2.0 * k + 2.0);
            f0 += a * p2k;
            g0 += b * p2k * t;
            g1 += b * (2 * k + 1) * p2k;
            if (k >= 1) {
                f1 += a * 2 * k * p2km2 * t;
                f2 += a * 2 * k * (2 * k - 1) * p2km2;
                g2 += b * (2 * k + 1) * (2 * k) * p2km2 * t;
            }
            p2km2 = p2k;
            p2k *= t * t;
            fact *= (2.0 * k + 2.0) * (2.0 * k + 3.0);
        }
        f[0] = f0; f[1] = f1; f[2] = f2;
        g[0] = g0; g[1] = g1; g[2] = g2;
        return;
    }
    double s = sin(t), c = cos(t), t2 = t * t, t3 = t2 * t;
    f[0] = s / t;
    f[1] = (t * c - s) / t2;
    f[2] = (-t2 * s - 2.0 * t * c + 2.0 * s) / t3;
    g[0] = (1.0 - c) / t;
    g[1] = (t * s - (1.0 - c)) / t2;
    g[2] = (t2 * c - 2.0 * t * s + 2.0 * (1.0 - c)) / t3;
}

/* I = w int_0^b rho(shat) (cos psi, sin psi) dshat by quadrature. */
static void section_quad(const sf_section *sec, int kind, const double *q,
                         double b, double v[2], double *dv, double *d2v)
{
    int nq = sec->nq;
    double Phi[65];
    v[0] = v[1] = 0.0;
    if (dv) memset(dv, 0, sizeof(double) * 2 * nq);
    if (d2v) memset(d2v, 0, sizeof(double) * 2 * nq * nq);
    for (int g = 0; g < sec->nquad; g++) {
        double sh = b * sec->xg[g];
        double wt = sec->w * b * sec->wg[g];
        if (kind == SF_SEC_CENTROID) wt *= 1.0 - sh;
        if (b == 1.0 && sec->Phiq) memcpy(Phi, sec->Phiq + (size_t)g * nq, sizeof(double) * (size_t)nq);
        else sf_section_basis(sec, sh, NULL, Phi);
        double psi = 0.0;
        for (int j = 0; j < nq; j++) psi += q[j] * Phi[j];
        double c = cos(psi), s = sin(psi);
        v[0] += wt * c;
        v[1] += wt * s;
        if (dv)
            for (int j = 0; j < nq; j++) {
                dv[j] -= wt * s * Phi[j];
                dv[nq + j] += wt * c * Phi[j];
            }
        if (d2v)
            for (int j = 0; j < nq; j++)
                for (int k = 0; k <= j; k++) {
                    double pp = wt * Phi[j] * Phi[k];
                    d2v[j * nq + k] -= pp * c;
                    d2v[(nq + j) * nq + k] -= pp * s;
                }
    }
    if (d2v) /* fill the upper triangles */
        for (int cpt = 0; cpt < 2; cpt++)
            for (int j = 0; j < nq; j++)
                for (int k = j + 1; k < nq; k++)
                    d2v[(cpt * nq + j) * nq + k] = d2v[(cpt * nq + k) * nq + j];
}

void sf_section_integral(const sf_section *sec, int kind, const double *q,
                         double v[2], double *dv, double *d2v)
{
    if (kind == SF_SEC_CHORD && sec->continuity == 1 && sec->K == 0) {
        double f[3], g[3], w = sec->w;
        sf_arc_functions(q[0], f, g);
        v[0] = w * f[0];
        v[1] = w * g[0];
        if (dv) { dv[0] = w * f[1]; dv[1] = w * g[1]; }
        if (d2v) { d2v[0] = w * f[2]; d2v[1] = w * g[2]; }
        return;
    }
    section_quad(sec, kind, q, 1.0, v, dv, d2v);
}

void sf_section_point(const sf_section *sec, const double *q, double s,
                      double r[2], double *dr, double *d2r)
{
    double b = s / sec->w;
    if (b < 0.0) b = 0.0;
    if (b > 1.0) b = 1.0;
    section_quad(sec, SF_SEC_CHORD, q, b, r, dr, d2r);
}
