/* test_finite.c - a non-finite number never reaches an output file, and
 * never as a 0 in its place (issue 14): sf_need_finite names the quantity;
 * the reactions table and the ParaView collection refuse a NaN or an
 * infinity at the point where the row is added (status SF_ENUMERIC, a
 * one-line message), and the file written afterwards holds only the
 * finite rows. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "outbuf.h"
#include "reactions.h"
#include "vtk.h"

/* The whole file (at most size - 1 bytes) into buf. */
static void slurp(const char *path, char *buf, size_t size)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    size_t n = fread(buf, 1, size - 1, f);
    buf[n] = '\0';
    fclose(f);
}

static void test_need_finite(void **state)
{
    (void)state;
    sf_error err;
    sf_error_clear(&err);
    assert_int_equal(sf_need_finite(&err, 1.5, "energy at row %d", 3), 0);
    assert_int_equal(sf_need_finite(&err, -0.0, "energy at row %d", 3), 0);
    assert_int_equal(err.code, SF_OK);
    assert_int_equal(sf_need_finite(&err, NAN, "probe %s uz at row %d (p = %g)", "tip", 7, 0.25), SF_ENUMERIC);
    assert_int_equal(err.code, SF_ENUMERIC);
    assert_string_equal(err.msg, "non-finite probe tip uz at row 7 (p = 0.25) (nan): not written");
    assert_null(strchr(err.msg, '\n'));
    sf_error_clear(&err);
    assert_int_equal(sf_need_finite(&err, -INFINITY, "time t at step %d", 2), SF_ENUMERIC);
    assert_string_equal(err.msg, "non-finite time t at step 2 (-inf): not written");
}

/* A reactions table with one row, the prescribed-displacement force
 * (probe 1, z): the NaN point is refused, the finite ones are written. */
static void test_reactions(void **state)
{
    (void)state;
    int rowc[1] = {2};
    sf_equil eq;
    memset(&eq, 0, sizeof eq);
    eq.nq = 2;
    eq.nsup = 1;
    eq.rowc = rowc;
    eq.disp_row = 0;
    sf_reactions t;
    sf_reactions_init(&t, 0);
    sf_error err;
    sf_error_clear(&err);
    double y1[3] = {0.1, 0.2, -4.0}, ybad[3] = {0.1, 0.2, NAN}, y2[3] = {0.1, 0.2, 8.0};
    assert_int_equal(sf_reactions_add(&t, &eq, 0, y1, 0.25, 0.25, &err), SF_OK);
    assert_int_equal(sf_reactions_add(&t, &eq, 1, ybad, 0.5, 0.5, &err), SF_ENUMERIC);
    assert_string_equal(err.msg, "non-finite reaction probe1_fz at point 1 (p = 0.5) (nan): not written");
    sf_error_clear(&err);
    double ybadp[3] = {0.1, 0.2, 1.0};
    assert_int_equal(sf_reactions_add(&t, &eq, 1, ybadp, INFINITY, 0.5, &err), SF_ENUMERIC);
    assert_string_equal(err.msg, "non-finite p at reactions.tsv point 1 (inf): not written");
    sf_error_clear(&err);
    assert_int_equal(sf_reactions_add(&t, &eq, 2, y2, 0.75, 0.75, &err), SF_OK);
    char dir[] = "/tmp/sf_finite_XXXXXX", path[64], buf[4096];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/reactions.tsv", dir);
    assert_int_equal(sf_reactions_write(&t, &eq, path, NULL, &err), SF_OK);
    slurp(path, buf, sizeof buf);
    /* the rows: exactly the two finite points, the reaction minus the multiplier */
    const char *rows = strstr(buf, "point\tp\tload\tprobe1_fz\n");
    assert_non_null(rows);
    rows += strlen("point\tp\tload\tprobe1_fz\n");
    assert_string_equal(rows, "0\t0.25\t0.25\t4\n2\t0.75\t0.75\t-8\n");
    assert_null(strstr(buf, "nan"));
    remove(path);
    rmdir(dir);
    sf_reactions_free(&t);
}

/* The .pvd collection: a non-finite time is refused when the shape is
 * added; the file lists the others. */
static void test_pvd(void **state)
{
    (void)state;
    char dir[] = "/tmp/sf_finite_XXXXXX", path[64], buf[4096];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/shapes.pvd", dir);
    sf_pvd p;
    sf_pvd_init(&p, path);
    sf_error err;
    sf_error_clear(&err);
    assert_int_equal(sf_pvd_add(&p, 0.0, "shapes/shape_0000.vtp", &err), SF_OK);
    assert_int_equal(sf_pvd_add(&p, NAN, "shapes/shape_0001.vtp", &err), SF_ENUMERIC);
    assert_non_null(strstr(err.msg, "non-finite time (nan) of shapes/shape_0001.vtp: not written"));
    sf_error_clear(&err);
    assert_int_equal(sf_pvd_add(&p, 2.0, "shapes/shape_0002.vtp", &err), SF_OK);
    assert_int_equal(sf_pvd_write(&p, &err), SF_OK);
    slurp(path, buf, sizeof buf);
    assert_non_null(strstr(buf, "timestep=\"0\" part=\"0\" file=\"shapes/shape_0000.vtp\""));
    assert_non_null(strstr(buf, "timestep=\"2\" part=\"0\" file=\"shapes/shape_0002.vtp\""));
    assert_null(strstr(buf, "shape_0001"));
    remove(path);
    rmdir(dir);
    sf_pvd_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_need_finite),
        cmocka_unit_test(test_reactions),
        cmocka_unit_test(test_pvd),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
