/* test_validation.c - whole equilibrium paths, run as
 * src/cli/run_equilibrium.c runs them (sf_equil + the continuation engine
 * with a point callback), against the
 * reference data of ../shared/data (CASES.md, data/README.md):
 *   strip3      against the paper's own code (the finite-element
 *               comparisons are in studies/strip3.cfg, checked by
 *               tests/test_accuracy.sh);
 *   waterbomb2  in the paper's penalty mode against the paper's code;
 *   square4     exact loop closure along the whole path (residuals and
 *               stationarity of the Lagrangian), and exact against the
 *               paper's penalty.
 * Each comparison says which effect its tolerance covers. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sf_test.h"

#include "cont.h"
#include "energy.h"
#include "equilibrium.h"
#include "kinematics.h"
#include "scene.h"
#include "study.h"

static char data_dir[1024];

/* ------------------------------------------------------------------------
 * Reference data: CSV with '#' provenance lines, a header row, numbers
 * ------------------------------------------------------------------------ */

#define CSV_MAXCOL 16
typedef struct csv {
    int ncol, nrow;
    char name[CSV_MAXCOL][32];
    double *v;   /* [nrow][ncol] */
} csv;

static void csv_read(csv *c, const char *file)
{
    char path[1200], line[1024];
    snprintf(path, sizeof path, "%s/%s", data_dir, file);
    FILE *f = fopen(path, "r");
    if (!f) {
        print_error("cannot open reference data %s (SF_SHARED)\n", path);
        fail();
    }
    memset(c, 0, sizeof *c);
    int cap = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#' || line[0] == '\n' || line[0] == '\r') continue;
        line[strcspn(line, "\r\n")] = '\0';
        if (c->ncol == 0) {
            for (char *tok = strtok(line, ","); tok && c->ncol < CSV_MAXCOL; tok = strtok(NULL, ","))
                snprintf(c->name[c->ncol++], sizeof c->name[0], "%s", tok);
            continue;
        }
        if (c->nrow == cap) {
            cap = cap ? 2 * cap : 32;
            c->v = realloc(c->v, sizeof(double) * (size_t)cap * c->ncol);
            assert_non_null(c->v);
        }
        char *s = line;
        for (int j = 0; j < c->ncol; j++) {
            char *end;
            c->v[(size_t)c->nrow * c->ncol + j] = strtod(s, &end);
            if (end == s) {
                print_error("%s: bad number in row %d column %d\n", path, c->nrow + 1, j + 1);
                fail();
            }
            s = end + (*end == ',');
        }
        c->nrow++;
    }
    fclose(f);
    assert_true(c->ncol > 0 && c->nrow > 0);
}

static int csv_col(const csv *c, const char *name)
{
    for (int j = 0; j < c->ncol; j++)
        if (strcmp(c->name[j], name) == 0) return j;
    print_error("reference data: no column %s\n", name);
    fail();
    return -1;
}

static double csv_at(const csv *c, int row, int col) { return c->v[(size_t)row * c->ncol + col]; }

static void csv_free(csv *c) { free(c->v); memset(c, 0, sizeof *c); }

/* ------------------------------------------------------------------------
 * Running a path as src/cli/run_equilibrium.c does
 * ------------------------------------------------------------------------ */

typedef struct path {
    const char *label;
    sf_scene sc;
    sf_equil eq;
    int have_eq;
    sf_mpoint probe;            /* the report probe (the first probe) */
    cont_solver *cs;
    double start, end, tol;
    int n, cap;                 /* collected points */
    double *p, *u, *y;          /* p[n], u[n][3], y[n][eq.n] */
    double *rr, *rt, *fres;     /* loop residuals (rotation, translation [m]), max |fscale F| */
} path;

static void probe_disp(path *P, const double *y, double u[3])
{
    double x[3];
    sf_kin_eval(P->eq.m, y, 0, &P->eq.k);
    sf_point_eval(P->eq.m, &P->eq.k, &P->probe, x, NULL);
    u[0] = x[0] - P->probe.X[0];
    u[1] = x[1] - P->probe.X[1];
    u[2] = x[2];
}

static double scaled_residual(path *P, const double *y, double p)
{
    int n = P->eq.n;
    double *F = calloc((size_t)n + 1, sizeof *F), r = 0.0;
    assert_non_null(F);
    if (sf_equil_residual(y, p, F, &P->eq)) r = INFINITY;
    else
        for (int i = 0; i < n; i++) r = fmax(r, fabs(P->eq.fscale[i] * F[i]));
    free(F);
    return r;
}

static void add_point(path *P, const double *y, double p)
{
    int n = P->eq.n;
    if (P->n == P->cap) {
        P->cap = P->cap ? 2 * P->cap : 64;
        P->p = realloc(P->p, sizeof(double) * P->cap);
        P->u = realloc(P->u, sizeof(double) * 3 * P->cap);
        P->y = realloc(P->y, sizeof(double) * (size_t)n * P->cap);
        P->rr = realloc(P->rr, sizeof(double) * P->cap);
        P->rt = realloc(P->rt, sizeof(double) * P->cap);
        P->fres = realloc(P->fres, sizeof(double) * P->cap);
        assert_true(P->p && P->u && P->y && P->rr && P->rt && P->fres);
    }
    int i = P->n++;
    double Pi;
    P->p[i] = p;
    memcpy(P->y + (size_t)i * n, y, sizeof(double) * n);
    sf_equil_report(&P->eq, y, p, &Pi, &P->rr[i], &P->rt[i]);
    probe_disp(P, y, P->u + 3 * i);
    P->fres[i] = scaled_residual(P, y, p);
}

static int on_point(const cont_point *pt, void *data)
{
    add_point(data, pt->y, pt->p);
    return 0;
}

static int make_solver(sf_equil *eq, cont_solver **out)
{
    return sf_equil_create_solver(eq, out);
}

/* The start of an exact path off the flat state, the library's own. */
static void penalty_homotopy(path *P, double p1, double *y)
{
    sf_error err;
    sf_error_clear(&err);
    if (sf_equil_start_off_flat(&P->eq, p1, P->tol, y, &err) != SF_OK) {
        print_error("%s: penalty start at p = %g: %s\n", P->label, p1, err.msg);
        fail();
    }
}

/* Open the study with its overrides, follow the analysis of the study
 * (parameter load, its start, end, step and tolerances) to its end and
 * collect every point. */
static void run_path(path *P, const char *study, int nset, const char **sets, const char *label)
{
    memset(P, 0, sizeof *P);
    P->label = label;
    char file[1200];
    snprintf(file, sizeof file, "%s/%s.cfg", studies_dir, study);
    sf_error err;
    sf_error_clear(&err);
    if (sf_scene_open(&P->sc, file, nset, sets, &err)) {
        print_error("%s: cannot open %s: %s\n", label, file, err.msg);
        fail();
    }
    const sf_study *s = &P->sc.study;
    double step, min_step, max_step;
    int max_steps;
    const char *param;
    assert_int_equal(sf_study_string(s, "analysis.parameter", "load", &param, &err), SF_OK);
    assert_string_equal(param, "load");
    assert_int_equal(sf_study_double(s, "analysis.start", 0.0, &P->start, &err), SF_OK);
    assert_int_equal(sf_study_double(s, "analysis.end", (double)s->nstages, &P->end, &err), SF_OK);
    assert_int_equal(sf_study_double(s, "analysis.step", 0.05, &step, &err), SF_OK);
    assert_int_equal(sf_study_double(s, "analysis.min_step", 1e-6, &min_step, &err), SF_OK);
    assert_int_equal(sf_study_double(s, "analysis.max_step", 0.2, &max_step, &err), SF_OK);
    assert_int_equal(sf_study_int(s, "analysis.max_steps", 500, &max_steps, &err), SF_OK);
    P->tol = s->tolerance > 0 ? s->tolerance : 1e-10;
    if (sf_equil_init(&P->eq, &P->sc.model, SF_PARAM_LOAD, -1, 0, 2, 0.0, &err)) {
        print_error("%s: %s\n", label, err.msg);
        fail();
    }
    P->have_eq = 1;
    sf_equil *eq = &P->eq;
    if (s->constraints == SF_CONSTRAINTS_PENALTY)
        sf_equil_use_penalty(eq, s->penalty_rotation, s->penalty_translation);
    assert_true(s->nprobes > 0);
    assert_int_equal(sf_model_locate(&P->sc.model, s->probes[0].at, &P->probe, &err), SF_OK);
    assert_int_equal(make_solver(eq, &P->cs), CONT_OK);
    cont_solver *cs = P->cs;
    cont_set_step(cs, step, min_step, max_step);
    cont_set_prange(cs, fmin(P->start, P->end), fmax(P->start, P->end));
    cont_set_max_steps(cs, max_steps);
    cont_set_newton(cs, P->tol, 12, 0);
    cont_set_callback(cs, on_point, P);
    cont_set_store(cs, 0);
    int dir = P->end >= P->start ? +1 : -1;
    double *y0 = calloc((size_t)eq->n + 1, sizeof(double));
    assert_non_null(y0);
    int rc;
    if (eq->nloop > 0 && scaled_residual(P, y0, P->start) <= 1e-14) {
        /* the flat state: report it, start one step further (src/cli/run_equilibrium.c) */
        add_point(P, y0, P->start);
        double p1 = P->start + dir * fmin(step, 0.25 * fabs(P->end - P->start));
        penalty_homotopy(P, p1, y0);
        rc = cont_start(cs, y0, p1, dir);
    } else {
        rc = cont_start(cs, y0, P->start, dir);
    }
    free(y0);
    if (rc != CONT_OK) {
        print_error("%s: no start: %s\n", label, cont_errmsg(cs));
        fail();
    }
    rc = cont_run(cs);
    if (rc == CONT_FAIL) {
        print_error("%s: path failed after %d points: %s\n", label, P->n, cont_errmsg(cs));
        fail();
    }
    /* the path reaches the end of the analysis */
    assert_true(P->n >= 2);
    CHECK_CLOSE(P->p[P->n - 1], P->end, 1e-9, "%s: last point of the path", label);
}

static void path_free(path *P)
{
    if (P->cs) cont_free(P->cs);
    if (P->have_eq) sf_equil_free(&P->eq);
    sf_scene_close(&P->sc);
    free(P->p); free(P->u); free(P->y); free(P->rr); free(P->rt); free(P->fres);
    memset(P, 0, sizeof *P);
}

/* Solve at exactly p from the nearest point of the path (cont_solve_fixed)
 * and return the probe displacement; y (eq.n) receives the state. */
static void solve_at(path *P, double p, double u[3], double *y)
{
    int best = 0;
    for (int i = 1; i < P->n; i++)
        if (fabs(P->p[i] - p) < fabs(P->p[best] - p)) best = i;
    int n = P->eq.n;
    memcpy(y, P->y + (size_t)best * n, sizeof(double) * n);
    if (fabs(P->p[best] - p) > 1e-14 || P->fres[best] > P->tol) {
        if (cont_solve_fixed(P->cs, y, p) != CONT_OK) {
            print_error("%s: no equilibrium at p = %g from the path point at p = %g: %s\n",
                        P->label, p, P->p[best], cont_errmsg(P->cs));
            fail();
        }
    }
    CHECK_LE(scaled_residual(P, y, p), P->tol, "%s: residual of the solution at p = %g", P->label, p);
    probe_disp(P, y, u);
}

/* ------------------------------------------------------------------------
 * strip3 against the paper's own code
 * ------------------------------------------------------------------------ */

/* strip3 with K = 0 is the paper's model (one variable per fold), but not
 * its numbers: the paper's code builds the fold cross-section from cubic
 * Hermite curves with parameters from tables, ours is the exact circular
 * arc (MODEL.md 2).  The two sections differ by ~2e-4 (relative) at the
 * fold angles of this path (|theta| < 0.5), which is what the end points
 * show: uz -0.057243 (ours) against -0.057253 m (theirs), 1.8e-4; ux, a
 * second-order quantity, 8e-4.  So the END POINT is held to 1e-3 of the
 * final deflection, and to 2e-6 m of MODEL.md's -0.057243 m.
 *
 * The INTERMEDIATE points of the paper's file are not converged to that
 * level.  Its load-deflection curve is not concave: the increments of uz
 * over the 2nd to 5th load steps are 3.99, 4.10, 4.22, 3.87 mm (and 2.96,
 * 3.01 mm at steps 9-10), where any smooth equilibrium path of this
 * softening structure has decreasing increments (ours: 4.27, 4.22, 4.14,
 * 4.02, ... 1.44 mm, checked below).  Our differences to that file
 * alternate between 2e-5 and 4.6e-3 of the end deflection from one load to
 * the next, which no model difference does: they are the scatter of the
 * paper's solver (20 load steps, loose tolerances).  Along the path the
 * tolerance is therefore 5e-3 of the end deflection, the size of that
 * scatter; it is applied only while the reference shows that scatter
 * (non-concave increments, counted below): a converged reference file
 * would bring back the 1e-3 of the end point everywhere. */
static void test_strip3_paper_code(void **state)
{
    (void)state;
    path P;
    run_path(&P, "strip3", 0, NULL, "strip3 K=0");
    csv c;
    csv_read(&c, "strip3_paper_code.csv");
    int cp = csv_col(&c, "load_factor"), cx = csv_col(&c, "probe1_ux"), cz = csv_col(&c, "probe1_uz");
    int cth = csv_col(&c, "theta1");
    int last = c.nrow - 1;
    double xend = fabs(csv_at(&c, last, cx)), zend = fabs(csv_at(&c, last, cz));
    /* scatter of the reference: increments of uz that grow (the curve must
     * be concave: |uz| increments decrease) */
    int ref_bumps = 0;
    for (int r = 2; r < c.nrow; r++) {
        double d1 = fabs(csv_at(&c, r - 1, cz) - csv_at(&c, r - 2, cz));
        double d2 = fabs(csv_at(&c, r, cz) - csv_at(&c, r - 1, cz));
        if (d2 > d1) ref_bumps++;
    }
    double tol_path = ref_bumps > 0 ? 5e-3 : 1e-3;
    double *y = calloc(P.eq.n, sizeof *y);
    double *uz = calloc(c.nrow, sizeof *uz);
    double ex = 0, ez = 0, eth = 0, u[3];
    int nload = 0;
    for (int r = 0; r < c.nrow; r++) {
        double p = csv_at(&c, r, cp);
        if (p > 0) nload++;
        solve_at(&P, p, u, y);
        uz[r] = u[2];
        double dx = fabs(u[0] - csv_at(&c, r, cx)) / xend;
        double dz = fabs(u[2] - csv_at(&c, r, cz)) / zend;
        ex = fmax(ex, dx);
        ez = fmax(ez, dz);
        /* fold angles: that code's sign convention, so magnitudes */
        for (int i = 0; i < 3; i++) {
            double th = y[P.sc.model.qoff[i]], ref = csv_at(&c, r, cth + i);
            eth = fmax(eth, fabs(fabs(th) - fabs(ref)) / fabs(csv_at(&c, last, cth)));
        }
        double tol = r == last ? 1e-3 : tol_path;
        CHECK_LE(dz, tol, "strip3 K=0 against the paper's code: |uz - uz_ref| / |uz_ref(end)| at p = %g", p);
        CHECK_LE(dx, tol, "strip3 K=0 against the paper's code: |ux - ux_ref| / |ux_ref(end)| at p = %g", p);
    }
    assert_int_equal(nload, 20);
    /* our path is smooth: uz increments decrease monotonically */
    for (int r = 2; r < c.nrow; r++)
        CHECK_LE(fabs(uz[r] - uz[r - 1]), fabs(uz[r - 1] - uz[r - 2]),
                 "strip3 K=0: uz increment at p = %g (concave load-deflection curve)",
                 csv_at(&c, r, cp));
    print_message("# strip3 K=0 vs paper's code (%d loads): max |duz|/|uz_end| %.3g, "
                  "max |dux|/|ux_end| %.3g, max ||theta|-|theta_ref||/|theta1_end| %.3g; "
                  "the reference has %d growing uz increments (path tolerance %g)\n",
                  nload, ez, ex, eth, ref_bumps, tol_path);
    /* the end point: MODEL.md section 3, -0.057243 m for K = 0 */
    solve_at(&P, 1.0, u, y);
    print_message("# strip3 K=0 end point uz = %.7f m, ux = %.7f m (paper's code %.7f, %.7f m)\n",
                  u[2], u[0], csv_at(&c, last, cz), csv_at(&c, last, cx));
    CHECK_CLOSE(u[2], -0.057243, 2e-6, "strip3 K=0: tip uz at 0.2 N (MODEL.md 3)");
    free(uz);
    free(y);
    csv_free(&c);
    path_free(&P);
}

/* strip3 against the plane-strain and 3-D shell finite elements, and fold1
 * against the exact elastica, moved to the reference-comparison feature:
 * the tolerances (with their reasons) are declared in studies/strip3.cfg
 * and checked at K = 0 and K = 6, and the convergence in K against the
 * elastica, by tests/test_accuracy.sh. */

/* ------------------------------------------------------------------------
 * waterbomb2, penalty mode, against the paper's code
 * ------------------------------------------------------------------------ */

/* The paper's setting: penalty loop closure with lambda_R = 100 J and
 * lambda_d = 1 J/m^2 (the study's solver.penalty_* values), K = 0, gravity
 * over p in [0, 1] then the point load over [1, 2].  Our end point is
 * uz = -0.071678 m against the paper's -0.071288 m (0.55%), while the
 * gravity-stage points differ by up to ~8%.  The 1% tolerance on the end
 * point is the OBSERVED agreement: it is not explained by the cross-section
 * difference alone (that is ~2e-4 on strip3, see above), and the cause of
 * the larger gravity-stage differences is not identified yet (candidates:
 * the paper's treatment of fold-band weight, its loose solver tolerances
 * (angle change 1e-4), or a different penalty frame).  The maximum
 * difference along the path is printed, not asserted. */
static void test_waterbomb2_penalty_paper(void **state)
{
    (void)state;
    const char *sets[] = {"solver.constraints=\"penalty\""};
    path P;
    run_path(&P, "waterbomb2", 1, sets, "waterbomb2 penalty");
    assert_int_equal(P.eq.nloop, 0);
    CHECK_CLOSE(P.eq.e.lR, 100.0, 0.0, "waterbomb2: paper's lambda_R");
    CHECK_CLOSE(P.eq.e.ld, 1.0, 0.0, "waterbomb2: paper's lambda_d");
    csv c;
    csv_read(&c, "waterbomb2_paper_code.csv");
    int cg = csv_col(&c, "gravity_factor"), cl = csv_col(&c, "load_factor");
    int cx = csv_col(&c, "probe1_ux"), cy = csv_col(&c, "probe1_uy"), cz = csv_col(&c, "probe1_uz");
    int ct = csv_col(&c, "translation_residual");
    double *y = calloc(P.eq.n, sizeof *y), u[3];
    double dmax = 0, pmax = 0, relg[3] = {0, 0, 0}, rell[3] = {0, 0, 0};
    for (int r = 0; r < c.nrow; r++) {
        double p = csv_at(&c, r, cg) + csv_at(&c, r, cl);
        solve_at(&P, p, u, y);
        double ref[3] = {csv_at(&c, r, cx), csv_at(&c, r, cy), csv_at(&c, r, cz)};
        double d = sqrt((u[0] - ref[0]) * (u[0] - ref[0]) + (u[1] - ref[1]) * (u[1] - ref[1]) +
                        (u[2] - ref[2]) * (u[2] - ref[2]));
        if (d > dmax) { dmax = d; pmax = p; }
        for (int k = 0; k < 3; k++) {
            double rel = ref[k] != 0 ? fabs(u[k] - ref[k]) / fabs(ref[k]) : 0.0;
            if (p <= 1.0) relg[k] = fmax(relg[k], rel);
            else rell[k] = fmax(rell[k], rel);
        }
        if (r == c.nrow - 1) {
            double Pi, rr, rt;
            sf_equil_report(&P.eq, y, p, &Pi, &rr, &rt);
            print_message("# waterbomb2 penalty end point: u = (%.6f, %.6f, %.6f) m, paper "
                          "(%.6f, %.6f, %.6f) m; loop residual rot %.3g, translation %.3g m "
                          "(paper's translation norm %.3g m)\n",
                          u[0], u[1], u[2], ref[0], ref[1], ref[2], rr, rt, csv_at(&c, r, ct));
            CHECK_CLOSE(u[2], ref[2], 1e-2 * fabs(ref[2]),
                        "waterbomb2 penalty: end point uz against the paper's code (observed 0.55%%)");
        }
    }
    print_message("# waterbomb2 penalty vs paper's code along the path: max |u - u_ref| %.3g m "
                  "(at p = %g); max relative difference (ux, uy, uz): gravity stage (%.1f%%, "
                  "%.1f%%, %.1f%%), load stage (%.1f%%, %.1f%%, %.1f%%)\n",
                  dmax, pmax, 100 * relg[0], 100 * relg[1], 100 * relg[2], 100 * rell[0],
                  100 * rell[1], 100 * rell[2]);
    free(y);
    csv_free(&c);
    path_free(&P);
}

/* ------------------------------------------------------------------------
 * square4: exact closure along the path, and exact against penalty
 * ------------------------------------------------------------------------ */

/* Stationarity of the Lagrangian assembled independently of
 * sf_equil_residual: max_j |dPi/dq_j + sum_c lambda_c dg_c/dq_j| / kref. */
static double lagrangian_stationarity(path *P, const double *y, double p)
{
    sf_equil *eq = &P->eq;
    const sf_model *m = eq->m;
    int nq = eq->nq, nc = m->ncon;
    double *gr = calloc((size_t)nq, sizeof *gr), *g = calloc((size_t)nc + 1, sizeof *g);
    double *J = calloc((size_t)nc * nq + 1, sizeof *J);
    sf_kin k;
    assert_int_equal(sf_kin_alloc(m, &k), SF_OK);
    sf_kin_eval(m, y, 1, &k);
    sf_equil_set_param(eq, p);
    sf_energy_eval(&eq->e, &k, &eq->par, gr, NULL, 0, NULL);
    sf_constraints(m, &k, g, J, NULL, NULL, 0);
    assert_int_equal(eq->nloop, nc);
    assert_int_equal(eq->nsup, 0);
    double r = 0.0;
    for (int j = 0; j < nq; j++) {
        double s = gr[j];
        for (int c = 0; c < nc; c++) s += y[nq + c] * J[(size_t)c * nq + j];
        r = fmax(r, fabs(s) / eq->kref);
    }
    sf_kin_free(&k);
    free(gr); free(g); free(J);
    return r;
}

static void test_square4_exact(void **state)
{
    (void)state;
    path E;
    run_path(&E, "square4", 0, NULL, "square4 exact");
    assert_true(E.eq.exact);
    assert_int_equal(E.eq.nloop, 24);
    double rr = 0, rt = 0, fr = 0, st = 0;
    for (int i = 0; i < E.n; i++) {
        const double *y = E.y + (size_t)i * E.eq.n;
        CHECK_LE(E.rr[i], 1e-10, "square4 exact: rotation loop residual at p = %g", E.p[i]);
        CHECK_LE(E.rt[i], 1e-10, "square4 exact: translation loop residual [m] at p = %g", E.p[i]);
        CHECK_LE(E.fres[i], E.tol, "square4 exact: max |fscale F| at p = %g", E.p[i]);
        double s = lagrangian_stationarity(&E, y, E.p[i]);
        CHECK_LE(s, E.tol, "square4 exact: |grad Pi + J^T lambda| / kref at p = %g", E.p[i]);
        rr = fmax(rr, E.rr[i]);
        rt = fmax(rt, E.rt[i]);
        fr = fmax(fr, E.fres[i]);
        st = fmax(st, s);
    }
    print_message("# square4 exact (K=%d): %d points to p = %g; max loop residual rot %.2g, "
                  "translation %.2g m; max |fscale F| %.2g; max |grad L|/kref %.2g\n",
                  E.sc.study.folds[0].modes, E.n, E.p[E.n - 1], rr, rt, fr, st);

    /* the paper's penalty (lambda_R = 100 J, lambda_d = 1 J/m^2) on the
     * same model (K of the study), and on the paper's model (K = 0) */
    double *y = calloc(E.eq.n, sizeof *y), ue[3];
    solve_at(&E, 1.0, ue, y);
    const char *pen1[] = {"solver.constraints=\"penalty\""};
    const char *pen0[] = {"solver.constraints=\"penalty\"", "defaults.modes=0"};
    for (int v = 0; v < 2; v++) {
        path P;
        run_path(&P, "square4", v ? 2 : 1, v ? pen0 : pen1, v ? "square4 penalty K=0" : "square4 penalty");
        CHECK_CLOSE(P.eq.e.lR, 100.0, 0.0, "square4: paper's lambda_R");
        CHECK_CLOSE(P.eq.e.ld, 1.0, 0.0, "square4: paper's lambda_d");
        double *yp = calloc(P.eq.n, sizeof *yp), up[3], Pi, prr, prt, maxrt = 0;
        solve_at(&P, 1.0, up, yp);
        sf_equil_report(&P.eq, yp, 1.0, &Pi, &prr, &prt);
        for (int i = 0; i < P.n; i++) maxrt = fmax(maxrt, P.rt[i]);
        print_message("# square4 at p = 1: exact K=%d (u2, u3) = (%.6f, %.6f) m; penalty K=%d "
                      "(%.6f, %.6f) m: difference (%.3g, %.3g) m = (%.2f%%, %.2f%%); penalty loop "
                      "residual at p = 1: rot %.3g, translation %.3g m (max on path %.3g m)\n",
                      E.sc.study.folds[0].modes, ue[1], ue[2], P.sc.study.folds[0].modes, up[1],
                      up[2], up[1] - ue[1], up[2] - ue[2], 100 * (up[1] - ue[1]) / fabs(ue[1]),
                      100 * (up[2] - ue[2]) / fabs(ue[2]), prr, prt, maxrt);
        /* the penalty leaves the loops open (CASES.md: up to ~3 mm in the
         * paper's code); the exact mode closes them to 1e-10 */
        assert_true(prt > 1e-5);
        assert_true(prt < 2e-2);
        free(yp);
        path_free(&P);
    }
    free(y);
    path_free(&E);
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    const char *shared = getenv("SF_SHARED");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : SF_SRCDIR);
    if (shared) snprintf(data_dir, sizeof data_dir, "%s/data", shared);
    else snprintf(data_dir, sizeof data_dir, "%s/../shared/data", src ? src : SF_SRCDIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_strip3_paper_code),
        cmocka_unit_test(test_waterbomb2_penalty_paper),
        cmocka_unit_test(test_square4_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
