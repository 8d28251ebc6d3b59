/* stab_test.h - helpers shared by the stability and bifurcation tests
 * (test_stability.c, test_bifurcation.c, test_multibp.c): the SF_OK check,
 * the one-fold closed forms of fold1-buckle / snap1, and the bisection on
 * the flat-state eigenvalues.  Include after cmocka.h and sf_test.h. */
#ifndef SF_STAB_TEST_H
#define SF_STAB_TEST_H

#include <math.h>

#include "check_test.h"
#include "equilibrium.h"
#include "stability.h"

/* ---- the one-fold closed forms (K = 0, G1) --------------------------- */

/* fold1's sheet: one fold of width w, its band ends 0.035 m from the
 * clamp side; the load (P_F = 1.5 N) acts at x = 0.06, b beyond the band.
 * The study's own material and geometry (studies/fold1-buckle.cfg). */
static const double E_F = 15.2e6, NU_F = 0.45, H_F = 1.8e-3, L_F = 0.03, W_F = 0.01, B_F = 0.025,
                    P_F = 1.5;

/* the fold's rotational stiffness k = D L / w */
static inline double k_fold(void)
{
    double D = E_F * H_F * H_F * H_F / (12.0 * (1.0 - NU_F * NU_F));
    return D * L_F / W_F;
}

/* the buckling load factor P_cr = k / (b + w/3) over the 1.5 N load */
static inline double pcr_fold(void) { return k_fold() / (B_F + W_F / 3.0) / P_F; }

/* x-displacement of the tip and its t-derivatives (circular arc) */
static inline double ux(double t)
{
    double c = fabs(t) < 1e-4 ? W_F * (1 - t * t / 6 + t * t * t * t / 120) : W_F * sin(t) / t;
    return c + B_F * cos(t) - W_F - B_F;
}
static inline double ux1(double t) { return W_F * (t * cos(t) - sin(t)) / (t * t) - B_F * sin(t); }
static inline double ux2(double t)
{
    return W_F * (-t * t * sin(t) - 2 * t * cos(t) + 2 * sin(t)) / (t * t * t) - B_F * cos(t);
}

/* ---- flat-state crossings --------------------------------------------- */

/* Bisection for the zero of the (j+1)-th smallest eigenvalue of the
 * constrained Hessian at the fixed state y, p in [a, b] (positive at a,
 * negative at b). */
static inline double flat_zero(sf_stab *st, sf_equil *eq, const double *y, int j, double a,
                               double b)
{
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_stab_eval(st, eq, y, a, &err), err);
    assert_true(st->res.eig[j] > 0);
    CHECK_OK(sf_stab_eval(st, eq, y, b, &err), err);
    assert_true(st->res.eig[j] < 0);
    for (int i = 0; i < 60; i++) {
        double m = 0.5 * (a + b);
        CHECK_OK(sf_stab_eval(st, eq, y, m, &err), err);
        if (st->res.eig[j] > 0) a = m;
        else b = m;
    }
    return 0.5 * (a + b);
}

#endif
