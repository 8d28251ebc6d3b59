/* topo_pat.c - crease patterns built in C for the topology tests
 * (topo_pat.h): the builder, and the CASES.md patterns strip3, waterbomb2,
 * square4 (and variants) and fold1. */
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

pat *pat_new(const char *path)
{
    pat *P = calloc(1, sizeof *P);
    assert_non_null(P);
    snprintf(P->s.name, sizeof P->s.name, "test");
    snprintf(P->s.path, sizeof P->s.path, "%s", path);
    P->s.vertices = P->v;
    P->s.folds = P->f;
    P->s.outline = P->outline;
    snprintf(P->mat.name, sizeof P->mat.name, "fold");
    P->mat.E = 15.2e6;
    P->mat.nu = 0.45;
    P->mat.thickness = 1.8e-3;
    P->mat.density = 1200.0;
    P->s.materials = &P->mat;
    P->s.nmaterials = 1;
    P->s.face_material = -1;
    P->s.fixed_line = 300;
    P->width = 0.01;
    return P;
}

int pat_find(const pat *P, const char *name)
{
    for (int i = 0; i < P->s.nvertices; i++)
        if (strcmp(P->v[i].name, name) == 0) return i;
    print_error("no vertex %s\n", name);
    fail();
    return -1;
}

void pat_vertex(pat *P, const char *name, double x, double y)
{
    assert_true(P->s.nvertices < MAXV);
    sf_vertex *v = &P->v[P->s.nvertices];
    snprintf(v->name, sizeof v->name, "%s", name);
    v->x[0] = x;
    v->x[1] = y;
    v->line = 100 + P->s.nvertices;
    P->s.nvertices++;
}

void pat_move(pat *P, const char *name, double x, double y)
{
    int i = pat_find(P, name);
    P->v[i].x[0] = x;
    P->v[i].x[1] = y;
}

/* outline from a space-separated list of names */
void pat_outline(pat *P, const char *names)
{
    char buf[512], *save = NULL;
    snprintf(buf, sizeof buf, "%s", names);
    P->s.noutline = 0;
    for (char *tok = strtok_r(buf, " ", &save); tok; tok = strtok_r(NULL, " ", &save))
        P->outline[P->s.noutline++] = pat_find(P, tok);
}

void pat_fold(pat *P, const char *a, const char *b, double da, double db)
{
    assert_true(P->s.nfolds < MAXF);
    sf_fold_def *f = &P->f[P->s.nfolds];
    memset(f, 0, sizeof *f);
    f->a = pat_find(P, a);
    f->b = pat_find(P, b);
    f->width = P->width;
    f->setback[0] = da;
    f->setback[1] = db;
    f->continuity = 1;
    f->group = -1;
    f->line = 200 + P->s.nfolds;
    P->s.nfolds++;
}

void pat_fixed(pat *P, double x, double y)
{
    P->s.fixed_point[0] = x;
    P->s.fixed_point[1] = y;
}

/* --- CASES.md patterns */

pat *make_strip3(int cw)
{
    pat *P = pat_new("studies/strip3.cfg");
    pat_vertex(P, "c1", 0.0, 0.0);
    pat_vertex(P, "c2", 0.12, 0.0);
    pat_vertex(P, "c3", 0.12, 0.03);
    pat_vertex(P, "c4", 0.0, 0.03);
    const double xs[3] = {0.03, 0.06, 0.09};
    for (int k = 0; k < 3; k++) {
        char a[16], b[16];
        snprintf(a, sizeof a, "f%da", k + 1);
        snprintf(b, sizeof b, "f%db", k + 1);
        pat_vertex(P, a, xs[k], 0.0);
        pat_vertex(P, b, xs[k], 0.03);
    }
    pat_outline(P, cw ? "c4 c3 c2 c1" : "c1 c2 c3 c4");
    pat_fold(P, "f1a", "f1b", 0, 0);
    pat_fold(P, "f2a", "f2b", 0, 0);
    pat_fold(P, "f3a", "f3b", 0, 0);
    pat_fixed(P, 0.01, 0.015);
    return P;
}

pat *make_waterbomb2(void)
{
    pat *P = pat_new("studies/waterbomb2.cfg");
    const double xy[14][2] = {{0, 0}, {0.04, 0}, {0.08, 0}, {0.12, 0}, {0.16, 0},
                              {0, 0.04}, {0.04, 0.04}, {0.12, 0.04}, {0.16, 0.04},
                              {0, 0.08}, {0.04, 0.08}, {0.08, 0.08}, {0.12, 0.08}, {0.16, 0.08}};
    for (int i = 0; i < 14; i++) {
        char nm[16];
        snprintf(nm, sizeof nm, "v%d", i + 1);
        pat_vertex(P, nm, xy[i][0], xy[i][1]);
    }
    pat_outline(P, "v1 v5 v14 v10");
    P->width = 8.25e-3;
    const double so = 1.0e-3, sd = 5.23e-3, si = 0.011;
    pat_fold(P, "v7", "v1", si, sd);
    pat_fold(P, "v7", "v2", si, so);
    pat_fold(P, "v7", "v3", si, sd);
    pat_fold(P, "v8", "v3", si, sd);
    pat_fold(P, "v8", "v4", si, so);
    pat_fold(P, "v8", "v5", si, sd);
    pat_fold(P, "v7", "v6", si, so);
    pat_fold(P, "v7", "v8", si, si);
    pat_fold(P, "v8", "v9", si, so);
    pat_fold(P, "v7", "v10", si, sd);
    pat_fold(P, "v7", "v11", si, so);
    pat_fold(P, "v7", "v12", si, sd);
    pat_fold(P, "v8", "v12", si, sd);
    pat_fold(P, "v8", "v13", si, so);
    pat_fold(P, "v8", "v14", si, sd);
    pat_fixed(P, 0.01, 0.03);
    return P;
}

pat *make_square4(int variant)
{
    pat *P = pat_new("studies/square4.cfg");
    const double xy[20][2] = {{-0.4, -0.4}, {-0.2, -0.4}, {0, -0.4}, {0.2, -0.4}, {0.4, -0.4},
                              {-0.4, -0.2}, {-0.2, -0.2}, {0.2, -0.2}, {0.4, -0.2},
                              {-0.4, 0}, {0.4, 0},
                              {-0.4, 0.2}, {-0.2, 0.2}, {0.2, 0.2}, {0.4, 0.2},
                              {-0.4, 0.4}, {-0.2, 0.4}, {0, 0.4}, {0.2, 0.4}, {0.4, 0.4}};
    for (int i = 0; i < 20; i++) {
        char nm[16];
        snprintf(nm, sizeof nm, "v%d", i + 1);
        pat_vertex(P, nm, xy[i][0], xy[i][1]);
    }
    if (variant == SQ_IRREGULAR) {
        pat_move(P, "v1", -0.5, -0.5);
        pat_move(P, "v5", 0.5, -0.5);
        pat_move(P, "v16", -0.5, 0.5);
        pat_move(P, "v20", 0.5, 0.5);
        pat_move(P, "v7", -0.18, -0.2);
        pat_move(P, "v8", 0.2, -0.18);
        pat_move(P, "v13", -0.2, 0.18);
        pat_move(P, "v14", 0.18, 0.2);
        /* the corners now stick out: every boundary vertex is an outline
         * corner; given clockwise to exercise the reorientation */
        pat_outline(P, "v1 v6 v10 v12 v16 v17 v18 v19 v20 v15 v11 v9 v5 v4 v3 v2");
    } else {
        pat_outline(P, "v1 v5 v20 v16");
    }
    P->width = variant == SQ_NARROW ? 0.02 : 0.04;
    static const char *folds[24][2] = {
        {"v7", "v1"}, {"v7", "v2"}, {"v7", "v3"}, {"v8", "v3"}, {"v8", "v4"}, {"v8", "v5"},
        {"v7", "v6"}, {"v7", "v8"}, {"v8", "v9"}, {"v7", "v10"}, {"v7", "v13"}, {"v8", "v14"},
        {"v8", "v11"}, {"v13", "v10"}, {"v14", "v11"}, {"v13", "v12"}, {"v13", "v14"},
        {"v14", "v15"}, {"v13", "v16"}, {"v13", "v17"}, {"v13", "v18"}, {"v14", "v18"},
        {"v14", "v19"}, {"v14", "v20"}};
    static const char *short_end[] = {"v2", "v4", "v6", "v9", "v12", "v15", "v17", "v19"};
    for (int i = 0; i < 24; i++) {
        double db = 0.08;
        for (int k = 0; k < 8; k++)
            if (strcmp(folds[i][1], short_end[k]) == 0) db = 0.04;
        pat_fold(P, folds[i][0], folds[i][1], 0.08, db);
    }
    if (variant == SQ_CORNER) pat_fixed(P, 0.0, -0.3);
    else pat_fixed(P, 0.0, 0.0);
    return P;
}

pat *make_fold1(void)
{
    pat *P = pat_new("tests/bad/topo_x.cfg");
    pat_vertex(P, "c1", 0.0, 0.0);
    pat_vertex(P, "c2", 0.06, 0.0);
    pat_vertex(P, "c3", 0.06, 0.03);
    pat_vertex(P, "c4", 0.0, 0.03);
    pat_vertex(P, "f1a", 0.03, 0.0);
    pat_vertex(P, "f1b", 0.03, 0.03);
    pat_outline(P, "c1 c2 c3 c4");
    pat_fold(P, "f1a", "f1b", 0, 0);
    pat_fixed(P, 0.01, 0.015);
    return P;
}

void build_ok(pat *P, sf_topology *t)
{
    sf_error err;
    sf_error_clear(&err);
    int rc = sf_topology_build(&P->s, t, &err);
    if (rc != SF_OK) {
        print_error("sf_topology_build failed (%d): %s\n", rc, err.msg);
        fail();
    }
}
