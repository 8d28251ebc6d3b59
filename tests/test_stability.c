/* test_stability.c - stability, special points and branch switching
 * (MODEL.md 6), checked against closed forms and independent computations:
 *  - fold1-buckle: the flat state of a compressed one-fold strip buckles at
 *    P_cr = k / (b + w/3); eig1 on the flat branch is k - P (b + w/3);
 *    the two post-buckled branches are mirror images;
 *  - snap1: the limit points of an actuation-driven snap-through against
 *    the stationarity conditions of the closed-form energy, confirmed by a
 *    scan of that energy;
 *  - dense LAPACK and ARPACK eigenvalues agree (stable and unstable points);
 *  - no spurious zero eigenvalue: the tangent space of square4 has
 *    nq - ncon dimensions and the constrained Hessian is regular there;
 *  - square4 under in-plane loads: the flat sheet buckles where the
 *    smallest eigenvalue of the (linear in p) flat-state Hessian vanishes,
 *    switching finds mirror-image branches, stable and unstable;
 *  - hard cases: fold angles through pi, a stiffness ratio of 1e8, widths
 *    of 1e-6 m: followed to the end, finite, no reversal of the tangent.
 * The program is run as a user would (src/smoothfold run) and its TSV
 * files are read by column name. */
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

#include "cont.h"
#include "equilibrium.h"
#include "scene.h"
#include "stability.h"
#include "sf_test.h"
#include "stab_test.h"
#include "tsv_test.h"

/* ---- TSV files written by smoothfold run (tsv_test.h) -------------- */

/* Every field of every row is a finite number, except `type`, `warning`
 * (words) and empty eigenvalue fields. */
static void tsv_all_finite(const tsv *t)
{
    for (int r = 0; r < t->nrow; r++)
        for (int c = 0; c < t->ncol; c++) {
            const char *s = t->cell[r][c];
            if (strcmp(t->name[c], "type") == 0 || strcmp(t->name[c], "warning") == 0) continue;
            if (!s[0] && strncmp(t->name[c], "eig", 3) == 0) continue;
            char *end;
            double v = strtod(s, &end);
            if (end == s || *end || !isfinite(v)) {
                print_error("row %d column %s: '%s'\n", r, t->name[c], s);
                fail();
            }
        }
}

/* Run a study; the output directory is returned in dir. */
static void run_study(const char *study, char *dir, size_t n, const char *extra)
{
    char top[600];
    tsv_out_dir(top, sizeof top, "stab-out");
    snprintf(dir, n, "%s/%s%s", top, study, extra && extra[0] ? "-x" : "");
    tsv_run(study, dir, extra);
}

/* Move the output of a first run aside, to DIR.dense (returned in keep),
 * before a second run of the same study writes DIR. */
static void keep_dense(const char *dir, char *keep, size_t n)
{
    snprintf(keep, n, "%s.dense", dir);
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mv '%s' '%s'", keep, dir, keep);
    assert_int_equal(system(cmd), 0);
}

static void read_out(const char *dir, const char *file, tsv *t)
{
    char p[2048];
    snprintf(p, sizeof p, "%s/%s", dir, file);
    tsv_read(t, p);
}

/* ---- the one-fold closed forms (K = 0, G1): stab_test.h ----------- */

static void test_buckle_closed_form(void **state)
{
    (void)state;
    char dir[1024];
    run_study("fold1-buckle", dir, sizeof dir, NULL);
    tsv br, sp;
    read_out(dir, "branch.tsv", &br);
    read_out(dir, "special.tsv", &sp);
    tsv_all_finite(&br);
    double k = k_fold(), P = 1.5;
    double pcr = k / (B_F + W_F / 3.0) / P;
    /* exactly one BP, on branch 1, at the closed-form load */
    assert_int_equal(sp.nrow, 1);
    assert_string_equal(tsv_str(&sp, 0, "type"), "BP");
    CHECK_CLOSE(tsv_num(&sp, 0, "p"), pcr, 1e-6 * pcr, "BP load factor");
    /* flat branch: eig1 = k - p P (b + w/3) (the Hessian of Pi at t = 0),
     * Morse index 0 below the BP, 1 above */
    int n2 = 0, n3 = 0;
    for (int r = 0; r < br.nrow; r++) {
        int b = (int)tsv_num(&br, r, "branch");
        if (b == 2) n2++;
        if (b == 3) n3++;
        if (b != 1) continue;
        double p = tsv_num(&br, r, "p");
        CHECK_CLOSE(tsv_num(&br, r, "theta1"), 0.0, 1e-14, "flat branch");
        CHECK_CLOSE(tsv_num(&br, r, "eig1"), k - p * P * (B_F + W_F / 3.0), 1e-9 * k, "eig1 flat");
        if (strcmp(tsv_str(&br, r, "type"), "BP") == 0) continue;
        assert_int_equal((int)tsv_num(&br, r, "morse"), p < pcr ? 0 : 1);
    }
    /* branches 2 and 3 leave the BP in opposite directions and are mirror
     * images: the same p, opposite fold angle and tip uz, both stable */
    assert_true(n2 > 5);
    assert_int_equal(n2, n3);
    int r2 = -1, r3 = -1;
    for (int r = 0; r < br.nrow; r++) {
        if (r2 < 0 && tsv_num(&br, r, "branch") == 2) r2 = r;
        if (r3 < 0 && tsv_num(&br, r, "branch") == 3) r3 = r;
    }
    for (int i = 0; i < n2; i++) {
        double p2 = tsv_num(&br, r2 + i, "p"), p3 = tsv_num(&br, r3 + i, "p");
        CHECK_CLOSE(p2, p3, 1e-10, "mirror p");
        CHECK_CLOSE(tsv_num(&br, r2 + i, "theta1"), -tsv_num(&br, r3 + i, "theta1"), 1e-10, "mirror");
        CHECK_CLOSE(tsv_num(&br, r2 + i, "probe1_uz"), -tsv_num(&br, r3 + i, "probe1_uz"), 1e-12,
                    "mirror uz");
        if (i > 0) {
            assert_true(p2 > pcr); /* supercritical */
            assert_int_equal((int)tsv_num(&br, r2 + i, "stable"), 1);
            /* on the branch, p as a function of the angle t: equilibrium
             * k t + p P ux'(t) = 0 */
            double t = tsv_num(&br, r2 + i, "theta1");
            CHECK_CLOSE(p2, -k * t / (P * ux1(t)), 1e-8 * p2, "post-buckling p(t)");
        }
    }
    tsv_free(&br);
    tsv_free(&sp);
}

/* snap1: Pi(t; th0) = k (t - th0)^2 / 2 + P ux(t): equilibria
 * th0 = t + (P/k) ux'(t); limit points where 1 + (P/k) ux''(t) = 0. */
static double snap_f(double t, double P) { return 1.0 + P / k_fold() * ux2(t); }

static double snap_energy(double t, double th0, double P)
{
    return 0.5 * k_fold() * (t - th0) * (t - th0) + P * ux(t);
}

/* Has Pi(.; th0) a local minimum with t in [a, b]?  (energy scan) */
static int has_min(double th0, double P, double a, double b)
{
    int n = 4000;
    double h = (b - a) / n;
    for (int i = 1; i < n; i++) {
        double t = a + i * h;
        if (snap_energy(t, th0, P) < snap_energy(t - h, th0, P) &&
            snap_energy(t, th0, P) < snap_energy(t + h, th0, P))
            return 1;
    }
    return 0;
}

static void test_snap_limit_points(void **state)
{
    (void)state;
    char dir[1024];
    run_study("snap1", dir, sizeof dir, NULL);
    tsv br, sp;
    read_out(dir, "branch.tsv", &br);
    read_out(dir, "special.tsv", &sp);
    tsv_all_finite(&br);
    double P = 1.5, k = k_fold();
    /* the limit point of the folded-down state: bisection for the root of
     * snap_f on t in [-1.5, -0.3] */
    double a = -1.5, b = -0.3;
    assert_true(snap_f(a, P) * snap_f(b, P) < 0);
    for (int i = 0; i < 200; i++) {
        double m = 0.5 * (a + b);
        if (snap_f(a, P) * snap_f(m, P) <= 0) b = m;
        else a = m;
    }
    double tlp = 0.5 * (a + b);
    double th_lp = tlp + P / k * ux1(tlp); /* rest angle at the LP; rest_angle = 1 rad */
    /* the energy scan agrees: a local minimum in the folded-down well just
     * before the LP, none just after */
    assert_true(has_min(th_lp - 1e-3, P, -2.0, -0.05));
    assert_false(has_min(th_lp + 1e-3, P, -2.0, -0.05));
    /* two LPs, symmetric: +th_lp (down state snaps up) and -th_lp */
    int nlp = 0;
    for (int r = 0; r < sp.nrow; r++) {
        assert_string_equal(tsv_str(&sp, r, "type"), "LP");
        double p = tsv_num(&sp, r, "p");
        CHECK_CLOSE(fabs(p), th_lp, 1e-6 * th_lp, "LP rest angle");
        CHECK_CLOSE(tsv_num(&sp, r, "eig1"), 0.0, 1e-7 * k, "zero eigenvalue at the LP");
        nlp++;
    }
    assert_int_equal(nlp, 2);
    CHECK_CLOSE(tsv_num(&sp, 0, "p"), th_lp, 1e-6 * th_lp, "first LP at +th_lp");
    /* Morse index: 0 up to the first LP, 1 between the LPs, 0 after */
    int seen = 0;
    for (int r = 0; r < br.nrow; r++) {
        const char *ty = tsv_str(&br, r, "type");
        if (strcmp(ty, "LP") == 0) {
            seen++;
            continue;
        }
        assert_int_equal((int)tsv_num(&br, r, "morse"), seen == 1 ? 1 : 0);
        assert_int_equal((int)tsv_num(&br, r, "stable"), seen == 1 ? 0 : 1);
        /* every point satisfies the closed-form equilibrium */
        double t = tsv_num(&br, r, "theta1");
        CHECK_CLOSE(tsv_num(&br, r, "p"), t + P / k * ux1(t), 1e-8, "snap1 equilibrium");
    }
    assert_int_equal(seen, 2);
    tsv_free(&br);
    tsv_free(&sp);
}

/* The eigenvalue columns of two runs of the same study with different
 * eigensolvers agree to 1e-8 relative; the Morse index is the same.  The
 * rows must be the same points: the step bound (analysis.step_bound) is
 * off, since it follows the eigenvalues' slopes, which the two solvers
 * give to round-off only. */
static void compare_solvers(const char *study, const char *extra)
{
    char d1[1024], d2[1024], x1[1024], x2[1024];
    snprintf(x1, sizeof x1, "--set analysis.eigensolver=\\\"dense\\\" --set analysis.step_bound=false %s", extra);
    snprintf(x2, sizeof x2, "--set analysis.eigensolver=\\\"arpack\\\" --set analysis.step_bound=false %s", extra);
    run_study(study, d1, sizeof d1, x1);
    char keep[1100];
    keep_dense(d1, keep, sizeof keep);
    run_study(study, d2, sizeof d2, x2);
    tsv A, B;
    read_out(keep, "branch.tsv", &A);
    read_out(d2, "branch.tsv", &B);
    /* ARPACK really did the work */
    assert_non_null(strstr(B.header, "0 points by the dense LAPACK method"));
    assert_int_equal(A.nrow, B.nrow);
    int ne = 0;
    for (int c = 0; c < A.ncol; c++)
        if (strncmp(A.name[c], "eig", 3) == 0) ne++;
    assert_true(ne >= 4);
    double worst = 0.0;
    for (int r = 0; r < A.nrow; r++) {
        if (tsv_str(&A, r, "type")[0]) continue; /* special points: eigenvalue ~ 0 */
        assert_int_equal((int)tsv_num(&A, r, "morse"), (int)tsv_num(&B, r, "morse"));
        for (int j = 1; j <= ne; j++) {
            char nm[16];
            snprintf(nm, sizeof nm, "eig%d", j);
            double a = tsv_num(&A, r, nm), b = tsv_num(&B, r, nm);
            double rel = fabs(a - b) / fmax(fabs(a), fabs(b));
            worst = fmax(worst, rel);
            if (rel > 1e-8)
                print_error("%s row %d %s: dense %.15g arpack %.15g\n", study, r, nm, a, b);
            assert_true(rel <= 1e-8);
        }
    }
    print_message("# %s: dense vs ARPACK, %d rows x %d eigenvalues, worst relative difference %.2g\n",
                  study, A.nrow, ne, worst);
    tsv_free(&A);
    tsv_free(&B);
}

static void test_dense_vs_arpack(void **state)
{
    (void)state;
    /* square4, exact constraints, K = 1: 48 coordinates, 24 loop rows */
    compare_solvers("square4", "--set analysis.end=0.5 --set analysis.eigenvalues=6");
    /* strip3 with K = 4: 15 coordinates, no constraint */
    compare_solvers("strip3", "--set defaults.modes=4 --set analysis.eigenvalues=5");
    /* unstable states (Morse index up to 4): square4 in plane, flat branch
     * beyond buckling, no switching */
    compare_solvers("square4-inplane", "--set analysis.branch_depth=0 --set analysis.end=0.5 "
                    "--set analysis.max_step=0.05");
}

/* ARPACK never ends a run.  With one restart per attempt the first
 * attempts fail at every point of square4-inplane; the retries (larger
 * subspace) converge to the dense method's eigenvalues (1e-8, same Morse
 * index) and branch.tsv says so.  With a single attempt every point fails:
 * the run still succeeds, stable is empty (unknown) where the Morse index
 * (from the MUMPS inertia) is 0 and 0 where it is positive, no
 * eigenvalue is written, and a note gives the reason. */
static void test_arpack_retry_unknown(void **state)
{
    (void)state;
    const char *base = "--set analysis.branch_depth=0 --set analysis.end=0.5 "
                       "--set analysis.max_step=0.05 --set analysis.arpack_maxiter=1";
    compare_solvers("square4-inplane", base);
    char d[1024], x[1024];
    tsv A, B;
    run_study("square4-inplane", d, sizeof d, "--set analysis.eigensolver=\\\"arpack\\\" "
              "--set analysis.branch_depth=0 --set analysis.end=0.5 --set analysis.max_step=0.05 "
              "--set analysis.arpack_maxiter=1");
    read_out(d, "branch.tsv", &A);
    assert_non_null(strstr(A.header, "retried, converged after"));
    assert_non_null(strstr(A.header, "attempt 1: ARPACK dsaupd info 1"));
    tsv_free(&A);
    snprintf(x, sizeof x, "--set analysis.eigensolver=\\\"arpack\\\" %s "
             "--set analysis.arpack_attempts=1", base);
    run_study("square4-inplane", d, sizeof d, x);
    read_out(d, "branch.tsv", &B);
    assert_non_null(strstr(B.header, "UNKNOWN after 1 ARPACK attempt(s): attempt 1: ARPACK dsaupd"));
    int unknown = 0, unstable = 0;
    for (int r = 0; r < B.nrow; r++) {
        int morse = (int)tsv_num(&B, r, "morse");
        const char *st = tsv_str(&B, r, "stable");
        assert_string_equal(tsv_str(&B, r, "eig1"), "");
        if (morse == 0) {
            assert_string_equal(st, "");
            unknown++;
        } else {
            assert_string_equal(st, "0");
            unstable++;
        }
    }
    assert_true(unknown > 0 && unstable > 0);
    tsv_free(&B);
}

/* Branch switching with the sparse linear solver (KLU): fold1-buckle's
 * one-coordinate problem, where [Jy Fp] vanishes as a whole at the branch
 * point, gives the dense run's three branches, point for point. */
static void test_sparse_switching(void **state)
{
    (void)state;
    char d1[1024], d2[1024], keep[1100];
    run_study("fold1-buckle", d1, sizeof d1, "--set output.shapes=0");
    keep_dense(d1, keep, sizeof keep);
    run_study("fold1-buckle", d2, sizeof d2,
              "--set output.shapes=0 --set solver.linear_solver=\\\"sparse\\\"");
    tsv A, B;
    read_out(keep, "branch.tsv", &A);
    read_out(d2, "branch.tsv", &B);
    assert_null(strstr(B.header, "no switching"));
    assert_int_equal(A.nrow, B.nrow);
    assert_int_equal((int)tsv_num(&B, B.nrow - 1, "branch"), 3);
    for (int r = 0; r < A.nrow; r++) {
        assert_int_equal((int)tsv_num(&A, r, "branch"), (int)tsv_num(&B, r, "branch"));
        CHECK_CLOSE(tsv_num(&B, r, "p"), tsv_num(&A, r, "p"), 1e-9, "p, row %d", r);
        CHECK_CLOSE(tsv_num(&B, r, "theta1"), tsv_num(&A, r, "theta1"), 1e-9, "theta1, row %d", r);
    }
    tsv_free(&A);
    tsv_free(&B);
}

/* At a solved point of square4 (exact loop closure, K = 1) away from the
 * flat state: the constraint rows have full rank, the tangent space has
 * nq - ncon dimensions, and no eigenvalue is spuriously zero. */
static void test_no_spurious_zero(void **state)
{
    (void)state;
    sf_scene sc;
    open_scene(&sc, "square4", 0, NULL);
    sf_equil eq;
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_equil_init(&eq, &sc.model, SF_PARAM_LOAD, -1, 0, 2, 0.0, &err), err);
    double *y = calloc((size_t)eq.n, sizeof(double));
    CHECK_OK(sf_equil_start_off_flat(&eq, 0.3, 1e-10, y, &err), err);
    cont_solver *cs = NULL;
    assert_int_equal(sf_equil_create_solver(&eq, &cs), CONT_OK);
    assert_int_equal(cont_solve_fixed(cs, y, 0.3), CONT_OK);
    sf_stab st;
    CHECK_OK(sf_stab_init(&st, &eq, SF_EIG_DENSE, 48, &err), err);
    CHECK_OK(sf_stab_eval(&st, &eq, y, 0.3, &err), err);
    assert_int_equal(st.res.rank, eq.ncon);
    assert_int_equal(st.res.dim, eq.nq - eq.ncon);
    assert_int_equal(st.res.neig, eq.nq - eq.ncon);
    double lo = INFINITY, hi = 0;
    for (int i = 0; i < st.res.neig; i++) {
        lo = fmin(lo, fabs(st.res.eig[i]));
        hi = fmax(hi, fabs(st.res.eig[i]));
    }
    /* the smallest eigenvalue is a physical stiffness, not round-off */
    assert_true(lo > 1e-6 * hi);
    sf_stab_free(&st);
    cont_free(cs);
    free(y);
    sf_equil_free(&eq);
    sf_scene_close(&sc);
}

/* square4 in plane: the flat branch buckles where the smallest eigenvalue
 * of the flat-state constrained Hessian vanishes.  That Hessian is computed
 * at y = 0 (no continuation) for any p; bisection on p finds its zero,
 * independently of the engine's determinant test and location. */
static void test_square4_inplane(void **state)
{
    (void)state;
    sf_scene sc;
    open_scene(&sc, "square4-inplane", 0, NULL);
    sf_equil eq;
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_equil_init(&eq, &sc.model, SF_PARAM_LOAD, -1, 0, 2, 0.0, &err), err);
    sf_equil_use_penalty(&eq, sc.study.penalty_rotation, sc.study.penalty_translation);
    double *y = calloc((size_t)eq.n + 1, sizeof(double));
    sf_stab st;
    CHECK_OK(sf_stab_init(&st, &eq, SF_EIG_DENSE, 1, &err), err);
    double pbp = flat_zero(&st, &eq, y, 0, 0.0, 0.6);
    /* the next crossing of the flat branch: a double eigenvalue (the two
     * buckling modes of the square, related by its symmetry), eig2 and
     * eig3, vanish together */
    sf_stab_free(&st);
    CHECK_OK(sf_stab_init(&st, &eq, SF_EIG_DENSE, 4, &err), err);
    double pbp2 = flat_zero(&st, &eq, y, 1, pbp + 1e-6, 0.6);
    CHECK_OK(sf_stab_eval(&st, &eq, y, pbp2 - 1e-3, &err), err);
    CHECK_CLOSE(st.res.eig[1], st.res.eig[2], 1e-9 * fabs(st.res.eig[3]), "double eigenvalue");
    sf_stab_free(&st);
    free(y);
    sf_equil_free(&eq);
    sf_scene_close(&sc);

    char dir[1024];
    run_study("square4-inplane", dir, sizeof dir, "--set analysis.end=0.7");
    tsv br, sp;
    read_out(dir, "branch.tsv", &br);
    read_out(dir, "special.tsv", &sp);
    tsv_all_finite(&br);
    /* the first BP of the flat branch */
    assert_true(sp.nrow >= 1);
    assert_int_equal((int)tsv_num(&sp, 0, "branch"), 1);
    assert_string_equal(tsv_str(&sp, 0, "type"), "BP");
    CHECK_CLOSE(tsv_num(&sp, 0, "p"), pbp, 1e-6 * pbp, "square4 in-plane buckling load");
    /* the double crossing, which the determinant test cannot see, is
     * located from the Morse index: BP2 on the flat branch */
    int found2 = 0;
    for (int r = 0; r < sp.nrow; r++)
        if ((int)tsv_num(&sp, r, "branch") == 1 && strcmp(tsv_str(&sp, r, "type"), "BP2") == 0) {
            CHECK_CLOSE(tsv_num(&sp, r, "p"), pbp2, 1e-6 * pbp2, "double crossing");
            found2++;
        }
    assert_int_equal(found2, 1);
    /* the secondary BP of the buckled branches (2 and 3): the engine's
     * determinant location stops early there (1.7e-6 in arclength), the
     * run locates it again on the eigenvalue: well located, one eigenvalue
     * zero to round-off against the next */
    int sec = 0;
    for (int r = 0; r < sp.nrow; r++) {
        int bno = (int)tsv_num(&sp, r, "branch");
        if ((bno != 2 && bno != 3) || strcmp(tsv_str(&sp, r, "type"), "BP") != 0) continue;
        sec++;
        assert_true(tsv_num(&sp, r, "loc_err") < 1e-9);
        double e1 = fabs(tsv_num(&sp, r, "eig1")), e2 = fabs(tsv_num(&sp, r, "eig2"));
        if (!(e1 < 1e-9 * e2)) {
            print_error("branch %d BP at p = %g: eig1 %g, eig2 %g\n", bno, tsv_num(&sp, r, "p"), e1, e2);
            fail();
        }
    }
    assert_int_equal(sec, 2);
    /* every change of the Morse index between consecutive rows of a branch
     * is accounted for by the special points there: 1 for LP and BP (and the
     * first point of a switched branch, a BP), k for BPk */
    for (int r = 1; r < br.nrow; r++) {
        int bno = (int)tsv_num(&br, r, "branch");
        if (bno != (int)tsv_num(&br, r - 1, "branch")) continue;
        int allowed = 0;
        for (int k = r - 1; k <= r; k++) {
            const char *ty = tsv_str(&br, k, "type");
            if (strcmp(ty, "LP") == 0 || strcmp(ty, "BP") == 0) allowed++;
            else if (strncmp(ty, "BP", 2) == 0) allowed += atoi(ty + 2);
            else if (bno > 1 && (k == 0 || (int)tsv_num(&br, k - 1, "branch") != bno)) allowed++;
        }
        int d = abs((int)tsv_num(&br, r, "morse") - (int)tsv_num(&br, r - 1, "morse"));
        if (d > allowed) {
            print_error("rows %d-%d of branch %d: Morse index changes by %d, special points "
                        "account for %d\n", r - 1, r, bno, d, allowed);
            fail();
        }
    }
    /* branches through it: 2 and 3, mirror images in uz; and the whole run
     * has stable and unstable states off the flat branch */
    int nb = 0, stable_off = 0, unstable_off = 0;
    for (int r = 0; r < br.nrow; r++) {
        int bno = (int)tsv_num(&br, r, "branch");
        nb = bno > nb ? bno : nb;
        if (bno > 1 && fabs(tsv_num(&br, r, "probe1_uz")) > 1e-4) {
            if (tsv_num(&br, r, "stable") == 1) stable_off++;
            else unstable_off++;
        }
        if (bno == 1) CHECK_CLOSE(tsv_num(&br, r, "probe1_uz"), 0.0, 1e-12, "flat branch stays flat");
    }
    assert_true(nb >= 3);
    assert_true(stable_off > 0);
    assert_true(unstable_off > 0);
    int r2 = -1, r3 = -1, n2 = 0, n3 = 0;
    for (int r = 0; r < br.nrow; r++) {
        int bno = (int)tsv_num(&br, r, "branch");
        if (bno == 2) { if (r2 < 0) r2 = r; n2++; }
        if (bno == 3) { if (r3 < 0) r3 = r; n3++; }
    }
    assert_int_equal(n2, n3);
    for (int i = 0; i < n2; i++) {
        CHECK_CLOSE(tsv_num(&br, r2 + i, "p"), tsv_num(&br, r3 + i, "p"), 1e-9, "mirror p");
        CHECK_CLOSE(tsv_num(&br, r2 + i, "probe1_uz"), -tsv_num(&br, r3 + i, "probe1_uz"), 1e-9,
                    "mirror uz");
    }
    tsv_free(&br);
    tsv_free(&sp);
}

/* Consecutive secants of a branch, in (fold angles, p), never reverse: a
 * reversal would be a jump back along the branch or onto another one. */
static void check_no_reversal(const tsv *t)
{
    int nf = 0;
    for (int c = 0; c < t->ncol; c++)
        if (strncmp(t->name[c], "theta", 5) == 0) nf++;
    double prev[64], cur[64];
    int have = 0;
    for (int r = 1; r < t->nrow; r++) {
        if (tsv_num(t, r, "branch") != tsv_num(t, r - 1, "branch")) { have = 0; continue; }
        char nm[16];
        cur[0] = tsv_num(t, r, "p") - tsv_num(t, r - 1, "p");
        for (int j = 1; j <= nf && j < 64; j++) {
            snprintf(nm, sizeof nm, "theta%d", j);
            cur[j] = tsv_num(t, r, nm) - tsv_num(t, r - 1, nm);
        }
        if (have) {
            double d = 0, na = 0, nb = 0;
            for (int j = 0; j <= nf; j++) {
                d += cur[j] * prev[j];
                na += cur[j] * cur[j];
                nb += prev[j] * prev[j];
            }
            if (!(d > 0 || na == 0 || nb == 0)) print_error("secants reverse at row %d\n", r);
            assert_true(d > 0 || na == 0 || nb == 0);
        }
        memcpy(prev, cur, sizeof cur);
        have = 1;
    }
}

static void test_hard_near_pi(void **state)
{
    (void)state;
    char dir[1024];
    run_study("hard-near-pi", dir, sizeof dir, NULL);
    tsv br;
    read_out(dir, "branch.tsv", &br);
    tsv_all_finite(&br);
    assert_int_equal(br.nrow > 10, 1);
    double pmax = 0, tmax = 0;
    for (int r = 0; r < br.nrow; r++) {
        pmax = fmax(pmax, tsv_num(&br, r, "p"));
        for (int j = 1; j <= 3; j++) {
            char nm[16];
            snprintf(nm, sizeof nm, "theta%d", j);
            tmax = fmax(tmax, tsv_num(&br, r, nm));
        }
        if (r > 0) assert_true(tsv_num(&br, r, "p") > tsv_num(&br, r - 1, "p")); /* no LP here */
    }
    CHECK_CLOSE(pmax, 1.0, 1e-12, "reached the end");
    assert_true(tmax > M_PI); /* the folds roll through pi */
    assert_string_equal(tsv_str(&br, br.nrow - 1, "type"), "EP");
    check_no_reversal(&br);
    tsv_free(&br);
}

static void test_hard_stiff_ratio(void **state)
{
    (void)state;
    char dir[1024];
    run_study("hard-stiff-ratio", dir, sizeof dir, NULL);
    tsv br;
    read_out(dir, "branch.tsv", &br);
    tsv_all_finite(&br);
    CHECK_CLOSE(tsv_num(&br, br.nrow - 1, "p"), 1.0, 1e-12, "reached the end");
    for (int r = 1; r < br.nrow; r++) {
        double t1 = tsv_num(&br, r, "theta1"), t2 = tsv_num(&br, r, "theta2");
        /* the middle fold carries a smaller moment than fold 1 and is 1e8
         * times stiffer: |theta2| < 1e-8 |theta1| */
        assert_true(fabs(t2) < 1e-8 * fabs(t1));
        assert_true(fabs(t1) > 1e-3 * tsv_num(&br, r, "p"));
        assert_int_equal((int)tsv_num(&br, r, "stable"), 1);
    }
    check_no_reversal(&br);
    tsv_free(&br);
}

static void test_hard_tiny_width(void **state)
{
    (void)state;
    char dir[1024];
    run_study("hard-tiny-width", dir, sizeof dir, NULL);
    tsv br;
    read_out(dir, "branch.tsv", &br);
    tsv_all_finite(&br);
    CHECK_CLOSE(tsv_num(&br, br.nrow - 1, "p"), 1.0, 1e-12, "reached the end");
    /* nearly creases with springs k = D L / w: to first order
     * theta_i = -P (x_load - x_i) / k (the 0.2 N load at x = 0.116 folds
     * the strip down); the neglected terms are of relative order theta
     * (about 1e-4) */
    double k = E_F * H_F * H_F * H_F / (12.0 * (1.0 - NU_F * NU_F)) * L_F / 1e-6;
    const double xf[3] = {0.03, 0.06, 0.09};
    for (int r = 1; r < br.nrow; r++) {
        double p = tsv_num(&br, r, "p");
        for (int j = 0; j < 3; j++) {
            char nm[16];
            snprintf(nm, sizeof nm, "theta%d", j + 1);
            double want = -0.2 * p * (0.116 - xf[j]) / k;
            CHECK_CLOSE(tsv_num(&br, r, nm), want, 1e-3 * fabs(want), "crease limit");
        }
    }
    check_no_reversal(&br);
    tsv_free(&br);
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : SF_SRCDIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_buckle_closed_form),
        cmocka_unit_test(test_snap_limit_points),
        cmocka_unit_test(test_dense_vs_arpack),
        cmocka_unit_test(test_arpack_retry_unknown),
        cmocka_unit_test(test_no_spurious_zero),
        cmocka_unit_test(test_sparse_switching),
        cmocka_unit_test(test_square4_inplane),
        cmocka_unit_test(test_hard_near_pi),
        cmocka_unit_test(test_hard_stiff_ratio),
        cmocka_unit_test(test_hard_tiny_width),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
