/* test_check_cost.c - the work of `smoothfold check`'s mobility analysis
 * grows linearly with the folds (docs/reference/output-files.md, "smoothfold check"):
 *  - sf_kin_eval_folds gives the listed folds the same folding maps and
 *    derivatives as sf_kin_eval (bitwise), leaves every other fold as it
 *    was, and a vertex's loop rows from it are those of the whole sheet's
 *    kinematics (bitwise), on the 2x2 Miura sheet at random states;
 *  - sf_mobility_analyse evaluates about as many folding maps per
 *    interior vertex on a Miura sheet of 6 x 6 cells as on one of 3 x 3
 *    (121 against 25 vertices, 264 against 60 folds): at most 10 % more,
 *    so the work grows linearly with the vertices and folds.  When each
 *    vertex's analysis evaluated the maps of the whole sheet (main at
 *    ab15385) the count per vertex grew with the folds (4.4 times here);
 *    each vertex alone keeps its 2 degrees of freedom (5 at first order)
 *    at both sizes. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "kinematics.h"
#include "mobility.h"
#include "scene.h"
#include "check_test.h"
#include "sf_test.h"

static char src_dir[1024];

/* Bitwise equality of n doubles. */
static int same(const double *a, const double *b, size_t n)
{
    return memcmp(a, b, sizeof(double) * n) == 0;
}

static void test_kin_eval_folds(void **state)
{
    (void)state;
    sf_scene sc;
    open_scene(&sc, "miura-2x2", 0, NULL);
    const sf_model *m = &sc.model;
    size_t mq = (size_t)m->maxqn + 1, x2 = mq * mq * 12;
    double *q = calloc((size_t)m->nq, sizeof(double)), *q2 = calloc((size_t)m->nq, sizeof(double));
    assert_true(q && q2);
    sf_kin full, part, before;
    assert_int_equal(sf_kin_alloc(m, &full), SF_OK);
    assert_int_equal(sf_kin_alloc(m, &part), SF_OK);
    assert_int_equal(sf_kin_alloc(m, &before), SF_OK);
    for (int v = 0; v < sc.topo.nivertices; v++) {
        random_state(m, q, 0.4, 0.05);
        random_state(m, q2, 0.4, 0.05);
        sf_kin_eval(m, q, 2, &full);
        /* part holds another state; then only the vertex's folds move to q */
        sf_kin_eval(m, q2, 2, &part);
        sf_kin_eval(m, q2, 2, &before);
        const sf_ivertex *iv = &sc.topo.ivertices[v];
        long n0 = part.fold_evals;
        sf_kin_eval_folds(m, q, 2, iv->degree, iv->folds, &part);
        assert_int_equal(part.fold_evals - n0, iv->degree);
        for (int i = 0; i < m->nfolds; i++) {
            int listed = 0;
            for (int a = 0; a < iv->degree; a++) listed |= iv->folds[a] == i;
            const sf_kin *want = listed ? &full : &before;
            size_t o = (size_t)m->qoff[i];
            if (!same(part.T + 12 * i, want->T + 12 * i, 12) ||
                !same(part.chord + 2 * i, want->chord + 2 * i, 2) ||
                !same(part.xi + 6 * o, want->xi + 6 * o, 6 * (size_t)m->qn[i]) ||
                !same(part.xi2 + x2 * i, want->xi2 + x2 * i, x2) ||
                !same(part.q + o, want->q + o, (size_t)m->qn[i])) {
                print_error("vertex %d, fold %d (%s): data differ from sf_kin_eval\n", v, i,
                            listed ? "listed" : "not listed, must be untouched");
                fail();
            }
        }
        double g1[6], g2[6], J1[6 * 64], J2[6 * 64], H1[64 * 64] = {0}, H2[64 * 64] = {0};
        double lam[6] = {0.3, -0.7, 0.2, 1.1, -0.4, 0.9};
        int c1[64], c2[64], n1 = 0, n2 = 0;
        assert_int_equal(sf_constraints_vertex(m, &full, v, g1, c1, &n1, J1, lam, H1), SF_OK);
        assert_int_equal(sf_constraints_vertex(m, &part, v, g2, c2, &n2, J2, lam, H2), SF_OK);
        assert_int_equal(n1, n2);
        assert_true(memcmp(c1, c2, sizeof(int) * (size_t)n1) == 0);
        assert_true(same(g1, g2, 6) && same(J1, J2, 6 * (size_t)n1) &&
                    same(H1, H2, (size_t)n1 * n1));
    }
    sf_kin_free(&full);
    sf_kin_free(&part);
    sf_kin_free(&before);
    free(q);
    free(q2);
    sf_scene_close(&sc);
}

/* Folding maps evaluated per interior vertex by the mobility analysis of
 * the flat Miura sheet of m x m cells (bench/miura-study.sh, K = 1). */
static double evals_per_vertex(int m, int *nfolds)
{
    char path[256], cmd[1600];
    snprintf(path, sizeof path, "/tmp/test_check_cost_%d_%d.cfg", (int)getpid(), m);
    snprintf(cmd, sizeof cmd, "sh '%s/bench/miura-study.sh' %d actuation 1 > '%s'", src_dir, m,
             path);
    assert_int_equal(system(cmd), 0);
    sf_scene sc;
    sf_error err;
    sf_error_clear(&err);
    if (sf_scene_open(&sc, path, 0, NULL, &err)) {
        print_error("%s: %s\n", path, err.msg);
        fail();
    }
    remove(path);
    sf_mobility mb;
    CHECK_OK(sf_mobility_analyse(&sc.model, NULL, &mb, &err), err);
    assert_int_equal(mb.probed, 0);   /* above SF_MOBILITY_DENSE_MAX coordinates */
    for (int v = 0; v < mb.nvertices; v++) {
        if (mb.v[v].dof != 2 || mb.v[v].first_order != 5) {
            print_error("%dx%d: vertex %d alone: %d dof (%d at first order), expected 2 (5)\n", m,
                        m, v, mb.v[v].dof, mb.v[v].first_order);
            fail();
        }
    }
    *nfolds = sc.model.nfolds;
    double per = (double)mb.fold_evals / mb.nvertices;
    sf_mobility_free(&mb);
    sf_scene_close(&sc);
    return per;
}

static void test_mobility_linear(void **state)
{
    (void)state;
    int f3 = 0, f6 = 0;
    double e3 = evals_per_vertex(3, &f3), e6 = evals_per_vertex(6, &f6);
    print_message("# folding maps evaluated per interior vertex: %.1f at 3x3 (%d folds), %.1f at "
                  "6x6 (%d folds)\n", e3, f3, e6, f6);
    assert_true(e3 > 0);
    CHECK_LE(e6, 1.1 * e3, "folding maps evaluated per interior vertex, 6x6 Miura against 1.1 x "
             "3x3");
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(src_dir, sizeof src_dir, "%s", src ? src : SF_SRCDIR);
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src_dir);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kin_eval_folds),
        cmocka_unit_test(test_mobility_linear),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
