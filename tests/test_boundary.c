/* test_boundary.c - the extended systems of boundary.h: their Jacobian
 * (analytic rows of F, differences of the analytic Jacobian for the test
 * functions and for d/dq) against central differences of their residual,
 * off the curve, for an LP system (snap1-boundary) and a BP system
 * (fold1-buckle-boundary); and the family over a vector component. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "boundary.h"
#include "sf_test.h"

static void check_jacobian(const char *study, const char *second, int kind, const double *y,
                           double p, double mu, double s)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s.cfg", studies_dir, study);
    sf_family f;
    sf_bnd B;
    sf_error err;
    sf_error_clear(&err);
    if (sf_family_init(&f, path, 0, NULL, second, &err) ||
        sf_bnd_init(&B, &f, kind, y, p, f.q0, &err)) {
        print_error("%s: %s\n", study, err.msg);
        fail();
    }
    int N = B.N, n = B.n;
    double *Y = calloc((size_t)N, sizeof(double)), *G1 = calloc((size_t)N, sizeof(double)),
           *G2 = calloc((size_t)N, sizeof(double)), *Gs = calloc((size_t)N, sizeof(double));
    assert_non_null(Y);
    assert_non_null(G1);
    assert_non_null(G2);
    assert_non_null(Gs);
    memcpy(Y, y, sizeof(double) * (size_t)n);
    Y[n] = p;
    if (kind == SF_BND_BP) Y[n + 1] = mu;
    SUNMatrix J = SUNDenseMatrix(N, N, B.ctx);
    assert_non_null(J);
    assert_int_equal(sf_bnd_jacobian(Y, s, J, Gs, &B), 0);
    const double *Jd = SUNDenseMatrix_Data(J);
    double scale = 0.0;
    for (int i = 0; i < N * N; i++) scale = fmax(scale, fabs(Jd[i]));
    for (int i = 0; i < N; i++) scale = fmax(scale, fabs(Gs[i]));
    for (int j = 0; j <= N; j++) {
        double h = 1e-6, keep = j < N ? Y[j] : s;
        if (j < N) Y[j] = keep + h;
        assert_int_equal(sf_bnd_residual(Y, j < N ? s : s + h, G1, &B), 0);
        if (j < N) Y[j] = keep - h;
        assert_int_equal(sf_bnd_residual(Y, j < N ? s : s - h, G2, &B), 0);
        if (j < N) Y[j] = keep;
        for (int i = 0; i < N; i++) {
            double fd = (G1[i] - G2[i]) / (2 * h), an = j < N ? Jd[i + (size_t)j * N] : Gs[i];
            CHECK_CLOSE(an, fd, 1e-6 * scale, "%s: d G%d / d %s%d", study, i,
                        j < N ? "Y" : "s", j < N ? j : 0);
        }
    }
    SUNMatDestroy(J);
    free(Y);
    free(G1);
    free(G2);
    free(Gs);
    sf_bnd_free(&B);
    sf_family_free(&f);
}

/* LP system of snap1 over E, at a folded state off the curve */
static void test_lp_jacobian(void **state)
{
    (void)state;
    double y[1] = {-0.7};
    check_jacobian("snap1-boundary", "materials.fold.E", SF_BND_LP, y, 0.2, 0.0, 0.05);
}

/* BP system of fold1-buckle over the width, off the flat state and mu != 0 */
static void test_bp_jacobian(void **state)
{
    (void)state;
    double y[1] = {0.3};
    check_jacobian("fold1-buckle-boundary", "defaults.width", SF_BND_BP, y, 0.5, 1e-3, -0.1);
}

/* The family over a load component (one element of a vector key): the
 * load term of the residual scales with it; then the BP system over it */
static void test_bp_jacobian_vector_key(void **state)
{
    (void)state;
    char path[1200];
    snprintf(path, sizeof path, "%s/fold1-buckle-boundary.cfg", studies_dir);
    sf_family f;
    sf_error err;
    sf_error_clear(&err);
    if (sf_family_init(&f, path, 0, NULL, "loads[0].force[0]", &err)) {
        print_error("%s\n", err.msg);
        fail();
    }
    CHECK_CLOSE(f.q0, -1.5, 0.0, "loads[0].force[0] of the study");
    sf_equil *eq;
    assert_int_equal(sf_family_get(&f, -3.0, &eq, &err), SF_OK);
    /* the residual at twice the force: the load term doubles */
    double y[1] = {0.4}, F1[1], F2[1];
    assert_int_equal(sf_equil_residual(y, 1.0, F2, eq), 0);
    assert_int_equal(sf_family_get(&f, -1.5, &eq, &err), SF_OK);
    assert_int_equal(sf_equil_residual(y, 1.0, F1, eq), 0);
    double F0[1];
    assert_int_equal(sf_equil_residual(y, 0.0, F0, eq), 0);   /* bending alone */
    CHECK_CLOSE(F2[0] - F0[0], 2.0 * (F1[0] - F0[0]), 1e-12 * fabs(F1[0]), "load term at -3 N");
    sf_family_free(&f);
    check_jacobian("fold1-buckle-boundary", "loads[0].force[0]", SF_BND_BP, y, 0.5, 1e-3, 0.2);
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : SF_SRCDIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lp_jacobian),
        cmocka_unit_test(test_bp_jacobian),
        cmocka_unit_test(test_bp_jacobian_vector_key),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
