/* dynamics.c - folding trajectories with IDA (see dynamics.h). */
#include "dynamics.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_newton.h>

#include "cont.h"
#include "study.h"

#define REG_EPS 1e-10

struct sf_dyn_ida {
    SUNContext ctx;
    void *mem;
    N_Vector y, yp, id, atol;
    SUNMatrix A, Aeq;
    SUNLinearSolver LS;
    SUNNonlinearSolver NLS;
    N_Vector ytry;       /* scratch: the Newton iterate */
    double ss, oldnrm;   /* convergence rate estimate of the Newton iteration */
    long nextra;         /* Newton iterations added for the constraint rows */
    long nchecks;        /* evaluations of the constraint rows in conv_test */
    double *stops;       /* kinks of the histories in (0, duration], then duration */
    int nstops, next;
    char msg[512];       /* last message of IDA */
};

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

/* --------------------------------------------------------------- masses */

static int add_mass(sf_dyn *d, int *cap, const sf_mpoint *pt, double mass)
{
    if (d->nmass == *cap) {
        int nc = *cap ? 2 * *cap : 64;
        sf_mpoint *np = realloc(d->mpt, sizeof(sf_mpoint) * (size_t)nc);
        if (!np) return SF_ENOMEM;
        d->mpt = np;
        double *nw = realloc(d->mw, sizeof(double) * (size_t)nc);
        if (!nw) return SF_ENOMEM;
        d->mw = nw;
        *cap = nc;
    }
    d->mpt[d->nmass] = *pt;
    d->mw[d->nmass] = mass;
    d->nmass++;
    return SF_OK;
}

/* Quadrature points carrying the mass of the moving faces and of the
 * fold bands (see dynamics.h). */
static int build_masses(sf_dyn *d, sf_error *err)
{
    const sf_model *m = d->m;
    const sf_study *s = m->study;
    const sf_topology *t = m->topo;
    int cap = 0;
    if (s->face_material >= 0) {
        const sf_material *fm = &s->materials[s->face_material];
        double rh = fm->density * fm->thickness;
        for (int f = 0; f < t->nfaces; f++) {
            if (f == t->root) continue;     /* it does not move */
            const sf_face *F = &t->faces[f];
            const sf_polygon *P = &F->body;
            const double *c = F->centroid;
            for (int i = 0; i < P->n; i++) {
                const double *a = P->p[i], *b = P->p[(i + 1) % P->n];
                double area = 0.5 * ((a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]));
                double mid[3][2] = {{0.5 * (c[0] + a[0]), 0.5 * (c[1] + a[1])},
                                    {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])},
                                    {0.5 * (b[0] + c[0]), 0.5 * (b[1] + c[1])}};
                for (int k = 0; k < 3; k++) {
                    sf_mpoint pt;
                    memset(&pt, 0, sizeof pt);
                    pt.X[0] = mid[k][0];
                    pt.X[1] = mid[k][1];
                    pt.face = f;
                    pt.fold = -1;
                    if (add_mass(d, &cap, &pt, rh * area / 3.0))
                        return sf_fail(err, SF_ENOMEM, "out of memory");
                }
            }
        }
    }
    /* fold bands: 4 Gauss points across, 2 along */
    static const double xs[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281,
                                 0.9305681557970263};
    static const double ws[4] = {0.1739274225687269, 0.3260725774312731, 0.3260725774312731,
                                 0.1739274225687269};
    static const double xt[2] = {0.2113248654051871, 0.7886751345948129};
    for (int i = 0; i < m->nfolds; i++) {
        const sf_fold_def *fd = &s->folds[i];
        const sf_fold_geom *g = &t->folds[i];
        const sf_material *mat = &s->materials[fd->material];
        double w = fd->width, L = g->L;
        double mass = mat->density * mat->thickness * w * L;
        for (int a = 0; a < 4; a++)
            for (int b = 0; b < 2; b++) {
                sf_mpoint pt;
                memset(&pt, 0, sizeof pt);
                pt.fold = i;
                pt.face = g->right;
                pt.s = w * xs[a];
                pt.tpos = fd->setback[0] + L * xt[b];
                for (int c = 0; c < 2; c++)
                    pt.X[c] = g->a[c] + pt.tpos * g->m[c] + (pt.s - 0.5 * w) * g->n[c];
                if (add_mass(d, &cap, &pt, mass * ws[a] * 0.5))
                    return sf_fail(err, SF_ENOMEM, "out of memory");
            }
    }
    return SF_OK;
}

/* Inertia terms at (q, v, a = v') with the kinematics of d->eq.k evaluated
 * at order 2: f += M a + h(q, v); when M is not NULL also M (nq x nq), Kq
 * (d f / d q without the third-derivative part of h) and Dv (d f / d v),
 * row-major, added.  Uses d->Hc (3 nq x nq) and d->work (3 nq + ...). */
static void inertia_eval(sf_dyn *d, const double *v, const double *a, double *f, double *M,
                         double *Kq, double *Dv)
{
    const sf_model *m = d->m;
    int nq = d->nq;
    size_t nn = (size_t)nq * nq;
    double *dx = d->work;                /* 3 nq */
    double *Hv = d->work + 3 * nq;       /* 3 nq: Hc v */
    double *Ha = d->work + 6 * nq;       /* 3 nq: Hc a */
    for (int p = 0; p < d->nmass; p++) {
        double x[3], w = d->mw[p];
        sf_point_eval(m, &d->eq.k, &d->mpt[p], x, dx);
        memset(d->Hc, 0, sizeof(double) * 3 * nn);
        for (int c = 0; c < 3; c++) {
            double e[3] = {0, 0, 0};
            e[c] = 1.0;
            sf_point_hess_add(m, &d->eq.k, &d->mpt[p], e, d->Hc + c * nn, nq);
        }
        double acc[3];
        for (int c = 0; c < 3; c++) {
            const double *H = d->Hc + c * nn;
            double s = 0.0, vHv = 0.0;
            for (int j = 0; j < nq; j++) s += dx[c * nq + j] * a[j];
            for (int j = 0; j < nq; j++) {
                double hv = 0.0, ha = 0.0;
                for (int l = 0; l < nq; l++) {
                    hv += H[(size_t)j * nq + l] * v[l];
                    ha += H[(size_t)j * nq + l] * a[l];
                }
                Hv[c * nq + j] = hv;
                Ha[c * nq + j] = ha;
                vHv += v[j] * hv;
            }
            acc[c] = s + vHv;
        }
        for (int j = 0; j < nq; j++)
            f[j] += w * (dx[j] * acc[0] + dx[nq + j] * acc[1] + dx[2 * nq + j] * acc[2]);
        if (!M) continue;
        for (int j = 0; j < nq; j++)
            for (int l = 0; l < nq; l++) {
                double mm = 0.0, kq = 0.0, dv = 0.0;
                for (int c = 0; c < 3; c++) {
                    double dj = dx[c * nq + j];
                    mm += dj * dx[c * nq + l];
                    kq += acc[c] * d->Hc[c * nn + (size_t)j * nq + l] + dj * Ha[c * nq + l];
                    dv += 2.0 * dj * Hv[c * nq + l];
                }
                M[(size_t)j * nq + l] += w * mm;
                Kq[(size_t)j * nq + l] += w * kq;
                Dv[(size_t)j * nq + l] += w * dv;
            }
    }
}

/* Kinetic energy (1/2) v^T M v at the kinematic state of d->eq.k (order >= 1). */
static double kinetic_energy(sf_dyn *d, const double *v)
{
    int nq = d->nq;
    double T = 0.0, x[3];
    for (int p = 0; p < d->nmass; p++) {
        sf_point_eval(d->m, &d->eq.k, &d->mpt[p], x, d->work);
        for (int c = 0; c < 3; c++) {
            double u = 0.0;
            for (int j = 0; j < nq; j++) u += d->work[c * nq + j] * v[j];
            T += 0.5 * d->mw[p] * u * u;
        }
    }
    return T;
}

/* Constraint Jacobian (every row, unscaled) into d->Jc after
 * sf_equil_residual has evaluated the kinematics at order >= 1. */
static void constraint_jacobian(sf_dyn *d)
{
    sf_equil *eq = &d->eq;
    int nq = d->nq;
    if (eq->nloop) memcpy(d->Jc, eq->J, sizeof(double) * (size_t)eq->nloop * nq);
    for (int r = 0; r < eq->nsup; r++) {
        double x[3];
        sf_point_eval(d->m, &eq->k, &eq->rowpt[r], x, d->work);
        memcpy(d->Jc + (size_t)(eq->nloop + r) * nq, d->work + eq->rowc[r] * nq,
               sizeof(double) * nq);
    }
}

/* d g_r / dt: only a prescribed displacement moves with time. */
static double row_rate(const sf_dyn *d, int r)
{
    const sf_equil *eq = &d->eq;
    if (eq->disp_row >= 0 && r == eq->nloop + eq->disp_row) return -d->pslope;
    return 0.0;
}

/* ----------------------------------------------------- IDA callbacks */

int sf_dyn_residual(sf_dyn *d, double t, const double *y, const double *yd, double *R)
{
    int nq = d->nq, nc = d->ncon, ne = d->eq.n;
    sf_dyn_set_time(d, t);
    for (int i = 0; i < d->n; i++)
        if (!isfinite(y[i]) || !isfinite(yd[i])) return 1;
    if (sf_equil_residual(y, d->p, d->F, &d->eq)) return 1;
    const double *v = d->inertia ? y + d->ov : yd;
    for (int j = 0; j < nq; j++) {
        double cv = 0.0;
        const double *Cj = d->C + (size_t)j * nq;
        for (int l = 0; l < nq; l++) cv += Cj[l] * v[l];
        R[j] = d->F[j] + cv;
    }
    int needJ = d->ic_mode || d->inertia;
    if (needJ) constraint_jacobian(d);
    for (int r = 0; r < nc; r++) {
        if (!d->ic_mode) {
            R[nq + r] = d->F[nq + r];
        } else {
            /* index-1 form: d g / dt = J q' + g_t */
            const double *Jr = d->Jc + (size_t)r * nq;
            double s = row_rate(d, r);
            for (int j = 0; j < nq; j++) s += Jr[j] * yd[j];
            R[nq + r] = s;
        }
    }
    if (d->inertia) {
        sf_kin_eval(d->m, y, 2, &d->eq.k);
        inertia_eval(d, v, yd + d->ov, R, NULL, NULL, NULL);
        const double *mu = y + d->om;
        const double *fs = d->eq.fscale + nq;
        for (int j = 0; j < nq; j++) {
            double s = 0.0;
            for (int r = 0; r < nc; r++) s += d->Jc[(size_t)r * nq + j] * fs[r] * mu[r];
            R[d->ov + j] = yd[j] - v[j] - s;
        }
        const double *w = d->ic_mode ? yd + d->ov : v;
        for (int r = 0; r < nc; r++) {
            const double *Jr = d->Jc + (size_t)r * nq;
            double s = 0.0;
            for (int j = 0; j < nq; j++) s += Jr[j] * w[j];
            R[d->om + r] = fs[r] * s;
        }
    }
    for (int i = 0; i < ne; i++) R[i] *= d->eq.fscale[i];
    for (int i = 0; i < d->n; i++)
        if (!isfinite(R[i])) return 1;
    return 0;
}

#define AEL(A, i, j) SM_ELEMENT_D(A, i, j)

static int dyn_res(sunrealtype t, N_Vector yy, N_Vector ypv, N_Vector rr, void *ud)
{
    return sf_dyn_residual(ud, t, N_VGetArrayPointer(yy), N_VGetArrayPointer(ypv),
                           N_VGetArrayPointer(rr));
}

int sf_dyn_jacobian(sf_dyn *d, double t, double cj, const double *y, const double *yd,
                    SUNMatrix A)
{
    int nq = d->nq, nc = d->ncon, ne = d->eq.n;
    if (d->ida) d->ida->ss = 20.0;    /* new Jacobian: no rate estimate yet */
    sf_dyn_set_time(d, t);
    SUNMatrix Aeq = d->inertia ? d->ida->Aeq : A;
    SUNMatZero(Aeq);
    if (sf_equil_jacobian(y, d->p, Aeq, d->Fp, &d->eq)) return 1;
    if (!d->inertia) {
        for (int j = 0; j < nq; j++)
            for (int l = 0; l < nq; l++) AEL(A, j, l) += cj * d->C[(size_t)j * nq + l];
        if (d->ic_mode)
            for (int r = 0; r < nc; r++)
                for (int j = 0; j < nq; j++) AEL(A, nq + r, j) *= cj;
    } else {
        SUNMatZero(A);
        size_t nn = (size_t)nq * nq;
        double *M = d->Hc + 3 * nn, *Kq = M + nn, *Dv = Kq + nn, *Hmu = Dv + nn;
        memset(M, 0, sizeof(double) * 4 * nn);
        /* first-order kinematics for the constraint rows, then order 2 */
        if (sf_equil_residual(y, d->p, d->F, &d->eq)) return 1;
        constraint_jacobian(d);
        sf_kin_eval(d->m, y, 2, &d->eq.k);
        double *f = d->F;   /* scratch for the inertial force */
        memset(f, 0, sizeof(double) * nq);
        const double *v = y + d->ov, *a = yd + d->ov, *mu = y + d->om;
        inertia_eval(d, v, a, f, M, Kq, Dv);
        /* sum_r (fs_r mu_r) d2 g_r */
        const sf_equil *eq = &d->eq;
        const double *fs = eq->fscale + nq;
        double *wl = d->work + 9 * nq;    /* nc weights */
        for (int r = 0; r < nc; r++) wl[r] = fs[r] * mu[r];
        if (eq->nloop) sf_constraints(d->m, &d->eq.k, d->Fp, NULL, wl, Hmu, nq);
        for (int r = 0; r < eq->nsup; r++) {
            double fr[3] = {0, 0, 0};
            fr[eq->rowc[r]] = wl[eq->nloop + r];
            sf_point_hess_add(d->m, &d->eq.k, &eq->rowpt[r], fr, Hmu, nq);
        }
        for (int j = 0; j < nq; j++) {
            for (int l = 0; l < nq; l++) {
                size_t jl = (size_t)j * nq + l;
                AEL(A, j, l) = AEL(Aeq, j, l) + Kq[jl];
                AEL(A, j, d->ov + l) = d->C[jl] + Dv[jl] + cj * M[jl];
                AEL(A, d->ov + j, l) = -Hmu[jl];
            }
            AEL(A, d->ov + j, j) += cj;
            AEL(A, d->ov + j, d->ov + j) = -1.0;
            for (int r = 0; r < nc; r++) {
                double Jrj = d->Jc[(size_t)r * nq + j];
                AEL(A, j, nq + r) = AEL(Aeq, j, nq + r);                    /* J^T */
                AEL(A, nq + r, j) = (d->ic_mode ? cj : 1.0) * AEL(Aeq, nq + r, j);
                AEL(A, d->ov + j, d->om + r) = -fs[r] * Jrj;
                AEL(A, d->om + r, d->ov + j) = (d->ic_mode ? cj : 1.0) * fs[r] * Jrj;
            }
        }
        for (int r = 0; r < nc; r++) {
            AEL(A, nq + r, nq + r) = AEL(Aeq, nq + r, nq + r);
            AEL(A, d->om + r, d->om + r) = -REG_EPS;
        }
    }
    for (int i = 0; i < ne; i++) {
        double s = d->eq.fscale[i];
        for (int j = 0; j < d->n; j++) AEL(A, i, j) *= s;
    }
    for (int i = 0; i < d->n; i++)
        for (int j = 0; j < d->n; j++)
            if (!isfinite(AEL(A, i, j))) return 1;
    return 0;
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
    if (inertia && build_masses(d, err)) return err->code;
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
        /* the rest angles first (see run.c), then the flat sheet */
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
        *kinetic = kinetic_energy(d, d->y + d->ov);
    }
}
