/* test_shape.c - fold cross-sections: closed forms, series, quadrature,
 * inextensibility and analytic derivatives against finite differences. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shape.h"

/* Fails with expected, got and tolerance. */
#define CHECK_CLOSE(got, want, tol, what)                                       \
    do {                                                                        \
        double g_ = (got), w_ = (want), t_ = (tol);                             \
        if (!(fabs(g_ - w_) <= t_)) {                                           \
            print_error("%s: expected %.17g, got %.17g (|diff| %.3g > tol %.3g)\n", \
                        what, w_, g_, fabs(g_ - w_), t_);                       \
            fail();                                                             \
        }                                                                       \
    } while (0)

static unsigned rng_state = 12345u;
static double urand(double a, double b)
{
    rng_state = rng_state * 1103515245u + 12345u;
    return a + (b - a) * ((rng_state >> 8) & 0xffffff) / (double)0x1000000;
}

/* The closed forms of the circular arc and their Taylor series agree where
 * sf_arc_functions switches between them. */
static void test_arc_series_switch(void **state)
{
    (void)state;
    for (int sgn = -1; sgn <= 1; sgn += 2) {
        double t = sgn * SF_ARC_SERIES;
        double fa[3], ga[3], fb[3], gb[3];
        sf_arc_functions(t * (1 - 1e-15), fa, ga); /* series side */
        sf_arc_functions(t * (1 + 1e-15), fb, gb); /* closed-form side */
        for (int d = 0; d < 3; d++) {
            char what[64];
            snprintf(what, sizeof what, "sin(t)/t derivative %d at t=%g", d, t);
            CHECK_CLOSE(fa[d], fb[d], 1e-14 * fmax(fabs(fb[d]), 1e-300) + 4e-15 * fabs(t), what);
            snprintf(what, sizeof what, "(1-cos t)/t derivative %d at t=%g", d, t);
            CHECK_CLOSE(ga[d], gb[d], 1e-14 * fmax(fabs(gb[d]), 1e-300) + 4e-15 * fabs(t), what);
        }
    }
    /* and the series is exact at 0 */
    double f[3], g[3];
    sf_arc_functions(0.0, f, g);
    CHECK_CLOSE(f[0], 1.0, 0, "f(0)");
    CHECK_CLOSE(f[1], 0.0, 0, "f'(0)");
    CHECK_CLOSE(f[2], -1.0 / 3.0, 1e-16, "f''(0)");
    CHECK_CLOSE(g[0], 0.0, 0, "g(0)");
    CHECK_CLOSE(g[1], 0.5, 1e-16, "g'(0)");
    CHECK_CLOSE(g[2], 0.0, 0, "g''(0)");
}

/* Circular-arc chord: closed form (G1, K = 0) against the quadrature path
 * (the point at s = w is integrated, never closed-form). */
static void test_arc_chord_vs_quadrature(void **state)
{
    (void)state;
    sf_section sec;
    assert_int_equal(sf_section_init(&sec, 0.01, 1, 0, 32, NULL), SF_OK);
    double ts[] = {0.0, 1e-9, 1e-3, 0.5, 1.0, 2.0, 3.0, M_PI - 1e-6, -2.5};
    for (size_t i = 0; i < sizeof ts / sizeof *ts; i++) {
        double q = ts[i], c[2], r[2];
        sf_section_integral(&sec, SF_SEC_CHORD, &q, c, NULL, NULL);
        sf_section_point(&sec, &q, sec.w, r, NULL, NULL);
        CHECK_CLOSE(c[0], r[0], 1e-15 * sec.w, "c_n closed vs quadrature");
        CHECK_CLOSE(c[1], r[1], 1e-15 * sec.w, "c_3 closed vs quadrature");
        double cn = q == 0 ? sec.w : sec.w * sin(q) / q;
        CHECK_CLOSE(c[0], cn, 1e-15 * sec.w, "c_n = w sin(t)/t");
    }
    sf_section_free(&sec);
}

/* Bending energy factors: G1 circular arc 1/2, G2 parabola 0.6 (MODEL.md 5),
 * and the basis: Phi_0(1) = 1, Phi_k(1) = 0, G2 curvature zero at edges. */
static void test_basis_and_gram(void **state)
{
    (void)state;
    for (int cont = 1; cont <= 2; cont++) {
        sf_section sec;
        assert_int_equal(sf_section_init(&sec, 0.02, cont, 6, 32, NULL), SF_OK);
        CHECK_CLOSE(0.5 * sec.gram[0], cont == 1 ? 0.5 : 0.6, 1e-15, "energy factor");
        double phi0[7], Phi0[7], phi1[7], Phi1[7];
        sf_section_basis(&sec, 0.0, phi0, Phi0);
        sf_section_basis(&sec, 1.0, phi1, Phi1);
        for (int j = 0; j < sec.nq; j++) {
            CHECK_CLOSE(Phi0[j], 0.0, 1e-15, "Phi_j(0)");
            CHECK_CLOSE(Phi1[j], j == 0 ? 1.0 : 0.0, 1e-14, "Phi_j(1)");
            if (cont == 2) {
                CHECK_CLOSE(phi0[j], 0.0, 1e-14, "G2 phi_j(0)");
                CHECK_CLOSE(phi1[j], 0.0, 1e-14, "G2 phi_j(1)");
            }
        }
        /* G2 phi_0 = 6 s (1 - s) */
        double phi[7];
        sf_section_basis(&sec, 0.3, phi, NULL);
        if (cont == 2) CHECK_CLOSE(phi[0], 6 * 0.3 * 0.7, 1e-14, "G2 phi_0(0.3)");
        /* Gram matrix against quadrature of the basis */
        for (int i = 0; i < sec.nq; i++)
            for (int j = 0; j < sec.nq; j++) {
                double s = 0.0;
                for (int g = 0; g < sec.nquad; g++) {
                    double pg[7];
                    sf_section_basis(&sec, sec.xg[g], pg, NULL);
                    s += sec.wg[g] * pg[i] * pg[j];
                }
                CHECK_CLOSE(sec.gram[i * sec.nq + j], s, 1e-14, "Gram entry");
            }
        sf_section_free(&sec);
    }
}

/* Inextensibility: a polyline through N points of the section, corrected
 * by its known chord defect sum kappa^2 h^3 / 24 (a symmetric expansion,
 * remainder O(h^5)), has length w to 1e-12 for any angle and modes. */
static void test_inextensible(void **state)
{
    (void)state;
    for (int cont = 1; cont <= 2; cont++)
        for (int K = 0; K <= 4; K += 2)
            for (int trial = 0; trial < 3; trial++) {
                sf_section sec;
                double w = 1.0;
                assert_int_equal(sf_section_init(&sec, w, cont, K, 40, NULL), SF_OK);
                double q[5];
                q[0] = urand(-3.1, 3.1);
                for (int k = 1; k <= K; k++) q[k] = urand(-1.0, 1.0);
                int N = 2000;
                double h = w / N, len = 0.0, defect = 0.0, prev[2] = {0, 0};
                for (int i = 1; i <= N; i++) {
                    double r[2];
                    sf_section_point(&sec, q, i * h, r, NULL, NULL);
                    len += hypot(r[0] - prev[0], r[1] - prev[1]);
                    double km = sf_section_kappa(&sec, q, (i - 0.5) * h / w);
                    defect += km * km * h * h * h / 24.0;
                    prev[0] = r[0];
                    prev[1] = r[1];
                }
                CHECK_CLOSE(len + defect, w, 1e-12 * w, "curve length");
                /* and the end tangent angle is theta */
                CHECK_CLOSE(sf_section_psi(&sec, q, 1.0), q[0], 1e-13, "psi(w) = theta");
                sf_section_free(&sec);
            }
}

/* Analytic first and second derivatives of chord, centroid and points
 * against central differences at random states. */
static void fd_check(const sf_section *sec, int which, double s, const double *q0)
{
    int nq = sec->nq;
    double v[2], dv[2 * 9], d2v[2 * 81];
    double qq[9];
#define EVAL(qv, V, DV, D2V)                                                     \
    do {                                                                         \
        if (which < 2) sf_section_integral(sec, which, qv, V, DV, D2V);          \
        else sf_section_point(sec, qv, s, V, DV, D2V);                           \
    } while (0)
    EVAL(q0, v, dv, d2v);
    double scale = sec->w;
    for (int j = 0; j < nq; j++) {
        double h = 1e-5;
        double vp[2], vm[2], dvp[18], dvm[18];
        memcpy(qq, q0, sizeof(double) * nq);
        qq[j] += h;
        EVAL(qq, vp, dvp, NULL);
        qq[j] -= 2 * h;
        EVAL(qq, vm, dvm, NULL);
        for (int c = 0; c < 2; c++) {
            double fd = (vp[c] - vm[c]) / (2 * h);
            char what[96];
            snprintf(what, sizeof what, "kind %d cont %d K %d: d v%d / dq%d", which,
                     sec->continuity, sec->K, c, j);
            CHECK_CLOSE(dv[c * nq + j], fd, 1e-6 * fmax(fabs(fd), 1e-3 * scale), what);
            for (int l = 0; l < nq; l++) {
                double fd2 = (dvp[c * nq + l] - dvm[c * nq + l]) / (2 * h);
                snprintf(what, sizeof what, "kind %d cont %d K %d: d2 v%d / dq%d dq%d",
                         which, sec->continuity, sec->K, c, j, l);
                CHECK_CLOSE(d2v[(c * nq + l) * nq + j], fd2,
                            1e-6 * fmax(fabs(fd2), 1e-3 * scale), what);
            }
        }
    }
#undef EVAL
}

static void test_section_derivatives(void **state)
{
    (void)state;
    for (int cont = 1; cont <= 2; cont++)
        for (int K = 0; K <= 3; K++) {
            sf_section sec;
            assert_int_equal(sf_section_init(&sec, 0.008, cont, K, 24, NULL), SF_OK);
            for (int trial = 0; trial < 4; trial++) {
                double q[4];
                q[0] = trial == 0 ? 1e-7 : urand(-3.0, 3.0);
                for (int k = 1; k <= K; k++) q[k] = urand(-0.8, 0.8);
                fd_check(&sec, SF_SEC_CHORD, 0, q);
                fd_check(&sec, SF_SEC_CENTROID, 0, q);
                fd_check(&sec, 2, urand(0, sec.w), q);
            }
            sf_section_free(&sec);
        }
}

/* The centroid integral equals (1/w) int_0^w r(s) ds. */
static void test_centroid(void **state)
{
    (void)state;
    sf_section sec;
    assert_int_equal(sf_section_init(&sec, 0.01, 2, 2, 32, NULL), SF_OK);
    double q[3] = {2.0, 0.3, -0.2}, C[2], acc[2] = {0, 0};
    sf_section_integral(&sec, SF_SEC_CENTROID, q, C, NULL, NULL);
    for (int g = 0; g < sec.nquad; g++) {
        double r[2];
        sf_section_point(&sec, q, sec.xg[g] * sec.w, r, NULL, NULL);
        acc[0] += sec.wg[g] * r[0];
        acc[1] += sec.wg[g] * r[1];
    }
    CHECK_CLOSE(C[0], acc[0], 1e-15, "centroid n");
    CHECK_CLOSE(C[1], acc[1], 1e-15, "centroid 3");
    sf_section_free(&sec);
}

static void test_bad_section(void **state)
{
    (void)state;
    sf_section sec;
    sf_error e;
    sf_error_clear(&e);
    assert_int_equal(sf_section_init(&sec, -0.01, 1, 0, 24, &e), SF_EINPUT);
    assert_non_null(strstr(e.msg, "width must be positive"));
    sf_error_clear(&e);
    assert_int_equal(sf_section_init(&sec, NAN, 1, 0, 24, &e), SF_EINPUT);
    sf_error_clear(&e);
    assert_int_equal(sf_section_init(&sec, 0.01, 3, 0, 24, &e), SF_EINPUT);
    assert_non_null(strstr(e.msg, "continuity"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_arc_series_switch),
        cmocka_unit_test(test_arc_chord_vs_quadrature),
        cmocka_unit_test(test_basis_and_gram),
        cmocka_unit_test(test_inextensible),
        cmocka_unit_test(test_section_derivatives),
        cmocka_unit_test(test_centroid),
        cmocka_unit_test(test_bad_section),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
