/* test_fold_wrench.c - the wrench a fold exerts on its faces in the pose
 * formulation (sf_peq_fold_wrench, equilibrium_poses.h), against statics:
 * - fold1 (one fold, the left face clamped, 4 N tip load on the right
 *   face, no gravity): along the load path the fold passes the whole load
 *   to the clamped face, F = (0, 0, -4 p) N, with the moment about the
 *   origin r x F of the load at its current position r;
 * - the 2x2 waterbomb tessellation driven on both groups (exact closure,
 *   no loads, no gravity; statically indeterminate): every free face is
 *   in equilibrium under the wrenches of its folds (left face: W, right
 *   face: -W), forces and moments about the origin, although the folds
 *   carry forces far from zero. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sf_test.h"

#include "check_test.h"
#include "cont.h"
#include "equilibrium.h"
#include "equilibrium_poses.h"
#include "kinematics.h"
#include "scene.h"
#include "study.h"

static char studies_dir[1024], tests_dir[1024];

static void open_poses(sf_scene *sc, const char *path, int nset, const char **sets, sf_equil *q)
{
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_scene_open(sc, path, nset, sets, &err), err);
    int ptype, gi, pi, ci;
    CHECK_OK(sf_equil_parse_param(&sc->study, &ptype, &gi, &pi, &ci, &err), err);
    CHECK_OK(sf_equil_init(q, &sc->model, ptype, gi, pi, ci, 0.0, &err), err);
    CHECK_OK(sf_equil_use_poses(q, &err), err);
}

static void test_fold1_clamp(void **state)
{
    (void)state;
    char path[1200];
    snprintf(path, sizeof path, "%s/fold1.cfg", studies_dir);
    sf_scene sc;
    sf_equil q;
    open_poses(&sc, path, 0, NULL, &q);
    const sf_model *m = &sc.model;
    assert_int_equal(m->nfolds, 1);
    cont_solver *cs = NULL;
    assert_int_equal(sf_equil_create_solver(&q, &cs), CONT_OK);
    cont_set_newton(cs, 1e-12, 20, 0);
    cont_set_step(cs, 0.0625, 1e-6, 0.2);
    cont_set_prange(cs, 0.0, 1.0);
    cont_set_max_steps(cs, 200);
    cont_set_store(cs, 1);
    double *y = calloc((size_t)q.n + 1, sizeof(double));
    assert_int_equal(sf_equil_poses_lift(&q, y), SF_OK);
    assert_int_equal(cont_start(cs, y, 0.0, 1), CONT_OK);
    cont_run(cs);
    long np = cont_num_points(cs);
    assert_true(np >= 5);
    /* the load of the study (studies/fold1.cfg) */
    const double Xload[2] = {0.058, 0.015}, P = -4.0;
    sf_mpoint lp;
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_model_locate(m, Xload, &lp, &err), err);
    sf_kin k;
    assert_int_equal(sf_kin_alloc(m, &k), SF_OK);
    int left = m->topo->folds[0].left;
    assert_int_equal(left, m->topo->root);
    double worst = 0.0, uzmax = 0.0;
    for (long t = 1; t < np; t++) {
        const cont_point *pt = cont_point_at(cs, t);
        double F[3], M[3], r[3];
        assert_int_equal(sf_peq_fold_wrench(&q, pt->y, 0, F, M), SF_OK);
        sf_kin_eval(m, pt->y, 0, &k);
        sf_point_eval(m, &k, &lp, r, NULL);
        uzmax = fmax(uzmax, fabs(r[2]));
        double Fz = P * pt->p;
        double Mw[3] = {r[1] * Fz, -r[0] * Fz, 0.0};
        double fs = fabs(Fz) + 1e-300, ms = fabs(Fz) * 0.06 + 1e-300;
        double e = fmax(fmax(fabs(F[0]), fabs(F[1])), fabs(F[2] - Fz)) / fs;
        for (int i = 0; i < 3; i++) e = fmax(e, fabs(M[i] - Mw[i]) / ms);
        worst = fmax(worst, e);
        CHECK_LE(e, 1e-8, "fold1 at p = %g: F (%g, %g, %g) M (%g, %g, %g) against F (0, 0, %g) "
                 "M (%g, %g, %g)", pt->p, F[0], F[1], F[2], M[0], M[1], M[2], Fz, Mw[0], Mw[1],
                 Mw[2]);
    }
    print_message("# fold1 in poses, %ld points to p = 1 (load point down %.4g m): the fold's "
                  "wrench on the clamped face equals the tip load and its moment to %.2g\n",
                  np, uzmax, worst);
    assert_true(uzmax > 0.01); /* a large deflection: the moment arm moved */
    sf_kin_free(&k);
    free(y);
    cont_free(cs);
    sf_equil_free(&q);
    sf_scene_close(&sc);
}

static void test_waterbomb_faces(void **state)
{
    (void)state;
    char path[1200];
    snprintf(path, sizeof path, "%s/waterbomb-2x2-all.cfg", tests_dir);
    const char *sets[] = {"solver.tolerance=1e-11", "solver.formulation=\"poses\""};
    sf_scene sc;
    sf_equil q;
    open_poses(&sc, path, 2, sets, &q);
    const sf_model *m = &sc.model;
    cont_solver *cs = NULL;
    assert_int_equal(sf_equil_create_solver(&q, &cs), CONT_OK);
    cont_set_newton(cs, 1e-11, 20, 0);
    cont_set_step(cs, 0.05, 1e-6, 0.1);
    cont_set_prange(cs, 0.0, 0.3);
    cont_set_max_steps(cs, 40);
    cont_set_store(cs, 1);
    double *y = calloc((size_t)q.n + 1, sizeof(double));
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_equil_poses_start_flat(&q, cs, 0.0, 0.05, 1, 1e-11, y, &err), err);
    cont_run(cs);
    long np = cont_num_points(cs);
    assert_true(np >= 3);
    const cont_point *pt = cont_point_at(cs, np - 1);
    int nf = m->topo->nfaces;
    double *S = calloc((size_t)6 * nf, sizeof(double)), fmaxv = 0.0, mmaxv = 0.0;
    for (int i = 0; i < m->nfolds; i++) {
        double F[3], M[3];
        assert_int_equal(sf_peq_fold_wrench(&q, pt->y, i, F, M), SF_OK);
        int l = m->topo->folds[i].left, r = m->topo->folds[i].right;
        for (int c = 0; c < 3; c++) {
            S[6 * l + c] += F[c];
            S[6 * l + 3 + c] += M[c];
            S[6 * r + c] -= F[c];
            S[6 * r + 3 + c] -= M[c];
            fmaxv = fmax(fmaxv, fabs(F[c]));
            mmaxv = fmax(mmaxv, fabs(M[c]));
        }
    }
    double worst = 0.0;
    for (int f = 0; f < nf; f++) {
        if (f == m->topo->root) continue;
        for (int c = 0; c < 6; c++) {
            double e = fabs(S[6 * f + c]) / (c < 3 ? fmaxv : mmaxv);
            worst = fmax(worst, e);
            CHECK_LE(e, 1e-8, "face %d, component %d: sum %g (largest fold value %g)", f, c,
                     S[6 * f + c], c < 3 ? fmaxv : mmaxv);
        }
    }
    print_message("# waterbomb 2x2 in poses at p = %g: %d free faces in equilibrium to %.2g of "
                  "the largest fold force %.3g N and moment %.3g N m\n", pt->p, nf - 1, worst,
                  fmaxv, mmaxv);
    assert_true(fmaxv > 0.0 && mmaxv > 0.0);
    free(S);
    free(y);
    cont_free(cs);
    sf_equil_free(&q);
    sf_scene_close(&sc);
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : SF_SRCDIR);
    snprintf(tests_dir, sizeof tests_dir, "%s/tests/studies", src ? src : SF_SRCDIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fold1_clamp),
        cmocka_unit_test(test_waterbomb_faces),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
