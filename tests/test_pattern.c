/* test_pattern.c - the tessellation generators (src/pattern/generators.c)
 * and the automatic setbacks (src/pattern/cpattern.c).
 *
 * Independent checks: vertex, edge and face counts from the lattice
 * formulas; Maekawa (|#M - #V| = 2) and Kawasaki (alternating sector
 * angles sum to pi) at the interior vertices of the flat-foldable patterns
 * (Miura-ori, Yoshimura, and the degree-6 vertices of the waterbomb);
 * the sheet area; the setback formula against the distance at which two
 * band edge lines meet, computed by intersecting the lines. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "generators.h"
#include "sf_test.h"

typedef struct vstat { int deg, nm, nv, nb; double ang[16]; } vstat;

static int dcmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void stats(const sf_cpattern *cp, vstat *vs)
{
    memset(vs, 0, (size_t)cp->nv * sizeof *vs);
    for (int e = 0; e < cp->ne; e++)
        for (int k = 0; k < 2; k++) {
            int v = k ? cp->e[e].b : cp->e[e].a, o = k ? cp->e[e].a : cp->e[e].b;
            vstat *s = &vs[v];
            char a = cp->e[e].assign;
            if (a == 'B') { s->nb++; continue; }
            if (a == 'M') s->nm++;
            if (a == 'V') s->nv++;
            assert_true(s->deg < 16);
            double t = atan2(cp->v[o].x[1] - cp->v[v].x[1], cp->v[o].x[0] - cp->v[v].x[0]);
            s->ang[s->deg++] = t < 0 ? t + 2 * M_PI : t;
        }
}

/* Maekawa and Kawasaki at every interior vertex of degree `only` (0: all) */
static int flat_foldable_vertices(const sf_cpattern *cp, int only)
{
    vstat *vs = calloc((size_t)cp->nv, sizeof *vs);
    assert_non_null(vs);
    stats(cp, vs);
    int n = 0;
    for (int v = 0; v < cp->nv; v++) {
        vstat *s = &vs[v];
        if (s->nb || s->deg == 0 || (only && s->deg != only)) continue;
        n++;
        if (abs(s->nm - s->nv) != 2)
            print_error("vertex %d: %d M, %d V\n", v, s->nm, s->nv);
        assert_int_equal(abs(s->nm - s->nv), 2);
        qsort(s->ang, (size_t)s->deg, sizeof(double), dcmp);
        double alt = 0;
        for (int k = 0; k < s->deg; k += 2) {
            double a1 = s->ang[(k + 1) % s->deg] - s->ang[k];
            if (a1 < 0) a1 += 2 * M_PI;
            alt += a1;
        }
        /* coordinates rounded to 12 digits: angles good to ~1e-11 */
        CHECK_CLOSE(alt, M_PI, 1e-10, "Kawasaki at vertex %d", v);
    }
    free(vs);
    return n;
}

static double outline_area(const sf_cpattern *cp)
{
    int *loop, n;
    sf_error e;
    sf_error_clear(&e);
    assert_int_equal(sf_cp_outline(cp, &loop, &n, NULL, &e), SF_OK);
    double a = 0;
    for (int k = 0; k < n; k++) {
        const double *p = cp->v[loop[k]].x, *q = cp->v[loop[(k + 1) % n]].x;
        a += p[0] * q[1] - q[0] * p[1];
    }
    free(loop);
    return 0.5 * a;
}

static int count(const sf_cpattern *cp, char a)
{
    int n = 0;
    for (int e = 0; e < cp->ne; e++) n += cp->e[e].assign == a;
    return n;
}

static void test_miura(void **state)
{
    (void)state;
    int cells[][2] = {{1, 1}, {2, 2}, {3, 2}, {1, 4}};
    double angles[] = {60, 45, 75};
    for (size_t c = 0; c < 4; c++)
        for (size_t k = 0; k < 3; k++) {
            sf_gen_opts o;
            sf_error e;
            sf_error_clear(&e);
            assert_int_equal(sf_gen_defaults("miura", &o, &e), SF_OK);
            o.m = cells[c][0]; o.n = cells[c][1]; o.angle = angles[k]; o.a = 0.03; o.b = 0.05;
            sf_cpattern cp;
            CHECK_OK(sf_generate("miura", &o, &cp, &e), e);
            CHECK_OK(sf_cp_check(&cp, NULL, &e), e);
            int M = 2 * o.m, N = 2 * o.n;
            assert_int_equal(cp.nv, (M + 1) * (N + 1));
            assert_int_equal(count(&cp, 'B'), 2 * M + 2 * N);
            assert_int_equal(count(&cp, 'M') + count(&cp, 'V'), (N - 1) * M + (M - 1) * N);
            assert_int_equal(flat_foldable_vertices(&cp, 0), (M - 1) * (N - 1));
            /* M x N parallelograms of sides a, b at the angle */
            /* (coordinates are rounded to 12 digits by the generator) */
            double A = M * N * o.a * o.b * sin(o.angle * M_PI / 180);
            CHECK_CLOSE(outline_area(&cp), A, 1e-11 * A, "miura %dx%d area", o.m, o.n);
            sf_cp_free(&cp);
        }
}

/* rigid loop closure at a degree-4 vertex: prod_k R(e_k, r_k) = I, the
 * creases counter-clockwise; r[0] fixed, r[1..3] solved by Newton's method
 * (finite-difference Jacobian: a test tool) from the given guess */
static void rot(const double a, double t, double R[3][3])
{
    double x = cos(a), y = sin(a), c = cos(t), s = sin(t), C = 1 - c;
    double M[3][3] = {{c + x * x * C, x * y * C, y * s}, {x * y * C, c + y * y * C, -x * s}, {-y * s, x * s, c}};
    memcpy(R, M, sizeof M);
}

static void closure(const double ang[4], const double r[4], double f[3])
{
    double P[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int k = 0; k < 4; k++) {
        double R[3][3], Q[3][3];
        rot(ang[k], r[k], R);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                Q[i][j] = P[i][0] * R[0][j] + P[i][1] * R[1][j] + P[i][2] * R[2][j];
        memcpy(P, Q, sizeof P);
    }
    f[0] = P[2][1]; f[1] = P[0][2]; f[2] = P[1][0];
}

static int solve_closure(const double ang[4], double r[4])
{
    for (int it = 0; it < 50; it++) {
        double f[3], J[3][3], h = 1e-7;
        closure(ang, r, f);
        if (fabs(f[0]) + fabs(f[1]) + fabs(f[2]) < 1e-13) return 1;
        for (int j = 0; j < 3; j++) {
            double rr[4], fj[3];
            memcpy(rr, r, sizeof rr);
            rr[j + 1] += h;
            closure(ang, rr, fj);
            for (int i = 0; i < 3; i++) J[i][j] = (fj[i] - f[i]) / h;
        }
        double D = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                   J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
        if (fabs(D) < 1e-14) return 0;
        for (int j = 0; j < 3; j++) {
            double A[3][3];
            memcpy(A, J, sizeof A);
            for (int i = 0; i < 3; i++) A[i][j] = -f[i];
            double Dj = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                        A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
            r[j + 1] += Dj / D;
        }
    }
    return 0;
}

/* Each interior degree-4 vertex of a Miura sheet folds rigidly with the
 * signs of its assignment: fix a zigzag crease at 0.3 rad with its sign,
 * start Newton from the assigned signs (magnitude 0.3), and the closed
 * state keeps every sign.  (With the straight creases' signs swapped, the
 * closed state near that start has other signs: the check can fail.) */
static void test_miura_rigid_mode(void **state)
{
    (void)state;
    double angles[] = {60, 45, 75};
    for (int k = 0; k < 3; k++) {
        sf_gen_opts o;
        sf_error e;
        sf_error_clear(&e);
        assert_int_equal(sf_gen_defaults("miura", &o, &e), SF_OK);
        o.angle = angles[k];
        o.fold_angle = 20 + 50 * k;   /* 20, 70, 120 degrees */
        sf_cpattern cp;
        CHECK_OK(sf_generate("miura", &o, &cp, &e), e);
        int checked = 0;
        for (int v = 0; v < cp.nv; v++) {
            double ang[4], sg[4], tg[4];
            int n = 0, boundary = 0;
            for (int i = 0; i < cp.ne; i++) {
                if (cp.e[i].a != v && cp.e[i].b != v) continue;
                if (cp.e[i].assign == 'B') boundary = 1;
                int o2 = cp.e[i].a == v ? cp.e[i].b : cp.e[i].a;
                if (n < 4) {
                    double t = atan2(cp.v[o2].x[1] - cp.v[v].x[1], cp.v[o2].x[0] - cp.v[v].x[0]);
                    ang[n] = t < 0 ? t + 2 * M_PI : t;
                    sg[n] = cp.e[i].assign == 'V' ? 1 : -1;
                    tg[n] = cp.e[i].angle;
                    if (cp.e[i].assign != 'B') assert_true(tg[n] * sg[n] > 0);
                }
                n++;
            }
            if (boundary || n != 4) continue;
            for (int a = 1; a < 4; a++)   /* counter-clockwise */
                for (int b = a; b > 0 && ang[b] < ang[b - 1]; b--) {
                    double t = ang[b]; ang[b] = ang[b - 1]; ang[b - 1] = t;
                    t = sg[b]; sg[b] = sg[b - 1]; sg[b - 1] = t;
                    t = tg[b]; tg[b] = tg[b - 1]; tg[b - 1] = t;
                }
            /* fix a zigzag crease (one without a collinear partner): the
             * straight line alone folding is another rigid motion, with
             * the zigzag flat, that a fixed straight crease could reach */
            int c0 = -1;
            for (int c = 0; c < 4 && c0 < 0; c++) {
                int partner = 0;
                for (int d = 0; d < 4; d++)
                    if (fabs(fabs(ang[d] - ang[c]) - M_PI) < 1e-9) partner = 1;
                if (!partner) c0 = c;
            }
            assert_true(c0 >= 0);
            double a2[4], s2[4], t2[4];
            for (int c = 0; c < 4; c++) {
                a2[c] = ang[(c + c0) % 4]; s2[c] = sg[(c + c0) % 4]; t2[c] = tg[(c + c0) % 4];
            }
            memcpy(ang, a2, sizeof ang);
            memcpy(sg, s2, sizeof sg);
            memcpy(tg, t2, sizeof tg);
            /* the pattern's own target angles close the loop: they are a
             * state of the rigid folding motion (to 1e-10: the crease
             * directions come from coordinates rounded to 12 digits) */
            double rg[4], f[3];
            for (int c = 0; c < 4; c++) rg[c] = tg[c] * M_PI / 180;
            closure(ang, rg, f);
            CHECK_CLOSE(fabs(f[0]) + fabs(f[1]) + fabs(f[2]), 0.0, 1e-10,
                        "angle %g, vertex %d: loop closure at the target angles", o.angle, v);
            double r[4] = {0.3 * sg[0], 0.3 * sg[1], 0.3 * sg[2], 0.3 * sg[3]};
            assert_true(solve_closure(ang, r));
            for (int c = 0; c < 4; c++) {
                if (r[c] * sg[c] <= 0 || fabs(r[c]) >= M_PI)
                    print_error("angle %g, vertex %d: crease %d assigned %+g, folds %+g\n", o.angle, v, c, sg[c], r[c]);
                assert_true(r[c] * sg[c] > 0 && fabs(r[c]) < M_PI);
            }
            checked++;
        }
        assert_int_equal(checked, 9);
        sf_cp_free(&cp);
    }
}

/* The generator's pattern NAME of m x n cells with its default options
 * (returned in o), checked as a crease pattern. */
static void generate_checked(const char *name, int m, int n, sf_gen_opts *o, sf_cpattern *cp)
{
    sf_error e;
    sf_error_clear(&e);
    assert_int_equal(sf_gen_defaults(name, o, &e), SF_OK);
    o->m = m; o->n = n;
    CHECK_OK(sf_generate(name, o, cp, &e), e);
    CHECK_OK(sf_cp_check(cp, NULL, &e), e);
}

static void test_yoshimura(void **state)
{
    (void)state;
    for (int m = 1; m <= 3; m++)
        for (int n = 1; n <= 3; n++) {
            sf_gen_opts o;
            sf_cpattern cp;
            generate_checked("yoshimura", m, n, &o, &cp);
            /* interior vertices: (m - 1) on even rows, m on odd rows */
            int want = 0;
            for (int j = 1; j < n; j++) want += j % 2 ? m : m - 1;
            assert_int_equal(flat_foldable_vertices(&cp, 0), want);
            assert_int_equal(count(&cp, 'V'), 2 * m * n);   /* two diagonals per half-diamond row cell */
            CHECK_CLOSE(outline_area(&cp), m * o.a * n * o.b, 1e-15, "yoshimura area");
            sf_cp_free(&cp);
        }
}

static void test_waterbomb(void **state)
{
    (void)state;
    for (int m = 1; m <= 3; m++)
        for (int n = 1; n <= 3; n++) {
            sf_gen_opts o;
            sf_cpattern cp;
            generate_checked("waterbomb", m, n, &o, &cp);
            /* one degree-6 base centre per whole base: m per even row,
             * m - 1 inside the shifted odd rows */
            int want = 0;
            for (int r = 0; r < n; r++) want += r % 2 ? m - 1 : m;
            assert_int_equal(flat_foldable_vertices(&cp, 6), want);
            /* diagonals: 4 per whole base, 2 per half base at the sides */
            int diag = 0;
            for (int r = 0; r < n; r++) diag += r % 2 ? 4 * (m - 1) + 4 : 4 * m;
            assert_int_equal(count(&cp, 'V'), diag);
            CHECK_CLOSE(outline_area(&cp), m * o.a * n * o.b, 1e-15, "waterbomb area");
            sf_cp_free(&cp);
        }
}

/* Square twist: 4 interior vertices, each flat-foldable (Maekawa, Kawasaki)
 * with sectors 90, 90 + angle, 90, 90 - angle degrees, the creases around
 * the small sector of opposite kinds (big-little-big); 8 valleys (the
 * square and one crease per pleat), 4 mountains; 9 faces' worth of area. */
static void test_twist(void **state)
{
    (void)state;
    for (int t = 0; t < 3; t++) {
        double angle[3] = {10, 22.5, 35};
        sf_gen_opts o;
        sf_cpattern cp;
        sf_error e;
        sf_error_clear(&e);
        assert_int_equal(sf_gen_defaults("twist", &o, &e), SF_OK);
        o.angle = angle[t];
        CHECK_OK(sf_generate("twist", &o, &cp, &e), e);
        CHECK_OK(sf_cp_check(&cp, NULL, &e), e);
        assert_int_equal(flat_foldable_vertices(&cp, 0), 4);
        assert_int_equal(count(&cp, 'V'), 8);
        assert_int_equal(count(&cp, 'M'), 4);
        CHECK_CLOSE(outline_area(&cp), o.a * o.a, 1e-15, "twist area");
        for (int v = 0; v < cp.nv; v++) {
            /* rays with their assignment, sorted by angle */
            double ang[8];
            char as[8];
            int d = 0, nb = 0;
            for (int k = 0; k < cp.ne; k++) {
                int end = cp.e[k].a == v ? 0 : cp.e[k].b == v ? 1 : -1;
                if (end < 0) continue;
                if (cp.e[k].assign == 'B') { nb++; continue; }
                int w = end ? cp.e[k].a : cp.e[k].b;
                double a = atan2(cp.v[w].x[1] - cp.v[v].x[1], cp.v[w].x[0] - cp.v[v].x[0]);
                ang[d] = a < 0 ? a + 2 * M_PI : a;
                as[d++] = cp.e[k].assign;
            }
            if (nb || d == 0) continue;
            assert_int_equal(d, 4);
            for (int i = 0; i < d; i++)   /* insertion sort, carrying the kinds */
                for (int j = i; j > 0 && ang[j] < ang[j - 1]; j--) {
                    double x = ang[j]; ang[j] = ang[j - 1]; ang[j - 1] = x;
                    char c = as[j]; as[j] = as[j - 1]; as[j - 1] = c;
                }
            double sec[4], small = 1e9;
            int ks = -1;
            for (int i = 0; i < 4; i++) {
                sec[i] = ang[(i + 1) % 4] - ang[i];
                if (sec[i] < 0) sec[i] += 2 * M_PI;
                if (sec[i] < small) { small = sec[i]; ks = i; }
            }
            CHECK_CLOSE(small, (90 - o.angle) * M_PI / 180, 1e-10, "twist: smallest sector at vertex %d", v);
            CHECK_CLOSE(sec[(ks + 2) % 4], (90 + o.angle) * M_PI / 180, 1e-10, "twist: largest sector");
            CHECK_CLOSE(sec[(ks + 1) % 4], M_PI / 2, 1e-10, "twist: right sector");
            assert_true(as[ks] != as[(ks + 1) % 4]);   /* big-little-big */
        }
        sf_cp_free(&cp);
    }
}

/* Hypar of R rings: 4 (R - 1) interior vertices, 4 of degree 3 (ring 1)
 * and 4 (R - 2) of degree 4 that are flat-foldable; 4 (R - 1) ring
 * creases and 4 (R - 1) diagonal ones, mountains on odd rings. */
static void test_hypar(void **state)
{
    (void)state;
    for (int R = 2; R <= 5; R++) {
        sf_gen_opts o;
        sf_cpattern cp;
        generate_checked("hypar", R, R, &o, &cp);
        assert_int_equal(flat_foldable_vertices(&cp, 4), 4 * (R - 2));
        vstat *vs = calloc((size_t)cp.nv, sizeof *vs);
        assert_non_null(vs);
        stats(&cp, vs);
        int n3 = 0, nint = 0;
        for (int v = 0; v < cp.nv; v++)
            if (!vs[v].nb && vs[v].deg) { nint++; n3 += vs[v].deg == 3; }
        free(vs);
        assert_int_equal(nint, 4 * (R - 1));
        assert_int_equal(n3, 4);
        int nm = 0;   /* ring j odd: 4 M edges; diagonals j -> j+1 take ring j+1's kind */
        for (int j = 1; j < R; j++) nm += 4 * (j % 2) + 4 * ((j + 1) % 2);
        assert_int_equal(count(&cp, 'M'), nm);
        assert_int_equal(count(&cp, 'M') + count(&cp, 'V'), 8 * (R - 1));
        CHECK_CLOSE(outline_area(&cp), o.a * o.a, 1e-15, "hypar area");
        sf_cp_free(&cp);
    }
}

/* two folds from one vertex at sector alpha: the setbacks equal margin
 * times the distances along each fold to where the facing band edges
 * meet, found here by intersecting the two edge lines */
static void test_setbacks(void **state)
{
    (void)state;
    double alphas[] = {0.3, 1.0, 2.0, 2.9};
    double w1 = 0.01, w2 = 0.004;
    for (size_t k = 0; k < 4; k++) {
        double al = alphas[k];
        sf_cpattern cp;
        sf_cp_init(&cp);
        int o = sf_cp_add_vertex(&cp, 0, 0, NULL);
        int a = sf_cp_add_vertex(&cp, 1, 0, NULL);
        int b = sf_cp_add_vertex(&cp, cos(al), sin(al), NULL);
        sf_cp_add_edge(&cp, o, a, 'M', NAN);
        sf_cp_add_edge(&cp, o, b, 'V', NAN);
        double w[2] = {w1, w2}, sb[2][2];
        sf_cp_setbacks(&cp, w, NULL, 0, 1.25, 0.0, sb);
        /* edge line of fold 1 on fold 2's side: y = w1/2; of fold 2 on
         * fold 1's side: points d (cos al, sin al) + (w2/2)(sin al, -cos al) */
        double d2 = (w1 / 2 + (w2 / 2) * cos(al)) / sin(al);
        double px = d2 * cos(al) + (w2 / 2) * sin(al);
        double py = d2 * sin(al) - (w2 / 2) * cos(al);
        CHECK_CLOSE(py, w1 / 2, 1e-15, "intersection on fold 1's edge line");
        /* (past a right angle the edge lines meet behind the vertex: 0) */
        CHECK_CLOSE(sb[0][0], fmax(0, 1.25 * px), 1e-15, "setback of fold 1 at alpha %g", al);
        CHECK_CLOSE(sb[1][0], fmax(0, 1.25 * d2), 1e-15, "setback of fold 2 at alpha %g", al);
        sf_cp_free(&cp);
    }
}

static void test_bad_parameters(void **state)
{
    (void)state;
    sf_gen_opts o;
    sf_cpattern cp;
    sf_error e;
    sf_error_clear(&e);
    assert_int_equal(sf_gen_defaults("miuraa", &o, &e), SF_EINPUT);
    CHECK_CONTAINS(e.msg, "unknown pattern 'miuraa' (patterns: miura, yoshimura, waterbomb, twist, hypar)");
    sf_error_clear(&e);
    assert_int_equal(sf_gen_defaults("twist", &o, &e), SF_OK);
    o.angle = 45;
    assert_int_equal(sf_generate("twist", &o, &cp, &e), SF_EINPUT);
    CHECK_CONTAINS(e.msg, "twist angle 45 degrees: must be in (0, 45)");
    sf_error_clear(&e);
    o.angle = 30;
    o.b = 0.09;   /* the turned square reaches out of the sheet */
    assert_int_equal(sf_generate("twist", &o, &cp, &e), SF_EINPUT);
    CHECK_CONTAINS(e.msg, "does not fit inside the sheet");
    sf_error_clear(&e);
    assert_int_equal(sf_gen_defaults("hypar", &o, &e), SF_OK);
    o.m = 1;
    assert_int_equal(sf_generate("hypar", &o, &cp, &e), SF_EINPUT);
    CHECK_CONTAINS(e.msg, "hypar: 1 ring: at least 2");
    sf_error_clear(&e);
    assert_int_equal(sf_gen_defaults("miura", &o, &e), SF_OK);
    o.angle = 90;
    assert_int_equal(sf_generate("miura", &o, &cp, &e), SF_EINPUT);
    CHECK_CONTAINS(e.msg, "sector angle 90 degrees: must be in (0, 90)");
    sf_error_clear(&e);
    o.angle = 60; o.m = 0;
    assert_int_equal(sf_generate("miura", &o, &cp, &e), SF_EINPUT);
    CHECK_CONTAINS(e.msg, "cells 0x2");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_miura),
        cmocka_unit_test(test_miura_rigid_mode),
        cmocka_unit_test(test_yoshimura),
        cmocka_unit_test(test_waterbomb),
        cmocka_unit_test(test_twist),
        cmocka_unit_test(test_hypar),
        cmocka_unit_test(test_setbacks),
        cmocka_unit_test(test_bad_parameters),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
