/* multibp.h - branch directions at a multiple branch point (kernel
 * dimension d = 2) by Lyapunov-Schmidt reduction, prefix sf_mbp_.
 *
 * At a point (y0, p0) of a known branch where the symmetric Jacobian Jy
 * of the equilibrium problem (the KKT matrix) has a two-dimensional kernel
 * Phi = [phi1 phi2] (orthonormal eigenvectors of its two eigenvalues
 * nearest zero; the rest of the spectrum must be at least 1e3 times
 * further from zero), solutions near it are y = y0 + lam ty0 + Phi xi + w,
 * p = p0 + lam, with ty0 = -Jy^+ Fp the known branch's tangent and w
 * orthogonal to the kernel and of higher order.  Projected onto the
 * kernel, F = 0 becomes the reduced algebraic bifurcation equations
 * (Keller 1977; Govaerts 2000, ch. 6; the non-simple branch points of
 * BifurcationKit and pde2path's qswibra / cswibra):
 *   quadratic:  lam A xi + (1/2) B(xi, xi) = 0,
 *   cubic, where the quadratic part vanishes (B = 0, as at the pitchforks of
 *   a sheet symmetric under z -> -z):
 *               lam A xi + (1/6) C(xi, xi, xi) = 0,
 * A = Phi^T (dJy/dp along the known branch) Phi,
 * B(u, u) = Phi^T F_yy[Phi u, Phi u],
 * C(u, u, u) = Phi^T (F_yyy[u, u, u] - 3 F_yy[u, Jy^+ (I - P) F_yy[u, u]])
 * (P the projector on the kernel; the second term is the contribution of
 * the quadratic part of w).  On a ray xi = r u, |u| = 1, at the working
 * amplitude r both read
 *   lam A u + r G(u) = 0,  G(u) = B(u, u) / 2 + (r / 6) C(u, u, u)
 * (B = 0 exactly at a symmetric point: the cubic equations; a small B next
 * to a large C, as at a branch point located only approximately, keeps
 * both terms where a pure quadratic reduction would be dominated by the
 * error of B).  Isolated solutions: the rays where A u is parallel to
 * G(u), zeros of the angle function h(theta) = (A u) x G(u),
 * u = (cos theta, sin theta), found by sampling [0, 2 pi) and bisection;
 * on each, lam = -r G(u).Au / |Au|^2 (r halved until |lam| <= lam_max).
 *
 * Derivatives: Jy and Fp are the analytic ones (equilibrium.c); F_yy and
 * F_yyy along kernel directions, and dJy/dp along the branch, are central
 * differences of the analytic Jacobian (first differences with step 1e-5,
 * second differences with step 1e-3 in the coordinates; the model has no
 * third or fourth derivatives of the energy).  B and C are binary
 * quadratic and cubic forms, so a few samples fix them exactly
 * (polarisation: B from e1, e2, e1 + e2; C from e1, e2, e1 + e2, e1 - e2).
 * The quadratic part counts as vanishing when its largest coefficient is
 * below 1e-6 times the largest cubic one.
 *
 * Each direction gives a predicted point and tangent (derivative in r) for
 * the continuation engine (cont_start_tangent), which corrects it by
 * Newton on the full system and follows the branch.  Kernel dimensions
 * above 2 are refused (SF_ENUMERIC with a message). */
#ifndef SF_MULTIBP_H
#define SF_MULTIBP_H

#include "equilibrium.h"
#include "sf_error.h"

#define SF_MBP_MAXDIR 16

typedef struct sf_mbp {
    int n;
    int order;            /* 3: cubic (quadratic part zero), 2: quadratic + cubic */
    int ndir;             /* directions found (both signs of each ray) */
    double theta[SF_MBP_MAXDIR];   /* angle of u in the kernel plane */
    double lam[SF_MBP_MAXDIR];     /* p - p0 of the predicted point */
    double *y, *ty;       /* ndir predicted points and tangents, n each */
    double p[SF_MBP_MAXDIR], tp[SF_MBP_MAXDIR];
    double eig[3];        /* the two eigenvalues of Jy nearest zero, then the next */
    double bnorm, cnorm;  /* largest coefficients of B and C */
} sf_mbp;

/* Directions at the multiple branch point (y0, p0) of eq with a kernel of
 * dimension d, predicted at distance r (in the kernel plane) from it, |lam|
 * at most lam_max.  On success res holds them (free with sf_mbp_free). */
int sf_mbp_directions(sf_equil *eq, const double *y0, double p0, int d, double r,
                      double lam_max, sf_mbp *res, sf_error *err);
void sf_mbp_free(sf_mbp *res);

#endif
