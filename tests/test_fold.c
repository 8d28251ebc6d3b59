/* test_fold.c - FOLD files: round trips through the writer (src/io) and
 * the reader (src/pattern/fold_read.c).
 *
 * - import(export(S)) for every study S in studies/: the same vertices
 *   (names and coordinates, bit for bit), the same folds in the same order
 *   with the same ends and the same fold signs, the same topology (faces
 *   as vertex sets, the outline loop, interior vertices and degrees);
 * - generator output written as FOLD and read back: the same pattern;
 * - frames, inheritance and units of the reader. */
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

#include "fold.h"
#include "foldread.h"
#include "generators.h"
#include "study.h"
#include "topology.h"
#include "sf_test.h"

#ifndef SF_SRCDIR
#define SF_SRCDIR "."
#endif

static void src_path(char *buf, size_t n, const char *rel)
{
    const char *d = getenv("SF_SRCDIR");
    snprintf(buf, n, "%s/%s", d && d[0] ? d : SF_SRCDIR, rel);
}

static void tmp_path(char *buf, size_t n, const char *name)
{
    const char *d = getenv("SF_BUILDDIR");
    snprintf(buf, n, "%s/%s.%ld", d && d[0] ? d : "/tmp", name, (long)getpid());
}

static int vidx(const sf_study *s, const char *name)
{
    int v = sf_study_vertex_index(s, name);
    if (v < 0) print_error("vertex %s missing after the round trip\n", name);
    assert_true(v >= 0);
    return v;
}

static int icmp(const void *a, const void *b) { return *(const int *)a - *(const int *)b; }

/* faces of t2 mapped to s1's vertex numbers, each sorted, compared as sets */
static void same_faces(const sf_study *s1, const sf_topology *t1, const sf_study *s2,
                       const sf_topology *t2)
{
    assert_int_equal(t1->nfaces, t2->nfaces);
    for (int f = 0; f < t1->nfaces; f++) {
        int n = t1->faces[f].nverts, found = 0;
        int *a = malloc((size_t)n * sizeof *a), *b = malloc((size_t)n * sizeof *b);
        for (int k = 0; k < n; k++) a[k] = t1->faces[f].verts[k];
        qsort(a, (size_t)n, sizeof *a, icmp);
        for (int g = 0; g < t2->nfaces && !found; g++) {
            if (t2->faces[g].nverts != n) continue;
            for (int k = 0; k < n; k++)
                b[k] = vidx(s1, s2->vertices[t2->faces[g].verts[k]].name);
            qsort(b, (size_t)n, sizeof *b, icmp);
            found = memcmp(a, b, (size_t)n * sizeof *a) == 0;
        }
        if (!found) print_error("%s: face %d has no counterpart after the round trip\n", s1->name, f + 1);
        assert_true(found);
        free(a);
        free(b);
    }
}

static void same_outline(const sf_study *s1, const sf_topology *t1, const sf_study *s2,
                         const sf_topology *t2)
{
    int n = t1->nboundary;
    assert_int_equal(n, t2->nboundary);
    int shift = -1;
    for (int k = 0; k < n; k++)
        if (vidx(s1, s2->vertices[t2->boundary[k]].name) == t1->boundary[0]) shift = k;
    assert_true(shift >= 0);
    for (int k = 0; k < n; k++)
        assert_int_equal(vidx(s1, s2->vertices[t2->boundary[(k + shift) % n]].name), t1->boundary[k]);
}

static void round_trip(const char *path)
{
    sf_study s1, s2;
    sf_topology t1, t2;
    sf_cpattern cp, cp2;
    sf_error e;
    sf_error_clear(&e);
    memset(&t1, 0, sizeof t1);
    memset(&t2, 0, sizeof t2);
    char fold[1100], cfg[1100];
    tmp_path(fold, sizeof fold, "rt.fold");
    tmp_path(cfg, sizeof cfg, "rt.cfg");
    CHECK_OK(sf_study_load(path, 0, NULL, &s1, &e), e);
    CHECK_OK(sf_topology_build(&s1, &t1, &e), e);
    CHECK_OK(sf_cp_from_study(&s1, &t1, &cp, &e), e);
    CHECK_OK(sf_fold_write_pattern(&cp, fold, &e), e);
    sf_import_opts io;
    sf_import_opts_default(&io);
    CHECK_OK(sf_import_read(fold, &io, &cp2, NULL, &e), e);
    sf_cp_study_opts o;
    sf_cp_study_opts_default(&o);
    CHECK_OK(sf_cp_write_study(&cp2, &o, cfg, 0, NULL, &e), e);
    /* a bending study's facet hinges come back as F edges, the imported
     * study's faces.facets (with bending off until it is switched on) */
    const char *bend[] = {"faces.bending=true"};
    CHECK_OK(sf_study_load(cfg, s1.bending, bend, &s2, &e), e);
    CHECK_OK(sf_topology_build(&s2, &t2, &e), e);
    /* vertices: every one the folds or the outline use, exactly */
    for (int v = 0; v < s2.nvertices; v++) {
        int u = vidx(&s1, s2.vertices[v].name);
        assert_true(s1.vertices[u].x[0] == s2.vertices[v].x[0]);
        assert_true(s1.vertices[u].x[1] == s2.vertices[v].x[1]);
    }
    /* folds: order, ends, signs (the facets: the same number, as given) */
    assert_int_equal(s1.nfolds, s2.nfolds);
    assert_int_equal(s1.nfacets, s2.nfacets);
    if (s1.bending) assert_int_equal(s1.nfacets, sf_study_count(&s2, "faces.facets"));
    for (int i = 0; i < s2.nfolds - s2.nfacets; i++) {
        assert_string_equal(s1.vertices[s1.folds[i].a].name, s2.vertices[s2.folds[i].a].name);
        assert_string_equal(s1.vertices[s1.folds[i].b].name, s2.vertices[s2.folds[i].b].name);
        assert_string_equal(s1.folds[i].name, s2.folds[i].name);
        char key[64];
        snprintf(key, sizeof key, "folds[%d].assignment", i);
        const char *a2 = "U";
        if (sf_study_has(&s2, key)) CHECK_OK(sf_study_string(&s2, key, "", &a2, &e), e);
        assert_int_equal(cp.e[i].assign, a2[0]);
        /* the sign of the rest angle at actuation 1 survives */
        double r1 = s1.folds[i].group >= 0 ? s1.groups[s1.folds[i].group].rest_angle : s1.folds[i].rest_angle;
        double r2 = s2.folds[i].group >= 0 ? s2.groups[s2.folds[i].group].rest_angle : s2.folds[i].rest_angle;
        if (cp.e[i].assign != 'U' && r1 != 0) {
            assert_true((r1 > 0) == (r2 > 0));
            assert_true(fabs(r1 - r2) <= 1e-15 * fabs(r1));
        }
    }
    /* topology */
    same_faces(&s1, &t1, &s2, &t2);
    same_outline(&s1, &t1, &s2, &t2);
    assert_int_equal(t1.nivertices, t2.nivertices);
    for (int v = 0; v < t1.nivertices; v++) {
        int w = t2.ivertex_of[vidx(&s2, s1.vertices[t1.ivertices[v].vertex].name)];
        assert_true(w >= 0);
        assert_int_equal(t1.ivertices[v].degree, t2.ivertices[w].degree);
    }
    remove(fold);
    remove(cfg);
    sf_cp_free(&cp);
    sf_cp_free(&cp2);
    sf_topology_free(&t1);
    sf_topology_free(&t2);
    sf_study_free(&s1);
    sf_study_free(&s2);
}

static void test_round_trip_studies(void **state)
{
    (void)state;
    char pat[2048];
    glob_t g;
    src_path(pat, sizeof pat, "studies/*.cfg");
    assert_int_equal(glob(pat, 0, NULL, &g), 0);
    assert_true(g.gl_pathc >= 19);
    for (size_t i = 0; i < g.gl_pathc; i++) round_trip(g.gl_pathv[i]);
    globfree(&g);
}

/* generator -> FOLD -> reader: the same pattern */
static void test_generators_reimported(void **state)
{
    (void)state;
    const char *names[] = {"miura", "yoshimura", "waterbomb"};
    char fold[1100];
    tmp_path(fold, sizeof fold, "gen.fold");
    for (int k = 0; k < 3; k++) {
        sf_gen_opts o;
        sf_cpattern a, b;
        sf_error e;
        sf_error_clear(&e);
        CHECK_OK(sf_gen_defaults(names[k], &o, &e), e);
        o.m = 3; o.n = 2;
        CHECK_OK(sf_generate(names[k], &o, &a, &e), e);
        CHECK_OK(sf_fold_write_pattern(&a, fold, &e), e);
        sf_import_opts io;
        sf_import_opts_default(&io);
        CHECK_OK(sf_import_read(fold, &io, &b, NULL, &e), e);
        assert_int_equal(a.nv, b.nv);
        assert_int_equal(a.ne, b.ne);
        for (int v = 0; v < a.nv; v++) {
            assert_true(a.v[v].x[0] == b.v[v].x[0] && a.v[v].x[1] == b.v[v].x[1]);
            assert_string_equal(a.v[v].name, b.v[v].name);
        }
        for (int i = 0; i < a.ne; i++) {
            assert_int_equal(a.e[i].a, b.e[i].a);
            assert_int_equal(a.e[i].b, b.e[i].b);
            assert_int_equal(a.e[i].assign, b.e[i].assign);
        }
        assert_true(b.unit == 1.0);
        sf_cp_free(&a);
        sf_cp_free(&b);
    }
    remove(fold);
}

static void test_frames_and_units(void **state)
{
    (void)state;
    char p[2048];
    sf_cpattern cp;
    sf_error e;
    sf_error_clear(&e);
    sf_import_opts io;
    sf_import_opts_default(&io);
    src_path(p, sizeof p, "tests/fold/frames-3d.fold");
    /* the first creasePattern frame is file_frames[0] (frame 1); it
     * inherits the edges from the top level and has its own angles */
    CHECK_OK(sf_import_read(p, &io, &cp, NULL, &e), e);
    assert_int_equal(cp.nv, 6);
    assert_int_equal(cp.ne, 7);
    assert_int_equal(cp.e[6].assign, 'M');
    assert_true(cp.e[6].angle == -45);
    assert_true(cp.unit == 0.0254);
    assert_string_equal(cp.title, "two frames");
    sf_cp_free(&cp);
    /* frame 0 is the same sheet in a tilted plane: turned into x-y, with
     * every distance kept (the diagonal from (0,0,0) to (2,1,0.5)) */
    io.frame = 0;
    sf_import_info info;
    CHECK_OK(sf_import_read(p, &io, &cp, &info, &e), e);
    double d = hypot(cp.v[2].x[0] - cp.v[0].x[0], cp.v[2].x[1] - cp.v[0].x[1]);
    CHECK_CLOSE(d, sqrt(4 + 1 + 0.25), 1e-14, "diagonal of the tilted frame after the rotation");
    CHECK_CLOSE(hypot(cp.v[1].x[0] - cp.v[0].x[0], cp.v[1].x[1] - cp.v[0].x[1]), 2.0, 1e-14, "edge v0-v1");
    assert_true(info.nnotes >= 1 && strstr(info.notes[0], "turned into the x-y plane"));
    sf_cp_free(&cp);
    io.frame = 2;
    assert_int_equal(sf_import_read(p, &io, &cp, NULL, &e), SF_EINPUT);
    assert_non_null(strstr(e.msg, "--frame 2: the file has 2 frames"));
    sf_error_clear(&e);
    /* --unit wins over frame_unit; --size over both */
    io.frame = 1;
    io.unit = "mm";
    CHECK_OK(sf_import_read(p, &io, &cp, &info, &e), e);
    assert_true(cp.unit == 1e-3);
    sf_cp_free(&cp);
    io.size = 0.5;
    CHECK_OK(sf_import_read(p, &io, &cp, &info, &e), e);
    CHECK_CLOSE(info.width, 0.5, 1e-15, "--size 0.5: the larger side");
    CHECK_CLOSE(info.height, 0.25, 1e-15, "--size 0.5: the other side in proportion");
    sf_cp_free(&cp);
    io.size = 0;
    io.unit = "furlong";
    assert_int_equal(sf_import_read(p, &io, &cp, NULL, &e), SF_EINPUT);
    assert_non_null(strstr(e.msg, "--unit furlong: unknown unit"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip_studies),
        cmocka_unit_test(test_generators_reimported),
        cmocka_unit_test(test_frames_and_units),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
