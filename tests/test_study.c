/* test_study.c - the study reader (src/pattern/study*.c): the paper's studies
 * load with the right contents, the writer round trip, the accessors, and
 * every broken study in tests/bad/ fails as expected (--set overrides:
 * test_study_set.c).
 *
 * Broken studies: every tests/bad/study_NAME.cfg has a tests/bad/study_NAME.expect
 * of two lines:
 *     line 1: the line number the error must name (0: the message names the
 *             file only, "<path>: ...", e.g. for a missing top-level key)
 *     line 2: a substring of the message after "<path>:<line>: "
 * Loading must fail with SF_EINPUT and a message that starts with
 * "<path>:<line>: " (or "<path>: " for line 0) and contains line 2.
 *
 * Files are found through $SF_SRCDIR (set by `make check`), else the source
 * directory compiled in.  Temporary files go to $SF_BUILDDIR or /tmp.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <glob.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "study.h"
#include "study_test.h"

/* ---------------------------------------------------------------------- */

/* Every study in studies/ loads. */
static void test_all_studies_load(void **state)
{
    (void)state;
    char pat[2048];
    glob_t g;
    src_path(pat, sizeof pat, "studies/*.cfg");
    assert_int_equal(glob(pat, 0, NULL, &g), 0);
    assert_true(g.gl_pathc >= 8);
    for (size_t i = 0; i < g.gl_pathc; i++) {
        sf_study s;
        sf_error e;
        sf_error_clear(&e);
        int rc = sf_study_load(g.gl_pathv[i], 0, NULL, &s, &e);
        if (rc) print_error("%s: %s\n", g.gl_pathv[i], e.msg);
        assert_int_equal(rc, SF_OK);
        /* common to every study */
        int m = sf_study_material_index(&s, "fold");
        assert_true(m >= 0);
        CHECK_EQ_D(s.materials[m].nu, 0.45, "fold nu");
        CHECK_EQ_D(s.materials[m].thickness, 1.8e-3, "fold thickness");
        CHECK_EQ_D(s.materials[m].density, 1200.0, "fold density");
        assert_true(s.face_material >= 0);
        CHECK_EQ_D(s.materials[s.face_material].thickness, 2.0e-3, "face thickness");
        CHECK_EQ_D(s.materials[s.face_material].density, 1040.0, "face density");
        assert_true(strcmp(s.analysis_type, "equilibrium") == 0 ||
                    strcmp(s.analysis_type, "dynamics") == 0 ||
                    strcmp(s.analysis_type, "boundary") == 0);
        const char *param;
        double end;
        sf_error_clear(&e);
        CHECK_OK(sf_study_string(&s, "analysis.parameter", "", &param, &e), e);
        CHECK_OK(sf_study_double(&s, "analysis.end", -1, &end, &e), e);
        /* the paper's cases ramp every load stage; the studies beyond them
         * (buckling, snap-through) choose their own range */
        if (strcmp(param, "load") == 0 && strstr(g.gl_pathv[i], "buckle") == NULL)
            CHECK_EQ_D(end, s.nstages, "analysis.end = number of stages");
        assert_true(s.nprobes >= 1);
        /* the common fold material everywhere, except in the solver's hard
         * cases (hard-*.cfg), which vary it on purpose */
        if (strstr(g.gl_pathv[i], "/hard-") == NULL)
            for (int f = 0; f < s.nfolds; f++)   /* facet hinges have their own (bending faces) */
                assert_true(s.folds[f].facet || s.folds[f].material == m);
        sf_study_free(&s);
    }
    globfree(&g);
}

static void test_strip3(void **state)
{
    (void)state;
    sf_study s;
    sf_error e;
    CHECK_OK(load("studies/strip3.cfg", 0, NULL, &s, &e), e);
    assert_string_equal(s.name, "strip3");
    CHECK_EQ_I(s.nvertices, 10, "vertices");
    CHECK_EQ_I(s.nfolds, 3, "folds");
    CHECK_EQ_I(s.nloads, 1, "loads");
    CHECK_EQ_I(s.nprobes, 1, "probes");
    CHECK_EQ_I(s.noutline, 4, "outline");
    CHECK_EQ_I(s.nstages, 1, "stages");
    assert_false(s.gravity_on);
    for (int i = 0; i < 3; i++) {
        CHECK_EQ_D(s.folds[i].width, 0.01, "width");
        CHECK_EQ_D(s.folds[i].setback[0], 0.0, "setback a");
        CHECK_EQ_D(s.folds[i].setback[1], 0.0, "setback b");
        CHECK_EQ_I(s.folds[i].continuity, 1, "continuity");
        CHECK_EQ_I(s.folds[i].modes, 0, "modes");
        CHECK_EQ_I(s.folds[i].group, -1, "group");
        CHECK_EQ_D(s.vertices[s.folds[i].a].x[0], 0.03 * (i + 1), "fold x");
        CHECK_EQ_D(s.vertices[s.folds[i].a].x[1], 0.0, "fold from y");
        CHECK_EQ_D(s.vertices[s.folds[i].b].x[1], 0.03, "fold to y");
    }
    CHECK_EQ_I(sf_study_fold_index(&s, "f2"), 1, "fold named f2");
    CHECK_EQ_D(s.materials[s.folds[0].material].E, 15.2e6, "E");
    CHECK_EQ_D(s.loads[0].at[0], 0.116, "load x");
    CHECK_EQ_D(s.loads[0].at[1], 0.015, "load y");
    CHECK_EQ_D(s.loads[0].force[2], -0.2, "load fz");
    CHECK_EQ_I(s.loads[0].stage, 1, "load stage");
    CHECK_EQ_D(s.probes[0].at[0], 0.12, "probe x");
    CHECK_EQ_D(s.probes[0].at[1], 0.015, "probe y");
    CHECK_EQ_D(s.fixed_point[0], 0.01, "fixed x");
    CHECK_EQ_D(s.fixed_point[1], 0.015, "fixed y");
    CHECK_EQ_I(s.constraints, SF_CONSTRAINTS_EXACT, "constraints");
    CHECK_EQ_D(s.penalty_rotation, 10.0, "lambda_R (paper, strip3)");
    CHECK_EQ_D(s.penalty_translation, 0.1, "lambda_d (paper, strip3)");
    CHECK_EQ_I(s.quadrature, 24, "quadrature");
    CHECK_EQ_I(s.samples, 8, "samples");
    sf_study_free(&s);
}

static void test_fold1(void **state)
{
    (void)state;
    sf_study s;
    sf_error e;
    CHECK_OK(load("studies/fold1.cfg", 0, NULL, &s, &e), e);
    CHECK_EQ_I(s.nvertices, 6, "vertices");
    CHECK_EQ_I(s.nfolds, 1, "folds");
    CHECK_EQ_I(s.nloads, 1, "loads");
    CHECK_EQ_I(s.nprobes, 1, "probes");
    CHECK_EQ_D(s.folds[0].width, 0.01, "width");
    CHECK_EQ_D(s.vertices[s.folds[0].a].x[0], 0.03, "fold x");
    CHECK_EQ_D(s.loads[0].force[2], -4.0, "load");
    CHECK_EQ_D(s.loads[0].at[0], 0.058, "load x");
    CHECK_EQ_D(s.probes[0].at[0], 0.06, "probe x");
    CHECK_EQ_I(s.constraints, SF_CONSTRAINTS_EXACT, "constraints");
    sf_study_free(&s);
}

static void test_waterbomb2(void **state)
{
    (void)state;
    sf_study s;
    sf_error e;
    CHECK_OK(load("studies/waterbomb2.cfg", 0, NULL, &s, &e), e);
    CHECK_EQ_I(s.nvertices, 14, "vertices");
    CHECK_EQ_I(s.nfolds, 15, "folds");
    CHECK_EQ_I(s.nloads, 1, "loads");
    CHECK_EQ_I(s.nprobes, 1, "probes");
    CHECK_EQ_I(s.nstages, 2, "stages");
    assert_true(s.gravity_on);
    CHECK_EQ_I(s.gravity_stage, 1, "gravity stage");
    CHECK_EQ_D(s.gravity[2], -9.81, "g");
    CHECK_EQ_I(s.loads[0].stage, 2, "load stage");
    CHECK_EQ_D(s.loads[0].force[2], -0.2, "load");
    CHECK_EQ_D(s.loads[0].at[0], 0.157, "load x");
    CHECK_EQ_D(s.loads[0].at[1], 0.0675, "load y");
    CHECK_EQ_D(s.probes[0].at[0], 0.1588, "probe x");
    CHECK_EQ_D(s.probes[0].at[1], 0.07383, "probe y");
    CHECK_EQ_D(s.fixed_point[0], 0.01, "fixed x");
    CHECK_EQ_D(s.fixed_point[1], 0.03, "fixed y");
    CHECK_EQ_I(s.constraints, SF_CONSTRAINTS_PENALTY, "constraints (penalty by default: exact closure does not start yet)");
    CHECK_EQ_D(s.vertices[vidx(&s, "v7")].x[0], 0.04, "v7 x");
    CHECK_EQ_D(s.vertices[vidx(&s, "v8")].x[0], 0.12, "v8 x");
    static const char *const pairs[15][2] = {
        {"v7", "v1"}, {"v7", "v2"}, {"v7", "v3"}, {"v8", "v3"}, {"v8", "v4"},
        {"v8", "v5"}, {"v7", "v6"}, {"v7", "v8"}, {"v8", "v9"}, {"v7", "v10"},
        {"v7", "v11"}, {"v7", "v12"}, {"v8", "v12"}, {"v8", "v13"}, {"v8", "v14"}};
    for (int i = 0; i < 15; i++) {
        const sf_fold_def *f = &s.folds[i];
        assert_string_equal(vname(&s, f->a), pairs[i][0]);
        assert_string_equal(vname(&s, f->b), pairs[i][1]);
        CHECK_EQ_D(f->width, 8.25e-3, "width");
        CHECK_EQ_D(f->setback[0], 0.011, "setback at the interior vertex");
        const char *to = pairs[i][1];
        double want;
        if (strcmp(to, "v8") == 0) want = 0.011;
        else if (!strcmp(to, "v2") || !strcmp(to, "v4") || !strcmp(to, "v6") || !strcmp(to, "v9")
                 || !strcmp(to, "v11") || !strcmp(to, "v13")) want = 1.0e-3;
        else want = 5.23e-3;
        CHECK_EQ_D(f->setback[1], want, pairs[i][1]);
    }
    double end;
    CHECK_OK(sf_study_double(&s, "analysis.end", 0, &end, &e), e);
    CHECK_EQ_D(end, 2.0, "analysis.end");
    sf_study_free(&s);
}

typedef struct sq4 {
    const char *file;
    double E, width, r;
    double fixed[2];
    int corner, irregular;
} sq4;

static void check_square4(const sq4 *c)
{
    sf_study s;
    sf_error e;
    CHECK_OK(load(c->file, 0, NULL, &s, &e), e);
    CHECK_EQ_I(s.nvertices, 20, "vertices");
    CHECK_EQ_I(s.nfolds, 24, "folds");
    CHECK_EQ_I(s.nloads, 4, "loads");
    CHECK_EQ_I(s.nprobes, 1, "probes");
    CHECK_EQ_I(s.nstages, 1, "stages");
    assert_false(s.gravity_on);
    CHECK_EQ_D(s.materials[s.folds[0].material].E, c->E, "E");
    CHECK_EQ_D(s.fixed_point[0], c->fixed[0], "fixed x");
    CHECK_EQ_D(s.fixed_point[1], c->fixed[1], "fixed y");
    static const int pairs[24][2] = {
        {7, 1}, {7, 2}, {7, 3}, {8, 3}, {8, 4}, {8, 5}, {7, 6}, {7, 8},
        {8, 9}, {7, 10}, {7, 13}, {8, 14}, {8, 11}, {13, 10}, {14, 11}, {13, 12},
        {13, 14}, {14, 15}, {13, 16}, {13, 17}, {13, 18}, {14, 18}, {14, 19}, {14, 20}};
    for (int i = 0; i < 24; i++) {
        const sf_fold_def *f = &s.folds[i];
        char a[8], b[8];
        snprintf(a, sizeof a, "v%d", pairs[i][0]);
        snprintf(b, sizeof b, "v%d", pairs[i][1]);
        assert_string_equal(vname(&s, f->a), a);
        assert_string_equal(vname(&s, f->b), b);
        CHECK_EQ_D(f->width, c->width, "width");
        CHECK_EQ_I(f->modes, 1, "modes (K = 1 for square4 for now)");
        CHECK_EQ_I(f->continuity, 1, "continuity");
        CHECK_EQ_D(f->setback[0], 0.08, "setback at the interior vertex");
        int t = pairs[i][1];
        int shortend = t == 2 || t == 4 || t == 6 || t == 9 || t == 12 || t == 15 || t == 17 || t == 19;
        CHECK_EQ_D(f->setback[1], shortend ? 0.04 : 0.08, b);
    }
    CHECK_EQ_I(s.noutline, c->irregular ? 16 : 4, "outline vertices");
    if (c->irregular) {
        CHECK_EQ_D(s.vertices[vidx(&s, "v1")].x[0], -0.5, "v1 x");
        CHECK_EQ_D(s.vertices[vidx(&s, "v20")].x[1], 0.5, "v20 y");
        CHECK_EQ_D(s.vertices[vidx(&s, "v7")].x[0], -0.18, "v7 x");
        CHECK_EQ_D(s.vertices[vidx(&s, "v8")].x[1], -0.18, "v8 y");
        CHECK_EQ_D(s.vertices[vidx(&s, "v13")].x[1], 0.18, "v13 y");
        CHECK_EQ_D(s.vertices[vidx(&s, "v14")].x[0], 0.18, "v14 x");
    } else {
        CHECK_EQ_D(s.vertices[vidx(&s, "v1")].x[0], -0.4, "v1 x");
        CHECK_EQ_D(s.vertices[vidx(&s, "v7")].x[0], -0.2, "v7 x");
    }
    if (c->corner) {
        static const double at[4][2] = {{0.3576, -0.3292}, {0.3576, 0.3292}, {-0.3576, 0.3292}, {-0.3576, -0.3292}};
        static const double fz[4] = {-0.11, 0.05, 0.05, -0.11};
        for (int i = 0; i < 4; i++) {
            CHECK_EQ_D(s.loads[i].at[0], at[i][0], "load x");
            CHECK_EQ_D(s.loads[i].at[1], at[i][1], "load y");
            CHECK_EQ_D(s.loads[i].force[0], 0.0, "load fx");
            CHECK_EQ_D(s.loads[i].force[1], 0.0, "load fy");
            CHECK_EQ_D(s.loads[i].force[2], fz[i], "load fz");
        }
        CHECK_EQ_D(s.probes[0].at[0], 0.0, "probe x");
        CHECK_EQ_D(s.probes[0].at[1], 0.3292, "probe y");
    } else {
        double r = c->r;
        const double at[4][2] = {{r, 0}, {0, r}, {-r, 0}, {0, -r}};
        static const double f[4][3] = {{-2, 0, -1.2}, {0, -2, -1.2}, {2, 0, -1.2}, {0, 2, -1.2}};
        for (int i = 0; i < 4; i++) {
            CHECK_EQ_D(s.loads[i].at[0], at[i][0], "load x");
            CHECK_EQ_D(s.loads[i].at[1], at[i][1], "load y");
            for (int d = 0; d < 3; d++) CHECK_EQ_D(s.loads[i].force[d], f[i][d], "load force");
        }
        CHECK_EQ_D(s.probes[0].at[0], 0.0, "probe x");
        CHECK_EQ_D(s.probes[0].at[1], -r, "probe y");
    }
    CHECK_EQ_D(s.penalty_rotation, 100.0, "lambda_R");
    CHECK_EQ_D(s.penalty_translation, 1.0, "lambda_d");
    sf_study_free(&s);
}

static void test_square4_family(void **state)
{
    (void)state;
    static const sq4 cases[] = {
        {"studies/square4.cfg", 15.2e6, 0.04, 0.3292, {0, 0}, 0, 0},
        {"studies/square4-stiff.cfg", 30.4e6, 0.04, 0.3292, {0, 0}, 0, 0},
        {"studies/square4-narrow.cfg", 15.2e6, 0.02, 0.3364, {0, 0}, 0, 0},
        {"studies/square4-corner.cfg", 15.2e6, 0.04, 0.3292, {0, -0.3}, 1, 0},
        {"studies/square4-irregular.cfg", 15.2e6, 0.04, 0.3272, {0, 0}, 0, 1},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) check_square4(&cases[i]);
}

/* ---------------------------------------------------------------------- */

static void compare_studies(const sf_study *a, const sf_study *b)
{
    assert_string_equal(a->name, b->name);
    CHECK_EQ_I(a->nvertices, b->nvertices, "vertices");
    for (int i = 0; i < a->nvertices; i++) {
        assert_string_equal(a->vertices[i].name, b->vertices[i].name);
        CHECK_EQ_D(a->vertices[i].x[0], b->vertices[i].x[0], "vertex x");
        CHECK_EQ_D(a->vertices[i].x[1], b->vertices[i].x[1], "vertex y");
    }
    CHECK_EQ_I(a->noutline, b->noutline, "outline");
    for (int i = 0; i < a->noutline; i++) CHECK_EQ_I(a->outline[i], b->outline[i], "outline vertex");
    CHECK_EQ_I(a->nmaterials, b->nmaterials, "materials");
    for (int i = 0; i < a->nmaterials; i++) {
        assert_string_equal(a->materials[i].name, b->materials[i].name);
        CHECK_EQ_D(a->materials[i].E, b->materials[i].E, "E");
        CHECK_EQ_D(a->materials[i].nu, b->materials[i].nu, "nu");
        CHECK_EQ_D(a->materials[i].thickness, b->materials[i].thickness, "thickness");
        CHECK_EQ_D(a->materials[i].density, b->materials[i].density, "density");
    }
    CHECK_EQ_I(a->face_material, b->face_material, "face material");
    CHECK_EQ_I(a->nfolds, b->nfolds, "folds");
    for (int i = 0; i < a->nfolds; i++) {
        const sf_fold_def *f = &a->folds[i], *g = &b->folds[i];
        assert_string_equal(f->name, g->name);
        CHECK_EQ_I(f->a, g->a, "a");
        CHECK_EQ_I(f->b, g->b, "b");
        CHECK_EQ_D(f->width, g->width, "width");
        CHECK_EQ_D(f->setback[0], g->setback[0], "setback a");
        CHECK_EQ_D(f->setback[1], g->setback[1], "setback b");
        CHECK_EQ_I(f->continuity, g->continuity, "continuity");
        CHECK_EQ_I(f->modes, g->modes, "modes");
        CHECK_EQ_I(f->material, g->material, "material");
        CHECK_EQ_I(f->group, g->group, "group");
        CHECK_EQ_D(f->rest_angle, g->rest_angle, "rest angle");
    }
    CHECK_EQ_D(a->fixed_point[0], b->fixed_point[0], "fixed x");
    CHECK_EQ_D(a->fixed_point[1], b->fixed_point[1], "fixed y");
    CHECK_EQ_I(a->nloads, b->nloads, "loads");
    for (int i = 0; i < a->nloads; i++) {
        for (int d = 0; d < 2; d++) CHECK_EQ_D(a->loads[i].at[d], b->loads[i].at[d], "load at");
        for (int d = 0; d < 3; d++) CHECK_EQ_D(a->loads[i].force[d], b->loads[i].force[d], "load force");
        CHECK_EQ_I(a->loads[i].stage, b->loads[i].stage, "load stage");
    }
    CHECK_EQ_I(a->gravity_on, b->gravity_on, "gravity");
    for (int d = 0; d < 3; d++) CHECK_EQ_D(a->gravity[d], b->gravity[d], "g");
    CHECK_EQ_I(a->gravity_stage, b->gravity_stage, "gravity stage");
    CHECK_EQ_I(a->nstages, b->nstages, "stages");
    CHECK_EQ_I(a->ngroups, b->ngroups, "groups");
    for (int i = 0; i < a->ngroups; i++) {
        assert_string_equal(a->groups[i].name, b->groups[i].name);
        CHECK_EQ_D(a->groups[i].rest_angle, b->groups[i].rest_angle, "group rest angle");
    }
    CHECK_EQ_I(a->nsupports, b->nsupports, "supports");
    for (int i = 0; i < a->nsupports; i++)
        for (int d = 0; d < 3; d++) {
            CHECK_EQ_I(a->supports[i].dof[d], b->supports[i].dof[d], "support dof");
            CHECK_EQ_D(a->supports[i].value[d], b->supports[i].value[d], "support value");
        }
    CHECK_EQ_I(a->nprobes, b->nprobes, "probes");
    for (int i = 0; i < a->nprobes; i++) {
        assert_string_equal(a->probes[i].name, b->probes[i].name);
        CHECK_EQ_D(a->probes[i].at[0], b->probes[i].at[0], "probe x");
        CHECK_EQ_D(a->probes[i].at[1], b->probes[i].at[1], "probe y");
    }
    CHECK_EQ_I(a->constraints, b->constraints, "constraints");
    CHECK_EQ_D(a->penalty_rotation, b->penalty_rotation, "lambda_R");
    CHECK_EQ_D(a->penalty_translation, b->penalty_translation, "lambda_d");
    CHECK_EQ_I(a->quadrature, b->quadrature, "quadrature");
    CHECK_EQ_D(a->tolerance, b->tolerance, "tolerance");
    CHECK_EQ_I(a->samples, b->samples, "samples");
    CHECK_EQ_I(a->shapes, b->shapes, "shapes");
    assert_string_equal(a->analysis_type, b->analysis_type);
}

static void roundtrip(const char *rel, int nset, const char *const *sets)
{
    sf_study a, b;
    sf_error e;
    char out[2048], tmp[2100];
    tmp_path(out, sizeof out, "test_study_roundtrip.cfg");
    CHECK_OK(load(rel, nset, sets, &a, &e), e);
    CHECK_OK(sf_study_write(&a, out, "smoothfold test\nmerged study\n\nend", &e), e);
    snprintf(tmp, sizeof tmp, "%s.tmp", out);
    assert_int_not_equal(access(tmp, F_OK), 0);   /* renamed away */
    FILE *f = fopen(out, "r");
    assert_non_null(f);
    char line[512];
    assert_non_null(fgets(line, sizeof line, f));
    assert_string_equal(line, "# smoothfold test\n");
    assert_non_null(fgets(line, sizeof line, f));
    assert_string_equal(line, "# merged study\n");
    assert_non_null(fgets(line, sizeof line, f));
    assert_string_equal(line, "#\n");
    fclose(f);
    sf_error_clear(&e);
    CHECK_OK(sf_study_load(out, 0, NULL, &b, &e), e);
    compare_studies(&a, &b);
    /* keys of the analysis plan survive too */
    const char *keys[] = {"analysis.step", "analysis.end", "analysis.max_step", "analysis.start"};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        double x, y;
        CHECK_OK(sf_study_double(&a, keys[i], NAN, &x, &e), e);
        CHECK_OK(sf_study_double(&b, keys[i], NAN, &y, &e), e);
        CHECK_EQ_D(y, x, keys[i]);
    }
    sf_study_free(&a);
    sf_study_free(&b);
    remove(out);
}

/* sf_study_print echoes the merged study as comments. */
static void test_print(void **state)
{
    (void)state;
    sf_study s;
    sf_error e;
    const char *sets[] = {"defaults.width=0.02"};
    CHECK_OK(load("studies/fold1.cfg", 1, sets, &s, &e), e);
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    assert_non_null(f);
    CHECK_OK(sf_study_print(&s, f, "# ", &e), e);
    fclose(f);
    assert_true(strncmp(buf, "# name = \"fold1\";\n", strlen("# name = \"fold1\";\n")) == 0);
    CHECK_CONTAINS(buf, "\n#   width = 0.02;  # --set defaults.width=0.02\n");
    CHECK_CONTAINS(buf, "\n#\n");
    for (const char *p = buf; *p; p = strchr(p, '\n') + 1) assert_true(p[0] == '#');
    free(buf);
    sf_study_free(&s);
}

static void test_write_roundtrip(void **state)
{
    (void)state;
    char pat[2048];
    glob_t g;
    src_path(pat, sizeof pat, "studies/*.cfg");
    assert_int_equal(glob(pat, 0, NULL, &g), 0);
    size_t ls = strlen(srcdir()) + 1;
    for (size_t i = 0; i < g.gl_pathc; i++) roundtrip(g.gl_pathv[i] + ls, 0, NULL);
    globfree(&g);
    /* awkward values: not short decimals, tiny, huge, negative zero, a
     * string needing escapes, overrides (written with their comments) */
    const char *sets[] = {"materials.fold.E=15200000.000000002", "defaults.width=0.1e-2",
                          "folds[0].rest_angle=0.3333333333333333", "folds[1].rest_angle=-0.0",
                          "solver.tolerance=1.2345678901234567e-300", "materials.face.density=1e300",
                          "description=\"a \\\"quoted\\\"\\tname\\\\\"",
                          "actuation=({ name = \"g1\"; rest_angle = 1.0; })",
                          "folds[2].group=\"g1\"",
                          "supports=({ at = [0.005, 0.005]; fix = [true, false, true]; value = [0.0, 0.0, 0.001]; })"};
    roundtrip("studies/strip3.cfg", (int)(sizeof sets / sizeof sets[0]), sets);
}

/* ---------------------------------------------------------------------- */

static void test_accessors(void **state)
{
    (void)state;
    sf_study s;
    sf_error e;
    CHECK_OK(load("studies/waterbomb2.cfg", 0, NULL, &s, &e), e);
    double x;
    int i;
    const char *str;
    double v[4];
    int n;

    CHECK_OK(sf_study_double(&s, "analysis.step", 1, &x, &e), e);
    CHECK_EQ_D(x, 0.05, "analysis.step");
    CHECK_OK(sf_study_double(&s, "materials.fold.E", 1, &x, &e), e);
    CHECK_EQ_D(x, 15.2e6, "materials.fold.E");
    assert_int_equal(sf_study_double(&s, "folds[7].setback", 1, &x, &e), SF_EINTERNAL); /* an array */
    sf_error_clear(&e);
    CHECK_OK(sf_study_int(&s, "analysis.max_steps", 1, &i, &e), e);
    CHECK_EQ_I(i, 500, "analysis.max_steps");
    CHECK_OK(sf_study_string(&s, "solver.constraints", "", &str, &e), e);
    assert_string_equal(str, "penalty");
    CHECK_OK(sf_study_doubles(&s, "gravity.g", 3, 3, v, &n, &e), e);
    CHECK_EQ_I(n, 3, "gravity.g length");
    CHECK_EQ_D(v[2], -9.81, "gravity.g z");
    CHECK_OK(sf_study_doubles(&s, "folds[0].setback", 2, 2, v, &n, &e), e);
    CHECK_EQ_D(v[1], 5.23e-3, "folds[0].setback[1]");
    CHECK_OK(sf_study_int(&s, "loads[0].stage", 7, &i, &e), e);
    CHECK_EQ_I(i, 2, "loads[0].stage (present)");
    assert_int_equal(sf_study_int(&s, "probes[tip].at", 0, &i, &e), SF_EINTERNAL);   /* not an int */
    sf_error_clear(&e);
    assert_int_equal(sf_study_doubles(&s, "supports[0].value", 3, 3, v, &n, &e), SF_EINTERNAL); /* no supports */
    sf_error_clear(&e);
    assert_int_equal(sf_study_doubles(&s, "gravity.g", 2, 2, v, &n, &e), SF_EINPUT);   /* wrong length */
    CHECK_CONTAINS(e.msg, "gravity.g: expected 2 numbers, got 3");
    sf_error_clear(&e);
    /* no schema default: the caller's */
    CHECK_OK(sf_study_double(&s, "analysis.duration", 3.5, &x, &e), e);
    CHECK_EQ_D(x, 3.5, "analysis.duration (caller default)");
    /* defaults are in the tree */
    CHECK_OK(sf_study_int(&s, "defaults.modes", 9, &i, &e), e);
    CHECK_EQ_I(i, 0, "defaults.modes");
    CHECK_OK(sf_study_string(&s, "analysis.report", "", &str, &e), e);
    assert_string_equal(str, "tip");
    int b;
    CHECK_OK(sf_study_bool(&s, "gravity.enabled", 0, &b, &e), e);
    assert_true(b);
    /* programming errors */
    assert_int_equal(sf_study_double(&s, "analysis.stepp", 1, &x, &e), SF_EINTERNAL);
    CHECK_CONTAINS(e.msg, "unknown key 'stepp' in analysis (did you mean 'step'?)");
    CHECK_CONTAINS(e.msg, "add the key to the schema table");
    sf_error_clear(&e);
    assert_int_equal(sf_study_int(&s, "analysis.step", 1, &i, &e), SF_EINTERNAL);
    sf_error_clear(&e);
    /* presence and counts */
    assert_true(sf_study_has(&s, "gravity"));
    assert_true(sf_study_has(&s, "folds[14].to"));
    assert_false(sf_study_has(&s, "folds[15].to"));
    assert_false(sf_study_has(&s, "supports"));
    assert_false(sf_study_has(&s, "nonsense"));
    CHECK_EQ_I(sf_study_count(&s, "folds"), 15, "count folds");
    CHECK_EQ_I(sf_study_count(&s, "vertices"), 14, "count vertices");
    CHECK_EQ_I(sf_study_count(&s, "analysis.schedule"), 0, "count schedule");
    /* locations and messages */
    char w[2048], want[2100];
    sf_study_where(&s, "folds[3].to", w, sizeof w);
    snprintf(want, sizeof want, "%s:%d", s.path, s.folds[3].line);
    assert_string_equal(w, want);
    assert_int_equal(sf_study_fail(&s, &e, SF_EINPUT, "folds[3]", "bands overlap (got %d)", 2), SF_EINPUT);
    snprintf(want, sizeof want, "%s:%d: folds[3]: bands overlap (got 2)", s.path, s.folds[3].line);
    assert_string_equal(e.msg, want);
    sf_error_clear(&e);
    /* lookups */
    CHECK_EQ_I(sf_study_vertex_index(&s, "v8"), 7, "v8");
    CHECK_EQ_I(sf_study_vertex_index(&s, "v99"), -1, "v99");
    CHECK_EQ_I(sf_study_material_index(&s, "face"), 1, "face");
    CHECK_EQ_I(sf_study_probe_index(&s, "tip"), 0, "tip");
    CHECK_EQ_I(sf_study_group_index(&s, "none"), -1, "group");
    CHECK_EQ_I(sf_study_fold_index(&s, ""), -1, "unnamed fold");
    sf_study_free(&s);
    sf_study_free(&s);   /* twice is harmless */

    /* schema default of an absent key */
    const char *sets0[] = {"loads=({ at = [0.058, 0.015]; force = [0.0, 0.0, -4.0]; })"};
    CHECK_OK(load("studies/fold1.cfg", 1, sets0, &s, &e), e);
    assert_false(sf_study_has(&s, "loads[0].stage"));
    CHECK_OK(sf_study_int(&s, "loads[0].stage", 7, &i, &e), e);
    CHECK_EQ_I(i, 1, "loads[0].stage (schema default)");
    CHECK_EQ_I(s.loads[0].stage, 1, "stage");
    sf_study_where(&s, "loads[0]", w, sizeof w);
    assert_string_equal(w, "--set loads=({ at = [0.058, 0.015]; force = [0.0, 0.0, -4.0]; })");
    sf_study_free(&s);

    /* dynamics defaults appear only for analysis.type "dynamics" */
    const char *sets[] = {"analysis.type=\"dynamics\"", "analysis.duration=2.0"};
    CHECK_OK(load("studies/strip3.cfg", 2, sets, &s, &e), e);
    CHECK_OK(sf_study_double(&s, "analysis.damping", 0, &x, &e), e);
    CHECK_EQ_D(x, 1.0, "damping default (dynamics)");
    CHECK_OK(sf_study_bool(&s, "analysis.inertia", 1, &b, &e), e);
    assert_false(b);
    sf_study_free(&s);
}

static void test_dynamics_checks(void **state)
{
    (void)state;
    sf_study s;
    sf_error e;
    const char *sets[] = {"analysis.type=\"dynamics\""};
    assert_int_equal(load("studies/strip3.cfg", 1, sets, &s, &e), SF_EINPUT);
    CHECK_CONTAINS(e.msg, "analysis: missing duration (required when type is \"dynamics\")");
    const char *sets2[] = {"analysis.type=\"dynamics\"", "analysis.duration=1.0",
                           "analysis.schedule=({ t = 0.0; value = 0.0; }, { t = 0.0; value = 1.0; })"};
    assert_int_equal(load("studies/strip3.cfg", 3, sets2, &s, &e), SF_EINPUT);
    CHECK_CONTAINS(e.msg, "analysis.schedule[1].t: times must increase");
    const char *sets3[] = {"analysis.type=\"dynamics\"", "analysis.duration=1.0", "analysis.inertia=true",
                           "materials.fold={ E = 1.0e6; nu = 0.3; thickness = 0.001; }"};
    assert_int_equal(load("studies/strip3.cfg", 4, sets3, &s, &e), SF_EINPUT);
    CHECK_CONTAINS(e.msg, "materials.fold: missing density (required when inertia is on)");
    const char *sets4[] = {"analysis.parameter=\"actuation\""};
    assert_int_equal(load("studies/strip3.cfg", 1, sets4, &s, &e), SF_EINPUT);
    CHECK_CONTAINS(e.msg, "needs at least one actuation group");
}

static void test_missing_file(void **state)
{
    (void)state;
    sf_study s;
    sf_error e;
    sf_error_clear(&e);
    assert_int_equal(sf_study_load("/nonexistent/x.cfg", 0, NULL, &s, &e), SF_EIO);
    CHECK_CONTAINS(e.msg, "/nonexistent/x.cfg: cannot read");
    sf_study_free(&s);
    char out[64];
    snprintf(out, sizeof out, "/nonexistent/dir/out.cfg");
    CHECK_OK(load("studies/fold1.cfg", 0, NULL, &s, &e), e);
    assert_int_equal(sf_study_write(&s, out, NULL, &e), SF_EIO);
    CHECK_CONTAINS(e.msg, "cannot write");
    sf_study_free(&s);
}

/* ---------------------------------------------------------------------- */

static int read_expect(const char *path, int *line, char *msg, size_t n)
{
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    char buf[64];
    int ok = fgets(buf, sizeof buf, f) && fgets(msg, (int)n, f);
    fclose(f);
    if (!ok) return -1;
    char *end;
    *line = (int)strtol(buf, &end, 10);
    if (end == buf) return -1;
    msg[strcspn(msg, "\r\n")] = '\0';
    return msg[0] ? 0 : -1;
}

static void test_bad_studies(void **state)
{
    (void)state;
    char pat[2048];
    glob_t g;
    src_path(pat, sizeof pat, "tests/bad/study_*.cfg");
    assert_int_equal(glob(pat, 0, NULL, &g), 0);
    assert_true(g.gl_pathc >= 15);
    int failures = 0;
    for (size_t i = 0; i < g.gl_pathc; i++) {
        const char *p = g.gl_pathv[i];
        char ex[2100], want[512], head[2100];
        int line;
        snprintf(ex, sizeof ex, "%.*s.expect", (int)(strlen(p) - 4), p);
        if (read_expect(ex, &line, want, sizeof want)) {
            print_error("%s: missing or malformed (line number, then message)\n", ex);
            failures++;
            continue;
        }
        sf_study s;
        sf_error e;
        sf_error_clear(&e);
        int rc = sf_study_load(p, 0, NULL, &s, &e);
        if (line > 0) snprintf(head, sizeof head, "%s:%d: ", p, line);
        else snprintf(head, sizeof head, "%s: ", p);
        if (rc != SF_EINPUT || strncmp(e.msg, head, strlen(head)) != 0 || !strstr(e.msg + strlen(head), want)) {
            print_error("%s:\n  expected SF_EINPUT, \"%s...%s\"\n  got      %d, \"%s\"\n", p, head, want, rc, e.msg);
            failures++;
        }
        if (rc == SF_OK) sf_study_free(&s);
        else {
            assert_null(s.cfg);
            assert_null(s.vertices);
        }
    }
    globfree(&g);
    if (failures) fail_msg("%d broken studies did not fail as expected", failures);
}

/* ---------------------------------------------------------------------- */

/* docs/reference/study-keys.md mentions every key of the schema as `path`. */
static void test_docs_cover_schema(void **state)
{
    (void)state;
    char p[2048];
    src_path(p, sizeof p, "docs/reference/study-keys.md");
    FILE *f = fopen(p, "r");
    assert_non_null(f);
    size_t cap = 1 << 20;
    char *doc = malloc(cap);
    assert_non_null(doc);
    size_t n = fread(doc, 1, cap - 1, f);
    doc[n] = '\0';
    fclose(f);
    int nk;
    const sf_study_key *k = sf_study_schema(&nk);
    int missing = 0;
    for (int i = 0; i < nk; i++) {
        char q[256];
        snprintf(q, sizeof q, "`%s`", k[i].path);
        if (!strstr(doc, q)) {
            print_error("docs/reference/study-keys.md does not mention %s\n", q);
            missing++;
        }
        assert_non_null(k[i].doc);
        assert_non_null(k[i].unit);
    }
    free(doc);
    if (missing) fail_msg("%d schema keys undocumented", missing);
}

static void test_suggest(void **state)
{
    (void)state;
    const char *c[] = {"width", "setback", "continuity", "modes", "material", "rest_angle"};
    assert_string_equal(sf_study_suggest("widht", 6, c), "width");
    assert_string_equal(sf_study_suggest("Width", 6, c), "width");
    assert_string_equal(sf_study_suggest("mode", 6, c), "modes");
    assert_string_equal(sf_study_suggest("continuty", 6, c), "continuity");
    assert_null(sf_study_suggest("zzz", 6, c));
    assert_null(sf_study_suggest("", 6, c));
    assert_null(sf_study_suggest("x", 0, NULL));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_all_studies_load),
        cmocka_unit_test(test_strip3),
        cmocka_unit_test(test_fold1),
        cmocka_unit_test(test_waterbomb2),
        cmocka_unit_test(test_square4_family),
        cmocka_unit_test(test_write_roundtrip),
        cmocka_unit_test(test_print),
        cmocka_unit_test(test_accessors),
        cmocka_unit_test(test_dynamics_checks),
        cmocka_unit_test(test_missing_file),
        cmocka_unit_test(test_bad_studies),
        cmocka_unit_test(test_docs_cover_schema),
        cmocka_unit_test(test_suggest),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
