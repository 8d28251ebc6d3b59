/* cont_step.c - following a branch (cont.h, ALGORITHM): the start
 * (cont_start, cont_start_tangent), one predictor-corrector step with
 * step-size control, special-point detection and the stop rules
 * (cont_step), cont_run, and the delivery of points (index, storage,
 * callback, statistics). */
#include "cont_impl.h"

#include <stdlib.h>
#include <string.h>

void ci_flush_stats(cont_solver *s, double t0, int is_step)
{
    s->stp.wall = ci_now_sec() - t0;
    if (is_step) s->stp.ds = s->last.ds;
    cont_stats *T = &s->total, *P = &s->stp;
    T->steps += P->steps; T->points += P->points; T->newton_iters += P->newton_iters;
    T->nres += P->nres; T->njac += P->njac; T->nfactor += P->nfactor;
    T->nlinsolve += P->nlinsolve; T->retries += P->retries; T->nlocate += P->nlocate;
    T->nfallback += P->nfallback;
    T->wall += P->wall;
    if (is_step) {
        double ds = s->last.ds;
        s->last = *P;
        s->last.ds = ds;
        T->ds = ds;
    }
    memset(P, 0, sizeof *P);
}

static int push_ptr(cpt ***arr, long *len, long *cap, cpt *q)
{
    if (*len == *cap) {
        long nc = *cap ? 2 * *cap : 64;
        cpt **na = realloc(*arr, (size_t)nc * sizeof *na);
        if (!na) return -1;
        *arr = na;
        *cap = nc;
    }
    (*arr)[(*len)++] = q;
    return 0;
}

/* Hand q (owned) to the caller: index, storage, callback.  Returns 1 when
 * the callback asks to stop, 0 otherwise, CONT_ENOMEM on failure. */
static int deliver(cont_solver *s, cpt *q)
{
    q->pub.index = s->index++;
    ci_pt_sync(s, q);
    if (s->cur_owned) ci_pt_free(s->cur);
    s->cur = NULL;
    s->cur_owned = 0;
    if (s->store) {
        if (push_ptr(&s->hist, &s->nhist, &s->hcap, q) != 0) {
            ci_pt_free(q);
            return ci_fail(s, CONT_ENOMEM, "out of memory storing point %ld", s->index - 1);
        }
    } else {
        s->cur_owned = 1;
    }
    s->cur = q;
    if (q->pub.type != CONT_PT_REGULAR) {
        cpt *c = ci_pt_dup(s, q);
        if (!c || push_ptr(&s->spec, &s->nspec, &s->scap, c) != 0) {
            ci_pt_free(c);
            return ci_fail(s, CONT_ENOMEM, "out of memory storing a special point");
        }
    }
    s->stp.points++;
    if (s->cb && s->cb(&q->pub, s->cb_data) != 0) return 1;
    return 0;
}

static void begin_run(cont_solver *s)
{
    ci_clear_run(s);
    s->msg[0] = '\0';
    s->err = 0;
    clock_gettime(CLOCK_MONOTONIC, &s->t_start);
}

static int finish_start(cont_solver *s, double t0, int nit, double fn)
{
    cpt *b = s->base;
    b->pub.newton_iters = nit;
    b->pub.resnorm = fn;
    b->pub.s = 0.0;
    b->pub.ds = 0.0;
    b->pub.loc_err = 0.0;
    b->pub.time = ci_since(&s->t_start);
    b->h = 0.0;
    b->terminal = 0;
    ci_set_label(b, CONT_PT_REGULAR, "");
    cpt *q = ci_pt_dup(s, b);
    if (!q) return ci_fail(s, CONT_ENOMEM, "out of memory");
    s->state = ST_RUN;
    s->first_step = 1;
    s->hprev = 0.0;
    s->ds = s->ds0;
    s->last.ds = 0.0;
    int r = deliver(s, q);
    ci_flush_stats(s, t0, 0);
    if (r < 0) {
        s->state = ST_FAIL;
        s->stop_reason = CONT_STOP_ERROR;
        return r;
    }
    if (r == 1) {
        s->state = ST_DONE;
        s->stop_reason = CONT_STOP_CALLBACK;
    }
    return CONT_OK;
}

static int start_check(cont_solver *s, const double *y0, double p0)
{
    if (!y0 || !isfinite(p0) || !ci_all_finite(y0, s->n))
        return ci_fail(s, CONT_EINPUT, "start point is missing or not finite");
    if (p0 < s->p_min || p0 > s->p_max)
        return ci_fail(s, CONT_EINPUT, "start parameter p0 = %.10g is outside [%g, %g]",
                    p0, s->p_min, s->p_max);
    return CONT_OK;
}

int cont_start(cont_solver *s, const double *y0, double p0, int dir)
{
    NEED(s);
    begin_run(s);
    double t0 = ci_now_sec();
    if (dir != 1 && dir != -1)
        return ci_fail(s, CONT_EINPUT, "cont_start: dir must be +1 or -1 (got %d)", dir);
    int r = start_check(s, y0, p0);
    if (r != CONT_OK) return r;
    long n = s->n;
    cpt *b = s->base;
    memcpy(b->x, y0, (size_t)n * sizeof(double));
    b->x[n] = p0;
    int nit;
    double fn;
    if (ci_solve_fixed(s, b->x, &nit, &fn) != 0) {
        ci_flush_stats(s, t0, 0);
        return ci_fail(s, CONT_ENUMERIC, "start: Newton at fixed p = %.10g failed: %s", p0, s->why);
    }
    for (long i = 0; i < s->m; i++) s->cw[i] = 0.0;
    s->cw[n] = 1.0;
    r = ci_eval_point(s, b, s->cw, dir, 0);
    if (r != 0) {
        ci_flush_stats(s, t0, 0);
        if (r == CONT_EUSER) return r;
        return ci_fail(s, CONT_ENUMERIC, "start: no tangent at p = %.10g (%s); Jy is singular "
                    "there (a limit or branch point?): give a tangent with "
                    "cont_start_tangent", p0, s->why);
    }
    return finish_start(s, t0, nit, fn);
}

int cont_start_tangent(cont_solver *s, const double *y0, double p0,
                       const double *ty0, double tp0)
{
    NEED(s);
    begin_run(s);
    double t0 = ci_now_sec();
    int r = start_check(s, y0, p0);
    if (r != CONT_OK) return r;
    long n = s->n, m = s->m;
    if (!ty0 || !ci_all_finite(ty0, n) || !isfinite(tp0))
        return ci_fail(s, CONT_EINPUT, "cont_start_tangent: tangent missing or not finite");
    cpt *b = s->base;
    memcpy(b->x, y0, (size_t)n * sizeof(double));
    b->x[n] = p0;
    memcpy(b->t, ty0, (size_t)n * sizeof(double));
    b->t[n] = tp0;
    double nt = sqrt(ci_dotw(s, b->t, b->t));
    if (!(nt > 0)) return ci_fail(s, CONT_EINPUT, "cont_start_tangent: zero tangent");
    for (long i = 0; i < m; i++) b->t[i] /= nt;
    ci_weigh(s, b->t, s->cw);
    /* correct in the hyperplane through x0 orthogonal to t only if needed */
    int nit = 0;
    double fn;
    if (ci_call_residual(s, b->x, p0, s->w1) != 0) {
        ci_flush_stats(s, t0, 0);
        return ci_fail(s, CONT_ENUMERIC, "cont_start_tangent: %s", s->why);
    }
    double fs = ci_fscaled_max(s, s->w1, n);
    fn = s->last_fnorm;
    if (fs > s->ftol) {
        double *anchor = malloc((size_t)m * sizeof(double));
        if (!anchor) return ci_fail(s, CONT_ENOMEM, "out of memory");
        memcpy(anchor, b->x, (size_t)m * sizeof(double));
        r = ci_correct(s, b->x, s->cw, anchor, 0.0, s->init_maxit, s->init_strategy, &nit, &fn);
        free(anchor);
        if (r != 0) {
            ci_flush_stats(s, t0, 0);
            return ci_fail(s, CONT_ENUMERIC, "cont_start_tangent: the start point (residual "
                        "%.3g) could not be corrected: %s", fs, s->why);
        }
    }
    /* determinant with the given tangent (may be singular at a BP) */
    r = ci_eval_point(s, b, s->cw, +1, 1);
    if (r == CONT_EUSER) {
        ci_flush_stats(s, t0, 0);
        return r;
    }
    if (r != 0) {   /* Jacobian failed here: the first step would fail too */
        ci_flush_stats(s, t0, 0);
        return ci_fail(s, CONT_ENUMERIC, "cont_start_tangent: %s", s->why);
    }
    return finish_start(s, t0, nit, fn);
}

/* Special points between the step base b and the step's end xe (at
 * arclength he from b): zeros of the LP, BP and user tests located, an LP
 * and a BP at the same place merged into the BP, ordered by arclength into
 * sp[0..*nsp_out).  0, or CONT_EUSER / CONT_ENOMEM (nothing left in sp). */
static int special_points(cont_solver *s, const cpt *b, const cpt *xe, double he, cpt **sp,
                          int *nsp_out)
{
    long n = s->n;
    int nsp = 0;
    int ids[40], nid = 0;
    if (s->detect & CONT_DETECT_LP) ids[nid++] = TEST_LP;
    if (s->detect & CONT_DETECT_BP) ids[nid++] = TEST_BP;
    if (s->detect & CONT_DETECT_USER)
        for (int k = 0; k < s->prob.ntest; k++) ids[nid++] = k;
    for (int j = 0; j < nid; j++) {
        int id = ids[j];
        double f0, f1;
        if (id == TEST_BP) {
            if (!b->det_valid || !xe->det_valid) continue;
            if (b->pub.det_sign == xe->pub.det_sign) continue;
            if (s->first_step &&
                b->pub.log_abs_det - xe->pub.log_abs_det <= log(SKIP_START_RATIO))
                continue;
        } else {
            f0 = ci_test_value(s, id, b, 0.0, 0.0);
            f1 = ci_test_value(s, id, xe, 0.0, 0.0);
            if (!ci_differ(f0, f1)) continue;
            if (s->first_step && fabs(f0) <= SKIP_START_RATIO * fabs(f1)) continue;
        }
        cpt *q = NULL;
        int r = ci_locate(s, id, b, xe, he, 0.0, &q);
        if (r == CONT_EUSER || r == CONT_ENOMEM) {
            for (int k = 0; k < nsp; k++) ci_pt_free(sp[k]);
            return r;
        }
        if (r != 0 || !q) continue;
        if (id == TEST_LP) ci_set_label(q, CONT_PT_LP, "LP");
        else if (id == TEST_BP) ci_set_label(q, CONT_PT_BP, "BP");
        else {
            ci_set_label(q, CONT_PT_USER, s->labels[id]);
            q->pub.user_index = id;
        }
        sp[nsp++] = q;
    }
    /* an LP and a BP at the same place are one BP (pitchfork crossed along
     * its bifurcating branch) */
    for (int i = 0; i < nsp; i++) {
        if (sp[i]->pub.type != CONT_PT_LP) continue;
        for (int j = 0; j < nsp; j++) {
            if (sp[j]->pub.type != CONT_PT_BP) continue;
            double tol = fmax(1e3 * s->loc_tol * (1.0 + s->theta * fabs(sp[j]->x[n])),
                              fmax(MERGE_FRAC * he,
                                   2.0 * (sp[i]->pub.loc_err + sp[j]->pub.loc_err)));
            if (fabs(sp[i]->h - sp[j]->h) <= tol) {
                ci_pt_free(sp[i]);
                sp[i] = sp[--nsp];
                i--;
                break;
            }
        }
    }
    /* order by arclength */
    for (int i = 1; i < nsp; i++)
        for (int j = i; j > 0 && sp[j]->h < sp[j - 1]->h; j--) {
            cpt *tmp = sp[j]; sp[j] = sp[j - 1]; sp[j - 1] = tmp;
        }
    *nsp_out = nsp;
    return 0;
}

/* How the trailing failed attempts of a step (from some step length down
 * to ds_min, at least TAIL_MIN_ATTEMPTS of them) ended, when all alike:
 *
 * - a residual floor: each stagnated with its scaled residual (the lowest
 *   reached, anchored solves included) within FLOOR_FACTOR times the
 *   Newton tolerance.  Newton stagnates at the same residual however
 *   short the step is (the predictor is the last point): the equations
 *   cannot be solved more accurately there (e.g. nearly dependent
 *   constraint rows whose share of the residual a regularised Newton
 *   step does not remove);
 * - a divergence: each came within DIVERGE_NEAR times the tolerance (the
 *   predictor or a plain Newton iterate) and then ended more than
 *   DIVERGE_GROWTH times higher, above the floor's range: Newton moves
 *   away from the branch however short the step is (continuation/
 *   README.md, "A corrector that diverges next to the tolerance").
 *
 * Neither is a turning point or a branch point of the path; the first
 * attempts of a step (long steps) may fail otherwise. */
#define FLOOR_FACTOR 10.0
#define DIVERGE_NEAR 1e4
#define DIVERGE_GROWTH 100.0
#define TAIL_MIN_ATTEMPTS 3
enum { TAIL_NONE, TAIL_FLOOR, TAIL_DIVERGE };
typedef struct { int kind, n; double lo, hi, end, ds; } tail_watch;

static void tail_count(const cont_solver *s, tail_watch *tw, double ds)
{
    double f = s->fail_fs, lo = f;
    int kind = TAIL_NONE;
    if (f <= FLOOR_FACTOR * s->ftol) {
        kind = TAIL_FLOOR;
    } else if (s->att_fsmin <= DIVERGE_NEAR * s->ftol && f > DIVERGE_GROWTH * s->att_fsmin) {
        kind = TAIL_DIVERGE;
        lo = s->att_fsmin;
    }
    if (kind == TAIL_NONE || kind != tw->kind)
        *tw = (tail_watch){ kind, 0, INFINITY, 0.0, INFINITY, ds };
    if (kind == TAIL_NONE) return;
    tw->n++;
    tw->lo = fmin(tw->lo, lo);
    tw->hi = fmax(tw->hi, lo);
    tw->end = fmin(tw->end, f);
}

/* The diagnosis of a stop at ds_min after such attempts (else ""). */
static void tail_note(const cont_solver *s, const tail_watch *tw, double tp, char *buf,
                      size_t len)
{
    buf[0] = '\0';
    if (tw->n < TAIL_MIN_ATTEMPTS) return;
    if (tw->kind == TAIL_FLOOR)
        snprintf(buf, len, "; diagnosis: the last %d attempts (steps %.3g down to ds_min) all "
                 "stagnated at a scaled residual of %.3g to %.3g, just above the Newton "
                 "tolerance %.3g, however short the step: a residual floor of the equations "
                 "at this point (e.g. nearly dependent constraint rows, whose share of the "
                 "residual a regularised Newton step does not remove), not a turning point "
                 "(dp/ds = %.3g at the last point); a Newton tolerance above %.3g gets past "
                 "this point (the floor may grow further on)", tw->n, tw->ds, tw->lo, tw->hi,
                 s->ftol, tp, tw->hi);
    else
        snprintf(buf, len, "; diagnosis: the last %d attempts (steps %.3g down to ds_min) each "
                 "came to a scaled residual of %.3g to %.3g (tolerance %.3g), then diverged "
                 "to %.3g or more: the Newton step moves away from the branch here (nearly "
                 "singular equations whose regularised step amplifies an error, or a "
                 "Jacobian that does not match the residual), not a turning point (dp/ds = "
                 "%.3g); the points so far meet the tolerance; where nearly dependent "
                 "constraint rows cause it, equations without them (e.g. a penalty) may get "
                 "past such a point (continuation/README.md, \"A corrector that diverges "
                 "next to the tolerance\")", tw->n, tw->ds, tw->lo, tw->hi, s->ftol, tw->end,
                 tp);
}

/* The failed attempts in a row, across steps, whose anchored reusing
 * corrector ended at its iteration limit with its residual (the lowest of
 * its iterates) within FLOOR_FACTOR times the tolerance: a floor of the
 * anchored Newton, which the attempts of a step at ds_min alone do not
 * show when accepted points come in between (an iteration that happens to
 * end below the tolerance; the step then grows and the next attempt fails
 * again, continuation/README.md, "The 12x12 load path").  Any other
 * failure ends the run of them. */
static void afloor_count(cont_solver *s, double ds, double p)
{
    double f = s->att_afs;
    if (!(f <= FLOOR_FACTOR * s->ftol)) {
        s->afl.n = 0;
        return;
    }
    if (s->afl.n == 0) {
        s->afl.lo = s->afl.hi = f;
        s->afl.p = p;
        s->afl.ds = ds;
        s->afl.pts = 0;
    }
    s->afl.n++;
    s->afl.lo = fmin(s->afl.lo, f);
    s->afl.hi = fmax(s->afl.hi, f);
}

/* The diagnosis of a stop at ds_min after such attempts, where tail_note
 * has none (else ""). */
static void afloor_note(const cont_solver *s, const tail_watch *tw, double tp, char *buf,
                        size_t len)
{
    if (tw->n >= TAIL_MIN_ATTEMPTS || s->afl.n < TAIL_MIN_ATTEMPTS) return;
    snprintf(buf, len, "; diagnosis: the last %d failed attempts (from p = %.6g, steps %.3g "
             "down to ds_min, %ld points accepted between them) each ended with the anchored "
             "corrector at its iteration limit, stagnating at a scaled residual of %.3g to "
             "%.3g (tolerance %.3g) however short the step: a residual floor (nearly dependent "
             "constraint rows), not a turning point (dp/ds = %.3g); the plain Newton "
             "failed too; a Newton tolerance above %.3g or equations without the dependent "
             "rows (e.g. a penalty) may get further (continuation/README.md, \"The 12x12 load "
             "path\")", s->afl.n, s->afl.p, s->afl.ds, s->afl.pts, s->afl.lo, s->afl.hi, s->ftol,
             tp, s->afl.hi);
}

/* Compute one step from s->base and queue the resulting points. */
static int compute_step(cont_solver *s)
{
    long n = s->n, m = s->m;
    cpt *b = s->base;
    double ds = s->ds;
    if (isfinite(s->s_max) && s->s_max - s->s_arc < ds) ds = s->s_max - s->s_arc;
    cpt *x1 = ci_pt_new(s);
    if (!x1) return ci_fail(s, CONT_ENOMEM, "out of memory");
    double *c = calloc((size_t)m, sizeof(double));
    if (!c) {
        ci_pt_free(x1);
        return ci_fail(s, CONT_ENOMEM, "out of memory");
    }
    ci_weigh(s, b->t, c);
    double cosmax = s->max_angle > 0 ? cos(s->max_angle) : -2.0;
    int nit = 0, r;
    double fn = NAN;
    tail_watch tw = { TAIL_NONE, 0, INFINITY, 0.0, INFINITY, 0.0 };
    for (;;) {
        if (ds < s->ds_min) {
            free(c);
            ci_pt_free(x1);
            s->stop_reason = CONT_STOP_DSMIN;
            char fl[700];
            tail_note(s, &tw, b->t[n], fl, sizeof fl);
            if (!fl[0]) afloor_note(s, &tw, b->t[n], fl, sizeof fl);
            return ci_fail(s, CONT_FAIL, "continuation stopped at step %ld: the step size "
                        "%.3g fell below ds_min = %.3g at p = %.12g (last accepted point, "
                        "s = %.6g, residual norm %.3g); last attempt: %s%s",
                        s->steps + 1, ds, s->ds_min, b->x[n], s->s_arc, b->pub.resnorm,
                        s->why[0] ? s->why : "no reason recorded", fl);
        }
        for (long i = 0; i < m; i++) x1->x[i] = b->x[i] + ds * b->t[i];
        if (s->predictor == 2 && s->hprev > 0 && s->anchor_level == 0 && s->reuse_level <= 1) {
            /* second order: the curvature from the tangents' change over
             * the last step, x(s) = x + s t + s^2/2 (t - t_prev) / h_prev;
             * not once a residual floor was met (an anchored level > 1):
             * the states there are fixed only to the floor's accuracy, and
             * so are the tangents' differences */
            double q = 0.5 * ds * ds / s->hprev;
            for (long i = 0; i < m; i++) x1->x[i] += q * (b->t[i] - s->tprev[i]);
        }
        /* the engine's own Newton only without a line search */
        r = ci_correct_step(s, x1->x, c, b->x, ds, &nit, &fn);
        if (r == 0) {
            r = ci_eval_point(s, x1, c, +1, 0);
            if (r == CONT_EUSER) {
                free(c); ci_pt_free(x1);
                s->stop_reason = CONT_STOP_ERROR;
                return r;
            }
            if (r == 0) {
                double ca = ci_dotw(s, x1->t, b->t);
                if (ca < cosmax) {
                    ci_why(s, "the tangent turned by %.3g rad (> max_angle %.3g) over a step "
                        "of %.3g", acos(fmax(-1.0, fmin(1.0, ca))), s->max_angle, ds);
                    r = -1;
                }
            }
        }
        if (r == 0) break;
        tail_count(s, &tw, ds);
        afloor_count(s, ds, b->x[n]);
        s->stp.retries++;
        ds *= s->shrink;
    }
    if (s->afl.n > 0) s->afl.pts++;
    x1->pub.newton_iters = nit;
    x1->pub.resnorm = fn;
    x1->pub.ds = ds;
    x1->h = ds;
    s->last.ds = ds;
    s->ds = nit - s->polish_iters <= s->fast_iters ? fmin(ds * s->grow, s->ds_max) : ds;

    cpt *xe = x1;
    int term = 0, reason = CONT_STOP_NONE;
    double p1 = x1->x[n];
    if (p1 > s->p_max || p1 < s->p_min) {
        double pb = p1 > s->p_max ? s->p_max : s->p_min;
        reason = p1 > s->p_max ? CONT_STOP_PMAX : CONT_STOP_PMIN;
        cpt *q = NULL;
        r = ci_land(s, b, x1, pb, &q);
        if (r != 0) {
            free(c); ci_pt_free(x1);
            s->stop_reason = CONT_STOP_ERROR;
            if (r == CONT_EUSER) return r;
            return ci_fail(s, CONT_FAIL, "could not land on the end of the parameter window "
                        "p = %.12g: %s", pb, s->why);
        }
        ci_pt_free(x1);
        xe = q;
        term = 1;
    }
    double he = xe->h;

    /* special points */
    cpt *sp[40];
    int nsp = 0;
    r = special_points(s, b, xe, he, sp, &nsp);
    if (r != 0) {
        free(c);
        ci_pt_free(xe);
        s->stop_reason = CONT_STOP_ERROR;
        return r;
    }
    double tnow = ci_since(&s->t_start);
    for (int i = 0; i < nsp; i++) {
        sp[i]->pub.s = s->s_arc + sp[i]->h;
        sp[i]->pub.time = tnow;
        s->queue[(s->q0 + s->nq++) % 64] = sp[i];
    }
    s->steps++;
    s->stp.steps++;
    s->s_arc += he;
    xe->pub.s = s->s_arc;
    xe->pub.time = tnow;
    xe->pub.loc_err = 0.0;
    if (!term && s->max_steps > 0 && s->steps >= s->max_steps) {
        term = 1;
        reason = CONT_STOP_MAXSTEPS;
    }
    if (!term && isfinite(s->s_max) && s->s_arc >= s->s_max * (1.0 - 1e-12)) {
        term = 1;
        reason = CONT_STOP_MAXARC;
    }
    if (!term && isfinite(s->s_max) && s->s_max - s->s_arc < s->ds_min) {
        term = 1;
        reason = CONT_STOP_MAXARC;
    }
    ci_set_label(xe, term ? CONT_PT_EP : CONT_PT_REGULAR, term ? "EP" : "");
    xe->terminal = term;
    xe->stop_reason = reason;
    memcpy(s->tprev, b->t, (size_t)m * sizeof(double));
    s->hprev = he;
    ci_pt_copy(s, b, xe);
    s->queue[(s->q0 + s->nq++) % 64] = xe;
    s->first_step = 0;
    free(c);
    return CONT_OK;
}

int cont_step(cont_solver *s)
{
    if (!s) return CONT_FAIL;
    if (s->state == ST_DONE) return CONT_DONE;
    if (s->state == ST_FAIL) return CONT_FAIL;
    if (s->state != ST_RUN) {
        ci_fail(s, CONT_ESTATE, "cont_step called before cont_start");
        return CONT_FAIL;
    }
    double t0 = ci_now_sec();
    int computed = 0;
    if (s->nq == 0) {
        int r = compute_step(s);
        computed = 1;
        if (r != CONT_OK) {
            ci_flush_stats(s, t0, 1);
            s->state = ST_FAIL;
            if (s->stop_reason == CONT_STOP_NONE) s->stop_reason = CONT_STOP_ERROR;
            return CONT_FAIL;
        }
    }
    cpt *q = s->queue[s->q0];
    s->q0 = (s->q0 + 1) % 64;
    s->nq--;
    int term = q->terminal, reason = q->stop_reason;
    int r = deliver(s, q);
    if (computed) ci_flush_stats(s, t0, 1);
    else ci_flush_stats(s, t0, 0);
    if (r < 0) {
        s->state = ST_FAIL;
        s->stop_reason = CONT_STOP_ERROR;
        return CONT_FAIL;
    }
    if (r == 1 || term) {
        s->state = ST_DONE;
        s->stop_reason = r == 1 ? CONT_STOP_CALLBACK : reason;
        while (s->nq > 0) {      /* the rest of the step is not delivered */
            ci_pt_free(s->queue[s->q0]);
            s->q0 = (s->q0 + 1) % 64;
            s->nq--;
        }
        return CONT_DONE;
    }
    return CONT_CONTINUE;
}

int cont_run(cont_solver *s)
{
    int st;
    while ((st = cont_step(s)) == CONT_CONTINUE) {}
    return st;
}
