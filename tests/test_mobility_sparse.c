/* test_mobility_sparse.c - the local loop rows of one vertex and the
 * sparse first-order mobility of a whole sheet (mobility.h):
 *  - sf_constraints_vertex against sf_constraints (the dense rows of all
 *    vertices) at random folded states of square4 and the 2x2 Miura:
 *    values, Jacobian and constraint Hessian to 1e-12;
 *  - sf_mobility_first_order (SuiteSparseQR rank of the sparse rows)
 *    against the count of an SVD computed here (LAPACK dgesvd of the
 *    dense, row-scaled Jacobian, cut 1e-8 times the largest singular
 *    value) on every study of studies/ and tests/studies/ with interior
 *    vertices, at the flat state and at a random folded state, and against
 *    sf_mobility_analyse's first-order count at the flat state where that
 *    runs its dense probe. */
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "kinematics.h"
#include "mobility.h"
#include "scene.h"
#include "check_test.h"
#include "sf_test.h"

extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, double *a,
                    const int *lda, double *s, double *u, const int *ldu, double *vt,
                    const int *ldvt, double *work, const int *lwork, int *info);

static char test_studies_dir[1024];

static void open_path(sf_scene *sc, const char *path)
{
    sf_error err;
    sf_error_clear(&err);
    if (sf_scene_open(sc, path, 0, NULL, &err)) {
        print_error("cannot open %s: %s\n", path, err.msg);
        fail();
    }
}

static void test_constraints_vertex(void **state)
{
    (void)state;
    const char *names[] = {"square4", "miura-2x2"};
    for (int c = 0; c < 2; c++) {
        sf_scene sc;
        open_scene(&sc, names[c], 0, NULL);
        const sf_model *m = &sc.model;
        int nq = m->nq, ncon = m->ncon;
        double *q = calloc((size_t)nq, sizeof(double));
        double *g = calloc((size_t)ncon, sizeof(double));
        double *J = calloc((size_t)ncon * nq, sizeof(double));
        double *lam = calloc((size_t)ncon, sizeof(double));
        double *H = calloc((size_t)nq * nq, sizeof(double));
        assert_true(q && g && J && lam && H);
        sf_kin k;
        assert_int_equal(sf_kin_alloc(m, &k), SF_OK);
        random_state(m, q, 0.4, 0.05);
        sf_kin_eval(m, q, 2, &k);
        sf_constraints(m, &k, g, J, NULL, NULL, 0);
        double worst = 0.0;
        for (int v = 0; v < sc.topo.nivertices; v++) {
            double gl[6], Jl[6 * 64], Hl[64 * 64] = {0}, lv[6];
            int cols[64], nl = 0;
            for (int e = 0; e < 6; e++) lv[e] = urand(-1.0, 1.0);
            assert_int_equal(sf_constraints_vertex(m, &k, v, gl, cols, &nl, Jl, lv, Hl), SF_OK);
            /* the dense Hessian of this vertex's rows alone */
            memset(lam, 0, sizeof(double) * (size_t)ncon);
            memset(H, 0, sizeof(double) * (size_t)nq * nq);
            for (int e = 0; e < 6; e++) lam[6 * v + e] = lv[e];
            sf_constraints(m, &k, NULL, NULL, lam, H, nq);
            for (int e = 0; e < 6; e++) {
                worst = fmax(worst, fabs(gl[e] - g[6 * v + e]));
                double rowsum = 0.0; /* Jacobian entries outside cols must be zero */
                for (int j = 0; j < nq; j++) rowsum += fabs(J[(size_t)(6 * v + e) * nq + j]);
                for (int a = 0; a < nl; a++) {
                    double d = J[(size_t)(6 * v + e) * nq + cols[a]];
                    worst = fmax(worst, fabs(Jl[e * nl + a] - d));
                    rowsum -= fabs(d);
                }
                worst = fmax(worst, fabs(rowsum));
            }
            for (int a = 0; a < nl; a++)
                for (int b = 0; b < nl; b++)
                    worst = fmax(worst, fabs(Hl[a * nl + b] - H[(size_t)cols[a] * nq + cols[b]]));
        }
        print_message("# %s: %d vertices, largest difference local - dense %.2g\n", names[c],
                      sc.topo.nivertices, worst);
        CHECK_LE(worst, 1e-12, "%s: local rows against sf_constraints", names[c]);
        sf_kin_free(&k);
        free(q);
        free(g);
        free(J);
        free(lam);
        free(H);
        sf_scene_close(&sc);
    }
}

/* nq - rank of the row-scaled dense Jacobian at q, by SVD. */
static int dense_first_order(const sf_model *m, const double *q)
{
    int nq = m->nq, nc = m->ncon, info, lw = -1, one = 1;
    double lref = 0.0;
    for (int i = 0; i < m->nfolds; i++) lref += m->study->folds[i].width / m->nfolds;
    sf_kin k;
    assert_int_equal(sf_kin_alloc(m, &k), SF_OK);
    double *J = calloc((size_t)nc * nq, sizeof(double));
    double *A = calloc((size_t)nc * nq, sizeof(double));
    double *S = calloc((size_t)(nc + nq), sizeof(double));
    assert_true(J && A && S);
    sf_kin_eval(m, q, 1, &k);
    sf_constraints(m, &k, NULL, J, NULL, NULL, 0);
    for (int r = 0; r < nc; r++)
        for (int j = 0; j < nq; j++)
            A[(size_t)j * nc + r] = (r % 6 < 3 ? 1.0 : 1.0 / lref) * J[(size_t)r * nq + j];
    double wq, du;
    dgesvd_("N", "N", &nc, &nq, A, &nc, S, &du, &one, &du, &one, &wq, &lw, &info);
    lw = (int)wq + 1;
    double *w = malloc(sizeof(double) * (size_t)lw);
    assert_non_null(w);
    dgesvd_("N", "N", &nc, &nq, A, &nc, S, &du, &one, &du, &one, w, &lw, &info);
    assert_int_equal(info, 0);
    int kmax = nc < nq ? nc : nq, rank = 0;
    for (int i = 0; i < kmax; i++) rank += S[i] > fmax(1e-8 * S[0], 1e-12);
    free(w);
    free(J);
    free(A);
    free(S);
    sf_kin_free(&k);
    return nq - rank;
}

static void check_dir(const char *dir, int *nstudies)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *de;
    while ((de = readdir(d))) {
        size_t len = strlen(de->d_name);
        if (len < 5 || strcmp(de->d_name + len - 4, ".cfg") != 0) continue;
        char path[2200];
        snprintf(path, sizeof path, "%s/%s", dir, de->d_name);
        sf_scene sc;
        open_path(&sc, path);
        const sf_model *m = &sc.model;
        if (m->ncon == 0) {
            sf_scene_close(&sc);
            continue;
        }
        double *q = calloc((size_t)m->nq, sizeof(double));
        assert_non_null(q);
        sf_error err;
        sf_error_clear(&err);
        for (int folded = 0; folded < 2; folded++) {
            if (folded) random_state(m, q, 0.5, 0.05);
            int sparse = -1, dense = dense_first_order(m, q);
            CHECK_OK(sf_mobility_first_order(m, q, &sparse, &err), err);
            print_message("# %s %s: %d coordinates, %d rows: first order %d (sparse) %d (SVD)\n",
                          de->d_name, folded ? "folded" : "flat", m->nq, m->ncon, sparse, dense);
            assert_int_equal(sparse, dense);
        }
        if (m->nq <= SF_MOBILITY_DENSE_MAX) {
            sf_mobility mb;
            CHECK_OK(sf_mobility_analyse(m, NULL, &mb, &err), err);
            int sparse = -1;
            CHECK_OK(sf_mobility_first_order(m, NULL, &sparse, &err), err);
            assert_int_equal(mb.probed, 1);
            assert_int_equal(mb.first_order, sparse);
            sf_mobility_free(&mb);
        }
        (*nstudies)++;
        free(q);
        sf_scene_close(&sc);
    }
    closedir(d);
}

static void test_first_order_studies(void **state)
{
    (void)state;
    int n = 0;
    check_dir(studies_dir, &n);
    check_dir(test_studies_dir, &n);
    print_message("# %d studies with interior vertices\n", n);
    assert_true(n >= 10);
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : SF_SRCDIR);
    snprintf(test_studies_dir, sizeof test_studies_dir, "%s/tests/studies", src ? src : SF_SRCDIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_constraints_vertex),
        cmocka_unit_test(test_first_order_studies),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
