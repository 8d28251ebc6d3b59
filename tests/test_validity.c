/* test_validity.c - the physical-validity checks (src/analysis/validity/validity.h,
 * tritri.h) against independent answers:
 *  - triangle pairs whose meeting set and material separation are known
 *    by hand (crossing, apart, a common edge, coplanar overlap, a point);
 *  - the strip of hard-near-pi rolled up: the cross-section of the 3-D
 *    shape is a 2-D polyline (faces, and each band's chord polygon at the
 *    `samples` generator lines), crossed segment by segment here in 2-D
 *    (a second formulation, O(n^2)); the verdicts and separations agree;
 *  - the R*-tree's pairs against every pair of parts (brute force) on
 *    deterministic states of tessellations;
 *  - no false alarm: the flat state of every study in studies/, neighbours
 *    folded to 179 degrees; true alarms: a fold at 200 degrees, three
 *    folds of 132 degrees that wrap the strip through itself. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sf_test.h"
#include "tritri.h"
#include "validity.h"

static void set_tri(sf_tri3 *T, const double x[3][3], const double X[3][2])
{
    memcpy(T->x, x, sizeof T->x);
    memcpy(T->X, X, sizeof T->X);
}

/* P in z = 0 with X = (x, y); Q in the plane y = 0.5 with X = (x + 10, z):
 * they meet on y = 0.5, z = 0 for x in [0, 1.5], where the material
 * points are (x, 0.5) and (x + 10, 0): separation sqrt(100.25). */
static void test_tri_crossing(void **state)
{
    (void)state;
    sf_tri3 P, Q;
    const double xp[3][3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
    const double Xp[3][2] = {{0, 0}, {2, 0}, {0, 2}};
    const double xq[3][3] = {{-1, 0.5, -1}, {3, 0.5, -1}, {1, 0.5, 1}};
    const double Xq[3][2] = {{9, -1}, {13, -1}, {11, 1}};
    set_tri(&P, xp, Xp);
    set_tri(&Q, xq, Xq);
    sf_tri_meet M;
    for (int swap = 0; swap < 2; swap++) {
        assert_int_equal(sf_tritri(swap ? &Q : &P, swap ? &P : &Q, 1e-12, &M), 1);
        assert_int_equal(M.n, 2);
        double lo = fmin(M.x[0][0], M.x[1][0]), hi = fmax(M.x[0][0], M.x[1][0]);
        CHECK_CLOSE(lo, 0.0, 1e-14, "segment start x");
        CHECK_CLOSE(hi, 1.5, 1e-14, "segment end x");
        for (int k = 0; k < 2; k++) {
            CHECK_CLOSE(M.x[k][1], 0.5, 1e-14, "segment y");
            CHECK_CLOSE(M.x[k][2], 0.0, 1e-14, "segment z");
            CHECK_CLOSE(sf_tri_meet_sep(&M, k), sqrt(100.25), 1e-12, "separation at end %d", k);
        }
    }
    /* Q lifted by 1.01: its lowest point is above P's plane */
    sf_tri3 Q2 = Q;
    for (int i = 0; i < 3; i++) Q2.x[i][2] += 1.01;
    assert_int_equal(sf_tritri(&P, &Q2, 1e-12, &M), 0);
    /* Q moved past P's hypotenuse along y: the line y = 2.5 misses P */
    for (int i = 0; i < 3; i++) Q2.x[i][2] = Q.x[i][2], Q2.x[i][1] = 2.5;
    assert_int_equal(sf_tritri(&P, &Q2, 1e-12, &M), 0);
}

/* A fold: two triangles sharing the edge (0,0,0)-(1,0,0), the second
 * turned 90 degrees about it, the same material along the edge: they meet
 * on the edge, with separation 0. */
static void test_tri_common_edge(void **state)
{
    (void)state;
    sf_tri3 P, Q;
    const double xp[3][3] = {{0, 0, 0}, {1, 0, 0}, {0.3, -1, 0}};
    const double Xp[3][2] = {{0, 0}, {1, 0}, {0.3, -1}};
    const double xq[3][3] = {{0, 0, 0}, {1, 0, 0}, {0.6, 0, 1}};
    const double Xq[3][2] = {{0, 0}, {1, 0}, {0.6, 1}};
    set_tri(&P, xp, Xp);
    set_tri(&Q, xq, Xq);
    sf_tri_meet M;
    assert_int_equal(sf_tritri(&P, &Q, 1e-12, &M), 1);
    CHECK_CLOSE(sf_tri_meet_max_sep(&M, NULL), 0.0, 1e-14, "separation along a common edge");
    /* folded on through 360 degrees onto P: coplanar, overlapping; the
     * overlap's material points lie apart by up to 2 in y */
    const double xf[3][3] = {{0, 0, 0}, {1, 0, 0}, {0.6, -1, 0}};
    memcpy(Q.x, xf, sizeof Q.x);
    assert_int_equal(sf_tritri(&P, &Q, 1e-12, &M), 1);
    double sep = sf_tri_meet_max_sep(&M, NULL);
    assert_true(sep > 1.0);
}

/* Coplanar: P = (0,0),(1,0),(0,1), Q the same shifted by (0.25, 0.25), with
 * Q's material 5 to the side: the overlap is the triangle (0.25,0.25),
 * (0.75,0.25), (0.25,0.75), area 1/8, separation 5 everywhere on it. */
static void test_tri_coplanar(void **state)
{
    (void)state;
    sf_tri3 P, Q;
    const double xp[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const double Xp[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    const double xq[3][3] = {{0.25, 0.25, 0}, {1.25, 0.25, 0}, {0.25, 1.25, 0}};
    const double Xq[3][2] = {{5.25, 0.25}, {6.25, 0.25}, {5.25, 1.25}};
    set_tri(&P, xp, Xp);
    set_tri(&Q, xq, Xq);
    sf_tri_meet M;
    assert_int_equal(sf_tritri(&P, &Q, 1e-12, &M), 1);
    assert_true(M.n >= 3);
    double area = 0;
    for (int k = 0; k < M.n; k++) {
        const double *a = M.x[k], *b = M.x[(k + 1) % M.n];
        area += 0.5 * (a[0] * b[1] - b[0] * a[1]);
        CHECK_CLOSE(sf_tri_meet_sep(&M, k), 5.0, 1e-12, "separation at overlap vertex %d", k);
    }
    /* the half-planes are widened by eps = 1e-12: the area by up to its
     * perimeter (1.7) times eps */
    CHECK_CLOSE(fabs(area), 0.125, 2e-12, "overlap area");
    /* Q moved to touch P's corner (1, 0) with its own corner: one point
     * (within the widening eps times sqrt(2)) */
    const double xt[3][3] = {{1, 0, 0}, {2, 0, 0}, {1.5, 1, 0}};
    memcpy(Q.x, xt, sizeof Q.x);
    assert_int_equal(sf_tritri(&P, &Q, 1e-12, &M), 1);
    for (int k = 0; k < M.n; k++) {
        CHECK_CLOSE(M.x[k][0], 1.0, 1.5e-12, "corner contact x");
        CHECK_CLOSE(M.x[k][1], 0.0, 1.5e-12, "corner contact y");
    }
    /* apart in the plane */
    for (int i = 0; i < 3; i++) Q.x[i][0] += 0.1;
    assert_int_equal(sf_tritri(&P, &Q, 1e-12, &M), 0);
}

/* A corner of Q resting on P's interior: one point, (0.2, 0.3, 0). */
static void test_tri_point(void **state)
{
    (void)state;
    sf_tri3 P, Q;
    const double xp[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const double Xp[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    const double xq[3][3] = {{0.2, 0.3, 0}, {0.5, 0.3, 1}, {0.2, 0.8, 1}};
    const double Xq[3][2] = {{3, 0}, {4, 0}, {3, 1}};
    set_tri(&P, xp, Xp);
    set_tri(&Q, xq, Xq);
    sf_tri_meet M;
    assert_int_equal(sf_tritri(&P, &Q, 1e-12, &M), 1);
    for (int k = 0; k < M.n; k++) {
        CHECK_CLOSE(M.x[k][0], 0.2, 1e-12, "point contact x");
        CHECK_CLOSE(M.x[k][1], 0.3, 1e-12, "point contact y");
        CHECK_CLOSE(M.x[k][2], 0.0, 1e-12, "point contact z");
        CHECK_CLOSE(sf_tri_meet_sep(&M, k), hypot(2.8, 0.3), 1e-12, "point contact separation");
    }
}

/* ---- the strip in 2-D: the second formulation ---- */

/* The cross-section of hard-near-pi's strip (faces 0.025, 0.02, 0.02,
 * 0.025 m between bands of 0.01 m, circular arcs: K = 0) as the polyline
 * the 3-D shape has: each band by its chords between ns + 1 sample points.
 * Material coordinate: x in the flat sheet.  Returns the points. */
static int strip_polyline(const double th[3], int ns, double (*p)[3])
{
    const double face_end[4] = {0.025, 0.055, 0.085, 0.12}, face_start[4] = {0, 0.035, 0.065, 0.095};
    const double w = 0.01;
    double x = 0, y = 0, a = 0;
    int n = 0;
    p[n][0] = x, p[n][1] = y, p[n][2] = 0, n++;
    for (int f = 0; f < 4; f++) {
        double L = face_end[f] - face_start[f];
        x += L * cos(a), y += L * sin(a);
        p[n][0] = x, p[n][1] = y, p[n][2] = face_end[f], n++;
        if (f == 3) break;
        /* arc of turning th[f] over w: the point at arclength s from its
         * start is start + R (sin(a + k s) - sin a, cos a - cos(a + k s)) */
        double k = th[f] / w, x0 = x, y0 = y, a0 = a;
        for (int j = 1; j <= ns; j++) {
            double s = w * j / ns;
            if (fabs(k) > 1e-12) {
                x = x0 + (sin(a0 + k * s) - sin(a0)) / k;
                y = y0 + (cos(a0) - cos(a0 + k * s)) / k;
            } else {
                x = x0 + s * cos(a0), y = y0 + s * sin(a0);
            }
            p[n][0] = x, p[n][1] = y, p[n][2] = face_end[f] + s, n++;
        }
        a = a0 + th[f];
    }
    return n;
}

/* The largest material separation over crossings of non-adjacent segments
 * (-1: none). */
static double strip_crossing_2d(const double th[3], int ns)
{
    double p[64][3];
    int n = strip_polyline(th, ns, p);
    double worst = -1;
    for (int i = 0; i + 1 < n; i++)
        for (int j = i + 2; j + 1 < n; j++) {
            double r[2] = {p[i + 1][0] - p[i][0], p[i + 1][1] - p[i][1]};
            double s[2] = {p[j + 1][0] - p[j][0], p[j + 1][1] - p[j][1]};
            double den = r[0] * s[1] - r[1] * s[0];
            if (fabs(den) < 1e-18) continue;
            double dx = p[j][0] - p[i][0], dy = p[j][1] - p[i][1];
            double t = (dx * s[1] - dy * s[0]) / den, u = (dx * r[1] - dy * r[0]) / den;
            if (t < 0 || t > 1 || u < 0 || u > 1) continue;
            double Xa = p[i][2] + t * (p[i + 1][2] - p[i][2]), Xb = p[j][2] + u * (p[j + 1][2] - p[j][2]);
            worst = fmax(worst, fabs(Xa - Xb));
        }
    return worst;
}

static void check_state(sf_validity *v, const sf_model *m, const double *theta, sf_validity_report *rep)
{
    double *q = calloc((size_t)m->nq, sizeof(double));
    assert_non_null(q);
    for (int i = 0; i < m->nfolds; i++) q[m->qoff[i]] = theta[i];
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_validity_check(v, q, 0, rep, &err), err);
    sf_validity_report brute;
    CHECK_OK(sf_validity_check(v, q, 1, &brute, &err), err);
    assert_int_equal(rep->ncross, brute.ncross);
    CHECK_CLOSE(rep->cross_sep, brute.cross_sep, 0, "separation, tree against brute force");
    free(q);
}

/* hard-near-pi's strip rolled up by its three folds (the family
 * theta_i = t + 0.1 i): the 3-D check's verdict and separation against
 * the 2-D polyline's. */
static void test_strip_against_2d(void **state)
{
    (void)state;
    sf_scene sc;
    const char *sets[] = {"output.samples=8"};
    open_scene(&sc, "hard-near-pi", 1, sets);
    sf_validity *v = NULL;
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_validity_create(&sc.model, 8, &v, &err), err);
    CHECK_CLOSE(sf_validity_delta(v), 0.001, 1e-15, "contact distance: a tenth of the 0.01 m band");
    int ncross = 0, nclear = 0;
    for (int k = 0; k <= 34; k++) {
        double t = 0.1 * k;
        double th[3] = {t, t + 0.1, t + 0.2};
        sf_validity_report rep;
        check_state(v, &sc.model, th, &rep);
        double ref = strip_crossing_2d(th, 8);
        int want = ref > sf_validity_delta(v);
        if (want != (rep.ncross > 0))
            print_error("theta = (%g, %g, %g): 2-D separation %.6g, 3-D %ld crossing pairs (%.6g)\n",
                        th[0], th[1], th[2], ref, rep.ncross, rep.cross_sep);
        assert_int_equal(rep.ncross > 0, want);
        if (want) CHECK_CLOSE(rep.cross_sep, ref, 1e-9, "separation at theta = %g", t);
        ncross += want;
        nclear += !want;
        int beyond = (th[0] > M_PI) + (th[1] > M_PI) + (th[2] > M_PI);
        assert_int_equal(rep.nbeyond, beyond);
    }
    /* the family covers both verdicts */
    assert_true(ncross >= 5 && nclear >= 5);
    sf_validity_free(v);
    sf_scene_close(&sc);
}

/* Constructed cases on the strip: two neighbours folded to face each
 * other (179 degrees) do not touch; one fold at 200 degrees passes its
 * two faces through each other; three folds of 132 degrees (none beyond
 * 180) wrap the last face through the first. */
static void test_strip_constructed(void **state)
{
    (void)state;
    sf_scene sc;
    open_scene(&sc, "hard-near-pi", 0, NULL);
    sf_validity *v = NULL;
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_validity_create(&sc.model, sc.study.samples, &v, &err), err);
    sf_validity_report rep;
    const double d = M_PI / 180;
    const double neighbours[3] = {179 * d, 0, 0}, beyond[3] = {0, 200 * d, 0}, wrap[3] = {132 * d, 132 * d, 132 * d};
    check_state(v, &sc.model, neighbours, &rep);
    assert_int_equal(rep.nbeyond, 0);
    assert_int_equal(rep.ncross, 0);
    check_state(v, &sc.model, beyond, &rep);
    assert_int_equal(rep.nbeyond, 1);
    assert_int_equal(rep.beyond_fold, 1);
    assert_true(rep.ncross >= 1);
    /* faces 2 and 3, on either side of fold 2 */
    char a[200], b[200];
    sf_validity_part_name(v, rep.cross_part[0], a, sizeof a);
    sf_validity_part_name(v, rep.cross_part[1], b, sizeof b);
    assert_int_equal(rep.cross_part[0], 1);
    assert_int_equal(rep.cross_part[1], 2);
    check_state(v, &sc.model, wrap, &rep);
    assert_int_equal(rep.nbeyond, 0);
    assert_true(rep.ncross >= 1);
    assert_int_equal(rep.cross_part[0], 0);
    assert_int_equal(rep.cross_part[1], 3);
    sf_validity_free(v);
    sf_scene_close(&sc);
}

/* The flat sheet of every study: neighbours touch along every band edge
 * and around every vertex, coplanar; nothing passes through anything. */
static void test_flat_studies(void **state)
{
    (void)state;
    const char *names[] = {"fold1", "fold1-buckle", "strip3", "snap1", "hard-near-pi", "hard-stiff-ratio",
                           "hard-tiny-width", "square4", "square4-stiff", "square4-narrow", "square4-corner",
                           "square4-irregular", "square4-inplane", "waterbomb2", "miura-2x2",
                           "waterbomb-2x2", "yoshimura-2x2", "selffold3-dynamics"};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        sf_scene sc;
        open_scene(&sc, names[i], 0, NULL);
        sf_validity *v = NULL;
        sf_error err;
        sf_error_clear(&err);
        CHECK_OK(sf_validity_create(&sc.model, sc.study.samples, &v, &err), err);
        double *th = calloc((size_t)sc.model.nfolds + 1, sizeof(double));
        assert_non_null(th);
        sf_validity_report rep;
        check_state(v, &sc.model, th, &rep);
        if (rep.ncross || rep.nbeyond) print_error("%s: flat sheet flagged\n", names[i]);
        assert_int_equal(rep.ncross, 0);
        assert_int_equal(rep.nbeyond, 0);
        assert_true(rep.part_pairs > 0);
        free(th);
        sf_validity_free(v);
        sf_scene_close(&sc);
    }
}

/* The tree's pairs against all pairs, on deterministic states of a
 * waterbomb and a Miura sheet (angles from a formula, loops left open:
 * shapes that pass through themselves in many places). */
static void test_tree_against_brute(void **state)
{
    (void)state;
    const char *names[] = {"waterbomb-2x2", "miura-2x2", "square4"};
    long total = 0;
    for (size_t s = 0; s < sizeof names / sizeof *names; s++) {
        sf_scene sc;
        open_scene(&sc, names[s], 0, NULL);
        sf_validity *v = NULL;
        sf_error err;
        sf_error_clear(&err);
        CHECK_OK(sf_validity_create(&sc.model, sc.study.samples, &v, &err), err);
        const sf_model *m = &sc.model;
        double *th = calloc((size_t)m->nfolds + 1, sizeof(double));
        assert_non_null(th);
        for (int k = 0; k < 12; k++) {
            for (int i = 0; i < m->nfolds; i++) th[i] = (0.25 * k) * sin(1.7 * i + 0.3 * k + 0.2);
            sf_validity_report rep;
            check_state(v, m, th, &rep);   /* asserts the same answer */
            total += rep.ncross;
        }
        free(th);
        sf_validity_free(v);
        sf_scene_close(&sc);
    }
    assert_true(total > 10);   /* the states do cross: the comparison has content */
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : ".");
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tri_crossing),
        cmocka_unit_test(test_tri_common_edge),
        cmocka_unit_test(test_tri_coplanar),
        cmocka_unit_test(test_tri_point),
        cmocka_unit_test(test_strip_against_2d),
        cmocka_unit_test(test_strip_constructed),
        cmocka_unit_test(test_flat_studies),
        cmocka_unit_test(test_tree_against_brute),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
