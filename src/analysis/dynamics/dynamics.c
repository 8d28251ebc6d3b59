/* dynamics.c - folding trajectories with IDA (see dynamics.h): histories,
 * time and parameters, the IDA set-up and callbacks, life cycle, start,
 * steps, report.  The DAE itself is in dynamics_dae.c. */
#include "dynamics_impl.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cont.h"
#include "study.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* ---------------------------------------------------------- histories */

double sf_schedule_eval(const sf_schedule *s, double t, double *slope)
{
    if (slope) *slope = 0.0;
    if (s->n <= 0) return 0.0;
    if (t < s->t[0]) return s->v[0];
    if (t >= s->t[s->n - 1]) return s->v[s->n - 1];
    int i = 0;
    while (i + 1 < s->n && t >= s->t[i + 1]) i++;
    double a = (s->v[i + 1] - s->v[i]) / (s->t[i + 1] - s->t[i]);
    if (slope) *slope = a;
    return s->v[i] + a * (t - s->t[i]);
}

static void schedule_free(sf_schedule *s)
{
    free(s->t);
    free(s->v);
    memset(s, 0, sizeof *s);
}

static int read_schedule(const sf_study *s, const char *path, sf_schedule *sc, sf_error *err)
{
    memset(sc, 0, sizeof *sc);
    int n = sf_study_count(s, path);
    if (n <= 0) return SF_OK;
    sc->t = calloc((size_t)n, sizeof(double));
    sc->v = calloc((size_t)n, sizeof(double));
    if (!sc->t || !sc->v) return sf_fail(err, SF_ENOMEM, "out of memory");
    char key[256];
    for (int i = 0; i < n; i++) {
        snprintf(key, sizeof key, "%s[%d].t", path, i);
        if (sf_study_double(s, key, 0.0, &sc->t[i], err)) return err->code;
        snprintf(key, sizeof key, "%s[%d].value", path, i);
        if (sf_study_double(s, key, 0.0, &sc->v[i], err)) return err->code;
    }
    sc->n = n;
    return SF_OK;
}

/* ------------------------------------------------------- time and params */

/* Rest angles of groups with their own history (called at the end of
 * sf_equil_set_param). */
static void dyn_param_hook(sf_equil *q, double p, void *data)
{
    (void)p;
    sf_dyn *d = data;
    const sf_study *s = d->m->study;
    if (!d->gsched) return;
    for (int i = 0; i < d->m->nfolds; i++) {
        int g = s->folds[i].group;
        if (g < 0 || d->gsched[g].n == 0) continue;
        q->par.rest[i] = sf_schedule_eval(&d->gsched[g], d->teval, NULL) * s->groups[g].rest_angle;
        q->par.drest[i] = 0.0;
    }
}

void sf_dyn_set_time(sf_dyn *d, double t)
{
    d->teval = t;
    d->p = sf_schedule_eval(&d->psched, t, &d->pslope);
    if (d->eq.param == SF_PARAM_LOAD) {
        d->load = d->p;
    } else {
        d->load = d->lsched.n ? sf_schedule_eval(&d->lsched, t, NULL) : d->load_fixed;
        d->eq.load = d->load;
    }
    sf_equil_set_param(&d->eq, d->p);
}

const double *sf_dyn_damping(const sf_dyn *d) { return d->C; }

/* ----------------------------------------------------- IDA callbacks */

static int dyn_res(sunrealtype t, N_Vector yy, N_Vector ypv, N_Vector rr, void *ud)
{
    return sf_dyn_residual(ud, t, N_VGetArrayPointer(yy), N_VGetArrayPointer(ypv),
                           N_VGetArrayPointer(rr));
}

/* Newton convergence test: the usual test on the weighted norm of the
 * update with a rate estimate (as IDA's own: stop when rate/(1 - rate)
 * |delta| <= tol; the estimate is kept across steps and reset to 20 when
 * the Jacobian is renewed), and in addition the constraint rows of the new
 * iterate must hold to the equilibrium solver's Newton tolerance
 * (solver.tolerance, scaled rows): a modified Newton iteration with an
 * older Jacobian may pass the first test while g is still at the level of
 * the local error, and g = 0 is what keeps the drift away. */
static int conv_test(SUNNonlinearSolver NLS, N_Vector ycor, N_Vector del, sunrealtype tol,
                     N_Vector ewt, void *data)
{
    sf_dyn *d = data;
    struct sf_dyn_ida *I = d->ida;
    double delnrm = N_VWrmsNorm(del, ewt);
    int m = 0;
    SUNNonlinSolGetCurIter(NLS, &m);
    if (m == 0) {
        I->oldnrm = delnrm;
    } else {
        double rate = pow(delnrm / I->oldnrm, 1.0 / m);
        if (rate > 0.9) return SUN_NLS_CONV_RECVR;
        I->ss = rate / (1.0 - rate);
    }
    if (I->ss * delnrm > tol) return SUN_NLS_CONTINUE;
    if (d->ncon == 0 || d->ic_mode) return SUN_NLS_SUCCESS;
    sunrealtype tcur, cj;
    N_Vector ypred, yppred, yyn, ypn, res;
    void *ud;
    if (IDAGetNonlinearSystemData(I->mem, &tcur, &ypred, &yppred, &yyn, &ypn, &res, &cj, &ud))
        return SUN_NLS_SUCCESS;
    N_VLinearSum(1.0, ypred, 1.0, ycor, I->ytry);
    sf_dyn_set_time(d, tcur);
    const double *y = N_VGetArrayPointer(I->ytry);
    I->nchecks++;
    if (sf_equil_residual(y, d->p, d->F, &d->eq)) return SUN_NLS_CONV_RECVR;
    double gmax = 0.0;
    for (int r = 0; r < d->ncon; r++)
        gmax = fmax(gmax, fabs(d->F[d->nq + r] * d->eq.fscale[d->nq + r]));
    if (gmax > d->ctol) {
        I->nextra++;
        return SUN_NLS_CONTINUE;
    }
    return SUN_NLS_SUCCESS;
}

static int dyn_jac(sunrealtype t, sunrealtype cj, N_Vector yy, N_Vector ypv, N_Vector rr,
                   SUNMatrix A, void *ud, N_Vector t1, N_Vector t2, N_Vector t3)
{
    (void)rr; (void)t1; (void)t2; (void)t3;
    return sf_dyn_jacobian(ud, t, cj, N_VGetArrayPointer(yy), N_VGetArrayPointer(ypv), A);
}

static void ida_err(int code, const char *module, const char *function, char *msg, void *data)
{
    (void)code;
    sf_dyn *d = data;
    snprintf(d->ida->msg, sizeof d->ida->msg, "%s/%s: %s", module, function, msg);
}

/* ------------------------------------------------------------ life cycle */

int sf_dyn_init(sf_dyn *d, const sf_model *m, sf_error *err)
{
    memset(d, 0, sizeof *d);
    d->m = m;
    const sf_study *s = m->study;
    const char *initial;
    double damping;
    int inertia, max_steps, ptype, gi, pi, ci;
    if (sf_equil_parse_param(s, &ptype, &gi, &pi, &ci, err) ||
        sf_study_double(s, "analysis.load", 0.0, &d->load_fixed, err) ||
        sf_study_double(s, "analysis.start", 0.0, &d->p_start, err) ||
        sf_study_double(s, "analysis.end", 1.0, &d->p_end, err) ||
        sf_study_double(s, "analysis.duration", 1.0, &d->duration, err) ||
        sf_study_double(s, "analysis.damping", 1.0, &damping, err) ||
        sf_study_bool(s, "analysis.inertia", 0, &inertia, err) ||
        sf_study_double(s, "analysis.settle_tolerance", 1e-8, &d->settle_tol, err) ||
        sf_study_double(s, "analysis.tolerance", 1e-6, &d->rtol, err) ||
        sf_study_int(s, "analysis.max_time_steps", 100000, &max_steps, err) ||
        sf_study_string(s, "analysis.initial", "equilibrium", &initial, err))
        return err->code;
    d->inertia = inertia;
    d->max_steps = max_steps;
    d->ctol = s->tolerance > 0 ? s->tolerance : 1e-10;
    d->initial_flat = strcmp(initial, "flat") == 0;
    if (ptype == SF_PARAM_DISPLACEMENT && inertia)
        return sf_study_fail(s, err, SF_EINPUT, "analysis.inertia",
                             "a prescribed displacement is only available for overdamped "
                             "trajectories (inertia = false)");
    if (ptype == SF_PARAM_LOAD && sf_study_count(s, "analysis.load_schedule") > 0)
        return sf_study_fail(s, err, SF_EINPUT, "analysis.load_schedule",
                             "the load is the parameter p here (analysis.parameter = \"load\"): "
                             "give its history in analysis.schedule");
    const char *form;
    if (sf_study_string(s, "solver.formulation", "folds", &form, err)) return err->code;
    if (strcmp(form, "poses") == 0)
        return sf_study_fail(s, err, SF_EINPUT, "solver.formulation",
                             "trajectories (analysis.type = \"dynamics\") use the fold "
                             "formulation only: set solver.formulation = \"folds\"");
    if (sf_equil_init(&d->eq, m, ptype, gi, pi, ci, d->load_fixed, err)) return err->code;
    if (s->constraints == SF_CONSTRAINTS_PENALTY)
        sf_equil_use_penalty(&d->eq, s->penalty_rotation, s->penalty_translation);
    d->eq.param_hook = dyn_param_hook;
    d->eq.param_hook_data = d;
    d->nq = m->nq;
    d->ncon = d->eq.ncon;
    d->n = d->eq.n + (inertia ? d->nq + d->ncon : 0);
    d->ov = d->eq.n;
    d->om = d->eq.n + d->nq;
    /* histories */
    if (read_schedule(s, "analysis.schedule", &d->psched, err) ||
        read_schedule(s, "analysis.load_schedule", &d->lsched, err))
        return err->code;
    if (d->psched.n == 0) {
        d->psched.t = calloc(2, sizeof(double));
        d->psched.v = calloc(2, sizeof(double));
        if (!d->psched.t || !d->psched.v) return sf_fail(err, SF_ENOMEM, "out of memory");
        d->psched.n = 2;
        d->psched.t[1] = d->duration;
        d->psched.v[0] = d->p_start;
        d->psched.v[1] = d->p_end;
    }
    if (s->ngroups) {
        d->gsched = calloc((size_t)s->ngroups, sizeof(sf_schedule));
        if (!d->gsched) return sf_fail(err, SF_ENOMEM, "out of memory");
        for (int g = 0; g < s->ngroups; g++) {
            char path[64];
            snprintf(path, sizeof path, "actuation[%d].schedule", g);
            if (read_schedule(s, path, &d->gsched[g], err)) return err->code;
        }
    }
    d->t_hist_end = d->psched.t[d->psched.n - 1];
    if (d->lsched.n) d->t_hist_end = fmax(d->t_hist_end, d->lsched.t[d->lsched.n - 1]);
    for (int g = 0; g < s->ngroups; g++)
        if (d->gsched[g].n) d->t_hist_end = fmax(d->t_hist_end, d->gsched[g].t[d->gsched[g].n - 1]);
    /* damping: c_i G_i / G_i[0][0] per fold */
    int nq = d->nq;
    size_t nn = (size_t)nq * nq;
    d->C = calloc(nn + 1, sizeof(double));
    if (!d->C) return sf_fail(err, SF_ENOMEM, "out of memory");
    d->cmin_tau = INFINITY;
    for (int i = 0; i < m->nfolds; i++) {
        char key[64];
        double c = damping;
        snprintf(key, sizeof key, "folds[%d].damping", i);
        if (sf_study_has(s, key) && sf_study_double(s, key, damping, &c, err)) return err->code;
        const double *G = m->sec[i].gram;
        int k = m->qn[i], off = m->qoff[i];
        for (int a = 0; a < k; a++)
            for (int b = 0; b < k; b++)
                d->C[(size_t)(off + a) * nq + off + b] = c * G[a * k + b] / G[0];
        double kth = d->eq.e.stiff[i] * G[0];
        if (kth > 0) d->cmin_tau = fmin(d->cmin_tau, c / kth);
    }
    if (!isfinite(d->cmin_tau)) d->cmin_tau = 1.0;
    if (inertia && dy_build_masses(d, err)) return err->code;
    size_t n = (size_t)d->n;
    d->y = calloc(n + 1, sizeof(double));
    d->yp = calloc(n + 1, sizeof(double));
    d->F = calloc(n + (size_t)d->eq.n + 1, sizeof(double));
    d->Fp = calloc(n + (size_t)d->eq.n + 1, sizeof(double));
    d->Jc = calloc((size_t)d->ncon * nq + 1, sizeof(double));
    d->Hc = calloc((inertia ? 7 : 3) * nn + 1, sizeof(double));
    d->work = calloc(9 * (size_t)nq + (size_t)d->ncon + 1, sizeof(double));
    if (!d->y || !d->yp || !d->F || !d->Fp || !d->Jc || !d->Hc || !d->work)
        return sf_fail(err, SF_ENOMEM, "out of memory");
    return SF_OK;
}

void sf_dyn_free(sf_dyn *d)
{
    if (d->ida) {
        struct sf_dyn_ida *I = d->ida;
        if (I->mem) IDAFree(&I->mem);
        if (I->LS) SUNLinSolFree(I->LS);
        if (I->NLS) SUNNonlinSolFree(I->NLS);
        if (I->ytry) N_VDestroy(I->ytry);
        if (I->A) SUNMatDestroy(I->A);
        if (I->Aeq) SUNMatDestroy(I->Aeq);
        if (I->y) N_VDestroy(I->y);
        if (I->yp) N_VDestroy(I->yp);
        if (I->id) N_VDestroy(I->id);
        if (I->atol) N_VDestroy(I->atol);
        free(I->stops);
        if (I->ctx) SUNContext_Free(&I->ctx);
        free(I);
    }
    sf_equil_free(&d->eq);
    schedule_free(&d->psched);
    schedule_free(&d->lsched);
    if (d->gsched && d->m)
        for (int g = 0; g < d->m->study->ngroups; g++) schedule_free(&d->gsched[g]);
    free(d->gsched);
    free(d->C);
    free(d->mpt);
    free(d->mw);
    free(d->y);
    free(d->yp);
    free(d->F);
    free(d->Fp);
    free(d->Jc);
    free(d->Hc);
    free(d->work);
    memset(d, 0, sizeof *d);
}

/* The state at rest at t = 0 (g = 0): the flat sheet, or the equilibrium
 * found as the continuation finds its first point. */
static int initial_state(sf_dyn *d, sf_error *err)
{
    sf_equil *eq = &d->eq;
    const sf_study *s = d->m->study;
    double tol = s->tolerance > 0 ? s->tolerance : 1e-10;
    double *y = d->y;
    memset(y, 0, sizeof(double) * (size_t)d->n);
    sf_dyn_set_time(d, 0.0);
    double p0 = d->p;
    double F0 = 0.0;
    if (sf_equil_residual(y, p0, d->F, eq) == 0)
        for (int i = 0; i < eq->n; i++) F0 = fmax(F0, fabs(d->F[i] * eq->fscale[i]));
    else
        F0 = INFINITY;
    if (d->initial_flat || F0 <= 1e-14) {
        if (eq->nloop > 0)
            return sf_fail(err, SF_EINPUT, "%s: the trajectory would start at the flat sheet, a "
                           "singular point of vertex loop closure (its multipliers are undetermined "
                           "there): start from a folded equilibrium (analysis.initial = "
                           "\"equilibrium\" with loads or actuation at t = 0)", s->path);
        return SF_OK;
    }
    cont_solver *cs = NULL;
    if (sf_equil_create_solver(eq, &cs) != CONT_OK) {
        if (cs) cont_free(cs);
        return sf_fail(err, SF_ENOMEM, "dynamics: cannot create the equilibrium solver");
    }
    cont_set_newton(cs, tol, 50, 1);
    cont_set_newton_init(cs, 200, 1);
    int rc;
    if (eq->nloop > 0) {
        /* off the flat state through the penalty homotopy, then exact */
        rc = sf_equil_start_off_flat(eq, p0, tol, y, err);
        if (!rc) {
            sf_dyn_set_time(d, 0.0);
            rc = cont_solve_fixed(cs, y, p0) == CONT_OK ? SF_OK
               : sf_fail(err, SF_ENUMERIC, "%s: no equilibrium at t = 0 (p = %g): %s", s->path,
                         p0, cont_errmsg(cs));
        }
    } else {
        /* the rest angles first (see src/cli/run_equilibrium.c), then the flat sheet */
        for (int i = 0; i < d->m->nfolds; i++) y[d->m->qoff[i]] = eq->par.rest[i];
        rc = cont_solve_fixed(cs, y, p0);
        if (rc != CONT_OK) {
            memset(y, 0, sizeof(double) * (size_t)d->n);
            rc = cont_solve_fixed(cs, y, p0);
        }
        rc = rc == CONT_OK ? SF_OK
           : sf_fail(err, SF_ENUMERIC, "%s: no equilibrium at t = 0 (p = %g): %s", s->path, p0,
                     cont_errmsg(cs));
    }
    cont_free(cs);
    return rc;
}

int sf_dyn_start(sf_dyn *d, sf_error *err)
{
    double w0 = now();
    const sf_study *s = d->m->study;
    d->err = err;
    d->t = 0.0;
    d->done = 0;
    if (initial_state(d, err)) return err->code;
    struct sf_dyn_ida *I = calloc(1, sizeof *I);
    if (!I) return sf_fail(err, SF_ENOMEM, "out of memory");
    d->ida = I;
    sunindextype n = d->n;
    if (SUNContext_Create(NULL, &I->ctx) || !I->ctx) return sf_fail(err, SF_ENOMEM, "IDA: no context");
    I->y = N_VMake_Serial(n, d->y, I->ctx);
    I->yp = N_VMake_Serial(n, d->yp, I->ctx);
    I->id = N_VNew_Serial(n, I->ctx);
    I->atol = N_VNew_Serial(n, I->ctx);
    I->A = SUNDenseMatrix(n, n, I->ctx);
    if (d->inertia) I->Aeq = SUNDenseMatrix(d->eq.n, d->eq.n, I->ctx);
    I->mem = IDACreate(I->ctx);
    if (!I->y || !I->yp || !I->id || !I->atol || !I->A || !I->mem || (d->inertia && !I->Aeq))
        return sf_fail(err, SF_ENOMEM, "IDA: out of memory");
    I->LS = SUNLinSol_Dense(I->y, I->A, I->ctx);
    if (!I->LS) return sf_fail(err, SF_ENOMEM, "IDA: out of memory");
    /* kinks of the histories, then the end */
    int cap = 2 + d->psched.n + d->lsched.n;
    for (int g = 0; g < s->ngroups; g++) cap += d->gsched[g].n;
    I->stops = calloc((size_t)cap, sizeof(double));
    if (!I->stops) return sf_fail(err, SF_ENOMEM, "out of memory");
    const sf_schedule *all[2] = {&d->psched, &d->lsched};
    for (int k = 0; k < 2 + s->ngroups; k++) {
        const sf_schedule *sc = k < 2 ? all[k] : &d->gsched[k - 2];
        for (int i = 0; i < sc->n; i++)
            if (sc->t[i] > 0.0 && sc->t[i] < d->duration) I->stops[I->nstops++] = sc->t[i];
    }
    I->stops[I->nstops++] = d->duration;
    for (int i = 1; i < I->nstops; i++)       /* sort (few entries) */
        for (int j = i; j > 0 && I->stops[j - 1] > I->stops[j]; j--) {
            double x = I->stops[j]; I->stops[j] = I->stops[j - 1]; I->stops[j - 1] = x;
        }
    int k = 0;
    for (int i = 0; i < I->nstops; i++)
        if (k == 0 || I->stops[i] > I->stops[k - 1] * (1 + 1e-12)) I->stops[k++] = I->stops[i];
    I->nstops = k;
    /* variables: differential (1) or algebraic (0); tolerances */
    double *id = N_VGetArrayPointer(I->id), *at = N_VGetArrayPointer(I->atol);
    double aq = 1e-2 * d->rtol;
    double tref = d->cmin_tau;
    for (int i = 0; i < d->n; i++) {
        int q = i < d->nq, lam = i >= d->nq && i < d->eq.n, v = d->inertia && i >= d->ov && i < d->om;
        id[i] = (q || v) ? 1.0 : 0.0;
        if (q) at[i] = aq;
        else if (lam) at[i] = d->rtol / d->eq.yscale[i];
        else at[i] = d->rtol / tref;   /* v, mu: rtol times 1 rad per relaxation time */
    }
    int f = IDAInit(I->mem, dyn_res, 0.0, I->y, I->yp);
    if (!f) f = IDASVtolerances(I->mem, d->rtol, I->atol);
    if (!f) f = IDASetUserData(I->mem, d);
    if (!f) f = IDASetErrHandlerFn(I->mem, ida_err, d);
    if (!f) f = IDASetLinearSolver(I->mem, I->LS, I->A);
    if (!f) f = IDASetJacFn(I->mem, dyn_jac);
    if (!f) f = IDASetId(I->mem, I->id);
    if (!f) f = IDASetSuppressAlg(I->mem, SUNTRUE);
    if (!f) f = IDASetMaxNumSteps(I->mem, 100000);
    I->NLS = SUNNonlinSol_Newton(I->y, I->ctx);
    I->ytry = N_VClone(I->y);
    if (!I->NLS || !I->ytry) return sf_fail(err, SF_ENOMEM, "IDA: out of memory");
    if (!f) f = IDASetNonlinearSolver(I->mem, I->NLS);
    if (!f) f = SUNNonlinSolSetConvTestFn(I->NLS, conv_test, d);
    if (!f) f = IDASetMaxNonlinIters(I->mem, 8);
    I->ss = 20.0;
    if (f) return sf_fail(err, SF_ENUMERIC, "IDA setup failed: %s", I->msg);
    /* consistent q' and multipliers on the index-1 form */
    d->ic_mode = 1;
    double tout1 = fmin(I->stops[0], 1e-2 * d->duration);
    f = IDACalcIC(I->mem, IDA_YA_YDP_INIT, tout1);
    d->ic_mode = 0;
    if (f < 0)
        return sf_fail(err, SF_ENUMERIC, "%s: no consistent initial rates at t = 0 (IDACalcIC: %s)",
                       s->path, I->msg);
    IDAGetConsistentIC(I->mem, I->y, I->yp);
    long nre = 0, nje = 0, nni = 0;
    IDAGetNumResEvals(I->mem, &nre);
    IDAGetNumJacEvals(I->mem, &nje);
    IDAGetNumNonlinSolvIters(I->mem, &nni);
    d->stats.ic_nres = nre;
    d->ic_nje = nje;
    d->ic_nni = nni;
    f = IDAReInit(I->mem, 0.0, I->y, I->yp);
    if (!f) f = IDASetStopTime(I->mem, I->stops[0]);
    if (f) return sf_fail(err, SF_ENUMERIC, "IDA re-initialisation failed: %s", I->msg);
    I->next = 0;
    sf_dyn_set_time(d, 0.0);
    d->stats.wall += now() - w0;
    d->stats.nres = d->stats.ic_nres;
    d->stats.njac = nje;
    d->stats.nni = nni;
    return SF_OK;
}

int sf_dyn_step(sf_dyn *d, sf_error *err)
{
    struct sf_dyn_ida *I = d->ida;
    const sf_study *s = d->m->study;
    if (!I) return sf_fail(err, SF_EINPUT, "dynamics: sf_dyn_step before sf_dyn_start");
    if (d->done) return SF_OK;
    if (d->stats.steps >= d->max_steps)
        return sf_fail(err, SF_ENUMERIC, "%s: %ld integrator steps reached at t = %g s before "
                       "the end (analysis.max_time_steps)", s->path, d->stats.steps, d->t);
    double w0 = now();
    d->err = err;
    double tret = d->t;
    int f = IDASolve(I->mem, d->duration, &tret, I->y, I->yp, IDA_ONE_STEP);
    d->stats.wall += now() - w0;
    if (f < 0)
        return sf_fail(err, SF_ENUMERIC, "%s: the integrator failed at t = %g s (%s)", s->path,
                       tret, I->msg[0] ? I->msg : IDAGetReturnFlagName(f));
    d->t = tret;
    long nst = 0, nre = 0, nje = 0, nni = 0, netf = 0, ncfn = 0;
    IDAGetNumSteps(I->mem, &nst);
    IDAGetNumResEvals(I->mem, &nre);
    IDAGetNumJacEvals(I->mem, &nje);
    IDAGetNumNonlinSolvIters(I->mem, &nni);
    IDAGetNumErrTestFails(I->mem, &netf);
    IDAGetNumNonlinSolvConvFails(I->mem, &ncfn);
    IDAGetLastStep(I->mem, &d->stats.h);
    IDAGetLastOrder(I->mem, &d->stats.order);
    long nreLS = 0;
    IDAGetNumLinResEvals(I->mem, &nreLS);
    d->stats.steps = nst;
    d->stats.nres = d->stats.ic_nres + nre + nreLS;
    d->stats.njac = d->ic_nje + nje;
    d->stats.nni = d->ic_nni + nni;
    d->stats.netf = netf;
    d->stats.ncfn = ncfn;
    d->stats.nchecks = I->nchecks;
    d->stats.nextra = I->nextra;
    if (f == IDA_TSTOP_RETURN) {
        while (I->next < I->nstops && I->stops[I->next] <= tret * (1 + 1e-12)) I->next++;
        if (I->next >= I->nstops) {
            d->done = 1;
        } else if (IDASetStopTime(I->mem, I->stops[I->next])) {
            return sf_fail(err, SF_ENUMERIC, "IDA: cannot set the stop time: %s", I->msg);
        }
    }
    if (tret >= d->duration * (1 - 1e-12)) d->done = 1;
    sf_dyn_set_time(d, tret);
    if (!d->done && tret >= d->t_hist_end) {
        double sp = 0.0;
        for (int j = 0; j < d->nq; j++) sp = fmax(sp, fabs(d->yp[j]));
        if (sp < d->settle_tol) d->done = 2;
    }
    return SF_OK;
}

void sf_dyn_report(sf_dyn *d, double *Pi, double *kinetic, double *drift, double *speed)
{
    sf_equil *eq = &d->eq;
    double rr, rt;
    sf_dyn_set_time(d, d->t);
    sf_equil_report(eq, d->y, d->p, Pi, &rr, &rt);
    double dr = 0.0;
    if (sf_equil_residual(d->y, d->p, d->F, eq) == 0)
        for (int r = 0; r < d->ncon; r++) dr = fmax(dr, fabs(d->F[d->nq + r]));
    else
        dr = INFINITY;
    /* in penalty mode the loops are not constraint rows: report them too */
    if (!eq->exact) dr = fmax(dr, fmax(rr, rt));
    *drift = dr;
    double sp = 0.0;
    for (int j = 0; j < d->nq; j++) sp = fmax(sp, fabs(d->yp[j]));
    *speed = sp;
    *kinetic = 0.0;
    if (d->inertia) {
        sf_kin_eval(d->m, d->y, 1, &eq->k);
        *kinetic = dy_kinetic_energy(d, d->y + d->ov);
    }
}
