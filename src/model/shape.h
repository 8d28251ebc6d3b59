/* shape.h - cross-section of one smooth fold (MODEL.md section 2).
 *
 * The section is defined by its curvature on s in [0, w], s_hat = s/w:
 *   kappa(s) = (1/w) sum_{j=0..K} q_j phi_j(s_hat),  q_0 = theta, q_k = a_k,
 *   psi(s)   = sum_j q_j Phi_j(s_hat),  Phi_j(x) = int_0^x phi_j,
 * with Phi_0(1) = 1 and Phi_k(1) = 0 (k >= 1), so psi(w) = theta.
 * Basis (x = 2 s_hat - 1, P_n Legendre):
 *   G1: phi_j = P_j(x)             (phi_0 = 1, circular arc)
 *   G2: phi_j = P_j(x) - P_{j+2}(x) (phi_0 = 6 s_hat (1 - s_hat)),
 * both vanishing-mean for j >= 1; G2 modes vanish at both edges.
 *
 * Section integrals of the form
 *   I(q) = w int_0^b rho(s_hat) (cos psi, sin psi) ds_hat
 * are evaluated with their first and second derivatives in q:
 *   chord     c = I with rho = 1,      b = 1
 *   centroid  C = (1/w) int_0^w r(s) ds = I with rho = 1 - s_hat, b = 1
 *   point     r(s) = I with rho = 1,   b = s/w
 * The G1 K = 0 chord has closed forms (series near theta = 0); everything
 * else uses Gauss-Legendre quadrature of the order set at init.
 */
#ifndef SF_SHAPE_H
#define SF_SHAPE_H

#include "sf_error.h"

typedef struct sf_section {
    double w;          /* width [m] */
    int continuity;    /* 1 or 2 */
    int K;             /* extra modes */
    int nq;            /* K + 1 coordinates: theta, a_1..a_K */
    int nquad;         /* Gauss-Legendre points on [0, 1] */
    double *xg, *wg;   /* nodes and weights on [0, 1] */
    double *coef;      /* phi_j = sum_n coef[j*(K+3) + n] P_n(x), n <= K+2 */
    double *gram;      /* nq x nq, int_0^1 phi_i phi_j ds_hat */
    double *Phiq;      /* nquad x nq: Phi_j at the nodes on [0, 1], cached for
                          the integrals over the whole width (chord, centroid) */
} sf_section;

/* Which integral: see above. */
enum { SF_SEC_CHORD = 0, SF_SEC_CENTROID = 1 };

int sf_section_init(sf_section *sec, double w, int continuity, int K,
                    int nquad, sf_error *err);
void sf_section_free(sf_section *sec);

/* Basis and its integral at s_hat in [0, 1]: phi[j], Phi[j], j < nq. */
void sf_section_basis(const sf_section *sec, double shat, double *phi,
                      double *Phi);

/* psi and kappa at s_hat for coordinates q[nq]. */
double sf_section_psi(const sf_section *sec, const double *q, double shat);
double sf_section_kappa(const sf_section *sec, const double *q, double shat);

/* Chord (kind SF_SEC_CHORD) or centroid (SF_SEC_CENTROID) in the (n, e3)
 * plane of the right face: v[2]; dv[2*nq] (dv[c*nq + j] = d v_c / d q_j);
 * d2v[2*nq*nq] (d2v[(c*nq + j)*nq + k]).  dv, d2v may be NULL. */
void sf_section_integral(const sf_section *sec, int kind, const double *q,
                         double v[2], double *dv, double *d2v);

/* Point r(s) of the section at arclength s in [0, w] from the right edge,
 * with derivatives as above (quadrature on [0, s]). */
void sf_section_point(const sf_section *sec, const double *q, double s,
                      double r[2], double *dr, double *d2r);

/* Bending energy factor: U = (1/2) (D L / w) (q - q0)^T G (q - q0),
 * with G = sec->gram. */

/* Closed forms for the circular arc (G1, K = 0): c_n = w sin(t)/t,
 * c_3 = w (1 - cos t)/t and derivatives; Taylor series below |t| < SF_ARC_SERIES, where the
 * closed forms would lose digits to cancellation.
 * f[3] = value, first, second derivative of sin(t)/t; g[3] of (1-cos t)/t. */
#define SF_ARC_SERIES 1.0
void sf_arc_functions(double t, double f[3], double g[3]);

#endif
