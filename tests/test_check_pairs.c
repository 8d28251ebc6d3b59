/* test_check_pairs.c - the nearby pairs the topology checks test
 * (tp_box_pairs, src/pattern/topology_grid.c) against the loop over all
 * pairs: on random boxes (spread, clustered, on one line, points, boxes
 * spanning the whole set, empty boxes), within one set and between two,
 * every pair whose boxes overlap when grown by tol is visited exactly
 * once, and no other pair. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "topology_impl.h"

static unsigned rng = 2463534242u;

static double urand(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 17;
    rng ^= rng << 5;
    return (rng & 0xffffff) / (double)0x1000000;
}

typedef struct seen {
    int na, nb;
    int *count;       /* na x nb visits */
    int bad;          /* visits with b >= a in one set */
    int self;
} seen;

static void visit(void *ctx, int a, int b)
{
    seen *s = ctx;
    if (s->self && b >= a) s->bad++;
    s->count[(size_t)a * s->nb + b]++;
}

static int near(const tp_box *x, const tp_box *y, double tol)
{
    if (!(x->lo[0] <= x->hi[0] && x->lo[1] <= x->hi[1])) return 0;
    if (!(y->lo[0] <= y->hi[0] && y->lo[1] <= y->hi[1])) return 0;
    return x->lo[0] <= y->hi[0] + tol && y->lo[0] <= x->hi[0] + tol &&
           x->lo[1] <= y->hi[1] + tol && y->lo[1] <= x->hi[1] + tol;
}

/* A random box of kind k: 0 spread short segments, 1 clustered, 2 on the
 * line y = 0.3, 3 points on a lattice (some 1e-10 off), 4 now and then one
 * over everything, 5 some empty. */
static void random_box(int k, tp_box *b)
{
    double p[2], q[2];
    if (k == 1) {
        p[0] = 0.5 + 1e-3 * urand();
        p[1] = 0.5 + 1e-3 * urand();
    } else if (k == 3) {
        /* on a lattice: coincident points, and points on cell edges */
        p[0] = floor(20.0 * urand()) / 20.0;
        p[1] = floor(20.0 * urand()) / 20.0 + (urand() < 0.3 ? 1e-10 : 0.0);
    } else {
        p[0] = urand();
        p[1] = k == 2 ? 0.3 : urand();
    }
    double len = k == 3 ? 0.0 : 0.05 * urand();
    q[0] = p[0] + len * (urand() - 0.5);
    q[1] = k == 2 ? 0.3 : p[1] + len * (urand() - 0.5);
    if (k == 4 && urand() < 0.05) {
        p[0] = p[1] = -0.1;
        q[0] = q[1] = 1.1;
    }
    tp_box_empty(b);
    if (k == 5 && urand() < 0.2) return;
    tp_box_add(b, p);
    tp_box_add(b, q);
}

static void check_sets(int k, int na, int nb, int self, double tol)
{
    tp_box *A = malloc(sizeof(tp_box) * (size_t)na), *B = malloc(sizeof(tp_box) * (size_t)nb);
    assert_true(A && B);
    for (int a = 0; a < na; a++) random_box(k, &A[a]);
    for (int b = 0; b < nb; b++) random_box(k, &B[b]);
    seen s = {na, self ? na : nb, NULL, 0, self};
    s.count = calloc((size_t)na * s.nb, sizeof(int));
    assert_non_null(s.count);
    assert_int_equal(tp_box_pairs(na, A, nb, self ? NULL : B, tol, visit, &s), 0);
    assert_int_equal(s.bad, 0);
    long pairs = 0;
    for (int a = 0; a < na; a++)
        for (int b = 0; b < (self ? a : nb); b++) {
            int want = near(&A[a], self ? &A[b] : &B[b], tol);
            int got = s.count[(size_t)a * s.nb + b];
            if (got != want) {
                print_error("kind %d, %s, tol %g: pair (%d, %d) visited %d times, expected %d\n", k,
                            self ? "one set" : "two sets", tol, a, b, got, want);
                fail();
            }
            pairs += want;
        }
    print_message("# kind %d, %s (%d, %d boxes), tol %g: %ld pairs\n", k,
                  self ? "one set" : "two sets", na, self ? na : nb, tol, pairs);
    free(s.count);
    free(A);
    free(B);
}

static void test_pairs(void **state)
{
    (void)state;
    for (int k = 0; k < 6; k++) {
        check_sets(k, 700, 0, 1, 1e-9);
        check_sets(k, 500, 300, 0, 1e-9);
        check_sets(k, 400, 0, 1, 0.01);
        check_sets(k, 1, 0, 1, 0.0);
        check_sets(k, 2, 1, 0, 0.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pairs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
