/* test_topology_errors.c - every pattern error the topology reports (the
 * same patterns as tests/bad/topo_*.cfg, checked against their .expect
 * files): one fault each added to fold1, which builds without it
 * (test_errors_base in test_topology.c). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "topo_pat.h"

#ifndef SF_SRCDIR
#define SF_SRCDIR "."
#endif

/* ------------------------------------------------------------ errors */

static pat *bad_zero_length(void)
{
    pat *P = make_fold1();
    pat_vertex(P, "p", 0.045, 0.01);
    pat_vertex(P, "q", 0.045, 0.01);
    pat_fold(P, "p", "q", 0, 0);
    return P;
}

static pat *bad_duplicate(void)
{
    pat *P = make_fold1();
    pat_fold(P, "f1b", "f1a", 0, 0);
    return P;
}

static pat *bad_crossing(void)
{
    pat *P = make_fold1();
    pat_vertex(P, "g1", 0.0, 0.015);
    pat_vertex(P, "g2", 0.06, 0.015);
    pat_fold(P, "g1", "g2", 0, 0);
    return P;
}

static pat *bad_through_vertex(void)
{
    pat *P = make_fold1();
    pat_vertex(P, "m", 0.03, 0.015);
    pat_vertex(P, "g2", 0.06, 0.015);
    pat_fold(P, "m", "g2", 0, 0);
    return P;
}

static pat *bad_outside(void)
{
    pat *P = make_fold1();
    pat_vertex(P, "o1", 0.07, 0.0);
    pat_vertex(P, "o2", 0.07, 0.03);
    pat_fold(P, "o1", "o2", 0, 0);
    return P;
}

static pat *bad_cross_outline(void)
{
    pat *P = make_fold1();
    pat_vertex(P, "e1", 0.045, 0.015);
    pat_vertex(P, "e2", 0.07, 0.015);
    pat_fold(P, "e1", "e2", 0, 0);
    return P;
}

static pat *bad_on_outline(void)
{
    pat *P = make_fold1();
    pat_fold(P, "c1", "f1a", 0, 0);
    return P;
}

static pat *bad_dangling(void)
{
    pat *P = make_fold1();
    pat_vertex(P, "d1", 0.045, 0.0);
    pat_vertex(P, "d2", 0.045, 0.015);
    pat_fold(P, "d1", "d2", 0, 0);
    return P;
}

static pat *bad_island(void)
{
    pat *P = make_fold1();
    pat_vertex(P, "i1", 0.04, 0.008);
    pat_vertex(P, "i2", 0.055, 0.008);
    pat_vertex(P, "i3", 0.05, 0.025);
    P->width = 0.001;
    pat_fold(P, "i1", "i2", 0.001, 0.001);
    pat_fold(P, "i2", "i3", 0.001, 0.001);
    pat_fold(P, "i3", "i1", 0.001, 0.001);
    return P;
}

static pat *bad_outline_self(void)
{
    pat *P = make_fold1();
    pat_outline(P, "c1 c2 c4 c3");
    return P;
}

static pat *bad_outline_short(void)
{
    pat *P = make_fold1();
    pat_outline(P, "c1 c2");
    return P;
}

static pat *bad_fixed_outside(void)
{
    pat *P = make_fold1();
    pat_fixed(P, 0.1, 0.015);
    return P;
}

static pat *bad_overlap(void)
{
    pat *P = make_fold1();
    pat_vertex(P, "f2a", 0.038, 0.0);
    pat_vertex(P, "f2b", 0.038, 0.03);
    pat_fold(P, "f2a", "f2b", 0, 0);
    return P;
}

static pat *bad_overlap_vertex(void)
{
    /* two folds from one outline vertex, no setback: bands overlap there */
    pat *P = make_fold1();
    pat_fold(P, "f1a", "c3", 0, 0);
    return P;
}

static pat *bad_too_wide(void)
{
    pat *P = make_fold1();
    pat_move(P, "f1a", 0.01, 0.0);
    pat_move(P, "f1b", 0.01, 0.03);
    P->f[0].width = 0.03;
    pat_fixed(P, 0.04, 0.015);
    return P;
}

static pat *bad_setback(void)
{
    pat *P = make_fold1();
    P->f[0].setback[0] = 0.02;
    P->f[0].setback[1] = 0.02;
    return P;
}

typedef struct bad_case {
    const char *name;     /* tests/bad/topo_<name>.cfg / .expect */
    pat *(*make)(void);
    int line;             /* line the message must name (test numbering) */
} bad_case;

static const bad_case bad_cases[] = {
    {"zero_length", bad_zero_length, 201},
    {"duplicate", bad_duplicate, 201},
    {"crossing", bad_crossing, 201},
    {"through_vertex", bad_through_vertex, 200},
    {"outside", bad_outside, 201},
    {"cross_outline", bad_cross_outline, 201},
    {"on_outline", bad_on_outline, 201},
    {"dangling", bad_dangling, 201},
    {"island", bad_island, 201},
    {"outline_self", bad_outline_self, 102},
    {"outline_short", bad_outline_short, 100},
    {"fixed_outside", bad_fixed_outside, 300},
    {"overlap", bad_overlap, 201},
    {"overlap_vertex", bad_overlap_vertex, 201},
    {"too_wide", bad_too_wide, 200},
    {"setback", bad_setback, 200},
};

static int read_expect(const char *name, char *buf, size_t size)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/bad/topo_%s.expect", SF_SRCDIR, name);
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    if (!fgets(buf, (int)size, f)) buf[0] = '\0';
    fclose(f);
    buf[strcspn(buf, "\r\n")] = '\0';
    return 0;
}

static void test_errors(void **state)
{
    (void)state;
    for (size_t k = 0; k < sizeof bad_cases / sizeof bad_cases[0]; k++) {
        const bad_case *c = &bad_cases[k];
        char expect[1024], prefix[1200];
        if (read_expect(c->name, expect, sizeof expect)) {
            print_error("tests/bad/topo_%s.expect: cannot read\n", c->name);
            fail();
        }
        assert_true(strlen(expect) > 10);
        pat *P = c->make();
        snprintf(P->s.path, sizeof P->s.path, "tests/bad/topo_%s.cfg", c->name);
        sf_topology t;
        sf_error err;
        sf_error_clear(&err);
        int rc = sf_topology_build(&P->s, &t, &err);
        snprintf(prefix, sizeof prefix, "%s:%d: ", P->s.path, c->line);
        if (rc != SF_EINPUT || strncmp(err.msg, prefix, strlen(prefix)) != 0 ||
            !strstr(err.msg, expect) || strchr(err.msg, '\n')) {
            print_error("topo_%s: expected SF_EINPUT and a line \"%s...%s...\", got %d \"%s\"\n",
                        c->name, prefix, expect, rc, err.msg);
            fail();
        }
        /* left empty, and freeing it again is harmless */
        assert_int_equal(t.nfaces, 0);
        assert_null(t.faces);
        sf_topology_free(&t);
        free(P);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
