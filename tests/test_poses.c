/* test_poses.c - the face-pose formulation (MODEL.md 9, src/model/poses.c,
 * src/analysis/equilibrium/equilibrium_poses.c):
 * - rotation vectors: R = exp([phi]x) against sf_rotation, dR and d2R
 *   against central differences (series and closed-form ranges);
 * - every derivative of the pose problem against central differences at
 *   random states: the gradient of Pi, the CSC Jacobian
 *   [HL J^T; J -eps D] (fold rows, loads, gravity on faces and bands,
 *   supports, prescribed displacement) and dF/dp;
 * - the two formulations give the same equilibria: along paths of the fold
 *   formulation, the pose problem solved at the same p from a perturbed
 *   lifted state gives probes (from the poses themselves) and fold angles
 *   equal to 1e-9 relative;
 * - Jacobian nonzeros grow linearly with the folds (two Miura sizes). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_sparse.h>

#define SF_TEST_SEED 987654321u
#include "sf_test.h"

#include "cont.h"
#include "equilibrium.h"
#include "equilibrium_poses.h"
#include "flatstart.h"
#include "kinematics.h"
#include "poses.h"
#include "scene.h"
#include "shape.h"
#include "study.h"

static SUNContext sun_ctx;
static char tests_dir[1024];

/* check_fd (sf_test.h) with an absolute floor of 1e-12 for blocks that
 * are zero by structure. */
static void compare(const double *A, const double *F, size_t n, const char *what)
{
    check_fd(A, F, n, 1e-12, what);
}

/* ------------------------------------------------------------ rotations */

static void test_rodrigues(void **state)
{
    (void)state;
    const double radius[] = {1e-7, 0.3, 1.2, 1.99, 2.01, 2.9, 4.5};
    for (size_t c = 0; c < sizeof radius / sizeof *radius; c++) {
        double phi[3] = {urand(-1, 1), urand(-1, 1), urand(-1, 1)};
        double nphi = sqrt(phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]);
        for (int i = 0; i < 3; i++) phi[i] *= radius[c] / nphi;
        double R[9], dR[3][9], d2R[9][9], Rs[9];
        sf_rodrigues(phi, R, dR, d2R);
        double axis[3] = {phi[0] / radius[c], phi[1] / radius[c], phi[2] / radius[c]};
        sf_rotation(axis, radius[c], Rs);
        for (int i = 0; i < 9; i++)
            CHECK_CLOSE(R[i], Rs[i], 1e-15, "R at |phi| = %g entry %d", radius[c], i);
        double h = 1e-6, fd[3][9], an[3][9], fd2[3][9][3], an2[3][9][3];
        for (int a = 0; a < 3; a++) {
            double pp[3], pm[3], Rp[9], Rm[9], dRp[3][9], dRm[3][9];
            memcpy(pp, phi, sizeof pp);
            memcpy(pm, phi, sizeof pm);
            pp[a] += h;
            pm[a] -= h;
            sf_rodrigues(pp, Rp, dRp, NULL);
            sf_rodrigues(pm, Rm, dRm, NULL);
            for (int i = 0; i < 9; i++) {
                fd[a][i] = (Rp[i] - Rm[i]) / (2 * h);
                an[a][i] = dR[a][i];
                for (int b = 0; b < 3; b++) {
                    fd2[b][i][a] = (dRp[b][i] - dRm[b][i]) / (2 * h);
                    an2[b][i][a] = d2R[3 * a + b][i];
                }
            }
        }
        char what[80];
        snprintf(what, sizeof what, "dR at |phi| = %g", radius[c]);
        compare(&an[0][0], &fd[0][0], 27, what);
        snprintf(what, sizeof what, "d2R at |phi| = %g", radius[c]);
        compare(&an2[0][0][0], &fd2[0][0][0], 81, what);
        /* the rotation vector back from R (angles below pi) */
        if (radius[c] < 3.0) {
            double back[3];
            sf_rotation_log(R, back);
            for (int i = 0; i < 3; i++)
                CHECK_CLOSE(back[i], phi[i], 1e-9 * radius[c] + 1e-15, "log at %g", radius[c]);
        }
    }
}

/* ------------------------------------------------------------ derivatives */

typedef struct jac_case {
    const char *label, *study;
    int nset;
    const char **sets;
    int param, probe, comp;
    const char *group;
    double load, p;
} jac_case;

static double Pi_at(sf_equil *q, const double *y, double p)
{
    double Pi, rr, rt;
    sf_equil_report(q, y, p, &Pi, &rr, &rt);
    return Pi;
}

static void check_jacobian(const jac_case *c)
{
    sf_scene sc;
    open_scene(&sc, c->study, c->nset, c->sets);
    const sf_model *m = &sc.model;
    sf_error err;
    sf_error_clear(&err);
    int gi = c->group ? sf_study_group_index(&sc.study, c->group) : -1;
    sf_equil eq;
    assert_int_equal(sf_equil_init(&eq, m, c->param, gi, c->probe, c->comp, c->load, &err), SF_OK);
    if (sf_equil_use_poses(&eq, &err)) {
        print_error("%s: %s\n", c->label, err.msg);
        fail();
    }
    int n = eq.n, nx = eq.nq;
    assert_int_equal(nx, m->nq + 6 * (m->nfaces - 1));
    assert_int_equal(eq.nloop, 6 * m->nfolds);
    double *y = calloc(n, sizeof *y), *yy = calloc(n, sizeof *y), *F = calloc(n, sizeof *y);
    double *F1 = calloc(n, sizeof *y), *F2 = calloc(n, sizeof *y), *Fp = calloc(n, sizeof *y);
    double *Fpfd = calloc(n, sizeof *y), *A = calloc((size_t)n * n, sizeof *A);
    double *Afd = calloc((size_t)n * n, sizeof *A), *g = calloc(nx, sizeof *g);
    double *gfd = calloc(nx, sizeof *g);
    /* a random state: fold coordinates, poses about the lifted ones, and
     * multipliers of their natural size */
    random_state(m, y, 0.9, 0.3);
    assert_int_equal(sf_equil_poses_lift(&eq, y), SF_OK);
    for (int j = m->nq; j < nx; j++) y[j] += urand(-0.3, 0.3) / eq.yscale[j];
    for (int r = nx; r < n; r++) y[r] = urand(-1.0, 1.0) / eq.yscale[r];
    long nnz = sf_equil_poses_nnz(&eq);
    SUNMatrix Jy = SUNSparseMatrix(n, n, nnz, CSC_MAT, sun_ctx);
    assert_non_null(Jy);
    assert_int_equal(sf_equil_residual(y, c->p, F, &eq), 0);
    assert_int_equal(sf_equil_jacobian(y, c->p, Jy, Fp, &eq), 0);
    const sunindextype *cp = SUNSparseMatrix_IndexPointers(Jy), *ri = SUNSparseMatrix_IndexValues(Jy);
    const sunrealtype *v = SUNSparseMatrix_Data(Jy);
    for (int j = 0; j < n; j++)
        for (sunindextype k = cp[j]; k < cp[j + 1]; k++) A[(size_t)j * n + ri[k]] += v[k];
    /* the gradient rows at lambda = 0 are grad Pi */
    memcpy(yy, y, sizeof(double) * n);
    memset(yy + nx, 0, sizeof(double) * (n - nx));
    assert_int_equal(sf_equil_residual(yy, c->p, F1, &eq), 0);
    for (int j = 0; j < nx; j++) {
        double h = 1e-6 / eq.yscale[j], s = yy[j];
        yy[j] = s + h;
        double Pp = Pi_at(&eq, yy, c->p);
        yy[j] = s - h;
        double Pm = Pi_at(&eq, yy, c->p);
        yy[j] = s;
        gfd[j] = (Pp - Pm) / (2 * h) * eq.fscale[j];
        g[j] = F1[j] * eq.fscale[j];
    }
    char what[200];
    snprintf(what, sizeof what, "%s: grad Pi", c->label);
    compare(g, gfd, nx, what);
    /* Jacobian by columns, in the solver's scaling */
    for (int j = 0; j < n; j++) {
        double h = 1e-6 / eq.yscale[j];
        memcpy(yy, y, sizeof(double) * n);
        yy[j] = y[j] + h;
        assert_int_equal(sf_equil_residual(yy, c->p, F1, &eq), 0);
        yy[j] = y[j] - h;
        assert_int_equal(sf_equil_residual(yy, c->p, F2, &eq), 0);
        for (int i = 0; i < n; i++) {
            int reg = i == j && i >= nx;   /* -eps D: Jacobian only */
            Afd[(size_t)j * n + i] = (F1[i] - F2[i]) / (2 * h) * eq.fscale[i] / eq.yscale[j];
            A[(size_t)j * n + i] *= eq.fscale[i] / eq.yscale[j];
            if (reg) {
                CHECK_CLOSE(A[(size_t)j * n + i], -1e-10, 1e-22, "%s: regularisation %d", c->label, i);
                A[(size_t)j * n + i] = Afd[(size_t)j * n + i];
            }
        }
    }
    snprintf(what, sizeof what, "%s: Jacobian", c->label);
    compare(A, Afd, (size_t)n * n, what);
    double hp = 1e-4;   /* F is linear in p in every case here (within a stage) */
    assert_int_equal(sf_equil_residual(y, c->p + hp, F1, &eq), 0);
    assert_int_equal(sf_equil_residual(y, c->p - hp, F2, &eq), 0);
    for (int i = 0; i < n; i++) {
        Fpfd[i] = (F1[i] - F2[i]) / (2 * hp) * eq.fscale[i];
        Fp[i] *= eq.fscale[i];
    }
    snprintf(what, sizeof what, "%s: dF/dp", c->label);
    if (maxabs(Fpfd, n) > 0) compare(Fp, Fpfd, n, what);
    else assert_true(maxabs(Fp, n) == 0.0);
    SUNMatDestroy(Jy);
    sf_equil_free(&eq);
    free(y); free(yy); free(F); free(F1); free(F2); free(Fp); free(Fpfd); free(A); free(Afd);
    free(g); free(gfd);
    sf_scene_close(&sc);
}

static const char *wb2_exact[] = {"solver.constraints=\"exact\""};
static const char *wb2_k2g2[] = {"defaults.modes=2", "defaults.continuity=2",
                                 "solver.constraints=\"exact\""};
static const char *wb2_disp[] = {"defaults.modes=1", "solver.constraints=\"exact\"",
                                 "analysis.parameter=\"displacement\"",
                                 "analysis.probe=\"tip\"", "analysis.component=\"x\"",
                                 "supports=( { at = [0.157, 0.0675]; fix = [false, true, true]; "
                                 "value = [0.0, 0.002, 0.001]; } )"};
/* a load inside a fold band (strip3's first band) and all groups actuated */
static const char *s3_band[] = {"defaults.modes=2",
                                "loads=( { at = [0.0301, 0.02]; force = [0.1, 0.2, -0.3]; stage = 1; } )"};
static const char *s3_act[] = {
    "actuation=( { name = \"hinge\"; rest_angle = 0.8; }, { name = \"tipfold\"; rest_angle = -1.1; } )",
    "folds[f2].group=\"hinge\"", "folds[f3].group=\"tipfold\"", "folds[f1].rest_angle=0.3"};

static void test_pose_jacobian(void **state)
{
    (void)state;
    const jac_case cases[] = {
        {"waterbomb2 load stage 2", "waterbomb2", 1, wb2_exact, SF_PARAM_LOAD, 0, 0, NULL, 0, 1.4},
        {"waterbomb2 K=2 G2 gravity stage", "waterbomb2", 3, wb2_k2g2, SF_PARAM_LOAD, 0, 0, NULL,
         0, 0.6},
        {"waterbomb2 displacement ux + support", "waterbomb2", 6, wb2_disp, SF_PARAM_DISPLACEMENT,
         0, 0, NULL, 1.0, -0.003},
        {"strip3 K=2 load in a band", "strip3", 2, s3_band, SF_PARAM_LOAD, 0, 0, NULL, 0, 0.8},
        {"strip3 actuation of all groups", "strip3", 4, s3_act, SF_PARAM_ACTUATION, 0, 0, NULL, 0.5, 0.7},
        {"square4 exact", "square4", 0, NULL, SF_PARAM_LOAD, 0, 0, NULL, 0, 0.9},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) check_jacobian(&cases[i]);
}

/* ------------------------------------------------------------ agreement */

typedef struct agree_case {
    const char *study;
    int nset;
    const char **sets;
    int max_points;
} agree_case;

/* Probe positions from the poses alone (poses.c), not through the tree. */
static void probes_from_poses(const sf_equil *q, const sf_poses *P, const sf_mpoint *pr, int np,
                              const double *y, double *out, double *work)
{
    for (int i = 0; i < np; i++) sf_poses_mpoint(P, y, &pr[i], out + 3 * i, NULL, NULL, NULL, work);
    (void)q;
}

static void check_agree(const agree_case *c, const char *sdir)
{
    sf_scene sc;
    char path[1200];
    snprintf(path, sizeof path, "%s/%s.cfg", sdir, c->study);
    sf_error err;
    sf_error_clear(&err);
    if (sf_scene_open(&sc, path, c->nset, c->sets, &err)) {
        print_error("%s: %s\n", path, err.msg);
        fail();
    }
    const sf_model *m = &sc.model;
    const sf_study *s = &sc.study;
    int ptype, gi, pi, ci;
    double start, end, step, load;
    assert_int_equal(sf_equil_parse_param(s, &ptype, &gi, &pi, &ci, &err), SF_OK);
    assert_int_equal(sf_study_double(s, "analysis.start", 0.0, &start, &err), SF_OK);
    assert_int_equal(sf_study_double(s, "analysis.end", (double)s->nstages, &end, &err), SF_OK);
    assert_int_equal(sf_study_double(s, "analysis.step", 0.05, &step, &err), SF_OK);
    assert_int_equal(sf_study_double(s, "analysis.load", 0.0, &load, &err), SF_OK);
    sf_equil fq, pq;
    assert_int_equal(sf_equil_init(&fq, m, ptype, gi, pi, ci, load, &err), SF_OK);
    assert_int_equal(sf_equil_init(&pq, m, ptype, gi, pi, ci, load, &err), SF_OK);
    assert_int_equal(sf_equil_use_poses(&pq, &err), SF_OK);
    cont_solver *fs = NULL, *ps = NULL;
    assert_int_equal(sf_equil_create_solver(&fq, &fs), CONT_OK);
    assert_int_equal(sf_equil_create_solver(&pq, &ps), CONT_OK);
    cont_set_newton(fs, 1e-14, 20, 0);
    cont_set_newton(ps, 1e-14, 20, 0);
    cont_set_step(fs, step, 1e-6, 0.2);
    cont_set_prange(fs, fmin(start, end), fmax(start, end));
    cont_set_max_steps(fs, c->max_points);
    cont_set_store(fs, 1);
    int dir = end >= start ? 1 : -1;
    double *y0 = calloc(fq.n + 1, sizeof *y0);
    if (fq.nloop > 0) {
        double p1 = start + dir * fmin(step, 0.25 * fabs(end - start));
        if (sf_equil_start_flat(&fq, fs, start, p1, dir, 1e-13, y0, 1, NULL, &err)) {
            print_error("%s: fold start: %s\n", c->study, err.msg);
            fail();
        }
    } else {
        /* as src/cli/run_equilibrium.c: from the rest angles, else from the flat sheet */
        sf_equil_set_param(&fq, start);
        for (int i = 0; i < m->nfolds; i++) y0[m->qoff[i]] = fq.par.rest[i];
        if (cont_start(fs, y0, start, dir) != CONT_OK) {
            memset(y0, 0, sizeof(double) * fq.n);
            assert_int_equal(cont_start(fs, y0, start, dir), CONT_OK);
        }
    }
    cont_run(fs);
    long np = cont_num_points(fs);
    assert_true(np >= 3);
    int npr = s->nprobes;
    sf_mpoint *pr = calloc(npr + 1, sizeof *pr);
    for (int i = 0; i < npr; i++) assert_int_equal(sf_model_locate(m, s->probes[i].at, &pr[i], &err), SF_OK);
    double *yg = calloc(pq.n + 1, sizeof *yg);
    int loose = 0;
    double *yp = calloc(pq.n + 1, sizeof *yp), *xf = calloc(3 * npr + 3, sizeof *xf);
    double *xp = calloc(3 * npr + 3, sizeof *xp);
    sf_poses P;
    assert_int_equal(sf_poses_init(&P, m, &err), SF_OK);
    double *work = calloc(sf_poses_work_size(&P), sizeof *work);
    sf_kin k;
    assert_int_equal(sf_kin_alloc(m, &k), SF_OK);
    /* column scales: the largest value along the path */
    double *scale = calloc(3 * npr + m->nfolds + 1, sizeof *scale);
    for (long t = 0; t < np; t++) {
        const cont_point *pt = cont_point_at(fs, t);
        sf_kin_eval(m, pt->y, 0, &k);
        for (int i = 0; i < npr; i++) {
            sf_point_eval(m, &k, &pr[i], xf + 3 * i, NULL);
            for (int cc = 0; cc < 3; cc++) {
                double u = xf[3 * i + cc] - (cc < 2 ? pr[i].X[cc] : 0.0);
                scale[3 * i + cc] = fmax(scale[3 * i + cc], fabs(u));
            }
        }
        for (int f = 0; f < m->nfolds; f++)
            scale[3 * npr + f] = fmax(scale[3 * npr + f], fabs(pt->y[m->qoff[f]]));
    }
    double worst = 0.0;
    int solved = 0;
    for (long t = 1; t < np; t++) {
        const cont_point *pt = cont_point_at(fs, t);
        /* at a limit or branch point the problem at fixed p is singular */
        if (strcmp(pt->label, "LP") == 0 || strcmp(pt->label, "BP") == 0) continue;
        /* lift, perturb the fold coordinates and the poses, solve */
        memset(yp, 0, sizeof(double) * pq.n);
        memcpy(yp, pt->y, sizeof(double) * m->nq);
        assert_int_equal(sf_equil_poses_lift(&pq, yp), SF_OK);
        for (int j = 0; j < pq.nq; j++) yp[j] += urand(-1e-4, 1e-4) / pq.yscale[j];
        memcpy(yg, yp, sizeof(double) * pq.n);
        if (cont_solve_fixed(ps, yp, pt->p) != CONT_OK) {
            /* next to the flat state the loop rows are nearly redundant and
             * Newton (regularised Jacobian) converges only linearly: stop
             * at 1e-13 there, as the fold path itself does */
            memcpy(yp, yg, sizeof(double) * pq.n);
            cont_set_newton(ps, 1e-13, 20, 0);
            int ok = cont_solve_fixed(ps, yp, pt->p) == CONT_OK;
            cont_set_newton(ps, 1e-14, 20, 0);
            if (!ok) {
                print_error("%s: pose solve at p = %g: %s\n", c->study, pt->p, cont_errmsg(ps));
                fail();
            }
            loose++;
        }
        solved++;
        sf_kin_eval(m, pt->y, 0, &k);
        for (int i = 0; i < npr; i++) sf_point_eval(m, &k, &pr[i], xf + 3 * i, NULL);
        probes_from_poses(&pq, &P, pr, npr, yp, xp, work);
        for (int i = 0; i < 3 * npr; i++) {
            /* relative to the column's largest displacement (a column that
             * does not move: to 1e-3 of the sheet size) */
            double d = fabs(xp[i] - xf[i]) / fmax(scale[i], 1e-3 * sc.topo.size);
            worst = fmax(worst, d);
            CHECK_LE(d, 1e-9, "%s: probe %d component %d at p = %.10g: %.15g (poses) vs %.15g "
                     "(folds)", c->study, i / 3 + 1, i % 3, pt->p, xp[i], xf[i]);
        }
        for (int f = 0; f < m->nfolds; f++) {
            double a = yp[m->qoff[f]], b = pt->y[m->qoff[f]];
            double d = fabs(a - b) / fmax(scale[3 * npr + f], 1e-6);
            worst = fmax(worst, d);
            CHECK_LE(d, 1e-9, "%s: theta%d at p = %.10g: %.15g (poses) vs %.15g (folds)",
                     c->study, f + 1, pt->p, a, b);
        }
    }
    assert_true(solved >= 2);
    print_message("# %s: %d points (%d solved to 1e-13 only), %d folds, worst relative "
                  "difference %.2e\n", c->study, solved, loose, m->nfolds, worst);
    free(yg);
    free(scale); free(work); free(yp); free(xf); free(xp); free(pr); free(y0);
    sf_kin_free(&k);
    sf_poses_free(&P);
    cont_free(fs);
    cont_free(ps);
    sf_equil_free(&fq);
    sf_equil_free(&pq);
    sf_scene_close(&sc);
}


static void test_formulations_agree(void **state)
{
    (void)state;
    const agree_case cases[] = {
        {"strip3", 0, NULL, 20},
        {"fold1", 0, NULL, 20},
        {"snap1", 0, NULL, 20},
        {"fold1-buckle", 0, NULL, 20},
        {"hard-near-pi", 0, NULL, 20},
        {"hard-stiff-ratio", 0, NULL, 10},
        {"square4", 0, NULL, 12},
        {"square4-irregular", 0, NULL, 12},
        {"square4-corner", 0, NULL, 20},
        {"square4-narrow", 0, NULL, 12},
        {"square4-stiff", 0, NULL, 12},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) check_agree(&cases[i], studies_dir);
}

/* ------------------------------------------------------------ nonzeros */

/* Nonzeros of the KKT pattern of a study (with overrides); its fold
 * count, and whether gravity and point loads are in it. */
static long nnz_of(const char *name, int nset, const char **sets, int *nfolds, int *loaded)
{
    sf_scene sc;
    char path[1200];
    snprintf(path, sizeof path, "%s/%s.cfg", tests_dir, name);
    sf_error err;
    sf_error_clear(&err);
    if (sf_scene_open(&sc, path, nset, sets, &err)) {
        print_error("%s: %s\n", path, err.msg);
        fail();
    }
    sf_equil eq;
    assert_int_equal(sf_equil_init(&eq, &sc.model, SF_PARAM_LOAD, -1, 0, 2, 0.0, &err), SF_OK);
    assert_int_equal(sf_equil_use_poses(&eq, &err), SF_OK);
    long nnz = sf_equil_poses_nnz(&eq);
    *nfolds = sc.model.nfolds;
    *loaded = sc.study.gravity_on && sc.study.nloads > 0;
    sf_equil_free(&eq);
    sf_scene_close(&sc);
    return nnz;
}

static void test_nonzeros_linear(void **state)
{
    (void)state;
    int n2, n4, l2, l4, u2, u4;
    /* miura2 and miura4 carry gravity (faces and bands) and a point load:
     * their patterns count every effect */
    long z2 = nnz_of("miura2", 0, NULL, &n2, &l2), z4 = nnz_of("miura4", 0, NULL, &n4, &l4);
    assert_true(l2 && l4);
    print_message("# nonzeros: miura2 %d folds %ld, miura4 %d folds %ld (%.1f and %.1f per fold)\n",
                  n2, z2, n4, z4, (double)z2 / n2, (double)z4 / n4);
    assert_true(n4 > 3 * n2);
    /* linear growth: nonzeros per fold nearly constant (boundary effects
     * only), far from the quadratic growth of a dense pattern */
    double r2 = (double)z2 / n2, r4 = (double)z4 / n4;
    CHECK_LE(fabs(r4 - r2) / r2, 0.15, "nonzeros per fold %g vs %g", r2, r4);
    /* MODEL.md 9: a point load or a face's weight acts on its face's pose
     * alone, a band's weight on its right face's pose and its fold, blocks
     * the fold rows already hold: without gravity and loads the pattern
     * is the same, at both sizes */
    const char *bare[] = {"gravity.enabled=false", "loads=()"};
    long b2 = nnz_of("miura2", 2, bare, &n2, &u2), b4 = nnz_of("miura4", 2, bare, &n4, &u4);
    assert_false(u2 || u4);
    print_message("# nonzeros without gravity and loads: miura2 %ld, miura4 %ld\n", b2, b4);
    assert_int_equal(b2, z2);
    assert_int_equal(b4, z4);
}

/* The lift's analytic derivative along a fold motion (the seed of the
 * sparse start's rigid modes) against a central difference of the lift,
 * at the flat sheet and at a random folded state, with shape modes. */
static void test_lift_direction(void **state)
{
    (void)state;
    const char *k2[] = {"defaults.modes=2"};
    struct { const char *name; int nset; const char **sets; } cases[] = {
        {"square4", 0, NULL}, {"waterbomb2", 1, k2}, {"strip3", 1, k2}};
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        sf_scene sc;
        open_scene(&sc, cases[c].name, cases[c].nset, cases[c].sets);
        const sf_model *m = &sc.model;
        sf_error err;
        sf_error_clear(&err);
        sf_poses P;
        assert_int_equal(sf_poses_init(&P, m, &err), SF_OK);
        int nq = m->nq, nx = nq + 6 * (m->nfaces - 1);
        double *q = calloc(nx, sizeof *q), *dq = calloc(nx, sizeof *q), *dx = calloc(nx, sizeof *q);
        double *xp = calloc(nx, sizeof *q), *xm = calloc(nx, sizeof *q), *qh = calloc(nx, sizeof *q);
        for (int at = 0; at < 2; at++) {
            if (at) random_state(m, q, 0.4, 0.2);
            random_state(m, dq, 1.0, 0.5);
            assert_int_equal(sf_poses_from_folds_dir(&P, q, dq, dx), SF_OK);
            double h = 1e-6, err_max = 0.0, big = 0.0;
            for (int sg = -1; sg <= 1; sg += 2) {
                for (int j = 0; j < nq; j++) qh[j] = q[j] + sg * h * dq[j];
                assert_int_equal(sf_poses_from_folds(&P, qh, sg > 0 ? xp : xm), SF_OK);
            }
            for (int j = 0; j < nx; j++) {
                double fd = (xp[j] - xm[j]) / (2.0 * h);
                err_max = fmax(err_max, fabs(fd - dx[j]));
                big = fmax(big, fabs(dx[j]));
            }
            print_message("# %s %s: |d poses| %.3g, against the central difference %.2e\n",
                          cases[c].name, at ? "folded" : "flat", big, err_max);
            assert_true(big > 1e-3);
            CHECK_LE(err_max, 1e-7 * big, "%s: lift derivative off by %g", cases[c].name, err_max);
        }
        free(q); free(dq); free(dx); free(xp); free(xm); free(qh);
        sf_poses_free(&P);
        sf_scene_close(&sc);
    }
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : SF_SRCDIR);
    snprintf(tests_dir, sizeof tests_dir, "%s/tests/studies", src ? src : SF_SRCDIR);
    if (SUNContext_Create(NULL, &sun_ctx) != 0) return 1;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rodrigues),
        cmocka_unit_test(test_pose_jacobian),
        cmocka_unit_test(test_formulations_agree),
        cmocka_unit_test(test_nonzeros_linear),
        cmocka_unit_test(test_lift_direction),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    SUNContext_Free(&sun_ctx);
    return rc;
}
