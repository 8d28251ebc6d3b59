/* test_topology.c - faces, fold sides, vertex cycles, face tree and face
 * bodies of the reference patterns (CASES.md), built in C without the study
 * parser (topo_pat.h).  The pattern errors are tested in
 * test_topology_errors.c. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


#ifndef SF_SRCDIR
#define SF_SRCDIR "."
#endif

#define PI_ 3.14159265358979323846


#define SF_TEST_SEED 2024u
#include "sf_test.h"    /* CHECK_CLOSE, urand */
#include "study_test.h" /* CHECK_EQ_I */
#include "topo_pat.h"

/* ------------------------------------------------------------ invariants */

static double dist2_(const double a[2], const double b[2])
{
    return hypot(b[0] - a[0], b[1] - a[1]);
}

static int face_has_vertex(const sf_face *F, int v)
{
    for (int i = 0; i < F->nverts; i++)
        if (F->verts[i] == v) return 1;
    return 0;
}

/* Checks every pattern must pass, whatever its shape. */
static void check_invariants(const pat *P, const sf_topology *t)
{
    const sf_study *s = &P->s;
    char what[256];
    CHECK_EQ_I(t->nfolds, s->nfolds, "number of folds");
    double tol = 1e-9 * t->size;

    /* faces: ccw polygons tiling the sheet; bodies inside them */
    double sum = 0.0;
    for (int f = 0; f < t->nfaces; f++) {
        const sf_face *F = &t->faces[f];
        double a = 0.0;
        for (int i = 0; i < F->nverts; i++) {
            const double *p = F->poly.p[i], *q = F->poly.p[(i + 1) % F->nverts];
            a += 0.5 * (p[0] * q[1] - q[0] * p[1]);
            CHECK_CLOSE(p[0], s->vertices[F->verts[i]].x[0], 0, "poly matches verts");
        }
        snprintf(what, sizeof what, "face %d is ccw", f + 1);
        assert_true(a > 0.0);
        sum += a;
        snprintf(what, sizeof what, "face %d body area <= face area", f + 1);
        assert_true(F->area > 0.0 && F->area < a);
        for (int k = 0; k < F->body.n; k++) assert_true(sf_polygon_contains(&F->poly, F->body.p[k], tol));
        assert_true(sf_polygon_contains(&F->body, F->centroid, 0.0));
        assert_int_equal(sf_topology_locate_band(t, F->centroid, NULL, NULL), -1);
        assert_int_equal(sf_topology_locate_face(t, F->centroid), f);
    }
    CHECK_CLOSE(sum, t->sheet_area, 1e-12 * t->sheet_area, "faces tile the sheet");

    /* folds: the left face is on the +n side, the right face on the -n side */
    for (int i = 0; i < t->nfolds; i++) {
        const sf_fold_geom *g = &t->folds[i];
        assert_true(g->left >= 0 && g->right >= 0 && g->left != g->right);
        double mid[2] = {0.5 * (g->a[0] + g->b[0]), 0.5 * (g->a[1] + g->b[1])};
        double h = 1e-6 * t->size;
        double pl[2] = {mid[0] + h * g->n[0], mid[1] + h * g->n[1]};
        double pr[2] = {mid[0] - h * g->n[0], mid[1] - h * g->n[1]};
        snprintf(what, sizeof what, "fold %d: left face %d contains a point +n of its middle",
                 i + 1, g->left + 1);
        if (!sf_polygon_contains(&t->faces[g->left].poly, pl, 0.0) ||
            sf_polygon_contains(&t->faces[g->left].poly, pr, 0.0) ||
            !sf_polygon_contains(&t->faces[g->right].poly, pr, 0.0)) {
            print_error("%s: failed\n", what);
            fail();
        }
        assert_int_equal(sf_topology_locate_face(t, pl), g->left);
        assert_int_equal(sf_topology_locate_face(t, pr), g->right);
        /* band geometry */
        const sf_fold_def *d = &s->folds[i];
        CHECK_CLOSE(g->L, g->l - d->setback[0] - d->setback[1], 1e-15, "band length");
        CHECK_CLOSE(dist2_(g->corner[0], g->corner[3]), d->width, 1e-12, "band width p1-p4");
        double bm[2] = {0.25 * (g->corner[0][0] + g->corner[1][0] + g->corner[2][0] + g->corner[3][0]),
                        0.25 * (g->corner[0][1] + g->corner[1][1] + g->corner[2][1] + g->corner[3][1])};
        double tp, up;
        assert_int_equal(sf_topology_locate_band(t, bm, &tp, &up), i);
        CHECK_CLOSE(tp, d->setback[0] + 0.5 * g->L, 1e-12, "band middle t");
        CHECK_CLOSE(up, 0.0, 1e-12, "band middle u");
        /* both faces of the fold have the fold as an edge */
        for (int side = 0; side < 2; side++) {
            const sf_face *F = &t->faces[side ? g->right : g->left];
            int found = 0;
            for (int k = 0; k < F->nverts; k++) found += F->edge_fold[k] == i;
            assert_int_equal(found, 1);
        }
    }

    /* interior vertices: ccw order, signs and faces between folds */
    int niv = 0;
    for (int v = 0; v < s->nvertices; v++) {
        int deg = 0, onb = 0;
        for (int i = 0; i < s->nfolds; i++) deg += s->folds[i].a == v || s->folds[i].b == v;
        for (int k = 0; k < t->nboundary; k++) onb |= t->boundary[k] == v;
        if (deg > 0 && !onb) {
            assert_int_equal(t->ivertex_of[v], niv);
            assert_int_equal(t->ivertices[niv].degree, deg);
            niv++;
        } else {
            assert_int_equal(t->ivertex_of[v], -1);
        }
    }
    assert_int_equal(t->nivertices, niv);
    for (int k = 0; k < t->nivertices; k++) {
        const sf_ivertex *iv = &t->ivertices[k];
        double prev = -1.0;
        for (int j = 0; j < iv->degree; j++) {
            int i = iv->folds[j];
            const sf_fold_geom *g = &t->folds[i];
            const sf_fold_def *d = &s->folds[i];
            assert_int_equal(iv->sign[j], d->a == iv->vertex ? +1 : -1);
            assert_true(d->a == iv->vertex || d->b == iv->vertex);
            double e[2] = {iv->sign[j] * g->m[0], iv->sign[j] * g->m[1]};
            double ang = atan2(e[1], e[0]);
            if (ang < 0) ang += 2 * PI_;
            snprintf(what, sizeof what, "vertex %s: folds sorted ccw from angle 0",
                     s->vertices[iv->vertex].name);
            assert_true(ang > prev);
            prev = ang;
            /* the face ccw after fold j is its left face when it leaves, its
             * right face when it arrives; and it lies in the angle between
             * fold j and fold j+1 */
            int want = iv->sign[j] > 0 ? g->left : g->right;
            assert_int_equal(iv->faces[j], want);
            int j2 = (j + 1) % iv->degree;
            const sf_fold_geom *g2 = &t->folds[iv->folds[j2]];
            double e2[2] = {iv->sign[j2] * g2->m[0], iv->sign[j2] * g2->m[1]};
            double a2 = atan2(e2[1], e2[0]);
            if (a2 < 0) a2 += 2 * PI_;
            double span = a2 - ang;
            if (span <= 0) span += 2 * PI_;
            double bis = ang + 0.5 * span, r = 1e-4 * t->size;
            const double *x = s->vertices[iv->vertex].x;
            double p[2] = {x[0] + r * cos(bis), x[1] + r * sin(bis)};
            assert_int_equal(sf_topology_locate_face(t, p), iv->faces[j]);
            assert_true(face_has_vertex(&t->faces[iv->faces[j]], iv->vertex));
        }
    }

    /* face tree: every face reached, parents first, parent folds between */
    assert_true(t->root >= 0 && t->root < t->nfaces);
    assert_true(sf_polygon_contains(&t->faces[t->root].poly, s->fixed_point, 0.0));
    assert_int_equal(t->faces[t->root].parent, -1);
    assert_int_equal(t->faces[t->root].parent_fold, -1);
    assert_int_equal(t->faces[t->root].depth, 0);
    assert_int_equal(t->order[0], t->root);
    int *seen = calloc((size_t)t->nfaces, sizeof(int));
    assert_non_null(seen);
    for (int k = 0; k < t->nfaces; k++) {
        int f = t->order[k];
        assert_true(f >= 0 && f < t->nfaces);
        assert_false(seen[f]);
        const sf_face *F = &t->faces[f];
        if (f != t->root) {
            assert_true(seen[F->parent]);
            assert_int_equal(F->depth, t->faces[F->parent].depth + 1);
            const sf_fold_geom *g = &t->folds[F->parent_fold];
            assert_true((g->left == f && g->right == F->parent) ||
                        (g->right == f && g->left == F->parent));
        }
        seen[f] = 1;
    }
    free(seen);
}

/* ------------------------------------------------------------ independent area budget */

/* Area of the small polygon each interior vertex leaves: for every fold in
 * ccw order, its band corner nearest the vertex on the cw side, then the one
 * on the ccw side.  Computed from the study alone. */
static double vertex_polygons_area(const pat *P)
{
    const sf_study *s = &P->s;
    double total = 0.0;
    for (int v = 0; v < s->nvertices; v++) {
        int idx[MAXF], n = 0;
        double ang[MAXF];
        for (int i = 0; i < s->nfolds; i++) {
            const sf_fold_def *f = &s->folds[i];
            if (f->a != v && f->b != v) continue;
            int o = f->a == v ? f->b : f->a;
            double a = atan2(s->vertices[o].x[1] - s->vertices[v].x[1],
                             s->vertices[o].x[0] - s->vertices[v].x[0]);
            int k = n++;
            while (k > 0 && ang[k - 1] > a) {
                ang[k] = ang[k - 1];
                idx[k] = idx[k - 1];
                k--;
            }
            ang[k] = a;
            idx[k] = i;
        }
        if (n < 3) continue;   /* in the reference cases: an outline vertex */
        double poly[2 * MAXF][2];
        const double *x = s->vertices[v].x;
        for (int k = 0; k < n; k++) {
            const sf_fold_def *f = &s->folds[idx[k]];
            double sb = f->a == v ? f->setback[0] : f->setback[1], h = 0.5 * f->width;
            double e[2] = {cos(ang[k]), sin(ang[k])}, q[2] = {-e[1], e[0]};
            for (int c = 0; c < 2; c++) {
                double sg = c == 0 ? -1.0 : 1.0;
                poly[2 * k + c][0] = x[0] + sb * e[0] + sg * h * q[0];
                poly[2 * k + c][1] = x[1] + sb * e[1] + sg * h * q[1];
            }
        }
        double a = 0.0;
        for (int k = 0; k < 2 * n; k++) {
            const double *p = poly[k], *q = poly[(k + 1) % (2 * n)];
            a += 0.5 * (p[0] * q[1] - q[0] * p[1]);
        }
        total += a;
    }
    return total;
}

static double bands_area(const pat *P)
{
    double a = 0.0;
    for (int i = 0; i < P->s.nfolds; i++) {
        const sf_fold_def *f = &P->s.folds[i];
        double l = dist2_(P->s.vertices[f->a].x, P->s.vertices[f->b].x);
        a += f->width * (l - f->setback[0] - f->setback[1]);
    }
    return a;
}

static double bodies_area(const sf_topology *t)
{
    double a = 0.0;
    for (int f = 0; f < t->nfaces; f++) a += t->faces[f].area;
    return a;
}

/* ------------------------------------------------------------ the cases */

static void test_strip3(void **state)
{
    (void)state;
    for (int cw = 0; cw < 2; cw++) {
        pat *P = make_strip3(cw);
        sf_topology t;
        build_ok(P, &t);
        CHECK_EQ_I(t.nfaces, 4, "strip3 faces");
        CHECK_EQ_I(t.nfolds, 3, "strip3 folds");
        CHECK_EQ_I(t.nivertices, 0, "strip3 interior vertices");
        /* 4 corners given, 6 fold ends inserted, ccw from c1 (or c4) */
        CHECK_EQ_I(t.nboundary, 10, "strip3 boundary length");
        CHECK_CLOSE(t.sheet_area, 0.12 * 0.03, 1e-18, "strip3 sheet area");
        check_invariants(P, &t);
        const double at[2] = {0.01, 0.015};
        assert_int_equal(t.root, sf_topology_locate_face(&t, at));
        assert_true(sf_polygon_contains(&t.faces[t.root].poly, at, 0.0));
        /* bodies: the bands [x-0.005, x+0.005] removed */
        const double probe[4] = {0.01, 0.045, 0.075, 0.11};
        const double width[4] = {0.025, 0.02, 0.02, 0.025};
        const double cx[4] = {0.0125, 0.045, 0.075, 0.1075};
        for (int k = 0; k < 4; k++) {
            int f = sf_topology_locate_face(&t, (double[2]){probe[k], 0.015});
            assert_true(f >= 0);
            char what[64];
            snprintf(what, sizeof what, "strip3 body area of the face at x=%g", probe[k]);
            CHECK_CLOSE(t.faces[f].area, width[k] * 0.03, 1e-15, "%s", what);
            CHECK_CLOSE(t.faces[f].centroid[0], cx[k], 1e-14, "strip3 centroid x");
            CHECK_CLOSE(t.faces[f].centroid[1], 0.015, 1e-14, "strip3 centroid y");
            assert_int_equal(t.faces[f].nverts, 4);
            assert_int_equal(t.faces[f].body.n, 4);
            assert_int_equal(t.faces[f].depth, k);
        }
        CHECK_CLOSE(bodies_area(&t), t.sheet_area - bands_area(P), 1e-15, "strip3 area budget");
        /* folds run upwards: n = (-1, 0), so the left face is the one at
         * smaller x */
        const double left_cx[3] = {0.0125, 0.045, 0.075};
        for (int i = 0; i < 3; i++)
            CHECK_CLOSE(t.faces[t.folds[i].left].centroid[0], left_cx[i], 1e-12, "strip3 left face");
        sf_topology_free(&t);
        free(P);
    }
}

static void test_waterbomb2(void **state)
{
    (void)state;
    pat *P = make_waterbomb2();
    sf_topology t;
    build_ok(P, &t);
    CHECK_EQ_I(t.nfaces, 14, "waterbomb2 faces");
    CHECK_EQ_I(t.nfolds, 15, "waterbomb2 folds");
    CHECK_EQ_I(t.nivertices, 2, "waterbomb2 interior vertices");
    for (int k = 0; k < 2; k++) CHECK_EQ_I(t.ivertices[k].degree, 8, "waterbomb2 degree");
    assert_string_equal(P->v[t.ivertices[0].vertex].name, "v7");
    assert_string_equal(P->v[t.ivertices[1].vertex].name, "v8");
    check_invariants(P, &t);
    /* fixed face: triangle v1 v7 v6 */
    const sf_face *R = &t.faces[t.root];
    assert_int_equal(R->nverts, 3);
    assert_true(face_has_vertex(R, pat_find(P, "v1")) && face_has_vertex(R, pat_find(P, "v7")) &&
                face_has_vertex(R, pat_find(P, "v6")));
    /* the load point (0.157, 0.0675) is in triangle v8 v9 v14 */
    int f = sf_topology_locate_face(&t, (double[2]){0.157, 0.0675});
    assert_true(f >= 0 && face_has_vertex(&t.faces[f], pat_find(P, "v14")) &&
                face_has_vertex(&t.faces[f], pat_find(P, "v9")));
    /* area budget: sheet = bodies + bands + vertex polygons + end strips.
     * Strips (band continued to the outline, width w, setback d there):
     * across a straight edge w d; a diagonal into a right-angled corner
     * w d - (w/2)^2; two diagonals meeting at right angles on an edge
     * 2 w d - w^2/2 (they share half a w-by-w square). */
    double w = 8.25e-3, so = 1.0e-3, sd = 5.23e-3;
    double strips = 6 * w * so + 4 * (w * sd - 0.25 * w * w) + 2 * (2 * w * sd - 0.5 * w * w);
    double want = t.sheet_area - bands_area(P) - vertex_polygons_area(P) - strips;
    CHECK_CLOSE(bodies_area(&t), want, 1e-12 * t.sheet_area, "waterbomb2 area budget");
    sf_topology_free(&t);
    free(P);
}

static void test_square4(void **state)
{
    (void)state;
    pat *P = make_square4(SQ_PLAIN);
    sf_topology t;
    build_ok(P, &t);
    CHECK_EQ_I(t.nfaces, 21, "square4 faces");
    CHECK_EQ_I(t.nfolds, 24, "square4 folds");
    CHECK_EQ_I(t.nivertices, 4, "square4 interior vertices");
    for (int k = 0; k < 4; k++) CHECK_EQ_I(t.ivertices[k].degree, 7, "square4 degree");
    CHECK_EQ_I(t.nboundary, 16, "square4 boundary (4 corners + 12 inserted)");
    check_invariants(P, &t);
    /* root: the central square */
    const sf_face *R = &t.faces[t.root];
    assert_int_equal(R->nverts, 4);
    assert_true(face_has_vertex(R, pat_find(P, "v7")) && face_has_vertex(R, pat_find(P, "v14")));
    /* the 0.36 x 0.36 square left by the bands, less a right triangle with
     * legs 0.08 - 0.02 at each corner (the vertex polygons' cuts) */
    CHECK_CLOSE(R->area, 0.36 * 0.36 - 4 * 0.5 * 0.06 * 0.06, 1e-15, "square4 central body");
    /* faces in the tree: the 4 middle triangles at depth 1 */
    int d1 = 0;
    for (int f = 0; f < t.nfaces; f++) d1 += t.faces[f].depth == 1;
    CHECK_EQ_I(d1, 4, "square4 faces next to the root");
    double w = 0.04;
    double strips = 8 * w * 0.04 + 4 * (w * 0.08 - 0.25 * w * w) + 4 * (2 * w * 0.08 - 0.5 * w * w);
    double want = t.sheet_area - bands_area(P) - vertex_polygons_area(P) - strips;
    CHECK_CLOSE(bodies_area(&t), want, 1e-12 * t.sheet_area, "square4 area budget");
    sf_topology_free(&t);
    free(P);
}

static void test_square4_variants(void **state)
{
    (void)state;
    for (int variant = SQ_NARROW; variant <= SQ_IRREGULAR; variant++) {
        pat *P = make_square4(variant);
        sf_topology t;
        build_ok(P, &t);
        CHECK_EQ_I(t.nfaces, 21, "square4 variant faces");
        CHECK_EQ_I(t.nivertices, 4, "square4 variant interior vertices");
        check_invariants(P, &t);
        if (variant == SQ_CORNER) {
            const sf_face *R = &t.faces[t.root];
            assert_int_equal(R->nverts, 3);
            assert_true(face_has_vertex(R, pat_find(P, "v3")) &&
                        face_has_vertex(R, pat_find(P, "v7")) &&
                        face_has_vertex(R, pat_find(P, "v8")));
        }
        if (variant == SQ_NARROW) {
            double w = 0.02;
            double strips = 8 * w * 0.04 + 4 * (w * 0.08 - 0.25 * w * w) +
                            4 * (2 * w * 0.08 - 0.5 * w * w);
            double want = t.sheet_area - bands_area(P) - vertex_polygons_area(P) - strips;
            CHECK_CLOSE(bodies_area(&t), want, 1e-12 * t.sheet_area, "square4-narrow area budget");
        }
        if (variant == SQ_IRREGULAR) {
            /* outline given clockwise: boundary comes out ccw, 16 corners */
            CHECK_EQ_I(t.nboundary, 16, "square4-irregular boundary");
            /* each corner pulled out adds two triangles, base 0.2, height 0.1 */
            CHECK_CLOSE(t.sheet_area, 0.64 + 4 * 2 * (0.5 * 0.2 * 0.1), 1e-15,
                        "square4-irregular sheet area");
            /* load and report points are inside the sheet */
            const double pts[5][2] = {{0.3272, 0}, {0, 0.3272}, {-0.3272, 0}, {0, -0.3272},
                                      {0, 0}};
            for (int k = 0; k < 5; k++) assert_true(sf_topology_locate_face(&t, pts[k]) >= 0);
        }
        sf_topology_free(&t);
        free(P);
    }
}

static void test_locate(void **state)
{
    (void)state;
    pat *P = make_strip3(0);
    sf_topology t;
    build_ok(P, &t);
    /* outside the sheet */
    assert_int_equal(sf_topology_locate_face(&t, (double[2]){-0.001, 0.015}), -1);
    assert_int_equal(sf_topology_locate_face(&t, (double[2]){0.05, 0.031}), -1);
    /* on the outline: still in the sheet (tolerance relative to its size) */
    assert_true(sf_topology_locate_face(&t, (double[2]){0.12, 0.015}) >= 0);
    assert_true(sf_topology_locate_face(&t, (double[2]){0.12 + 1e-12, 0.015}) >= 0);
    /* on a fold: either face */
    int f = sf_topology_locate_face(&t, (double[2]){0.03, 0.015});
    assert_true(f == t.folds[0].left || f == t.folds[0].right);
    /* bands: fold 1 runs up x = 0.03, n = (-1, 0) */
    double tp = -1, up = -1;
    assert_int_equal(sf_topology_locate_band(&t, (double[2]){0.032, 0.01}, &tp, &up), 0);
    CHECK_CLOSE(tp, 0.01, 1e-15, "band t");
    CHECK_CLOSE(up, -0.002, 1e-15, "band u");
    assert_int_equal(sf_topology_locate_band(&t, (double[2]){0.09, 0.03}, NULL, NULL), 2);
    assert_int_equal(sf_topology_locate_band(&t, (double[2]){0.0355, 0.01}, NULL, NULL), -1);
    assert_int_equal(sf_topology_locate_band(&t, (double[2]){0.06, 0.031}, NULL, NULL), -1);
    sf_topology_free(&t);
    free(P);

    /* a band with setbacks stops short of its ends */
    P = make_square4(SQ_PLAIN);
    build_ok(P, &t);
    /* fold 2 (v7->v2) is vertical, band y in [-0.36, -0.28] */
    assert_int_equal(sf_topology_locate_band(&t, (double[2]){-0.2, -0.3}, &tp, &up), 1);
    CHECK_CLOSE(tp, 0.1, 1e-15, "v7->v2 band t");
    assert_int_equal(sf_topology_locate_band(&t, (double[2]){-0.2, -0.37}, NULL, NULL), -1);
    assert_int_equal(sf_topology_locate_band(&t, (double[2]){-0.2, -0.25}, NULL, NULL), -1);
    sf_topology_free(&t);
    free(P);

    /* sf_polygon_contains: non-convex polygon, boundary and tolerance */
    double L[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
    sf_polygon poly = {6, L};
    assert_true(sf_polygon_contains(&poly, (double[2]){0.5, 1.5}, 0.0));
    assert_false(sf_polygon_contains(&poly, (double[2]){1.5, 1.5}, 0.0));
    assert_true(sf_polygon_contains(&poly, (double[2]){1.0, 1.5}, 1e-12));
    assert_true(sf_polygon_contains(&poly, (double[2]){2.0 + 1e-10, 0.5}, 1e-9));
    assert_false(sf_polygon_contains(&poly, (double[2]){2.0 + 1e-8, 0.5}, 1e-9));
    assert_false(sf_polygon_contains(&poly, (double[2]){-1.0, 0.0}, 1e-9));
}

/* A face that is not convex, with a degree-2 interior vertex bent at it:
 * the construction must handle both the reflex and the convex side. */
static void test_nonconvex(void **state)
{
    (void)state;
    pat *P = pat_new("tests/nonconvex.cfg");
    pat_vertex(P, "c1", 0.0, 0.0);
    pat_vertex(P, "c2", 0.1, 0.0);
    pat_vertex(P, "c3", 0.1, 0.05);
    pat_vertex(P, "c4", 0.0, 0.05);
    pat_vertex(P, "a", 0.04, 0.0);
    pat_vertex(P, "k", 0.06, 0.025);
    pat_vertex(P, "b", 0.04, 0.05);
    pat_outline(P, "c1 c2 c3 c4");
    P->width = 0.004;
    pat_fold(P, "a", "k", 0.0, 0.005);
    pat_fold(P, "k", "b", 0.005, 0.0);
    pat_fixed(P, 0.01, 0.01);
    sf_topology t;
    build_ok(P, &t);
    CHECK_EQ_I(t.nfaces, 2, "bent fold faces");
    CHECK_EQ_I(t.nivertices, 1, "bent fold interior vertices");
    CHECK_EQ_I(t.ivertices[0].degree, 2, "bent fold degree");
    check_invariants(P, &t);
    /* area budget: at the reflex side the band ends are continued up to the
     * vertex (rectangles w/2 x setback, and the wedge between the two feet);
     * at the convex side the corners are joined.  Check only that nothing is
     * counted twice: bodies + bands < sheet, and the bodies are close to it */
    double rest = t.sheet_area - bands_area(P) - bodies_area(&t);
    assert_true(rest > 0.0 && rest < 0.004 * 0.012);
    sf_topology_free(&t);
    free(P);
}

/* The outline may list only some of its vertices; folds may end anywhere on
 * its edges; faces numbered along the boundary. */
static void test_face_numbering(void **state)
{
    (void)state;
    pat *P = make_strip3(0);
    sf_topology t;
    build_ok(P, &t);
    const char *want[10] = {"c1", "f1a", "f2a", "f3a", "c2", "c3", "f3b", "f2b", "f1b", "c4"};
    for (int k = 0; k < 10; k++) assert_string_equal(P->v[t.boundary[k]].name, want[k]);
    char buf[256];
    sf_topology_face_name(&P->s, &t, 0, buf, sizeof buf);
    assert_string_equal(buf, "face 1 (c1 f1a f1b c4)");
    sf_topology_fold_name(&P->s, 2, buf, sizeof buf);
    assert_string_equal(buf, "fold 3 (f3a->f3b)");
    sf_topology_free(&t);
    free(P);
}

/* Units and position do not matter: square4 in millimetres, shifted, gives
 * the same faces with areas scaled by 1e6; a sheet with no folds is one face;
 * an outline listing every boundary vertex (collinear ones included) gives
 * the same faces as one listing the corners only. */
static void test_scale_and_plain(void **state)
{
    (void)state;
    pat *P = make_square4(SQ_PLAIN);
    sf_topology t, u;
    build_ok(P, &t);
    pat *Q = make_square4(SQ_PLAIN);
    for (int i = 0; i < Q->s.nvertices; i++) {
        Q->v[i].x[0] = 1000.0 * Q->v[i].x[0] + 5000.0;
        Q->v[i].x[1] = 1000.0 * Q->v[i].x[1] - 3000.0;
    }
    for (int i = 0; i < Q->s.nfolds; i++) {
        Q->f[i].width *= 1000.0;
        Q->f[i].setback[0] *= 1000.0;
        Q->f[i].setback[1] *= 1000.0;
    }
    pat_fixed(Q, 5000.0, -3000.0);
    build_ok(Q, &u);
    assert_int_equal(u.nfaces, t.nfaces);
    assert_int_equal(u.root, t.root);
    for (int f = 0; f < t.nfaces; f++) {
        assert_int_equal(u.faces[f].nverts, t.faces[f].nverts);
        assert_int_equal(u.faces[f].body.n, t.faces[f].body.n);
        CHECK_CLOSE(u.faces[f].area, 1e6 * t.faces[f].area, 1e-9 * u.faces[f].area, "scaled area");
        CHECK_CLOSE(u.faces[f].centroid[0], 1000.0 * t.faces[f].centroid[0] + 5000.0, 1e-9,
                    "scaled centroid");
    }
    check_invariants(Q, &u);
    sf_topology_free(&u);
    free(Q);

    /* every boundary vertex listed, straight runs included */
    Q = make_square4(SQ_PLAIN);
    pat_outline(Q, "v1 v2 v3 v4 v5 v9 v11 v15 v20 v19 v18 v17 v16 v12 v10 v6");
    build_ok(Q, &u);
    assert_int_equal(u.nfaces, t.nfaces);
    CHECK_CLOSE(bodies_area(&u), bodies_area(&t), 1e-15, "full outline: same bodies");
    sf_topology_free(&u);
    free(Q);
    sf_topology_free(&t);

    /* no folds at all */
    P->s.nfolds = 0;
    build_ok(P, &t);
    assert_int_equal(t.nfaces, 1);
    assert_int_equal(t.nivertices, 0);
    assert_int_equal(t.root, 0);
    CHECK_CLOSE(t.faces[0].area, 0.64, 1e-15, "plain sheet area");
    sf_topology_free(&t);
    free(P);
}

/* square4 with every vertex moved at random (outline vertices along their
 * edges, corners and interior vertices anywhere nearby): each pattern either
 * builds and passes every invariant, with bodies clear of the bands and of
 * each other, or is refused with a one-line input error. */
static void test_jitter(void **state)
{
    (void)state;
    int built = 0, refused = 0;
    for (int trial = 0; trial < 300; trial++) {
        pat *P = make_square4(SQ_PLAIN);
        double amp = trial < 200 ? 0.03 : 0.06;
        for (int i = 0; i < P->s.nvertices; i++) {
            double *x = P->v[i].x;
            int onx = fabs(fabs(x[0]) - 0.4) < 1e-12, ony = fabs(fabs(x[1]) - 0.4) < 1e-12;
            if (onx && ony) continue;                 /* keep the corners */
            if (!onx) x[0] += urand(-amp, amp);
            if (!ony) x[1] += urand(-amp, amp);
        }
        for (int i = 0; i < P->s.nfolds; i++) {
            P->f[i].width *= urand(0.5, 1.2);
            P->f[i].setback[0] *= urand(0.8, 1.2);
        }
        sf_topology t;
        sf_error err;
        sf_error_clear(&err);
        int rc = sf_topology_build(&P->s, &t, &err);
        if (rc != SF_OK) {
            if (rc != SF_EINPUT || strchr(err.msg, '\n') || strncmp(err.msg, "studies/square4.cfg:", 20)) {
                print_error("trial %d: unexpected failure %d: %s\n", trial, rc, err.msg);
                fail();
            }
            refused++;
            free(P);
            continue;
        }
        built++;
        check_invariants(P, &t);
        for (int f = 0; f < t.nfaces; f++) {
            const sf_face *F = &t.faces[f];
            for (int k = 0; k < F->body.n; k++) {
                /* a point just inside the body near each of its corners */
                double p[2] = {F->body.p[k][0] + 1e-6 * (F->centroid[0] - F->body.p[k][0]),
                               F->body.p[k][1] + 1e-6 * (F->centroid[1] - F->body.p[k][1])};
                if (sf_topology_locate_band(&t, p, NULL, NULL) >= 0 ||
                    sf_topology_locate_face(&t, p) != f) {
                    print_error("trial %d: body of face %d reaches into a band or another face\n",
                                trial, f + 1);
                    fail();
                }
            }
        }
        sf_topology_free(&t);
        free(P);
    }
    /* most of them are fine patterns */
    assert_true(built > 150);
    (void)refused;
}


/* The bad patterns minus their one fault build: the errors above are not
 * side effects of something else. */
static void test_errors_base(void **state)
{
    (void)state;
    pat *P = make_fold1();
    sf_topology t;
    build_ok(P, &t);
    CHECK_EQ_I(t.nfaces, 2, "fold1 faces");
    check_invariants(P, &t);
    sf_topology_free(&t);
    free(P);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_strip3),
        cmocka_unit_test(test_waterbomb2),
        cmocka_unit_test(test_square4),
        cmocka_unit_test(test_square4_variants),
        cmocka_unit_test(test_locate),
        cmocka_unit_test(test_nonconvex),
        cmocka_unit_test(test_face_numbering),
        cmocka_unit_test(test_scale_and_plain),
        cmocka_unit_test(test_jitter),
        cmocka_unit_test(test_errors_base),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
