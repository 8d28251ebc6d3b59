/* study_test.h - paths, checks and helpers shared by the study reader's
 * tests (test_study.c, test_study_set.c; test_topology.c takes CHECK_EQ_I).
 * Include after cmocka.h.
 * Files are found through $SF_SRCDIR (set by `make check`), else the source
 * directory compiled in.  Temporary files go to $SF_BUILDDIR or /tmp. */
#ifndef SF_STUDY_TEST_H
#define SF_STUDY_TEST_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "study.h"
#include "check_test.h"

#ifndef SF_SRCDIR
#define SF_SRCDIR "."
#endif

static inline const char *srcdir(void)
{
    const char *d = getenv("SF_SRCDIR");
    return d && d[0] ? d : SF_SRCDIR;
}

static inline void src_path(char *buf, size_t n, const char *rel)
{
    snprintf(buf, n, "%s/%s", srcdir(), rel);
}

static inline void tmp_path(char *buf, size_t n, const char *name)
{
    const char *d = getenv("SF_BUILDDIR");
    snprintf(buf, n, "%s/%s.%ld", d && d[0] ? d : "/tmp", name, (long)getpid());
}

#define CHECK_EQ_D(got, want, what)                                            \
    do {                                                                       \
        double g_ = (got), w_ = (want);                                        \
        if (!(g_ == w_)) {                                                     \
            print_error("%s: expected %.17g, got %.17g (exact)\n", what, w_, g_); \
            fail();                                                            \
        }                                                                      \
    } while (0)

#define CHECK_EQ_I(got, want, what)                                            \
    do {                                                                       \
        long g_ = (long)(got), w_ = (long)(want);                              \
        if (g_ != w_) {                                                        \
            print_error("%s: expected %ld, got %ld\n", what, w_, g_);          \
            fail();                                                            \
        }                                                                      \
    } while (0)

static inline int load(const char *rel, int nset, const char *const *sets,
                sf_study *s, sf_error *e)
{
    char p[2048];
    src_path(p, sizeof p, rel);
    sf_error_clear(e);
    return sf_study_load(p, nset, sets, s, e);
}

static inline int vidx(const sf_study *s, const char *name)
{
    int i = sf_study_vertex_index(s, name);
    if (i < 0) {
        print_error("vertex %s not found\n", name);
        fail();
    }
    return i;
}

static inline const char *vname(const sf_study *s, int i) { return s->vertices[i].name; }

#endif
