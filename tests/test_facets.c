/* test_facets.c - bending faces (src/pattern/facets.c,
 * docs/guides/bending-faces.md): where the facets lie (the shorter diagonal of a
 * parallelogram, given facet edges, a non-convex face triangulated inside
 * itself), their width, and the hinge stiffness of the model against the
 * closed form of Filipov et al. (2017), C_B (l/t)^(1/3) E t^3 / 12 (1 - nu^2);
 * bad facet edges rejected with the key named. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sf_test.h"

#include "energy.h"
#include "facets.h"
#include "kinematics.h"
#include "scene.h"
#include "study.h"
#include "topology.h"

static const char *bend_sets[] = {"faces.bending=true", "materials.face.E=3e9",
                                  "materials.face.nu=0.3", "faces.bending_coefficient=0.55"};

static double fold_len(const sf_study *s, int i)
{
    const double *a = s->vertices[s->folds[i].a].x, *b = s->vertices[s->folds[i].b].x;
    return hypot(a[0] - b[0], a[1] - b[1]);
}

/* miura-2x2: 16 parallelograms of sides 0.04 m at 60 degrees; diagonals
 * sqrt(2 - 2 cos 60) 0.04 = 0.04 m and sqrt(2 + 2 cos 60) 0.04 = 0.0693 m. */
static void test_miura_split_and_stiffness(void **state)
{
    (void)state;
    sf_scene sc;
    open_scene(&sc, "miura-2x2", 4, bend_sets);
    const sf_study *s = &sc.study;
    assert_int_equal(s->nfacets, 16);
    assert_int_equal(s->nfolds, 24 + 16);
    assert_int_equal(sc.topo.nfaces, 32);
    assert_int_equal(s->nraised, 0);   /* the 60 and 120 degree sectors leave the folds' setbacks */
    sf_energy e;
    sf_error err;
    sf_error_clear(&err);
    assert_int_equal(sf_energy_init(&e, &sc.model, &err), SF_OK);
    double E = 3e9, nu = 0.3, t = 2.0e-3, cb = 0.55;
    for (int i = 24; i < s->nfolds; i++) {
        const sf_fold_def *f = &s->folds[i];
        assert_true(f->facet);
        assert_int_equal(f->group, -1);
        assert_int_equal(f->modes, 0);
        assert_true(f->rest_angle == 0.0);
        double l = fold_len(s, i);
        CHECK_CLOSE(l, 0.04, 1e-12, "facet %d length (the shorter diagonal)", i + 1);
        CHECK_CLOSE(f->width, 0.02 * 0.04, 1e-10 * 0.02 * 0.04, "facet %d width (coordinates to 12 digits)", i + 1);
        double KB = cb * pow(l / t, 1.0 / 3.0) * E * t * t * t / (12.0 * (1.0 - nu * nu));
        CHECK_CLOSE(e.stiff[i], KB, 1e-12 * KB, "facet %d hinge stiffness", i + 1);
        CHECK_CLOSE(sf_facet_stiffness(E, nu, t, l, cb), KB, 1e-12 * KB, "sf_facet_stiffness");
    }
    for (int i = 0; i < 24; i++) assert_false(s->folds[i].facet);
    sf_energy_free(&e);
    sf_scene_close(&sc);
}

/* A facet edge given in faces.facets: the longer diagonal of one panel. */
static void test_given_facet(void **state)
{
    (void)state;
    const char *sets[] = {bend_sets[0], bend_sets[1], bend_sets[2], "faces.facets=[\"v0_0 v1_1\"]"};
    sf_scene sc;
    open_scene(&sc, "miura-2x2", 4, sets);
    const sf_study *s = &sc.study;
    assert_int_equal(s->nfacets, 16);
    int nlong = 0;
    for (int i = 24; i < s->nfolds; i++) {
        double l = fold_len(s, i);
        if (fabs(l - 0.04 * sqrt(3.0)) < 1e-9) {
            nlong++;
            int a = s->folds[i].a, b = s->folds[i].b;
            int v00 = sf_study_vertex_index(s, "v0_0"), v11 = sf_study_vertex_index(s, "v1_1");
            assert_true((a == v00 && b == v11) || (a == v11 && b == v00));
        } else {
            CHECK_CLOSE(l, 0.04, 1e-12, "facet %d length", i + 1);
        }
    }
    assert_int_equal(nlong, 1);
    sf_scene_close(&sc);
}

static const char lshape[] =
    "name = \"lshape\";\n"
    "vertices = { o = [0.0, 0.0]; a = [0.15, 0.0]; b = [0.2, 0.0]; c = [0.2, 0.05]; d = [0.2, 0.1];\n"
    "  e = [0.1, 0.1]; f = [0.1, 0.2]; g = [0.0, 0.2]; };\n"
    "sheet = { outline = [\"o\", \"b\", \"d\", \"e\", \"f\", \"g\"]; };\n"
    "materials = { fold = { E = 1e7; nu = 0.4; thickness = 1e-3; };\n"
    "  face = { E = 1e9; nu = 0.3; thickness = 1e-3; }; };\n"
    "faces = { material = \"face\"; bending = true; };\n"
    "defaults = { width = 0.002; setback = [0.002, 0.002]; };\n"
    "folds = ( { from = \"a\"; to = \"c\"; } );\n"
    "fixed_face = [0.05, 0.05];\n";

/* The L-shaped face (o a c d e f g; reflex corner e) has 7 corners: 4
 * facets, none through the notch x > 0.1, y > 0.1 or outside the sheet;
 * the corner triangle a b c none. */
static void test_nonconvex_face(void **state)
{
    (void)state;
    char path[] = "/tmp/test_facets_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    fputs(lshape, f);
    fclose(f);
    sf_study s;
    sf_topology t;
    sf_error err;
    sf_error_clear(&err);
    int rc = sf_study_load(path, 0, NULL, &s, &err);
    if (rc) print_error("%s\n", err.msg);
    assert_int_equal(rc, SF_OK);
    assert_int_equal(s.nfacets, 4);
    rc = sf_topology_build(&s, &t, &err);
    if (rc) print_error("%s\n", err.msg);
    assert_int_equal(rc, SF_OK);
    assert_int_equal(t.nfaces, 6);
    for (int i = s.nfolds - s.nfacets; i < s.nfolds; i++) {
        const double *a = s.vertices[s.folds[i].a].x, *b = s.vertices[s.folds[i].b].x;
        for (int k = 1; k < 10; k++) {   /* points along the facet: inside the L */
            double x = a[0] + (b[0] - a[0]) * k / 10.0, y = a[1] + (b[1] - a[1]) * k / 10.0;
            assert_false(x > 0.1 + 1e-12 && y > 0.1 + 1e-12);
            assert_true(x >= -1e-12 && y >= -1e-12 && x <= 0.2 + 1e-12 && y <= 0.2 + 1e-12);
        }
    }
    sf_topology_free(&t);
    sf_study_free(&s);
    unlink(path);
}

static void expect_error(const char *set, const char *text)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/miura-2x2.cfg", studies_dir);
    const char *sets[] = {bend_sets[0], bend_sets[1], bend_sets[2], set};
    sf_study s;
    sf_error err;
    sf_error_clear(&err);
    int rc = sf_study_load(path, set ? 4 : 1, set ? sets : sets, &s, &err);
    assert_int_not_equal(rc, SF_OK);
    if (!strstr(err.msg, text)) print_error("expected '%s' in: %s\n", text, err.msg);
    assert_non_null(strstr(err.msg, text));
    assert_null(strchr(err.msg, '\n'));
}

static void test_errors(void **state)
{
    (void)state;
    expect_error("faces.facets=[\"v0_0 v2_0\"]", "faces.facets[0]: v0_0-v2_0 is not a diagonal of a face");
    expect_error("faces.facets=[\"v0_0\"]", "a facet edge is two vertex names");
    expect_error("faces.facets=[\"v0_0 nowhere\"]", "unknown vertex 'nowhere'");
    /* no E in the face material (the first override only) */
    expect_error(NULL, "missing E (required because faces.bending is on");
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : SF_SRCDIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_miura_split_and_stiffness),
        cmocka_unit_test(test_given_facet),
        cmocka_unit_test(test_nonconvex_face),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
