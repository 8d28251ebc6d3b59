/* test_sweep_plan.c - the plan of a sweep (src/analysis/sweep/sweep.h): values
 * of --vary specs, product order, list mode, key paths against the study
 * schema, and the messages of bad specs.  The running side is tested
 * through the program by test_sweep.sh.
 *
 * The study (studies/fold1.cfg) is found through $SF_SRCDIR. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sweep.h"

#ifndef SF_SRCDIR
#define SF_SRCDIR "."
#endif

static void study(char *buf, size_t n)
{
    const char *d = getenv("SF_SRCDIR");
    snprintf(buf, n, "%s/studies/fold1.cfg", d && d[0] ? d : SF_SRCDIR);
}

/* Plan from --vary specs; returns the status, err filled. */
static int plan(sf_sweep_plan *pl, int nvary, const char *const *vary, int list, sf_error *err)
{
    char path[2048];
    study(path, sizeof path);
    sf_error_clear(err);
    return sf_sweep_plan_make(pl, path, 0, NULL, nvary, vary, list, NULL, err);
}

static void check_values(const sf_sweep_key *k, int n, const char *const *set, const char *const *label)
{
    assert_int_equal(k->nvalues, n);
    for (int i = 0; i < n; i++) {
        assert_string_equal(k->set[i], set[i]);
        assert_string_equal(k->label[i], label[i]);
    }
}

/* START:STOP:N: N values, the ends exact, 15 digits; explicit lists kept
 * as typed, bare words quoted for --set, brackets not split. */
static void test_values(void **state)
{
    (void)state;
    sf_sweep_plan pl;
    sf_error err;
    const char *vary[] = {"defaults.width=0.004:0.008:6", "solver.constraints=exact,\"penalty\"",
                          "loads[0].force=[0.0, 0.0, -1.0],[0.0,0.0,-2.0]"};
    assert_int_equal(plan(&pl, 3, vary, 0, &err), SF_OK);
    const char *w[] = {"0.004", "0.0048", "0.0056", "0.0064", "0.0072", "0.008"};
    check_values(&pl.keys[0], 6, w, w);
    const char *cs[] = {"\"exact\"", "\"penalty\""}, *cl[] = {"exact", "penalty"};
    check_values(&pl.keys[1], 2, cs, cl);
    const char *f[] = {"[0.0, 0.0, -1.0]", "[0.0,0.0,-2.0]"};
    check_values(&pl.keys[2], 2, f, f);
    assert_int_equal(pl.nvariants, 24);
    assert_int_equal(pl.width, 2);
    sf_sweep_plan_free(&pl);
}

/* Product: the last key varies fastest; list: variant i takes value i. */
static void test_order(void **state)
{
    (void)state;
    sf_sweep_plan pl;
    sf_error err;
    const char *vary[] = {"defaults.width=1e-3,2e-3", "materials.fold.E=1,2,3", "defaults.modes=0:3:4"};
    assert_int_equal(plan(&pl, 3, vary, 0, &err), SF_OK);
    assert_int_equal(pl.nvariants, 24);
    for (int v = 0; v < 24; v++) {
        assert_int_equal(sf_sweep_value(&pl, v, 0), v / 12);
        assert_int_equal(sf_sweep_value(&pl, v, 1), (v / 4) % 3);
        assert_int_equal(sf_sweep_value(&pl, v, 2), v % 4);
    }
    char buf[256];
    assert_string_equal(sf_sweep_describe(&pl, 17, buf, sizeof buf),
                        "defaults.width=2e-3 materials.fold.E=2 defaults.modes=1");
    assert_string_equal(sf_sweep_vdir(&pl, "D", 7, buf, sizeof buf), "D/07");
    sf_sweep_plan_free(&pl);

    const char *lv[] = {"defaults.width=1e-3,2e-3,3e-3", "materials.fold.E=1,2,3"};
    assert_int_equal(plan(&pl, 2, lv, 1, &err), SF_OK);
    assert_int_equal(pl.nvariants, 3);
    for (int v = 0; v < 3; v++) {
        assert_int_equal(sf_sweep_value(&pl, v, 0), v);
        assert_int_equal(sf_sweep_value(&pl, v, 1), v);
    }
    sf_sweep_plan_free(&pl);
}

/* Key paths: list elements by index or name, free member names. */
static void test_keys(void **state)
{
    (void)state;
    sf_sweep_plan pl;
    sf_error err;
    const char *ok[] = {"folds[0].width=0.01", "folds[f1].rest_angle=0.1", "materials.fold.nu=0.3",
                        "probes[tip].at=[0.06, 0.015]"};
    for (size_t i = 0; i < sizeof ok / sizeof *ok; i++) {
        assert_int_equal(plan(&pl, 1, &ok[i], 0, &err), SF_OK);
        sf_sweep_plan_free(&pl);
    }
    const char *bad[] = {"folds.width=1", "materials.fold.Young=1", "folds[].width=1", "default.width=1"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        if (plan(&pl, 1, &bad[i], 0, &err) != SF_EINPUT || !strstr(err.msg, "unknown study key"))
            fail_msg("%s: expected 'unknown study key', got '%s'", bad[i], err.msg);
        sf_sweep_plan_free(&pl);
    }
}

static void expect_error(int nvary, const char *const *vary, int list, const char *msg)
{
    sf_sweep_plan pl;
    sf_error err;
    int rc = plan(&pl, nvary, vary, list, &err);
    sf_sweep_plan_free(&pl);
    if (rc != SF_EINPUT || strcmp(err.msg, msg) != 0)
        fail_msg("expected SF_EINPUT '%s', got %d '%s'", msg, rc, err.msg);
}

static void test_bad_specs(void **state)
{
    (void)state;
    const char *a[] = {"defaults.width"};
    expect_error(1, a, 0, "--vary defaults.width: expected KEY=V1,V2,... or KEY=START:STOP:N");
    const char *b[] = {"defaults.width=1:2:0"};
    expect_error(1, b, 0, "--vary defaults.width=1:2:0: N must be an integer from 1 to 1000000");
    const char *c[] = {"defaults.width=1:2:3,4"};
    expect_error(1, c, 0, "--vary defaults.width=1:2:3,4: a START:STOP:N range stands alone");
    const char *d[] = {"defaults.width=1,,2"};
    expect_error(1, d, 0, "--vary defaults.width=1,,2: empty or overlong value");
    const char *e[] = {"defaults.width=1,2", "defaults.width=3"};
    expect_error(2, e, 0, "--vary defaults.width=3: key varied twice");
    const char *f[] = {"defaults.width=1,2", "materials.fold.E=1,2,3"};
    expect_error(2, f, 1, "sweep list: materials.fold.E has 3 values, defaults.width 2 (a list needs "
                          "equal lengths)");
    const char *g[] = {"defaults.width=a:b:3"};
    expect_error(1, g, 0, "--vary defaults.width=a:b:3: START and STOP must be numbers");
    const char *h[] = {"defaults.width=1:2:1"};
    expect_error(1, h, 0, "--vary defaults.width=1:2:1: N = 1 needs START = STOP");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_values),
        cmocka_unit_test(test_order),
        cmocka_unit_test(test_keys),
        cmocka_unit_test(test_bad_specs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
