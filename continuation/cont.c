/* cont.c - pseudo-arclength continuation engine (see cont.h for the
 * algorithm and references): life cycle, options, getters, and the small
 * helpers, errors, timing and point allocation the other files share.
 * The engine's files are listed in cont_impl.h. */
#include "cont_impl.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

double ci_now_sec(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double ci_since(const struct timespec *t0)
{
    return ci_now_sec() - ((double)t0->tv_sec + 1e-9 * (double)t0->tv_nsec);
}

/* Record the first error. */
int ci_fail(cont_solver *s, int code, const char *fmt, ...)
{
    if (s->msg[0] == '\0') {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(s->msg, sizeof s->msg, fmt, ap);
        va_end(ap);
        s->err = code;
    }
    return code;
}

/* Reason of the current failed attempt (overwrites). */
void ci_why(cont_solver *s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(s->why, sizeof s->why, fmt, ap);
    va_end(ap);
}

/* the y part of the arclength inner product, weighted, before arc2 */
static double dot_y(const cont_solver *s, const double *a, const double *b)
{
    double d = 0.0;
    if (s->wy)
        for (long i = 0; i < s->n; i++) d += s->wy[i] * a[i] * b[i];
    else
        for (long i = 0; i < s->n; i++) d += a[i] * b[i];
    return d;
}

double ci_dotw(const cont_solver *s, const double *a, const double *b)
{
    return s->arc2 * dot_y(s, a, b) + s->theta * s->theta * a[s->n] * b[s->n];
}

double cont_arc_norm(const cont_solver *s, const double *dy, double dp)
{
    return sqrt(s->arc2 * dot_y(s, dy, dy) + s->theta * s->theta * dp * dp);
}

/* c = W t */
void ci_weigh(const cont_solver *s, const double *t, double *c)
{
    for (long i = 0; i < s->n; i++) c[i] = s->arc2 * (s->wy ? s->wy[i] * t[i] : t[i]);
    c[s->n] = s->theta * s->theta * t[s->n];
}

int ci_all_finite(const double *v, long len)
{
    for (long i = 0; i < len; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

double ci_norm_inf(const double *v, long len)
{
    double r = 0.0;
    for (long i = 0; i < len; i++) {
        double a = fabs(v[i]);
        if (!(a <= r)) r = a;   /* propagates NaN */
    }
    return r;
}

cpt *ci_pt_new(cont_solver *s)
{
    long m = s->m;
    int nt = s->prob.ntest;
    cpt *q = calloc(1, sizeof *q);
    if (!q) return NULL;
    q->x = calloc((size_t)(2 * m + nt), sizeof(double));
    if (!q->x) {
        free(q);
        return NULL;
    }
    q->t = q->x + m;
    q->test = nt > 0 ? q->t + m : NULL;
    q->pub.y = q->x;
    q->pub.ty = q->t;
    q->pub.test = q->test;
    return q;
}

void ci_pt_free(cpt *q)
{
    if (!q) return;
    free(q->x);
    free(q);
}

void ci_pt_copy(const cont_solver *s, cpt *dst, const cpt *src)
{
    double *x = dst->x, *t = dst->t, *test = dst->test;
    memcpy(x, src->x, (size_t)(2 * s->m + s->prob.ntest) * sizeof(double));
    *dst = *src;
    dst->x = x;
    dst->t = t;
    dst->test = test;
    dst->pub.y = x;
    dst->pub.ty = t;
    dst->pub.test = test;
}

cpt *ci_pt_dup(cont_solver *s, const cpt *src)
{
    cpt *q = ci_pt_new(s);
    if (q) ci_pt_copy(s, q, src);
    return q;
}

void ci_pt_sync(const cont_solver *s, cpt *q)
{
    q->pub.p = q->x[s->n];
    q->pub.tp = q->t[s->n];
}

void ci_set_label(cpt *q, int type, const char *label)
{
    q->pub.type = type;
    snprintf(q->pub.label, sizeof q->pub.label, "%s", label);
}

void ci_clear_run(cont_solver *s)
{
    while (s->nq > 0) {
        ci_pt_free(s->queue[s->q0]);
        s->q0 = (s->q0 + 1) % 64;
        s->nq--;
    }
    s->q0 = 0;
    if (s->cur_owned) ci_pt_free(s->cur);
    s->cur = NULL;
    s->cur_owned = 0;
    for (long i = 0; i < s->nhist; i++) ci_pt_free(s->hist[i]);
    s->nhist = 0;
    for (long i = 0; i < s->nspec; i++) ci_pt_free(s->spec[i]);
    s->nspec = 0;
    s->state = ST_IDLE;
    s->anchor_level = 0;
    s->reuse_level = 0;
    memset(&s->afl, 0, sizeof s->afl);
    s->stop_reason = CONT_STOP_NONE;
    s->steps = 0;
    s->index = 0;
    s->s_arc = 0.0;
    memset(&s->stp, 0, sizeof s->stp);
    memset(&s->last, 0, sizeof s->last);
    memset(&s->total, 0, sizeof s->total);
}

void cont_free(cont_solver *s)
{
    if (!s) return;
    ci_clear_run(s);
    free(s->hist);
    free(s->spec);
    for (int i = 0; i < 3; i++) ci_pt_free(s->lw[i]);
    ci_pt_free(s->base);
    if (s->kmem) KINFree(&s->kmem);
    ci_bm_free(&s->bk);
    ci_bm_free(&s->bt);
    if (s->u) N_VDestroy(s->u);
    if (s->uscale) N_VDestroy(s->uscale);
    if (s->fscale) N_VDestroy(s->fscale);
    if (s->vx) N_VDestroy(s->vx);
    if (s->vb) N_VDestroy(s->vb);
    if (s->Jy) SUNMatDestroy(s->Jy);
    free(s->Fp);
    free(s->bc);
    free(s->bxa);
    free(s->cw);
    free(s->w1);
    free(s->rc);
    free(s->tprev);
    free(s->rw);
    free(s->mark);
    free(s->stamp);
    free(s->yscale_copy);
    free(s->fscale_copy);
    free(s->wy);
    free(s->ulast);
    free(s->labels);
    if (s->ctx) SUNContext_Free(&s->ctx);
    free(s);
}

int cont_create(const cont_problem *prob, int linsol, cont_solver **out)
{
    if (!out) return CONT_EINPUT;
    *out = NULL;
    cont_solver *s = calloc(1, sizeof *s);
    if (!s) return CONT_ENOMEM;
    *out = s;
    if (!prob) return ci_fail(s, CONT_EINPUT, "cont_create: no problem given");
    s->prob = *prob;
    long n = prob->n;
    if (n < 1) return ci_fail(s, CONT_EINPUT, "cont_create: dimension n = %ld must be >= 1", n);
    if (!prob->residual || !prob->jacobian)
        return ci_fail(s, CONT_EINPUT, "cont_create: residual and jacobian callbacks are required");
    if (prob->jac_matrix != CONT_MATRIX_DENSE && prob->jac_matrix != CONT_MATRIX_SPARSE)
        return ci_fail(s, CONT_EINPUT, "cont_create: jac_matrix must be CONT_MATRIX_DENSE or "
                    "CONT_MATRIX_SPARSE (got %d)", prob->jac_matrix);
    if (prob->ntest < 0 || (prob->ntest > 0 && !prob->test))
        return ci_fail(s, CONT_EINPUT, "cont_create: ntest = %d needs a test callback", prob->ntest);
    if (prob->ntest > 32)
        return ci_fail(s, CONT_EINPUT, "cont_create: at most 32 user test functions (got %d)",
                    prob->ntest);
    if (linsol == CONT_LINSOL_AUTO)
        linsol = (prob->jac_matrix == CONT_MATRIX_SPARSE && n > CONT_AUTO_KLU_N)
                     ? CONT_LINSOL_MUMPS : CONT_LINSOL_DENSE;
    if (linsol != CONT_LINSOL_DENSE && linsol != CONT_LINSOL_KLU && linsol != CONT_LINSOL_MUMPS)
        return ci_fail(s, CONT_EINPUT, "cont_create: unknown linear solver %d", linsol);
    s->linsol = linsol;
    s->n = n;
    s->m = n + 1;
    long m = s->m;

    /* defaults */
    s->ds0 = 0.01; s->ds_min = 1e-8; s->ds_max = 0.1;
    s->grow = 1.5; s->shrink = 0.5; s->fast_iters = 3; s->max_angle = 0.5;
    s->p_min = -HUGE_VAL; s->p_max = HUGE_VAL; s->s_max = HUGE_VAL;
    s->max_steps = 1000; s->theta = 1.0; s->arc2 = 1.0; s->predictor = 1;
    s->ftol = 1e-10; s->xtol = 1e-6; s->max_newton = 10; s->strategy = KIN_NONE;
    s->init_maxit = 50; s->init_strategy = KIN_LINESEARCH;
    s->detect = CONT_DETECT_ALL; s->loc_tol = 1e-10;
    s->store = 1;

    /* copies of user arrays */
    if (prob->ntest > 0) {
        s->labels = calloc((size_t)prob->ntest, sizeof *s->labels);
        if (!s->labels) return ci_fail(s, CONT_ENOMEM, "out of memory");
        for (int k = 0; k < prob->ntest; k++) {
            if (prob->test_labels && prob->test_labels[k])
                snprintf(s->labels[k], sizeof s->labels[k], "%s", prob->test_labels[k]);
            else
                snprintf(s->labels[k], sizeof s->labels[k], "USER%d", k + 1);
        }
    }
    s->prob.test_labels = NULL;

    if (SUNContext_Create(NULL, &s->ctx) != 0 || !s->ctx)
        return ci_fail(s, CONT_ENOMEM, "cannot create the SUNDIALS context");
    s->u = N_VNew_Serial(m, s->ctx);
    s->uscale = N_VNew_Serial(m, s->ctx);
    s->fscale = N_VNew_Serial(m, s->ctx);
    s->vx = N_VNew_Serial(m, s->ctx);
    s->vb = N_VNew_Serial(m, s->ctx);
    s->Fp = calloc((size_t)n, sizeof(double));
    s->bc = calloc((size_t)m, sizeof(double));
    s->bxa = calloc((size_t)m, sizeof(double));
    s->cw = calloc((size_t)m, sizeof(double));
    s->w1 = calloc((size_t)m, sizeof(double));
    s->rc = calloc((size_t)m, sizeof(double));
    s->tprev = calloc((size_t)m, sizeof(double));
    s->rw = calloc(2 * (size_t)m, sizeof(double));
    s->rgen = -1;
    s->corrector = linsol == CONT_LINSOL_DENSE ? CONT_CORRECTOR_NEWTON : CONT_CORRECTOR_REUSE;
    s->mark = calloc((size_t)m + 2, 1);
    s->stamp = calloc((size_t)n, sizeof(long));
    if (!s->u || !s->uscale || !s->fscale || !s->vx || !s->vb || !s->Fp || !s->bc ||
        !s->bxa || !s->cw || !s->w1 || !s->mark || !s->stamp || !s->rc || !s->rw || !s->tprev)
        return ci_fail(s, CONT_ENOMEM, "out of memory (n = %ld)", n);
    N_VConst(1.0, s->uscale);
    N_VConst(1.0, s->fscale);
    for (long i = 0; i < n; i++) {
        if (prob->yscale) {
            if (!(prob->yscale[i] > 0) || !isfinite(prob->yscale[i]))
                return ci_fail(s, CONT_EINPUT, "cont_create: yscale[%ld] = %g must be positive",
                            i, prob->yscale[i]);
            NV_Ith_S(s->uscale, i) = prob->yscale[i];
        }
        if (prob->fscale) {
            if (!(prob->fscale[i] > 0) || !isfinite(prob->fscale[i]))
                return ci_fail(s, CONT_EINPUT, "cont_create: fscale[%ld] = %g must be positive",
                            i, prob->fscale[i]);
            NV_Ith_S(s->fscale, i) = prob->fscale[i];
        }
    }
    if (prob->pscale != 0.0) {
        if (!(prob->pscale > 0) || !isfinite(prob->pscale))
            return ci_fail(s, CONT_EINPUT, "cont_create: pscale = %g must be positive", prob->pscale);
        NV_Ith_S(s->uscale, n) = prob->pscale;
    }
    s->prob.yscale = s->prob.fscale = NULL;   /* copied into the N_Vectors */

    if (prob->jac_matrix == CONT_MATRIX_SPARSE) {
        sunindextype nnz = prob->jac_nnz > 0 ? prob->jac_nnz : 8 * (sunindextype)n;
        s->Jy = SUNSparseMatrix(n, n, nnz, CSC_MAT, s->ctx);
    } else {
        s->Jy = SUNDenseMatrix(n, n, s->ctx);
    }
    if (!s->Jy) return ci_fail(s, CONT_ENOMEM, "out of memory for the Jacobian (n = %ld)", n);

    sunindextype bnnz = (prob->jac_matrix == CONT_MATRIX_SPARSE ? SM_NNZ_S(s->Jy)
                                                                 : (sunindextype)n * n) +
                        2 * (sunindextype)n + 1;
    if (ci_bm_init(s, &s->bk, m, linsol, bnnz, s->u) != CONT_OK ||
        ci_bm_init(s, &s->bt, m, linsol, bnnz, s->u) != CONT_OK ||
        (prob->jac_symmetric && prob->jac_matrix == CONT_MATRIX_SPARSE &&
         linsol == CONT_LINSOL_MUMPS && ci_blk_init(s, &s->bt) != CONT_OK))
        return ci_fail(s, CONT_ENOMEM, "cannot create the %s linear solver (n = %ld)",
                    linsol == CONT_LINSOL_KLU ? "KLU" : linsol == CONT_LINSOL_MUMPS ? "MUMPS"
                                              : "dense", n);

    s->kmem = KINCreate(s->ctx);
    if (!s->kmem) return ci_fail(s, CONT_ENOMEM, "KINCreate failed");
    KINSetErrHandlerFn(s->kmem, ci_kin_err, s);
    KINSetPrintLevel(s->kmem, 0);
    if (KINInit(s->kmem, ci_kin_sys, s->u) != KIN_SUCCESS ||
        KINSetUserData(s->kmem, s) != KIN_SUCCESS ||
        KINSetLinearSolver(s->kmem, s->bk.LS, s->bk.A) != KIN_SUCCESS ||
        KINSetJacFn(s->kmem, ci_kin_jac) != KIN_SUCCESS ||
        KINSetMaxSetupCalls(s->kmem, 1) != KIN_SUCCESS ||
        KINSetNoResMon(s->kmem, SUNTRUE) != KIN_SUCCESS)
        return ci_fail(s, CONT_ENOMEM, "KINSOL initialisation failed: %s", s->kin_msg);

    s->base = ci_pt_new(s);
    for (int i = 0; i < 3; i++) s->lw[i] = ci_pt_new(s);
    if (!s->base || !s->lw[0] || !s->lw[1] || !s->lw[2])
        return ci_fail(s, CONT_ENOMEM, "out of memory");
    return CONT_OK;
}


int cont_set_step(cont_solver *s, double ds0, double ds_min, double ds_max)
{
    NEED(s);
    if (!(ds_min > 0 && ds_min <= ds0 && ds0 <= ds_max && isfinite(ds_max)))
        return ci_fail(s, CONT_EINPUT, "cont_set_step: need 0 < ds_min <= ds0 <= ds_max "
                    "(got %g, %g, %g)", ds_min, ds0, ds_max);
    s->ds0 = ds0; s->ds_min = ds_min; s->ds_max = ds_max;
    if (s->state == ST_RUN) s->ds = fmin(fmax(s->ds, ds_min), ds_max);
    return CONT_OK;
}

int cont_set_step_control(cont_solver *s, double grow, double shrink, int fast_iters,
                          double max_angle)
{
    NEED(s);
    if (!(grow >= 1.0 && isfinite(grow)) || !(shrink > 0 && shrink < 1) || fast_iters < 0)
        return ci_fail(s, CONT_EINPUT, "cont_set_step_control: need grow >= 1, 0 < shrink < 1, "
                    "fast_iters >= 0 (got %g, %g, %d)", grow, shrink, fast_iters);
    s->grow = grow; s->shrink = shrink; s->fast_iters = fast_iters; s->max_angle = max_angle;
    return CONT_OK;
}

int cont_set_prange(cont_solver *s, double p_min, double p_max)
{
    NEED(s);
    if (!(p_min < p_max) || isnan(p_min) || isnan(p_max))
        return ci_fail(s, CONT_EINPUT, "cont_set_prange: need p_min < p_max (got %g, %g)",
                    p_min, p_max);
    s->p_min = p_min; s->p_max = p_max;
    return CONT_OK;
}

int cont_set_max_steps(cont_solver *s, long max_steps)
{
    NEED(s);
    s->max_steps = max_steps;
    return CONT_OK;
}

int cont_set_max_arclength(cont_solver *s, double s_max)
{
    NEED(s);
    if (!(s_max > 0))
        return ci_fail(s, CONT_EINPUT, "cont_set_max_arclength: need s_max > 0 (got %g)", s_max);
    s->s_max = s_max;
    return CONT_OK;
}

int cont_set_theta(cont_solver *s, double theta_p)
{
    NEED(s);
    if (!(theta_p > 0) || !isfinite(theta_p))
        return ci_fail(s, CONT_EINPUT, "cont_set_theta: need theta_p > 0 (got %g)", theta_p);
    if (s->state == ST_RUN)
        return ci_fail(s, CONT_ESTATE, "cont_set_theta: cannot change the norm during a run");
    s->theta = theta_p;
    return CONT_OK;
}

int cont_set_arc_scale(cont_solver *s, double a)
{
    NEED(s);
    if (!(a > 0) || !isfinite(a))
        return ci_fail(s, CONT_EINPUT, "cont_set_arc_scale: need a > 0 (got %g)", a);
    if (s->state == ST_RUN)
        return ci_fail(s, CONT_ESTATE, "cont_set_arc_scale: cannot change the norm during a run");
    s->arc2 = a * a;
    return CONT_OK;
}

int cont_set_predictor(cont_solver *s, int order)
{
    NEED(s);
    if (order != 1 && order != 2)
        return ci_fail(s, CONT_EINPUT, "cont_set_predictor: order 1 or 2 (got %d)", order);
    s->predictor = order;
    return CONT_OK;
}

int cont_set_anchor_first(cont_solver *s, int on)
{
    NEED(s);
    s->anchor_first = on != 0;
    return CONT_OK;
}

int cont_set_weights(cont_solver *s, const double *w)
{
    NEED(s);
    if (s->state == ST_RUN)
        return ci_fail(s, CONT_ESTATE, "cont_set_weights: cannot change the norm during a run");
    if (!w) {
        free(s->wy);
        free(s->ulast);
        s->wy = NULL;
        s->ulast = NULL;
        return CONT_OK;
    }
    double wmax = 0.0;
    for (long i = 0; i < s->n; i++) {
        if (!(w[i] >= 0) || !isfinite(w[i]))
            return ci_fail(s, CONT_EINPUT, "cont_set_weights: weight %ld is %g (need finite >= 0)",
                        i, w[i]);
        wmax = fmax(wmax, w[i]);
    }
    if (!(wmax > 0))
        return ci_fail(s, CONT_EINPUT, "cont_set_weights: all weights are zero");
    if (!s->wy) s->wy = malloc((size_t)s->n * sizeof(double));
    if (!s->ulast) s->ulast = calloc((size_t)s->m, sizeof(double));
    if (!s->wy || !s->ulast) return ci_fail(s, CONT_ENOMEM, "out of memory");
    memcpy(s->wy, w, (size_t)s->n * sizeof(double));
    return CONT_OK;
}

int cont_set_newton(cont_solver *s, double ftol, int max_iters, int strategy)
{
    NEED(s);
    if (!(ftol > 0) || max_iters < 1 || (strategy != KIN_NONE && strategy != KIN_LINESEARCH))
        return ci_fail(s, CONT_EINPUT, "cont_set_newton: need ftol > 0, max_iters >= 1, "
                    "strategy KIN_NONE or KIN_LINESEARCH (got %g, %d, %d)",
                    ftol, max_iters, strategy);
    s->ftol = ftol; s->max_newton = max_iters; s->strategy = strategy;
    return CONT_OK;
}

int cont_set_newton_steptol(cont_solver *s, double xtol)
{
    NEED(s);
    if (!(xtol >= 0) || !isfinite(xtol))
        return ci_fail(s, CONT_EINPUT, "cont_set_newton_steptol: need xtol >= 0 (got %g)", xtol);
    s->xtol = xtol;
    return CONT_OK;
}

int cont_set_point_inertia(cont_solver *s, int on)
{
    NEED(s);
    s->point_inertia = on != 0;
    return CONT_OK;
}

int cont_set_corrector(cont_solver *s, int kind)
{
    NEED(s);
    if (kind != CONT_CORRECTOR_NEWTON && kind != CONT_CORRECTOR_REUSE)
        return ci_fail(s, CONT_EINPUT, "cont_set_corrector: unknown corrector %d", kind);
    s->corrector = kind;
    return CONT_OK;
}

int cont_get_corrector(const cont_solver *s) { return s ? s->corrector : 0; }

int cont_set_newton_init(cont_solver *s, int max_iters, int strategy)
{
    NEED(s);
    if (max_iters < 1 || (strategy != KIN_NONE && strategy != KIN_LINESEARCH))
        return ci_fail(s, CONT_EINPUT, "cont_set_newton_init: need max_iters >= 1 and "
                    "strategy KIN_NONE or KIN_LINESEARCH (got %d, %d)", max_iters, strategy);
    s->init_maxit = max_iters; s->init_strategy = strategy;
    return CONT_OK;
}

int cont_set_detect(cont_solver *s, unsigned mask, double loc_tol)
{
    NEED(s);
    if ((mask & ~(unsigned)CONT_DETECT_ALL) || !(loc_tol > 0))
        return ci_fail(s, CONT_EINPUT, "cont_set_detect: bad mask %u or loc_tol %g", mask, loc_tol);
    s->detect = mask; s->loc_tol = loc_tol;
    return CONT_OK;
}

int cont_set_callback(cont_solver *s, cont_point_fn fn, void *data)
{
    NEED(s);
    s->cb = fn; s->cb_data = data;
    return CONT_OK;
}

int cont_set_store(cont_solver *s, int store_points)
{
    NEED(s);
    if (s->state == ST_RUN)
        return ci_fail(s, CONT_ESTATE, "cont_set_store: cannot change during a run");
    s->store = store_points != 0;
    return CONT_OK;
}

/* ---- getters ---- */

const cont_point *cont_get_point(const cont_solver *s)
{
    return s && s->cur ? &s->cur->pub : NULL;
}

long cont_num_points(const cont_solver *s) { return s ? s->nhist : 0; }

const cont_point *cont_point_at(const cont_solver *s, long i)
{
    if (!s || i < 0 || i >= s->nhist) return NULL;
    return &s->hist[i]->pub;
}

long cont_num_special(const cont_solver *s) { return s ? s->nspec : 0; }

const cont_point *cont_special_at(const cont_solver *s, long i)
{
    if (!s || i < 0 || i >= s->nspec) return NULL;
    return &s->spec[i]->pub;
}

int cont_get_stats(const cont_solver *s, cont_stats *last, cont_stats *total)
{
    NEED(s);
    if (last) *last = s->last;
    if (total) *total = s->total;
    return CONT_OK;
}

int cont_stop_reason(const cont_solver *s) { return s ? s->stop_reason : CONT_STOP_NONE; }

const char *cont_stop_name(int reason)
{
    switch (reason) {
    case CONT_STOP_NONE: return "none";
    case CONT_STOP_PMIN: return "p reached p_min";
    case CONT_STOP_PMAX: return "p reached p_max";
    case CONT_STOP_MAXSTEPS: return "maximum number of steps";
    case CONT_STOP_MAXARC: return "maximum arclength";
    case CONT_STOP_CALLBACK: return "stopped by the point callback";
    case CONT_STOP_DSMIN: return "step size below ds_min";
    case CONT_STOP_ERROR: return "error";
    default: return "unknown";
    }
}

const char *cont_errmsg(const cont_solver *s) { return s ? s->msg : "no solver"; }

int cont_get_linsol(const cont_solver *s) { return s ? s->linsol : 0; }

int cont_get_factor_stats(const cont_solver *s, cont_factor_stats *fs)
{
    memset(fs, 0, sizeof *fs);
    if (!s || !s->bt.mumps || s->bt.gen == 0) return -1;
    if (s->bt.blk_active) {
        ci_blk_factor_stats(&s->bt, fs);
        fs->ldlt = 1;
    } else {
        cont_mumps_factor_stats(s->bt.LS, fs);
    }
    return fs->entries > 0 ? 0 : -1;
}

double cont_get_ds(const cont_solver *s) { return s ? s->ds : 0.0; }

int cont_set_next_step(cont_solver *s, double ds)
{
    if (!s || !(ds > 0) || !isfinite(ds)) return CONT_EINPUT;
    s->ds = fmax(fmin(ds, s->ds_max), s->ds_min);
    return CONT_OK;
}

const char *cont_reference(void)
{
    return "H. B. Keller, Numerical solution of bifurcation and nonlinear eigenvalue "
           "problems, in: P. Rabinowitz (ed.), Applications of Bifurcation Theory, "
           "Academic Press, 1977, 359-384 (pseudo-arclength continuation, branch switching)\n"
           "E. L. Allgower, K. Georg, Introduction to Numerical Continuation Methods, "
           "SIAM Classics in Applied Mathematics 45, 2003 (tangent orientation, "
           "augmented-Jacobian determinant as bifurcation test, step control)\n"
           "W. J. F. Govaerts, Numerical Methods for Bifurcations of Dynamical Equilibria, "
           "SIAM, 2000 (bordered systems for singular matrices)\n";
}
