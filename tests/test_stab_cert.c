/* test_stab_cert.c - stability where the loop rows are redundant and do not
 * keep their rank (src/analysis/stability/stab_cert.c): the 2x2 waterbomb
 * tessellation with both fold groups driven, fold coordinates, exact
 * closure.  Its path carries a self-stress of the loop rows (from the
 * flat start), and under most BLAS kernels Z^T HL Z at those multipliers
 * has a negative eigenvalue although the pose formulation finds every
 * point stable; where it has none, the test adds a self-stress that
 * makes it indefinite (the point stays a KKT point).  Checked here against the energy
 * alone, with no multiplier:
 * - the unstable direction v of Z^T HL Z at the path's own multipliers is
 *   no motion of the sheet: q* + t v projected back on the loop
 *   equations (Gauss-Newton, minimum-norm steps on all 6 rows per loop)
 *   comes back to within t / 10 of q*, and the energy does not drop where
 *   the quadratic model predicted t^2 eig / 2;
 * - at random closed states next to q* (random directions, projected the
 *   same way, 1e-3 rad away) the energy is above E* every time: a local
 *   minimum on the constraint set, which the certificate (a self-stress
 *   making Z^T HL Z positive definite) claims;
 * - with the certificate the dense method says stable, Morse index 0 (no
 *   eigenvalues: the certificate's depend on the self-stress).
 * And the search on its own (sf_stab_cert_search) on small matrices whose
 * answer is known in closed form: one the local ascent cannot certify
 * and the semidefinite program (DSDP) does, and two that no self-stress
 * certifies, with the largest smallest eigenvalue t* = -1 and 0. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SF_TEST_SEED 24681357u
#include "sf_test.h"

#include "check_test.h"
#include "cont.h"
#include "equilibrium.h"
#include "flatstart.h"
#include "kinematics.h"
#include "scene.h"
#include "stability.h"
#include "study.h"

extern void dgesvd_(const char *, const char *, const int *, const int *, double *, const int *,
                    double *, double *, const int *, double *, const int *, double *,
                    const int *, int *);
extern void dsyev_(const char *, const char *, const int *, double *, const int *, double *,
                   double *, const int *, int *);

static char tests_dir[1024];
static double raw_lowest(sf_equil *q, const double *y, double p, double *v);

/* SVD of C^T (C: nc x nq row-major): U (nq x nq), S, Vt (nc x nc). */
static void svd_ct(const double *C, int nq, int nc, double *U, double *S, double *Vt)
{
    double *A = malloc(sizeof(double) * (size_t)nq * nc), wq;
    memcpy(A, C, sizeof(double) * (size_t)nq * nc);
    int lw = -1, info;
    dgesvd_("A", "A", &nq, &nc, A, &nq, S, U, &nq, Vt, &nc, &wq, &lw, &info);
    lw = (int)wq + 1;
    double *W = malloc(sizeof(double) * (size_t)lw);
    dgesvd_("A", "A", &nq, &nc, A, &nq, S, U, &nq, Vt, &nc, W, &lw, &info);
    assert_int_equal(info, 0);
    free(W);
    free(A);
}

static double energy_at(sf_equil *q, const double *x, double p)
{
    double *y = calloc((size_t)q->n + 1, sizeof(double)), e, rr, rt;
    memcpy(y, x, sizeof(double) * q->nq);
    sf_equil_report(q, y, p, &e, &rr, &rt);
    free(y);
    return e;
}

/* Gauss-Newton with minimum-norm steps (pseudo-inverse, cut 1e-12) onto
 * the loop rows g(x) = 0; the largest |g| at the end. */
static double project(sf_equil *q, double *x)
{
    const sf_model *m = q->m;
    int nq = q->nq, nc = m->ncon, mn = nq < nc ? nq : nc;
    sf_kin k;
    assert_int_equal(sf_kin_alloc(m, &k), SF_OK);
    double *g = malloc(sizeof(double) * nc), *J = malloc(sizeof(double) * (size_t)nc * nq);
    double *U = malloc(sizeof(double) * (size_t)nq * nq), *S = calloc((size_t)nq + nc, sizeof(double));
    double *Vt = malloc(sizeof(double) * (size_t)nc * nc), gm = 0.0;
    for (int it = 0; it < 80; it++) {
        sf_kin_eval(m, x, 1, &k);
        sf_constraints(m, &k, g, J, NULL, NULL, 0);
        gm = 0.0;
        for (int r = 0; r < nc; r++) gm = fmax(gm, fabs(g[r]));
        if (gm < 1e-15) break;
        svd_ct(J, nq, nc, U, S, Vt);
        for (int i = 0; i < mn && S[i] > 1e-12 * S[0]; i++) {
            double c = 0.0;
            for (int r = 0; r < nc; r++) c += Vt[(size_t)r * nc + i] * g[r];
            for (int j = 0; j < nq; j++) x[j] -= c / S[i] * U[(size_t)i * nq + j];
        }
    }
    sf_kin_free(&k);
    free(g); free(J); free(U); free(S); free(Vt);
    return gm;
}

/* Lowest eigenpair of Z^T HL Z at the point's own multipliers (no
 * certificate): v (nq, unit 2-norm), the eigenvalue returned. */
static double raw_lowest(sf_equil *q, const double *y, double p, double *v)
{
    int nq = q->nq, nc = q->ncon, mn = nq < nc ? nq : nc;
    double *HL = calloc((size_t)nq * nq, sizeof(double)), *C = calloc((size_t)nc * nq, sizeof(double));
    assert_int_equal(sf_equil_kkt(q, y, p, HL, C), 0);
    double *U = malloc(sizeof(double) * (size_t)nq * nq), *S = calloc((size_t)nq + nc, sizeof(double));
    double *Vt = malloc(sizeof(double) * (size_t)nc * nc);
    svd_ct(C, nq, nc, U, S, Vt);
    int rank = 0;
    for (int i = 0; i < mn; i++) rank += S[i] > 1e-9 * S[0];
    int d = nq - rank, info, lw = -1;
    const double *Z = U + (size_t)rank * nq;
    double *H = calloc((size_t)d * d, sizeof(double)), *ev = malloc(sizeof(double) * d), wq;
    for (int a = 0; a < d; a++)
        for (int b = 0; b < d; b++) {
            double s = 0.0;
            for (int i = 0; i < nq; i++)
                for (int j = 0; j < nq; j++)
                    s += Z[(size_t)a * nq + i] * HL[(size_t)i * nq + j] * Z[(size_t)b * nq + j];
            H[(size_t)a * d + b] = s;
        }
    dsyev_("V", "U", &d, H, &d, ev, &wq, &lw, &info);
    lw = (int)wq + 1;
    double *W = malloc(sizeof(double) * (size_t)lw);
    dsyev_("V", "U", &d, H, &d, ev, W, &lw, &info);
    assert_int_equal(info, 0);
    for (int i = 0; i < nq; i++) {
        v[i] = 0.0;
        for (int a = 0; a < d; a++) v[i] += Z[(size_t)a * nq + i] * H[a];
    }
    double e = ev[0];
    free(HL); free(C); free(U); free(S); free(Vt); free(H); free(ev); free(W);
    return e;
}

/* The multipliers of redundant rows are fixed only up to a self-stress
 * (mu with C^T mu = 0), and which one the path carries depends on
 * rounding: under some BLAS kernels Z^T HL Z is already positive definite
 * there.  This adds to y's multipliers a self-stress (a left null vector
 * of C, scaled by 1e2 .. 1e8, either sign) under which Z^T HL Z has a
 * negative eigenvalue, the situation the certificate is for; y stays a
 * KKT point.  Returns the eigenvalue, v its vector. */
static double make_indefinite(sf_equil *q, double *y, double p, double *v)
{
    double l = raw_lowest(q, y, p, v);
    if (l < 0.0) return l;
    int nq = q->nq, nc = q->ncon, mn = nq < nc ? nq : nc;
    double *HL = calloc((size_t)nq * nq, sizeof(double)), *C = calloc((size_t)nc * nq, sizeof(double));
    assert_int_equal(sf_equil_kkt(q, y, p, HL, C), 0);
    double *U = malloc(sizeof(double) * (size_t)nq * nq), *S = calloc((size_t)nq + nc, sizeof(double));
    double *Vt = malloc(sizeof(double) * (size_t)nc * nc), *lam = malloc(sizeof(double) * nc);
    svd_ct(C, nq, nc, U, S, Vt);
    int rank = 0;
    for (int i = 0; i < mn; i++) rank += S[i] > 1e-9 * S[0];
    memcpy(lam, y + nq, sizeof(double) * nc);
    for (int i = rank; i < nc && !(l < 0.0); i++)
        for (double t = 1e2; t <= 1e8 && !(l < 0.0); t *= 10.0)
            for (int sg = -1; sg <= 1 && !(l < 0.0); sg += 2) {
                for (int r = 0; r < nc; r++) y[nq + r] = lam[r] + sg * t * Vt[(size_t)r * nc + i];
                l = raw_lowest(q, y, p, v);
            }
    free(HL); free(C); free(U); free(S); free(Vt); free(lam);
    return l;
}

static void test_waterbomb_certificate(void **state)
{
    (void)state;
    char path[1200];
    snprintf(path, sizeof path, "%s/waterbomb-2x2-all.cfg", tests_dir);
    const char *sets[] = {"solver.tolerance=1e-11", "analysis.end=0.3"};
    sf_scene sc;
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_scene_open(&sc, path, 2, sets, &err), err);
    const sf_model *m = &sc.model;
    int ptype, gi, pi, ci;
    CHECK_OK(sf_equil_parse_param(&sc.study, &ptype, &gi, &pi, &ci, &err), err);
    sf_equil q;
    CHECK_OK(sf_equil_init(&q, m, ptype, gi, pi, ci, 0.0, &err), err);
    cont_solver *cs = NULL;
    assert_int_equal(sf_equil_create_solver(&q, &cs), CONT_OK);
    cont_set_newton(cs, 1e-11, 20, 0);
    cont_set_step(cs, 0.05, 1e-6, 0.1);
    cont_set_prange(cs, 0.0, 0.3);
    cont_set_max_steps(cs, 40);
    cont_set_store(cs, 1);
    double *y0 = calloc((size_t)q.n + 1, sizeof(double));
    CHECK_OK(sf_equil_start_flat(&q, cs, 0.0, 0.05, 1, 1e-11, y0, 1, NULL, &err), err);
    cont_run(cs);
    long np = cont_num_points(cs);
    assert_true(np >= 3);
    const cont_point *pt = cont_point_at(cs, np - 1);
    double p = pt->p;
    int nq = q.nq;
    double *y = malloc(sizeof(double) * ((size_t)q.n + 1));
    memcpy(y, pt->y, sizeof(double) * (size_t)q.n);
    /* the path's own multipliers, or with a self-stress added: an unstable
     * direction v of Z^T HL Z */
    double *v = malloc(sizeof(double) * nq), *x = malloc(sizeof(double) * nq);
    double lraw = make_indefinite(&q, y, p, v);
    sf_stab st;
    CHECK_OK(sf_stab_init(&st, &q, SF_EIG_DENSE, 4, &err), err);
    CHECK_OK(sf_stab_eval(&st, &q, y, p, &err), err);
    print_message("# p = %g: certified %d (self-stress %.3g, its lowest eigenvalue %.6g), stable "
                  "%d, morse %d\n", p, st.res.certified, st.res.cert_mu, st.res.cert_eig,
                  st.res.stable, st.res.morse);
    double e0 = energy_at(&q, y, p);
    print_message("# without the certificate: lowest eigenvalue %.6g (E* = %.12g J)\n", lraw, e0);
    assert_true(lraw < 0.0); /* the situation this test is about */
    /* independent check 1: v is no motion of the sheet */
    const double ts[] = {1e-3, 1e-2};
    for (int i = 0; i < 2; i++)
        for (int sg = -1; sg <= 1; sg += 2) {
            double t = ts[i];
            for (int j = 0; j < nq; j++) x[j] = y[j] + sg * t * v[j];
            CHECK_LE(project(&q, x), 1e-13, "projection along v");
            double dist = 0.0;
            for (int j = 0; j < nq; j++) dist += (x[j] - y[j]) * (x[j] - y[j]);
            dist = sqrt(dist);
            double de = energy_at(&q, x, p) - e0, model = 0.5 * t * t * lraw;
            print_message("# along v, t = %+g: back to %.2g of q*, energy change %.3g J "
                          "(quadratic model %.3g J)\n", sg * t, dist, de, model);
            CHECK_LE(dist, 0.1 * t, "the projection of q* + t v comes back to q*");
            CHECK_LE(-de, 1e-3 * fabs(model), "the energy does not drop along v");
        }
    /* independent check 2: random closed states next to q* lie higher */
    int nsample = 40, lower = 0;
    double demin = INFINITY;
    for (int s = 0; s < nsample; s++) {
        double nr = 0.0;
        for (int j = 0; j < nq; j++) {
            v[j] = urand(-1, 1);
            nr += v[j] * v[j];
        }
        for (int j = 0; j < nq; j++) x[j] = y[j] + 1e-3 * v[j] / sqrt(nr);
        CHECK_LE(project(&q, x), 1e-13, "projection of a random state");
        double de = energy_at(&q, x, p) - e0, dist = 0.0;
        for (int j = 0; j < nq; j++) dist += (x[j] - y[j]) * (x[j] - y[j]);
        /* relative to the distance squared: the energy's curvature there */
        double c = de / fmax(dist, 1e-300);
        demin = fmin(demin, c);
        if (!(de > 0.0)) lower++;
    }
    print_message("# %d random closed states 1e-3 rad from q*: smallest (E - E*) / |x - q*|^2 = "
                  "%.4g J, %d below E*\n", nsample, demin, lower);
    assert_int_equal(lower, 0);
    /* the corrected verdict (by the local ascent or the SDP search: which
     * one finds the self-stress depends on rounding, the verdict not) */
    assert_true(st.res.certified == SF_CERT_ASCENT || st.res.certified == SF_CERT_SDP);
    assert_int_equal(st.res.stable, 1);
    assert_int_equal(st.res.morse, 0);
    assert_true(st.res.cert_eig > 0.0);
    assert_int_equal(st.res.neig, 0);
    sf_stab_free(&st);
    free(v); free(x); free(y0); free(y);
    cont_free(cs);
    sf_equil_free(&q);
    sf_scene_close(&sc);
}

/* Smallest eigenvalue of H0 + sum mu_k A_k (d x d), computed here. */
static double lmin_at(int d, int k, const double *H0, const double *A, const double *mu)
{
    double H[16], ev[4], W[64];
    int lw = 64, info;
    for (int i = 0; i < d * d; i++) {
        H[i] = H0[i];
        for (int q = 0; q < k; q++) H[i] += mu[q] * A[q * d * d + i];
    }
    dsyev_("N", "U", &d, H, &d, ev, W, &lw, &info);
    assert_int_equal(info, 0);
    return ev[0];
}

/* H0 = diag(-1, 1e-10), A_1 = diag(1, 0), A_2 = diag(0, 1): mu = (2, 1)
 * gives diag(1, 1 + 1e-10), positive definite.  The ascent aims at tau,
 * the smallest positive eigenvalue at mu = 0 (1e-10), which lies below the
 * margin (1e-8 of the largest, 1e-8): it lifts -1 to 1e-10 and stalls.
 * The SDP: max t with mu_1 - 1 >= t, mu_2 + 1e-10 >= t, |mu| <= R (R =
 * 1e6 emax / amax = 1e6), optimum on the circle at mu_1 - 1 = mu_2 + 1e-10:
 * t* = (-(a + b) + sqrt(2 R^2 - (a - b)^2)) / 2, a = 1, b = -1e-10. */
static void test_search_sdp_certifies(void **state)
{
    (void)state;
    double H0[4] = {-1.0, 0.0, 0.0, 1e-10};
    double A[8] = {1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
    double mu[2], mu0[2] = {2.0, 1.0};
    assert_true(lmin_at(2, 2, H0, A, mu0) > 0.99); /* the closed-form certificate */
    sf_cert_search o;
    assert_int_equal(sf_stab_cert_search(2, 2, H0, A, mu, &o), 0);
    double R = 1e6, a = 1.0, b = -1e-10, ts = (-(a + b) + sqrt(2.0 * R * R - (a - b) * (a - b))) / 2.0;
    print_message("# found %d (2: by the SDP), bound %g, mu (%.6g, %.6g), lmin %.9g, DSDP t %.9g, "
                  "upper bound %.9g, t* %.9g\n", o.found, o.bound, mu[0], mu[1], o.lmin, o.t_lo,
                  o.t_up, ts);
    assert_int_equal(o.found, SF_CERT_SDP); /* the ascent did not */
    assert_int_equal(o.sdp_ran, 1);
    CHECK_CLOSE(o.bound, R, 1e-12 * R, "the bound 1e6 emax / amax");
    double l = lmin_at(2, 2, H0, A, mu);
    CHECK_CLOSE(l, o.lmin, 1e-9 * fabs(o.lmin), "the certificate's eigenvalue, recomputed");
    assert_true(l > o.margin);
    assert_true(mu[0] * mu[0] + mu[1] * mu[1] <= R * R * (1.0 + 1e-9));
    CHECK_LE(o.lmin, ts * (1.0 + 1e-12), "no eigenvalue above t*");
    CHECK_LE(ts, o.t_up * (1.0 + 1e-12), "the upper bound from X is one");
    CHECK_CLOSE(o.lmin, ts, 1e-6 * ts, "DSDP's optimum, to its accuracy");
}

/* H0 = diag(1, -3), A_1 = diag(1, -1), A_2 = [0 1; 1 0]: the eigenvalues
 * of H0 + mu_1 A_1 + mu_2 A_2 are -1 +- sqrt((2 + mu_1)^2 + mu_2^2), the
 * smallest at most -1, equal at mu = (-2, 0) (inside the bound): t* = -1,
 * no self-stress makes it positive definite. */
static void test_search_none(void **state)
{
    (void)state;
    double H0[4] = {1.0, 0.0, 0.0, -3.0};
    double A[8] = {1.0, 0.0, 0.0, -1.0, 0.0, 1.0, 1.0, 0.0};
    double mu[2];
    sf_cert_search o;
    assert_int_equal(sf_stab_cert_search(2, 2, H0, A, mu, &o), 0);
    print_message("# found %d, bound %g, mu (%.9g, %.3g), lmin %.12g, DSDP t %.12g, upper "
                  "bound %.12g (t* = -1)\n", o.found, o.bound, mu[0], mu[1], o.lmin, o.t_lo, o.t_up);
    assert_int_equal(o.found, SF_CERT_NONE);
    assert_int_equal(o.sdp_ran, 1);
    CHECK_CLOSE(o.bound, 1e6 * 3.0 / sqrt(2.0), 1e-12 * 1e6 * 3.0 / sqrt(2.0), "the bound 1e6 emax / amax");
    CHECK_LE(o.lmin, -1.0 + 1e-12, "an eigenvalue at a self-stress: not above t*");
    CHECK_LE(-1.0 - 1e-12, o.t_up, "the upper bound from X: not below t*");
    CHECK_LE(o.t_up, -1.0 + 1e-6, "the upper bound, to DSDP's accuracy");
    CHECK_LE(-1.0 - 1e-6, o.lmin, "DSDP's self-stress, to its accuracy");
    CHECK_LE(fabs(mu[0] + 2.0) + fabs(mu[1]), 1e-3, "the optimum mu = (-2, 0)");
}

/* H0 = diag(1, -1), A_1 = diag(1, -1): the smallest eigenvalue is
 * min(1 + mu, -1 - mu), at most 0 (mu = -1): t* = 0, semidefinite at best,
 * never positive definite. */
static void test_search_semidefinite(void **state)
{
    (void)state;
    double H0[4] = {1.0, 0.0, 0.0, -1.0}, A[4] = {1.0, 0.0, 0.0, -1.0}, mu[1];
    sf_cert_search o;
    assert_int_equal(sf_stab_cert_search(2, 1, H0, A, mu, &o), 0);
    print_message("# found %d, mu %.9g, lmin %.3g, DSDP t %.3g, upper bound %.3g (t* = 0)\n",
                  o.found, mu[0], o.lmin, o.t_lo, o.t_up);
    assert_int_equal(o.found, SF_CERT_NONE);
    assert_int_equal(o.sdp_ran, 1);
    CHECK_LE(o.lmin, 1e-12, "an eigenvalue at a self-stress: not above t*");
    CHECK_LE(-1e-12, o.t_up, "the upper bound from X: not below t*");
    CHECK_LE(o.t_up, 1e-6, "the upper bound, to DSDP's accuracy");
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(tests_dir, sizeof tests_dir, "%s/tests/studies", src ? src : SF_SRCDIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_search_sdp_certifies),
        cmocka_unit_test(test_search_none),
        cmocka_unit_test(test_search_semidefinite),
        cmocka_unit_test(test_waterbomb_certificate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
