/* test_bifurcation.c - the bifurcation bookkeeping (src/analysis/bifurcation/bifurcation.h)
 * on its own, without the run command, against independent values:
 *  - Morse-index bounds at located LP/BP points (constructed spectra);
 *  - fold1-buckle: the eigenvalue crossing of the flat state located by
 *    regula falsi at fixed p lands on the closed form P_cr = k / (b + w/3)
 *    (load factor 0.653855...), and the Morse-index check between two flat
 *    points emits it as a BP, but not when the engine already labelled the
 *    end point BP;
 *  - branch switching from that BP: two branches, numbered 2 and 3, mirror
 *    images in the fold angle, on the closed-form post-buckling curve
 *    k t + p P ux'(t) = 0;
 *  - square4-inplane: the double crossing of the flat state (two buckling
 *    modes related by the symmetry of the square) is emitted as one BP2,
 *    at the zero of eig2 found by bisection on the flat-state constrained
 *    Hessian alone (no continuation, no fixed-p solve). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bifurcation.h"
#include "cont.h"
#include "equilibrium.h"
#include "scene.h"
#include "stability.h"
#include "sf_test.h"
#include "stab_test.h"

/* ---- what the hooks receive ------------------------------------------- */

#define MAXREC 64
typedef struct rec {
    int nemit, nnote, nbegin, begin_branch[MAXREC];
    char label[MAXREC][16];
    double p[MAXREC], tp[MAXREC], loc_err[MAXREC];
    int has_ty[MAXREC], morse[MAXREC];
    long nrows;                 /* the caller's row counter */
    sf_stab *st;
    char notes[4096];
    /* points of switched branches: branch, p, fold angle */
    sf_bif *bif;
    int npt, pt_branch[512];
    double pt_p[512], pt_t[512];
    int qoff;
} rec;

static void rec_note(void *ctx, const char *line)
{
    rec *r = ctx;
    r->nnote++;
    strncat(r->notes, line, sizeof r->notes - strlen(r->notes) - 2);
    strcat(r->notes, "\n");
}

static int rec_emit(void *ctx, const cont_point *q)
{
    rec *r = ctx;
    assert_true(r->nemit < MAXREC);
    int i = r->nemit++;
    snprintf(r->label[i], sizeof r->label[i], "%s", q->label);
    r->p[i] = q->p;
    r->tp[i] = q->tp;
    r->loc_err[i] = q->loc_err;
    r->has_ty[i] = q->ty != NULL;
    r->morse[i] = r->st ? r->st->res.morse : -1;
    r->nrows++;
    return 0;
}

static int rec_begin(void *ctx, const sf_bif_bp *bp, int branch)
{
    rec *r = ctx;
    (void)bp;
    assert_true(r->nbegin < MAXREC);
    r->begin_branch[r->nbegin++] = branch;
    return SF_OK;
}

static int rec_point(const cont_point *pt, void *data)
{
    rec *r = data;
    if (r->npt < 512) {
        r->pt_branch[r->npt] = r->bif->branch;
        r->pt_p[r->npt] = pt->p;
        r->pt_t[r->npt] = pt->y[r->qoff];
        r->npt++;
    }
    r->nrows++;
    return 0;
}

/* A path point at state y, load factor p, with label (for the check). */
static cont_point point(const double *y, double p, const char *label)
{
    cont_point pt;
    memset(&pt, 0, sizeof pt);
    pt.index = 1;
    pt.y = y;
    pt.p = p;
    pt.s = p;
    snprintf(pt.label, sizeof pt.label, "%s", label);
    return pt;
}

/* The equilibrium problem of an opened study, as `run` sets it up. */
static void study_problem(sf_scene *sc, sf_equil *eq)
{
    sf_error err;
    sf_error_clear(&err);
    int ptype, gi, pi, ci;
    CHECK_OK(sf_equil_parse_param(&sc->study, &ptype, &gi, &pi, &ci, &err), err);
    CHECK_OK(sf_equil_init(eq, &sc->model, ptype, gi, pi, ci, 0.0, &err), err);
    if (sc->study.constraints == SF_CONSTRAINTS_PENALTY)
        sf_equil_use_penalty(eq, sc->study.penalty_rotation, sc->study.penalty_translation);
}

/* ---- Morse-index bounds ------------------------------------------------ */

static void test_morse_bounds(void **state)
{
    (void)state;
    double eig[3] = {-2e-13, 0.5, 1.0};
    sf_stab_result R = {.morse = 1, .neig = 3, .eig = eig};
    cont_point pt = point(NULL, 0.0, "");
    int lo, hi;
    sf_bif_morse_bounds(&R, &pt, 0, &lo, &hi);
    assert_int_equal(lo, 1);
    assert_int_equal(hi, 1);
    /* a located BP: its eigenvalue at zero counts either way */
    snprintf(pt.label, sizeof pt.label, "BP");
    sf_bif_morse_bounds(&R, &pt, 0, &lo, &hi);
    assert_int_equal(lo, 0);
    assert_int_equal(hi, 1);
    eig[0] = 3e-13;
    R.morse = 0;
    snprintf(pt.label, sizeof pt.label, "LP");
    sf_bif_morse_bounds(&R, &pt, 0, &lo, &hi);
    assert_int_equal(lo, 0);
    assert_int_equal(hi, 1);
    /* the first point of a switched branch is a branch point */
    pt.label[0] = '\0';
    sf_bif_morse_bounds(&R, &pt, 1, &lo, &hi);
    assert_int_equal(lo, 0);
    assert_int_equal(hi, 1);
    /* the signs of the eigenvalues decide when all the negative ones were
     * computed (the inertia count may disagree at round-off distance) */
    double eig2[3] = {-1.0, -1e-14, 2.0};
    sf_stab_result R2 = {.morse = 1, .neig = 3, .eig = eig2};
    sf_bif_morse_bounds(&R2, &pt, 0, &lo, &hi);
    assert_int_equal(lo, 2);
    assert_int_equal(hi, 2);
    /* otherwise the count: fewer eigenvalues computed than negative ones */
    sf_stab_result R3 = {.morse = 4, .neig = 2, .eig = eig2};
    sf_bif_morse_bounds(&R3, &pt, 0, &lo, &hi);
    assert_int_equal(lo, 4);
    assert_int_equal(hi, 4);
}

/* ---- fold1-buckle: one simple crossing in closed form ------------------ */

/* P_cr = k / (b + w/3), k = D L / w: pcr_fold(), k_fold() in stab_test.h */

typedef struct fold1 {
    sf_scene sc;
    sf_equil eq;
    sf_stab st;
    sf_bif bif;
    rec r;
    double *y0;
} fold1;

static void fold1_open(fold1 *f)
{
    memset(f, 0, sizeof *f);
    open_scene(&f->sc, "fold1-buckle", 0, NULL);
    study_problem(&f->sc, &f->eq);
    sf_error err;
    sf_error_clear(&err);
    CHECK_OK(sf_stab_init(&f->st, &f->eq, SF_EIG_DENSE, 1, &err), err);
    f->r.st = &f->st;
    f->r.qoff = f->sc.model.qoff[0];
    sf_bif_hooks h = {&f->r, rec_note, rec_emit, rec_begin, NULL};
    sf_bif_init(&f->bif, &f->eq, &f->st, 1e-10, 1, &f->r.nrows, &h);
    f->r.bif = &f->bif;
    f->y0 = calloc((size_t)f->eq.n + 1, sizeof(double));   /* the flat state */
    assert_non_null(f->y0);
}

static void fold1_close(fold1 *f)
{
    sf_bif_free(&f->bif);
    sf_stab_free(&f->st);
    free(f->y0);
    sf_equil_free(&f->eq);
    sf_scene_close(&f->sc);
}

static void test_fold1_locate(void **state)
{
    (void)state;
    fold1 f;
    fold1_open(&f);
    sf_error err;
    sf_error_clear(&err);
    double pa = 0.5, pb = 0.8, pcr = pcr_fold();
    CHECK_CLOSE(pcr, 0.653855061774, 1e-11, "closed form");
    CHECK_OK(sf_stab_eval(&f.st, &f.eq, f.y0, pa, &err), err);
    double fa = f.st.res.eig[0];
    /* eig1 = k - p P (b + w/3) on the flat state */
    CHECK_CLOSE(fa, k_fold() - pa * P_F * (B_F + W_F / 3.0), 1e-9 * k_fold(), "eig1 at a");
    CHECK_OK(sf_bif_prepare(&f.bif), err);
    double p = 0.0;
    double w = sf_bif_locate_eig(&f.bif, f.y0, pa, fa, 1, f.y0, pb, 1, &p);
    assert_true(w >= 0.0);
    CHECK_LE(w, 1e-9, "bracket width");
    CHECK_CLOSE(p, pcr, 1e-9 * pcr, "located crossing");
    /* the state left there is the flat one, with its eigenvalue at zero */
    CHECK_LE(maxabs(f.bif.yt, (size_t)f.eq.n), 1e-12, "flat state");
    CHECK_LE(fabs(f.st.res.eig[0]), 1e-8 * k_fold(), "eig1 at the crossing");
    /* bisection on the index alone (the eigenvalue at a unknown) finds it
     * as well */
    w = sf_bif_locate_eig(&f.bif, f.y0, pa, 1.0, 0, f.y0, pb, 1, &p);
    assert_true(w >= 0.0);
    CHECK_CLOSE(p, pcr, 1e-9 * pcr, "located from the sign");
    fold1_close(&f);
}

/* The check between two flat points on either side of P_cr: one BP row,
 * with the secant (pure p) as its tangent; none when the engine labelled
 * the second point BP itself. */
static void test_fold1_check(void **state)
{
    (void)state;
    fold1 f;
    fold1_open(&f);
    sf_error err;
    sf_error_clear(&err);
    double pa = 0.6, pb = 0.7, pcr = pcr_fold();
    cont_point a = point(f.y0, pa, ""), b = point(f.y0, pb, "");
    CHECK_OK(sf_stab_eval(&f.st, &f.eq, f.y0, pa, &err), err);
    f.r.nrows = 1;
    sf_bif_point_written(&f.bif, &a, pa);
    CHECK_OK(sf_stab_eval(&f.st, &f.eq, f.y0, pb, &err), err);
    assert_int_equal(f.st.res.morse, 1);
    CHECK_OK(sf_bif_check(&f.bif, &b, 0.0, 0, &err), err);
    assert_int_equal(f.r.nemit, 1);
    assert_string_equal(f.r.label[0], "BP");
    CHECK_CLOSE(f.r.p[0], pcr, 1e-9 * pcr, "BP from the Morse index");
    assert_int_equal(f.r.has_ty[0], 1);
    CHECK_CLOSE(f.r.tp[0], 1.0, 1e-15, "secant along p");
    /* arclength of the path here is p: its error is the bracket */
    CHECK_LE(f.r.loc_err[0], 1e-9, "location error");
    assert_int_equal(f.r.nnote, 1);
    assert_non_null(strstr(f.r.notes, "BP at row 1 (branch 1"));
    /* the check leaves the stability at b */
    CHECK_CLOSE(f.st.res.eig[0], k_fold() - pb * P_F * (B_F + W_F / 3.0), 1e-9 * k_fold(), "eig1 at b");
    /* as the first point of a branch, or when the engine located it: no row */
    f.r.nemit = 0;
    CHECK_OK(sf_bif_check(&f.bif, &b, 0.0, 1, &err), err);
    snprintf(b.label, sizeof b.label, "BP");
    CHECK_OK(sf_bif_check(&f.bif, &b, 0.0, 0, &err), err);
    assert_int_equal(f.r.nemit, 0);
    fold1_close(&f);
}

/* Switching at the BP: two branches, mirror images, on the closed-form
 * post-buckling curve. */
static void test_fold1_switch(void **state)
{
    (void)state;
    fold1 f;
    fold1_open(&f);
    sf_error err;
    sf_error_clear(&err);
    double pcr = pcr_fold();
    cont_solver *cs = NULL;
    assert_int_equal(sf_equil_create_solver(&f.eq, &cs), CONT_OK);
    cont_set_step(cs, 0.05, 1e-6, 0.05);
    cont_set_prange(cs, 0.0, 1.0);
    cont_set_max_steps(cs, 6);
    cont_set_newton(cs, 1e-10, 12, 0);
    cont_set_callback(cs, rec_point, &f.r);
    /* the BP on the flat branch, tangent along p */
    double *ty = calloc((size_t)f.eq.n, sizeof(double));
    assert_non_null(ty);
    cont_point bp = point(f.y0, pcr, "BP");
    bp.ty = ty;
    bp.tp = 1.0;
    f.r.nrows = 7;
    CHECK_OK(sf_bif_add_bp(&f.bif, &bp, &err), err);
    CHECK_OK(sf_bif_add_bp(&f.bif, &bp, &err), err);   /* known: not twice */
    assert_int_equal(f.bif.nbp, 1);
    assert_int_equal(f.bif.bp[0].point, 7);
    CHECK_OK(sf_bif_switch(&f.bif, cs, &err), err);
    assert_int_equal(f.r.nbegin, 2);
    assert_int_equal(f.r.begin_branch[0], 2);
    assert_int_equal(f.r.begin_branch[1], 3);
    assert_int_equal(f.bif.nbranches, 3);
    assert_int_equal(f.bif.bp[0].switched, 1);
    /* depth 1 reached: branch points on the new branches are not kept */
    CHECK_OK(sf_bif_add_bp(&f.bif, &bp, &err), err);
    assert_int_equal(f.bif.nbp, 1);
    int n2 = 0, n3 = 0, i2 = -1, i3 = -1;
    for (int i = 0; i < f.r.npt; i++) {
        if (f.r.pt_branch[i] == 2) { if (i2 < 0) i2 = i; n2++; }
        if (f.r.pt_branch[i] == 3) { if (i3 < 0) i3 = i; n3++; }
    }
    assert_true(n2 >= 4);
    assert_int_equal(n2, n3);
    double k = k_fold();
    for (int i = 1; i < n2; i++) {
        double t2 = f.r.pt_t[i2 + i], t3 = f.r.pt_t[i3 + i], p2 = f.r.pt_p[i2 + i];
        CHECK_CLOSE(t2, -t3, 1e-10, "mirror branches");
        CHECK_CLOSE(f.r.pt_p[i3 + i], p2, 1e-10, "mirror p");
        assert_true(fabs(t2) > 1e-4);
        CHECK_CLOSE(p2, -k * t2 / (P_F * ux1(t2)), 1e-8 * p2, "post-buckling p(t)");
    }
    free(ty);
    cont_free(cs);
    fold1_close(&f);
}

/* ---- square4-inplane: a double crossing -------------------------------- */

/* square4-inplane's flat branch with the dense stability: the first
 * eigenvalue crosses zero at pbp, the double one at pbp2 (bisection on the
 * flat state, y0 = 0). */
typedef struct square4 {
    sf_scene sc;
    sf_equil eq;
    sf_stab st;
    double *y0;
    double pbp, pbp2;
} square4;

static void square4_open(square4 *q)
{
    sf_error err;
    sf_error_clear(&err);
    open_scene(&q->sc, "square4-inplane", 0, NULL);
    study_problem(&q->sc, &q->eq);
    CHECK_OK(sf_stab_init(&q->st, &q->eq, SF_EIG_DENSE, 4, &err), err);
    q->y0 = calloc((size_t)q->eq.n + 1, sizeof(double));
    assert_non_null(q->y0);
    q->pbp = flat_zero(&q->st, &q->eq, q->y0, 0, 0.0, 0.6);
    q->pbp2 = flat_zero(&q->st, &q->eq, q->y0, 1, q->pbp + 1e-6, 0.6);
}

static void square4_close(square4 *q)
{
    sf_stab_free(&q->st);
    free(q->y0);
    sf_equil_free(&q->eq);
    sf_scene_close(&q->sc);
}

static void test_square4_double(void **state)
{
    (void)state;
    square4 q;
    square4_open(&q);
    sf_error err;
    sf_error_clear(&err);
    double pbp = q.pbp, pbp2 = q.pbp2;
    double pbp3 = flat_zero(&q.st, &q.eq, q.y0, 2, pbp + 1e-6, 0.6);
    CHECK_CLOSE(pbp3, pbp2, 1e-9 * pbp2, "eig2 and eig3 vanish together");
    rec r;
    memset(&r, 0, sizeof r);
    r.st = &q.st;
    sf_bif_hooks h = {&r, rec_note, rec_emit, NULL, NULL};
    sf_bif bif;
    sf_bif_init(&bif, &q.eq, &q.st, q.sc.study.tolerance, 1, &r.nrows, &h);
    /* a just past the first (simple) crossing, b past the double one */
    double pa = pbp + 0.005, pb = pbp2 + 0.005;
    cont_point a = point(q.y0, pa, ""), b = point(q.y0, pb, "");
    CHECK_OK(sf_stab_eval(&q.st, &q.eq, q.y0, pa, &err), err);
    assert_int_equal(q.st.res.morse, 1);
    r.nrows = 1;
    sf_bif_point_written(&bif, &a, pa);
    CHECK_OK(sf_stab_eval(&q.st, &q.eq, q.y0, pb, &err), err);
    assert_int_equal(q.st.res.morse, 3);
    CHECK_OK(sf_bif_check(&bif, &b, 0.0, 0, &err), err);
    assert_int_equal(r.nemit, 1);
    assert_string_equal(r.label[0], "BP2");
    assert_int_equal(r.has_ty[0], 0);          /* not switched at */
    CHECK_CLOSE(r.p[0], pbp2, 1e-8 * pbp2, "BP2 against bisection on the flat state");
    assert_non_null(strstr(r.notes, "a multiple branch point"));
    assert_int_equal(q.st.res.morse, 3);       /* back at b */
    sf_bif_free(&bif);
    square4_close(&q);
}

/* ---- guards: the step bound and a point of unknown index ------------- */

/* The step bound (sf_bif_step_bound) on square4-inplane's flat branch,
 * the tangent along p: from p = pbp - 0.012 the first eigenvalue crosses
 * at pbp, the double one at pbp2 (both by bisection on the flat state),
 * so the step is bounded to end between them.  Then the guard: when the
 * eigenvalues handed in differ from those of the second evaluation by
 * more than 1e-2 of the spectrum (two evaluations returning different
 * eigenvalue sets, as the bounded ARPACK attempt of large sheets can), the
 * slopes are meaningless (crossings predicted at about h = 1e-6) and no
 * bound is given. */
static void test_step_bound_guard(void **state)
{
    (void)state;
    square4 q;
    square4_open(&q);
    sf_error err;
    sf_error_clear(&err);
    sf_stab st2;
    CHECK_OK(sf_stab_init(&st2, &q.eq, SF_EIG_DENSE, 4, &err), err);
    double *ty = calloc((size_t)q.eq.n + 1, sizeof(double));
    assert_non_null(ty);
    double pbp = q.pbp, pbp2 = q.pbp2;
    double pa = pbp - 0.012;
    CHECK_OK(sf_stab_eval(&q.st, &q.eq, q.y0, pa, &err), err);
    assert_int_equal(q.st.res.neig, 4);
    cont_point pt = point(q.y0, pa, "");
    pt.ty = ty;   /* unit tangent: along p alone */
    pt.tp = 1.0;
    double bound = sf_bif_step_bound(&q.st.res, &st2, &q.eq, &pt, 0.1);
    print_message("# step bound from p = %.6f: %.6g (crossings at %.6f and %.6f)\n", pa, bound,
                  pbp, pbp2);
    assert_true(pa + bound > pbp && pa + bound < pbp2);
    /* beyond the next step (ds_next short of pbp2): no bound */
    CHECK_LE(sf_bif_step_bound(&q.st.res, &st2, &q.eq, &pt, 0.5 * (pbp + pbp2) - pa - 0.004),
             0.0, "bound beyond the next step");
    /* eig1 and eig4 as another evaluation might have them, 2e-2 of the
     * spectrum higher: without the guard, crossings predicted within about
     * 1e-6 and a bound of that size */
    double eig[4], scale = 0.0;
    for (int j = 0; j < 4; j++) scale = fmax(scale, fabs(q.st.res.eig[j]));
    for (int j = 0; j < 4; j++) eig[j] = q.st.res.eig[j];
    eig[0] += 2e-2 * scale;
    eig[3] += 2e-2 * scale;
    sf_stab_result other = q.st.res;
    other.eig = eig;
    double b2 = sf_bif_step_bound(&other, &st2, &q.eq, &pt, 0.1);
    print_message("# step bound from another eigenvalue set: %.3g\n", b2);
    CHECK_LE(b2, 0.0, "no bound from two different eigenvalue sets");
    free(ty);
    sf_stab_free(&st2);
    square4_close(&q);
}

/* A point whose Morse index is unknown (an ambiguous KKT inertia: the
 * sparse method writes morse_unknown, morse 0, no eigenvalues, stability
 * unknown; its morse field is written empty) is no bracket end: between a
 * (p = 0.6, index 0) and b (p = 0.7, index 1) on fold1-buckle's flat
 * branch, an unknown point m at p = 0.66, past P_cr, is written; the
 * check at m does nothing, and the check at b locates the crossing
 * between a and b, at the closed form P_cr, the note naming a's row.
 * Were m a bracket end (index 0 at 0.66), the crossing would be sought in
 * [0.66, 0.7], where there is none. */
static void test_unknown_index_skipped(void **state)
{
    (void)state;
    fold1 f;
    fold1_open(&f);
    sf_error err;
    sf_error_clear(&err);
    double pa = 0.6, pm = 0.66, pb = 0.7, pcr = pcr_fold();
    assert_true(pa < pcr && pcr < pm);
    cont_point a = point(f.y0, pa, ""), m = point(f.y0, pm, ""), b = point(f.y0, pb, "");
    CHECK_OK(sf_stab_eval(&f.st, &f.eq, f.y0, pa, &err), err);
    assert_int_equal(f.st.res.morse, 0);
    f.r.nrows = 1;
    sf_bif_point_written(&f.bif, &a, pa);
    /* m: what an ambiguous inertia leaves (stability.c, take_sparse_result) */
    CHECK_OK(sf_stab_eval(&f.st, &f.eq, f.y0, pm, &err), err);
    assert_int_equal(f.st.res.morse, 1);
    f.st.res.morse_unknown = 1;
    f.st.res.stable = -1;
    CHECK_OK(sf_bif_check(&f.bif, &m, 0.0, 0, &err), err);
    assert_int_equal(f.r.nemit, 0);
    f.st.res.morse = 0;
    f.st.res.neig = 0;
    f.r.nrows = 2;
    sf_bif_point_written(&f.bif, &m, pm);
    CHECK_OK(sf_stab_eval(&f.st, &f.eq, f.y0, pb, &err), err);
    assert_int_equal(f.st.res.morse, 1);
    assert_int_equal(f.st.res.morse_unknown, 0);
    CHECK_OK(sf_bif_check(&f.bif, &b, 0.0, 0, &err), err);
    print_message("# unknown index at p = %.2f skipped: %s", pm, f.r.notes);
    assert_int_equal(f.r.nemit, 1);
    assert_string_equal(f.r.label[0], "BP");
    CHECK_CLOSE(f.r.p[0], pcr, 1e-9 * pcr, "BP between a and b");
    assert_non_null(strstr(f.r.notes, "between rows 0 and 3"));
    fold1_close(&f);
}

int main(void)
{
    const char *src = getenv("SF_SRCDIR");
    snprintf(studies_dir, sizeof studies_dir, "%s/studies", src ? src : SF_SRCDIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_morse_bounds),
        cmocka_unit_test(test_fold1_locate),
        cmocka_unit_test(test_fold1_check),
        cmocka_unit_test(test_fold1_switch),
        cmocka_unit_test(test_square4_double),
        cmocka_unit_test(test_step_bound_guard),
        cmocka_unit_test(test_unknown_index_skipped),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
