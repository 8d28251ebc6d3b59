/* test_svg.c - the SVG reader's small languages and its colour
 * convention against values worked out by hand: path data (relative,
 * implicit lineto, numbers run together), transform lists (composition,
 * rotation about a point), colours and opacities to assignments and
 * angles (attributes, style, <style> rules, inheritance, rgba alpha), and
 * drawn lines made planar (a crossing split, a T-junction, a near miss
 * merged, a line drawn twice). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cpattern.h"
#include "foldread.h"
#include "svg_impl.h"
#include "sf_test.h"

typedef struct segs { int n; double s[16][4]; } segs;

static int collect(void *ctx, double x0, double y0, double x1, double y1)
{
    segs *g = ctx;
    if (g->n == 16) return 1;
    double *q = g->s[g->n++];
    q[0] = x0; q[1] = y0; q[2] = x1; q[3] = y1;
    return 0;
}

static void same_segs(const segs *g, int n, const double (*want)[4])
{
    assert_int_equal(g->n, n);
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 4; k++) CHECK_CLOSE(g->s[i][k], want[i][k], 1e-12, "segment %d, coordinate %d", i, k);
}

static void test_path_data(void **state)
{
    (void)state;
    char curve = 0, why[160];
    segs g = {0};
    /* relative lineto with numbers run together, h, V, z back to the start */
    assert_int_equal(svg_parse_path("M10,20l5-5h3V0z", collect, &g, &curve, why, sizeof why), 0);
    const double w1[4][4] = {{10, 20, 15, 15}, {15, 15, 18, 15}, {18, 15, 18, 0}, {18, 0, 10, 20}};
    same_segs(&g, 4, w1);
    /* a first relative moveto is absolute; its further pairs are linetos */
    g.n = 0;
    assert_int_equal(svg_parse_path("m 1 1 2 2 .5.5", collect, &g, &curve, why, sizeof why), 0);
    const double w2[2][4] = {{1, 1, 3, 3}, {3, 3, 3.5, 3.5}};
    same_segs(&g, 2, w2);
    /* exponents; a second subpath after z starts from the first's start */
    g.n = 0;
    assert_int_equal(svg_parse_path("M0 0L1e1 0Zm0 1e-1 l0 1", collect, &g, &curve, why, sizeof why), 0);
    const double w3[3][4] = {{0, 0, 10, 0}, {10, 0, 0, 0}, {0, 0.1, 0, 1.1}};
    same_segs(&g, 3, w3);
    /* curves are reported with their letter, bad syntax with a reason */
    g.n = 0;
    assert_int_equal(svg_parse_path("M0 0 L 1 1 c 1 1 2 2 3 3", collect, &g, &curve, why, sizeof why), 1);
    assert_int_equal(curve, 'c');
    assert_int_equal(svg_parse_path("M0 0 L 1", collect, &g, &curve, why, sizeof why), -1);
    assert_int_equal(svg_parse_path("L0 0", collect, &g, &curve, why, sizeof why), -1);
    assert_int_equal(svg_parse_path("M0 0 L inf 1", collect, &g, &curve, why, sizeof why), -1);
    /* a polygon closes, a polyline does not */
    g.n = 0;
    assert_int_equal(svg_parse_points("0,0 1,0 1,1", 1, collect, &g, why, sizeof why), 0);
    assert_int_equal(g.n, 3);
    g.n = 0;
    assert_int_equal(svg_parse_points("0,0 1,0 1,1", 0, collect, &g, why, sizeof why), 0);
    assert_int_equal(g.n, 2);
}

static void test_transforms(void **state)
{
    (void)state;
    char why[160];
    svg_xf t;
    double x, y;
    /* applied right to left: scale, then rotate by 90 degrees, then translate */
    svg_xf_identity(&t);
    assert_int_equal(svg_parse_transform("translate(10 5) rotate(90) scale(2)", &t, why, sizeof why), 0);
    svg_xf_apply(&t, 1, 0, &x, &y);
    CHECK_CLOSE(x, 10, 1e-12, "x of (1, 0)");
    CHECK_CLOSE(y, 7, 1e-12, "y of (1, 0)");
    /* rotate(90, 1, 1) turns (2, 1) about (1, 1) into (1, 2) */
    svg_xf_identity(&t);
    assert_int_equal(svg_parse_transform("rotate(90,1,1)", &t, why, sizeof why), 0);
    svg_xf_apply(&t, 2, 1, &x, &y);
    CHECK_CLOSE(x, 1, 1e-12, "x about (1, 1)");
    CHECK_CLOSE(y, 2, 1e-12, "y about (1, 1)");
    /* matrix(a b c d e f) and skewX(45): x' = x + y */
    svg_xf_identity(&t);
    assert_int_equal(svg_parse_transform("matrix(1 0 0 1 3 4), skewX(45)", &t, why, sizeof why), 0);
    svg_xf_apply(&t, 1, 2, &x, &y);
    CHECK_CLOSE(x, 1 + 2 + 3, 1e-12, "x of skewX then matrix");
    CHECK_CLOSE(y, 2 + 4, 1e-12, "y of skewX then matrix");
    svg_xf_identity(&t);
    assert_int_equal(svg_parse_transform("rotate(1 2)", &t, why, sizeof why), -1);
    /* CSS's units: a quarter turn in deg, rad and turn, translate in px */
    const char *quarter[] = {"translate(3px, 4px) rotate(90deg)", "translate(3px,4px) rotate(1.5707963267948966rad)",
                             "translate(3px 4px) rotate(0.25turn)"};
    for (int i = 0; i < 3; i++) {
        svg_xf_identity(&t);
        assert_int_equal(svg_parse_transform(quarter[i], &t, why, sizeof why), 0);
        svg_xf_apply(&t, 1, 0, &x, &y);
        CHECK_CLOSE(x, 3, 1e-12, quarter[i]);
        CHECK_CLOSE(y, 5, 1e-12, quarter[i]);
    }
    svg_xf_identity(&t);
    assert_int_equal(svg_parse_transform("translate(10%)", &t, why, sizeof why), -1);
    assert_non_null(strstr(why, "unit '%)' not read"));
    assert_int_equal(svg_parse_transform("rotate(90px)", &t, why, sizeof why), -1);
    /* lengths: mm is 1e-3 m, px no physical size */
    double v, m;
    assert_int_equal(svg_length("210mm", &v, &m), 0);
    CHECK_CLOSE(v * m, 0.21, 1e-15, "210mm");
    assert_int_equal(svg_length("1291.4px", &v, &m), 0);
    assert_true(m == 0);
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* the edge from (x0, y0) to (x1, y1) in either direction, or -1 */
static int edge_at(const sf_cpattern *cp, double x0, double y0, double x1, double y1)
{
    for (int e = 0; e < cp->ne; e++) {
        const double *a = cp->v[cp->e[e].a].x, *b = cp->v[cp->e[e].b].x;
        if ((fabs(a[0] - x0) < 1e-9 && fabs(a[1] - y0) < 1e-9 && fabs(b[0] - x1) < 1e-9 && fabs(b[1] - y1) < 1e-9) ||
            (fabs(b[0] - x0) < 1e-9 && fabs(b[1] - y0) < 1e-9 && fabs(a[0] - x1) < 1e-9 && fabs(a[1] - y1) < 1e-9))
            return e;
    }
    return -1;
}

static void test_convention_and_planarize(void **state)
{
    (void)state;
    char path[64];
    snprintf(path, sizeof path, "/tmp/sf-test-svg-%ld.svg", (long)getpid());
    /* a 100 x 100 mm square (width 100mm over a viewBox of 100): a red
     * diagonal at opacity 0.5 x stroke-opacity 0.5 from its group, a blue
     * one (class rule) crossing it at the centre, a yellow facet line from
     * the centre's right (drawn from 50.05: merged into the crossing's
     * vertex within 0.003 x 100) to the right side, a magenta line from
     * the red diagonal to the right side (T-junctions at both ends), and
     * the top side drawn twice, once red: the outline wins */
    write_file(path,
        "<svg xmlns='http://www.w3.org/2000/svg' width='100mm' height='100mm' viewBox='0 0 100 100'>\n"
        "<style>.v { stroke: #0000FF; stroke-opacity: 0.8 }</style>\n"
        "<rect x='0' y='0' width='100' height='100' style='stroke:black;fill:none'/>\n"
        "<g stroke='red' stroke-opacity='0.5' opacity='0.5'><line x1='0' y1='0' x2='100' y2='100'/></g>\n"
        "<line class='v' x1='100' y1='0' x2='0' y2='100'/>\n"
        "<line stroke='rgba(255,255,0,1)' x1='50.05' y1='50' x2='100' y2='50'/>\n"
        "<line stroke='#f0f' x1='75' y1='75' x2='100' y2='75'/>\n"
        "<line stroke='red' x1='0' y1='0' x2='100' y2='0'/>\n"
        "</svg>\n");
    sf_import_opts io;
    sf_import_opts_default(&io);
    sf_cpattern cp;
    sf_import_info info;
    sf_error e;
    sf_error_clear(&e);
    CHECK_OK(sf_import_read(path, &io, &cp, &info, &e), e);
    CHECK_CLOSE(cp.unit, 1e-3, 1e-15, "user unit from width 100mm over viewBox 100");
    CHECK_CLOSE(info.width, 0.1, 1e-15, "sheet width");
    /* the red diagonal, split at the centre and where the magenta line
     * starts (75, 75): 0.5 x 0.5 of -180 degrees */
    int e1 = edge_at(&cp, 0, 0, 50, 50), e2 = edge_at(&cp, 50, 50, 75, 75), e3 = edge_at(&cp, 75, 75, 100, 100);
    assert_true(e1 >= 0 && e2 >= 0 && e3 >= 0);
    assert_int_equal(cp.e[e1].assign, 'M');
    CHECK_CLOSE(cp.e[e3].angle, -45, 1e-12, "red at opacity 0.5 x stroke-opacity 0.5");
    int b1 = edge_at(&cp, 100, 0, 50, 50);
    assert_true(b1 >= 0);
    assert_int_equal(cp.e[b1].assign, 'V');
    CHECK_CLOSE(cp.e[b1].angle, 144, 1e-12, "blue (a <style> rule) at stroke-opacity 0.8");
    int f1 = edge_at(&cp, 50, 50, 100, 50);
    assert_true(f1 >= 0);
    assert_int_equal(cp.e[f1].assign, 'F');
    int u1 = edge_at(&cp, 75, 75, 100, 75);
    assert_true(u1 >= 0);
    assert_int_equal(cp.e[u1].assign, 'U');
    /* the right side split at (100, 50) and (100, 75), the top side one
     * boundary edge */
    assert_true(edge_at(&cp, 100, 0, 100, 50) >= 0 && edge_at(&cp, 100, 50, 100, 75) >= 0 &&
                edge_at(&cp, 100, 75, 100, 100) >= 0);
    int top = edge_at(&cp, 0, 0, 100, 0);
    assert_true(top >= 0);
    assert_int_equal(cp.e[top].assign, 'B');
    /* 4 corners, the centre, (100, 50), (75, 75), (100, 75); 6 boundary
     * edges, 3 + 2 diagonal pieces, the facet, the magenta line */
    assert_int_equal(cp.nv, 8);
    assert_int_equal(cp.ne, 6 + 5 + 1 + 1);
    sf_cp_free(&cp);
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_path_data),
        cmocka_unit_test(test_transforms),
        cmocka_unit_test(test_convention_and_planarize),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
