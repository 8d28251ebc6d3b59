/* test_study_set.c - --set overrides of a study (src/pattern/study_set.c):
 * values replaced and added at key paths (names and indices), and the
 * one-line messages of bad overrides. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "study.h"
#include "study_test.h"

static void test_set_overrides(void **state)
{
    (void)state;
    sf_study s;
    sf_error e;
    const char *sets1[] = {"materials.fold.E=30.4e6"};
    CHECK_OK(load("studies/strip3.cfg", 1, sets1, &s, &e), e);
    CHECK_EQ_D(s.materials[sf_study_material_index(&s, "fold")].E, 30.4e6, "E after --set");
    char where[256];
    sf_study_where(&s, "materials.fold.E", where, sizeof where);
    assert_string_equal(where, "--set materials.fold.E=30.4e6");
    sf_study_free(&s);

    /* defaults.width moves every fold without its own width; a fold's own
     * width wins, whatever the order of the options */
    const char *sets2[] = {"folds[1].width = 0.02", "defaults.width=0.015"};
    CHECK_OK(load("studies/strip3.cfg", 2, sets2, &s, &e), e);
    CHECK_EQ_D(s.folds[0].width, 0.015, "fold 0 width");
    CHECK_EQ_D(s.folds[1].width, 0.02, "fold 1 width (own)");
    CHECK_EQ_D(s.folds[2].width, 0.015, "fold 2 width");
    sf_study_free(&s);
    const char *sets3[] = {"defaults.width=0.015", "folds[f2].width=0.02"};
    CHECK_OK(load("studies/strip3.cfg", 2, sets3, &s, &e), e);
    CHECK_EQ_D(s.folds[0].width, 0.015, "fold 0 width");
    CHECK_EQ_D(s.folds[1].width, 0.02, "fold f2 width (own)");
    sf_study_free(&s);

    /* strings, arrays, booleans, new groups, type change int -> float */
    const char *sets4[] = {"solver.constraints=\"penalty\"", "defaults.setback=[0.001, 0.002]",
                           "analysis.stability=false", "gravity={ g = [0.0, 0.0, -9.81]; }",
                           "defaults.modes=3", "solver.penalty_rotation=7",
                           "loads[0].force=[0.0, 0.0, -0.1];"};
    CHECK_OK(load("studies/strip3.cfg", 7, sets4, &s, &e), e);
    CHECK_EQ_I(s.constraints, SF_CONSTRAINTS_PENALTY, "constraints");
    CHECK_EQ_D(s.folds[2].setback[1], 0.002, "setback b");
    CHECK_EQ_I(s.folds[2].modes, 3, "modes");
    assert_true(s.gravity_on);
    CHECK_EQ_D(s.penalty_rotation, 7.0, "integer accepted for a number");
    CHECK_EQ_D(s.loads[0].force[2], -0.1, "load");
    int b = 1;
    CHECK_OK(sf_study_bool(&s, "analysis.stability", 1, &b, &e), e);
    assert_false(b);
    sf_study_free(&s);

    /* a key absent from the file is created */
    const char *sets5[] = {"folds[0].rest_angle=0.5", "output.shapes=3"};
    CHECK_OK(load("studies/waterbomb2.cfg", 2, sets5, &s, &e), e);
    CHECK_EQ_D(s.folds[0].rest_angle, 0.5, "rest angle");
    CHECK_EQ_I(s.shapes, 3, "shapes");
    sf_study_free(&s);
}

static void expect_set_error(const char *set, const char *sub)
{
    sf_study s;
    sf_error e;
    const char *sets[] = {set};
    int rc = load("studies/strip3.cfg", 1, sets, &s, &e);
    if (rc != SF_EINPUT) print_error("--set %s: expected SF_EINPUT, got %d (%s)\n", set, rc, e.msg);
    assert_int_equal(rc, SF_EINPUT);
    CHECK_CONTAINS(e.msg, sub);
    if (strncmp(e.msg, "--set ", 6) != 0) fail_msg("expected the message to start with '--set ', got '%s'", e.msg);
    assert_null(s.cfg);
    assert_null(s.folds);
}

static void test_set_errors(void **state)
{
    (void)state;
    expect_set_error("widht=0.02", "--set widht=0.02: unknown key 'widht' at top level (did you mean 'defaults.width'?)");
    expect_set_error("defaults.widht=0.02", "unknown key 'widht' in defaults (did you mean 'width'?)");
    expect_set_error("defaults.width=0,02", "--set defaults.width=0,02: syntax error");
    expect_set_error("defaults.width=abc", "syntax error");
    expect_set_error("defaults.width=-0.01", "--set defaults.width=-0.01: defaults.width: must be positive (got -0.01)");
    expect_set_error("defaults.width=1e999", "defaults.width: must be a finite number (got inf)");
    expect_set_error("defaults.width=\"wide\"", "defaults.width: expected a number");
    expect_set_error("defaults.modes=2.0", "defaults.modes: expected an integer, got 2.0");
    expect_set_error("defaults.modes=15200000000", "integer 15200000000 is out of range");
    expect_set_error("folds[9].width=0.01", "folds has 3 elements (index 0 to 2)");
    expect_set_error("folds[f7].width=0.01", "no element named 'f7' in folds");
    expect_set_error("defaults.setback[0]=0.1", "defaults.setback is an array: set it whole");
    expect_set_error("defaults.width", "expected key=value");
    expect_set_error("=1", "empty key");
    expect_set_error("defaults.width=", "empty value");
    expect_set_error("defaults.width=1; x = 2", "single value");
    expect_set_error("folds[0]=1", "expected a group");
    expect_set_error("folds[0].to=\"f1a\"", "folds[0]: from and to are the same vertex 'f1a'");
    expect_set_error("gravity.stage=1", "--set gravity.stage=1: gravity: missing required key 'g'");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_set_overrides),
        cmocka_unit_test(test_set_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
