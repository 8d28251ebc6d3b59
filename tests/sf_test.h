/* sf_test.h - helpers shared by the model tests (include after cmocka.h).
 *
 * Define SF_TEST_SEED before including to give a file its own sequence of
 * random states. */
#ifndef SF_TEST_H
#define SF_TEST_H

#include <math.h>
#include <stdio.h>

#include "check_test.h"
#include "scene.h"

/* Fails with what was expected, what came, and the tolerance. */
#define CHECK_CLOSE(got, want, tol, ...)                                        \
    do {                                                                        \
        double g_ = (got), w_ = (want), t_ = (tol);                             \
        if (!(fabs(g_ - w_) <= t_)) {                                           \
            char what_[256];                                                    \
            snprintf(what_, sizeof what_, __VA_ARGS__);                         \
            print_error("%s: expected %.15g, got %.15g (|diff| %.3g > tol %.3g)\n", \
                        what_, w_, g_, fabs(g_ - w_), t_);                      \
            fail();                                                             \
        }                                                                       \
    } while (0)

/* Fails when got exceeds bound. */
#define CHECK_LE(got, bound, ...)                                               \
    do {                                                                        \
        double g_ = (got), b_ = (bound);                                        \
        if (!(g_ <= b_)) {                                                      \
            char what_[256];                                                    \
            snprintf(what_, sizeof what_, __VA_ARGS__);                         \
            print_error("%s: %.6g exceeds %.6g\n", what_, g_, b_);              \
            fail();                                                             \
        }                                                                       \
    } while (0)

#ifndef SF_TEST_SEED
#define SF_TEST_SEED 12345u
#endif

static unsigned rng_state = SF_TEST_SEED;

/* Uniform in [a, b): a small LCG, so failures are reproducible. */
static inline double urand(double a, double b)
{
    rng_state = rng_state * 1103515245u + 12345u;
    return a + (b - a) * ((rng_state >> 8) & 0xffffff) / (double)0x1000000;
}

/* A random state of model m: fold angles in [-amax, amax], shape mode
 * amplitudes in [-amodes, amodes]. */
static inline void random_state(const sf_model *m, double *q, double amax, double amodes)
{
    for (int i = 0; i < m->nfolds; i++) {
        q[m->qoff[i]] = urand(-amax, amax);
        for (int k = 1; k < m->qn[i]; k++) q[m->qoff[i] + k] = urand(-amodes, amodes);
    }
}

/* Directory of the studies, set by main from SF_SRCDIR. */
static char studies_dir[1024];

/* Open studies/NAME.cfg with overrides, or fail the test with the message. */
static inline void open_scene(sf_scene *sc, const char *name, int nset, const char **sets)
{
    char path[1200];
    sf_error err;
    sf_error_clear(&err);
    snprintf(path, sizeof path, "%s/%s.cfg", studies_dir, name);
    if (sf_scene_open(sc, path, nset, sets, &err)) {
        print_error("cannot open %s: %s\n", path, err.msg);
        fail();
    }
}

static inline double maxabs(const double *a, size_t n)
{
    double m = 0;
    for (size_t i = 0; i < n; i++) m = fmax(m, fabs(a[i]));
    return m;
}

/* Analytic A (n entries) against finite differences F, entry by entry:
 * |A_i - F_i| <= 1e-6 max(|F_i|, 1e-3 max|F|) + floor, the floor an
 * absolute bound for entries that are zero by structure. */
static inline void check_fd(const double *A, const double *F, size_t n, double floor,
                            const char *what)
{
    double scale = maxabs(F, n);
    for (size_t i = 0; i < n; i++)
        CHECK_CLOSE(A[i], F[i], 1e-6 * fmax(fabs(F[i]), 1e-3 * scale) + floor,
                    "%s entry %zu", what, i);
}

#endif
