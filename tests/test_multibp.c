/* test_multibp.c - branch switching at the double branch point of the flat
 * square4-inplane sheet (multibp.h, docs/guides/stability.md).
 *
 * Independent values: the symmetry group of the square, D4 (8 elements),
 * built here from the study's geometry as permutations of its folds.  The
 * two buckling modes of a double eigenvalue of a D4-symmetric sheet carry
 * its two-dimensional irreducible representation; by the equivariant
 * branching lemma the branches are the fixed lines of the reflections,
 * which fall in two conjugacy classes ({x, y axes}, {diagonals}), so the
 * branches form 2 orbits of |D4| / |Z2| = 4 rays each: 8 branches.  The
 * test checks that count and that partition, with the orbits computed
 * from the geometric permutations (not from the program's own invariant),
 *  - at library level: the directions of sf_mbp_directions, each corrected
 *    and followed for a few steps by the engine: every state an
 *    equilibrium (scaled residual <= 1e-9);
 *  - at run level: `smoothfold run` on the study: the branches its note
 *    names for the flat BP2, their first states partitioned by D4, and on
 *    every row of those branches the Morse index equal to the number of
 *    negative eigenvalues listed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "cont.h"
#include "multibp.h"
#include "stability.h"
#include "sf_test.h"
#include "stab_test.h"
#include "d4_test.h"
#include "tsv_test.h"

/* Same orbit: some g maps the fold-angle magnitudes of a onto those of b. */
static int same_orbit(int nf, int perm[NG][MAXF], const double *a, const double *b)
{
    double m = 0.0;
    for (int f = 0; f < nf; f++) m = fmax(m, fabs(a[f]));
    for (int g = 0; g < NG; g++) {
        int ok = 1;
        for (int f = 0; f < nf && ok; f++)
            if (fabs(fabs(b[perm[g][f]]) - fabs(a[f])) > 1e-6 * m) ok = 0;
        if (ok) return 1;
    }
    return 0;
}

/* Partition nb states (fold angles, nf each) into orbits; checks 2 orbits
 * of 4 and that states in one orbit differ (8 distinct branches). */
static void check_orbits(const char *what, int nf, int perm[NG][MAXF], const double *th, int nb)
{
    int cls[16], ncls = 0, size[16] = {0};
    assert_true(nb <= 16);
    for (int i = 0; i < nb; i++) {
        cls[i] = -1;
        for (int j = 0; j < i && cls[i] < 0; j++)
            if (same_orbit(nf, perm, th + (size_t)j * nf, th + (size_t)i * nf)) cls[i] = cls[j];
        if (cls[i] < 0) cls[i] = ncls++;
        size[cls[i]]++;
        for (int j = 0; j < i; j++) {
            double d = 0.0;
            for (int f = 0; f < nf; f++) d = fmax(d, fabs(th[(size_t)i * nf + f] - th[(size_t)j * nf + f]));
            if (!(d > 1e-6)) {
                print_error("%s: branches %d and %d start at the same state\n", what, j + 1, i + 1);
                fail();
            }
        }
    }
    if (nb != 8 || ncls != 2 || size[0] != 4 || size[1] != 4) {
        print_error("%s: %d branches in %d D4 orbits (sizes %d, %d); the equivariant branching "
                    "lemma gives 8 in 2 orbits of 4\n", what, nb, ncls, size[0], size[1]);
        fail();
    }
}

/* The double crossing of the flat branch: bisection on eig2 at y = 0
 * (eig3 is below zero too at the upper end). */
static double flat_bp2(sf_equil *eq)
{
    sf_stab st;
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_stab_init(&st, eq, SF_EIG_DENSE, 4, &err), err);
    double *y = calloc((size_t)eq->n, sizeof(double)), a = 0.296, b = 0.31;
    assert_non_null(y);
    CHECK_OK(sf_stab_eval(&st, eq, y, b, &err), err);
    assert_true(st.res.eig[2] < 0);
    double p = flat_zero(&st, eq, y, 1, a, b);
    free(y);
    sf_stab_free(&st);
    return p;
}

static void test_library(void **state)
{
    (void)state;
    sf_scene sc;
    open_scene(&sc, "square4-inplane", 0, NULL);
    int perm[NG][MAXF];
    d4_perms(&sc.study, perm);
    sf_equil eq;
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_equil_init(&eq, &sc.model, SF_PARAM_LOAD, -1, 0, 2, 0.0, &err), err);
    sf_equil_use_penalty(&eq, sc.study.penalty_rotation, sc.study.penalty_translation);
    double p2 = flat_bp2(&eq);
    double *y0 = calloc((size_t)eq.n, sizeof(double));
    assert_non_null(y0);
    sf_mbp M;
    CHECK_OK(sf_mbp_directions(&eq, y0, p2, 2, 0.02, 0.05, &M, &err), err);
    assert_int_equal(M.order, 3);   /* z -> -z symmetry: no quadratic part */
    int nf = sc.model.nfolds, n = eq.n;
    double *th = calloc((size_t)M.ndir * nf, sizeof(double)), *F = calloc((size_t)n, sizeof(double));
    assert_non_null(th);
    assert_non_null(F);
    cont_solver *cs = NULL;
    assert_int_equal(sf_equil_create_solver(&eq, &cs), CONT_OK);
    cont_set_step(cs, 0.005, 1e-8, 0.01);
    cont_set_newton(cs, 1e-10, 12, 0);
    for (int k = 0; k < M.ndir; k++) {
        int st = cont_start_tangent(cs, M.y + (size_t)k * n, M.p[k], M.ty + (size_t)k * n, M.tp[k]);
        if (st != CONT_OK) print_error("direction %d: %s\n", k, cont_errmsg(cs));
        assert_int_equal(st, CONT_OK);
        for (int f = 0; f < nf; f++) th[(size_t)k * nf + f] = cont_get_point(cs)->y[sc.model.qoff[f]];
        for (int step = 0; step <= 8; step++) {
            const cont_point *pt = cont_get_point(cs);
            assert_int_equal(sf_equil_residual(pt->y, pt->p, F, &eq), 0);
            double r = 0.0, amp = 0.0;
            for (int i = 0; i < n; i++) r = fmax(r, fabs(F[i] * eq.fscale[i]));
            for (int i = 0; i < n; i++) amp = fmax(amp, fabs(pt->y[i]));
            CHECK_LE(r, 1e-9, "direction %d, point %d: scaled residual", k, step);
            CHECK_LE(1e-3, amp, "direction %d, point %d: off the flat state", k, step);
            if (step < 8) assert_int_equal(cont_step(cs), CONT_CONTINUE);
        }
    }
    check_orbits("sf_mbp_directions", nf, perm, th, M.ndir);
    cont_free(cs);
    free(th);
    free(F);
    free(y0);
    sf_mbp_free(&M);
    sf_equil_free(&eq);
    sf_scene_close(&sc);
}

/* ---- run level ---------------------------------------------------------- */

static void test_run(void **state)
{
    (void)state;
    char dir[1200], path[1300];
    tsv_out_dir(dir, sizeof dir, "multibp-out");
    tsv_run("square4-inplane", dir, "--set analysis.end=0.45");
    snprintf(path, sizeof path, "%s/branch.tsv", dir);
    tsv t;
    tsv_read(&t, path);
    /* the note of the flat branch's BP2 names its branches */
    const char *key = ": 8 distinct branches in 2 classes of symmetric images";
    char *nt = strstr(t.header, key);
    if (!nt) print_error("no note \"%s\" in %s\n", key, path);
    assert_non_null(nt);
    int br[16], nb = 0;
    for (char *p = strchr(nt, '['); p && *p && *p != '\n' && nb < 16; p++)
        if (*p >= '0' && *p <= '9') {
            br[nb++] = (int)strtol(p, &p, 10);
            p--;
        }
    sf_scene sc;
    open_scene(&sc, "square4-inplane", 0, NULL);
    int perm[NG][MAXF], nf = sc.study.nfolds;
    d4_perms(&sc.study, perm);
    double *th = calloc((size_t)nb * nf + 1, sizeof(double));
    assert_non_null(th);
    for (int i = 0; i < nb; i++) {
        int first = -1, rows = 0;
        for (int r = 0; r < t.nrow; r++) {
            if (atoi(tsv_str(&t, r, "branch")) != br[i]) continue;
            if (first < 0) first = r;
            rows++;
            /* the Morse index is the number of negative eigenvalues listed
             * (all of them when fewer than eig1..eig4 are negative) */
            if (tsv_str(&t, r, "type")[0]) continue;
            int morse = atoi(tsv_str(&t, r, "morse")), neg = 0, ne = 0;
            for (int k = 1; k <= 4; k++) {
                char nm[8];
                snprintf(nm, sizeof nm, "eig%d", k);
                const char *s = tsv_str(&t, r, nm);
                if (s[0]) { ne++; neg += strtod(s, NULL) < 0; }
            }
            if (morse < ne ? neg != morse : neg != ne) {
                print_error("branch %d row %s: Morse index %d, %d of %d eigenvalues negative\n",
                            br[i], tsv_str(&t, r, "point"), morse, neg, ne);
                fail();
            }
        }
        if (rows < 3) print_error("branch %d has %d rows\n", br[i], rows);
        assert_true(rows >= 3);
        for (int f = 0; f < nf; f++) {
            char nm[16];
            snprintf(nm, sizeof nm, "theta%d", f + 1);
            th[(size_t)i * nf + f] = strtod(tsv_str(&t, first, nm), NULL);
        }
    }
    check_orbits("smoothfold run", nf, perm, th, nb);
    free(th);
    tsv_free(&t);
    sf_scene_close(&sc);
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : SF_SRCDIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_library),
        cmocka_unit_test(test_run),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
