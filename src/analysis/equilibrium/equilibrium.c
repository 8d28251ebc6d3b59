/* equilibrium.c - residual and Jacobian of the equilibrium problem. */
#include "equilibrium.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "cont.h"
#include "equilibrium_poses.h"
#include "study.h"

#define REG_EPS 1e-10

static void sf_equil_scales(sf_equil *q);

double sf_equil_reg_eps(const sf_equil *q, const double *y)
{
    if (q->eps_anchor > 0) return q->eps_anchor;   /* anchored: its weight */
    if (!(q->reg_rel > 0)) return REG_EPS;
    double a = 0.0;
    for (int j = 0; j < q->m->nq; j++) a = fmax(a, fabs(y[j]));
    return fmin(REG_EPS, fmax(q->reg_min, q->reg_rel * a * a));
}

int sf_equil_anchor(const double *y, double p, int on, void *user)
{
    (void)p;
    sf_equil *q = user;
    q->eps_anchor = 0.0;
    if (!on || q->ncon == 0) return 0;
    if (!q->lam_anchor && !(q->lam_anchor = malloc(sizeof(double) * (size_t)q->ncon))) return 1;
    memcpy(q->lam_anchor, y + q->nq, sizeof(double) * (size_t)q->ncon);
    q->eps_anchor = sf_equil_reg_eps(q, y);
    for (int k = 1; k < on; k++) q->eps_anchor *= 0.1;   /* cont.h: the levels */
    return 0;
}

double sf_equil_row_eps(const sf_equil *q, double eps, int r)
{
    return q->eps_anchor > 0 && q->anchor_w ? eps * q->anchor_w[r] : eps;
}

void sf_equil_anchor_rows(const sf_equil *q, const double *y, double *F)
{
    if (!(q->eps_anchor > 0)) return;
    for (int r = 0; r < q->ncon; r++) {
        int i = q->nq + r;
        F[i] -= sf_equil_row_eps(q, q->eps_anchor, r) * q->yscale[i] / q->fscale[i] * (y[i] - q->lam_anchor[r]);
    }
}

int sf_equil_init(sf_equil *q, const sf_model *m, int param, int group, int probe,
                  int component, double load, sf_error *err)
{
    memset(q, 0, sizeof *q);
    const sf_study *s = m->study;
    q->m = m;
    q->param = param;
    q->group = group;
    q->load = load;
    q->disp_row = -1;
    q->ramp_stage = -1;
    if (sf_energy_init(&q->e, m, err)) return err->code;
    if (sf_params_alloc(&q->e, &q->par) || sf_kin_alloc(m, &q->k)) {
        sf_equil_free(q);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    q->exact = s->constraints == SF_CONSTRAINTS_EXACT;
    q->nq = m->nq;
    q->nloop = q->exact ? m->ncon : 0;
    int nrows = 0;
    for (int i = 0; i < s->nsupports; i++)
        for (int c = 0; c < 3; c++) nrows += s->supports[i].dof[c] != 0;
    if (param == SF_PARAM_DISPLACEMENT) nrows++;
    q->rowpt = calloc((size_t)nrows + 1, sizeof(sf_mpoint));
    q->rowc = calloc((size_t)nrows + 1, sizeof(int));
    q->rowval = calloc((size_t)nrows + 1, sizeof(double));
    if (!q->rowpt || !q->rowc || !q->rowval) {
        sf_equil_free(q);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int i = 0; i < s->nsupports; i++)
        for (int c = 0; c < 3; c++) {
            if (!s->supports[i].dof[c]) continue;
            if (sf_model_locate(m, s->supports[i].at, &q->rowpt[q->nsup], err)) {
                sf_error_prefix(err, "%s:%d: support %d", s->path, s->supports[i].line, i + 1);
                sf_equil_free(q);
                return err->code;
            }
            q->rowc[q->nsup] = c;
            q->rowval[q->nsup] = s->supports[i].value[c];
            q->nsup++;
        }
    if (param == SF_PARAM_DISPLACEMENT) {
        if (probe < 0 || probe >= s->nprobes || component < 0 || component > 2) {
            sf_equil_free(q);
            return sf_fail(err, SF_EINPUT, "%s: displacement parameter needs a probe and a "
                           "component x, y or z", s->path);
        }
        if (sf_model_locate(m, s->probes[probe].at, &q->rowpt[q->nsup], err)) {
            sf_equil_free(q);
            return err->code;
        }
        q->rowc[q->nsup] = component;
        q->disp_row = q->nsup;
        q->nsup++;
    }
    q->ncon = q->nloop + q->nsup;
    q->n = q->nq + q->ncon;
    /* reference scales: mean fold stiffness D L / w and mean width */
    q->kref = 0.0;
    q->lref = 0.0;
    for (int i = 0; i < m->nfolds; i++) {
        q->kref += q->e.stiff[i] / m->nfolds;
        q->lref += s->folds[i].width / m->nfolds;
    }
    if (!(q->kref > 0)) q->kref = 1.0;
    if (!(q->lref > 0)) q->lref = 1.0;
    size_t nq = (size_t)q->nq, n = (size_t)q->n;
    q->grad = calloc(nq + 1, sizeof(double));
    q->gp = calloc(nq + 1, sizeof(double));
    q->H = calloc(nq * nq + 1, sizeof(double));
    q->g = calloc((size_t)m->ncon + 1, sizeof(double));
    q->J = calloc((size_t)m->ncon * nq + 1, sizeof(double));
    q->dx = calloc(3 * nq + 1, sizeof(double));
    q->yscale = calloc(n + 1, sizeof(double));
    q->fscale = calloc(n + 1, sizeof(double));
    if (!q->grad || !q->gp || !q->H || !q->g || !q->J || !q->dx || !q->yscale || !q->fscale) {
        sf_equil_free(q);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    sf_equil_scales(q);
    return SF_OK;
}

/* Newton scaling: angles O(1); multipliers of rotation rows ~ kref [J], of
 * translation rows and supports ~ kref / lref [N]; gradient rows ~ kref;
 * rotation rows O(1), translation rows ~ lref [m]. */
static void sf_equil_scales(sf_equil *q)
{
    for (int j = 0; j < q->nq; j++) {
        q->yscale[j] = 1.0;
        q->fscale[j] = 1.0 / q->kref;
    }
    for (int r = 0; r < q->ncon; r++) {
        int rot = r < q->nloop && r % 6 < 3;
        q->yscale[q->nq + r] = rot ? 1.0 / q->kref : q->lref / q->kref;
        q->fscale[q->nq + r] = rot ? 1.0 : 1.0 / q->lref;
    }
}

void sf_equil_use_penalty(sf_equil *q, double lR, double ld)
{
    q->exact = 0;
    q->nloop = 0;
    q->ncon = q->nsup;
    q->n = q->nq + q->ncon;
    q->e.penalty = 1;
    q->e.lR = lR;
    q->e.ld = ld;
    sf_equil_scales(q);
}

void sf_equil_free(sf_equil *q)
{
    sf_peq_free(q);
    free(q->lam_anchor);
    free(q->anchor_w);
    sf_energy_free(&q->e);
    sf_params_free(&q->par);
    sf_kin_free(&q->k);
    free(q->rowpt);
    free(q->rowc);
    free(q->rowval);
    free(q->grad);
    free(q->gp);
    free(q->H);
    free(q->g);
    free(q->J);
    free(q->dx);
    free(q->yscale);
    free(q->fscale);
    if (q->Jd) SUNMatDestroy(q->Jd);
    free(q->pattern);
    memset(q, 0, sizeof *q);
}

int sf_equil_parse_param(const sf_study *s, int *param, int *group, int *probe,
                         int *component, sf_error *err)
{
    const char *par, *grp, *prb, *comp;
    if (sf_study_string(s, "analysis.parameter", "load", &par, err) ||
        sf_study_string(s, "analysis.group", "", &grp, err) ||
        sf_study_string(s, "analysis.probe", "", &prb, err) ||
        sf_study_string(s, "analysis.component", "z", &comp, err))
        return err->code;
    *param = strcmp(par, "actuation") == 0 ? SF_PARAM_ACTUATION
           : strcmp(par, "displacement") == 0 ? SF_PARAM_DISPLACEMENT : SF_PARAM_LOAD;
    *group = grp[0] ? sf_study_group_index(s, grp) : -1;
    *probe = prb[0] ? sf_study_probe_index(s, prb) : 0;
    *component = strcmp(comp, "x") == 0 ? 0 : strcmp(comp, "y") == 0 ? 1 : 2;
    if (*param == SF_PARAM_DISPLACEMENT && (*probe < 0 || s->nprobes == 0))
        return sf_study_fail(s, err, SF_EINPUT, "analysis.parameter",
                             "the displacement parameter needs a probe");
    return SF_OK;
}

void sf_equil_set_param(sf_equil *q, double p)
{
    const sf_study *s = q->m->study;
    int ns = q->e.nstages;
    double lp = q->param == SF_PARAM_LOAD ? p : q->load;
    /* stage k ramps over [k, k+1]; the first stage extends linearly below
     * 0 and the last above ns, so the load never saturates where the
     * continuation may step past the end of the range */
    for (int k = 0; k < ns; k++) {
        double x = lp - k;
        double lo = k == 0 ? -INFINITY : 0.0, hi = k == ns - 1 ? INFINITY : 1.0;
        if (q->ramp_stage >= 0 && k != q->ramp_stage) {
            /* one stage at a time: the others hold their value */
            q->par.stage[k] = k < q->ramp_stage ? 1.0 : 0.0;
            q->par.dstage[k] = 0.0;
            continue;
        }
        if (q->ramp_stage >= 0) {
            lo = -INFINITY;
            hi = INFINITY;
        }
        q->par.stage[k] = x <= lo ? lo : x >= hi ? hi : x;
        /* right derivative at the stage boundaries */
        int ramping = x >= lo && (x < hi || k == ns - 1);
        q->par.dstage[k] = (q->param == SF_PARAM_LOAD && ramping) ? 1.0 : 0.0;
    }
    for (int i = 0; i < q->m->nfolds; i++) {
        const sf_fold_def *f = &s->folds[i];
        double rest = f->rest_angle, drest = 0.0;
        if (f->group >= 0) {
            double r0 = s->groups[f->group].rest_angle;
            if (q->param == SF_PARAM_ACTUATION && (q->group < 0 || f->group == q->group)) {
                rest = p * r0;
                drest = r0;
            } else {
                rest = s->groups[f->group].rest_angle;
            }
        }
        q->par.rest[i] = rest;
        q->par.drest[i] = drest;
    }
    if (q->param_hook) q->param_hook(q, p, q->param_hook_data);
}

static int finite_all(const double *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

/* Value of support/displacement row r at the current kinematic state, and
 * its gradient in dx (row c of the point's dx). */
static double row_value(sf_equil *q, int r, double p, int want_grad)
{
    double x[3];
    sf_point_eval(q->m, &q->k, &q->rowpt[r], x, want_grad ? q->dx : NULL);
    int c = q->rowc[r];
    double X = c < 2 ? q->rowpt[r].X[c] : 0.0;
    double target = r == q->disp_row ? p : q->rowval[r];
    return x[c] - X - target;
}

int sf_equil_residual(const double *y, double p, double *F, void *user)
{
    sf_equil *q = user;
    if (q->pz) return sf_peq_residual(q, y, p, F);
    const sf_model *m = q->m;
    int nq = q->nq;
    if (!finite_all(y, q->n) || !isfinite(p)) return 1;
    q->nres++;
    sf_equil_set_param(q, p);
    sf_kin_eval(m, y, 1, &q->k);
    memset(q->grad, 0, sizeof(double) * nq);
    sf_energy_eval(&q->e, &q->k, &q->par, q->grad, NULL, 0, NULL);
    memcpy(F, q->grad, sizeof(double) * nq);
    const double *lam = y + nq;
    if (q->nloop) {
        sf_constraints(m, &q->k, q->g, q->J, NULL, NULL, 0);
        for (int r = 0; r < q->nloop; r++) {
            F[nq + r] = q->g[r];
            const double *Jr = q->J + (size_t)r * nq;
            for (int j = 0; j < nq; j++) F[j] += lam[r] * Jr[j];
        }
    }
    for (int r = 0; r < q->nsup; r++) {
        int row = q->nloop + r;
        F[nq + row] = row_value(q, r, p, 1);
        const double *d = q->dx + q->rowc[r] * nq;
        for (int j = 0; j < nq; j++) F[j] += lam[row] * d[j];
    }
    sf_equil_anchor_rows(q, y, F);
    return finite_all(F, q->n) ? 0 : 1;
}

int sf_equil_jacobian(const double *y, double p, SUNMatrix Jy, double *Fp, void *user)
{
    sf_equil *q = user;
    if (q->pz) return sf_peq_jacobian(q, y, p, Jy, Fp);
    const sf_model *m = q->m;
    int nq = q->nq, n = q->n;
    if (!finite_all(y, n) || !isfinite(p)) return 1;
    q->njac++;
    sf_equil_set_param(q, p);
    sf_kin_eval(m, y, 2, &q->k);
    memset(q->grad, 0, sizeof(double) * nq);
    memset(q->gp, 0, sizeof(double) * nq);
    memset(q->H, 0, sizeof(double) * nq * nq);
    sf_energy_eval(&q->e, &q->k, &q->par, q->grad, q->H, nq, q->gp);
    const double *lam = y + nq;
    if (q->nloop) sf_constraints(m, &q->k, q->g, q->J, lam, q->H, nq);
    for (int r = 0; r < q->nsup; r++) {
        double f[3] = {0, 0, 0};
        f[q->rowc[r]] = lam[q->nloop + r];
        sf_point_hess_add(m, &q->k, &q->rowpt[r], f, q->H, nq);
    }
    /* dense matrix, column-major */
    sunrealtype *A = SUNDenseMatrix_Data(Jy);
    long ld = SUNDenseMatrix_LData(Jy) / SUNDenseMatrix_Columns(Jy);
    for (int j = 0; j < nq; j++)
        for (int i = 0; i < nq; i++) A[(size_t)j * ld + i] = q->H[(size_t)i * nq + j];
    for (int r = 0; r < q->nloop; r++)
        for (int j = 0; j < nq; j++) {
            double v = q->J[(size_t)r * nq + j];
            A[(size_t)(nq + r) * ld + j] = v; /* J^T block */
            A[(size_t)j * ld + nq + r] = v;   /* J block */
        }
    for (int r = 0; r < q->nsup; r++) {
        int row = q->nloop + r;
        row_value(q, r, p, 1);
        const double *d = q->dx + q->rowc[r] * nq;
        for (int j = 0; j < nq; j++) {
            A[(size_t)(nq + row) * ld + j] = d[j];
            A[(size_t)j * ld + nq + row] = d[j];
        }
    }
    double eps = sf_equil_reg_eps(q, y);
    for (int r = 0; r < q->ncon; r++) {
        /* regularisation of the multiplier block: -eps in the solver's
         * scaled system (fscale A / yscale), so -eps yscale / fscale here */
        A[(size_t)(nq + r) * ld + nq + r] = -sf_equil_row_eps(q, eps, r) * q->yscale[nq + r] / q->fscale[nq + r];
    }
    memset(Fp, 0, sizeof(double) * n);
    memcpy(Fp, q->gp, sizeof(double) * nq);
    if (q->disp_row >= 0) Fp[nq + q->nloop + q->disp_row] = -1.0;
    if (!finite_all(Fp, n)) return 1;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            if (!isfinite(A[(size_t)j * ld + i])) return 1;
    return 0;
}

int sf_equil_kkt(sf_equil *q, const double *y, double p, double *HL, double *C)
{
    if (q->pz) return sf_peq_kkt(q, y, p, HL, C);
    const sf_model *m = q->m;
    int nq = q->nq;
    if (!finite_all(y, q->n) || !isfinite(p)) return 1;
    sf_equil_set_param(q, p);
    sf_kin_eval(m, y, 2, &q->k);
    memset(HL, 0, sizeof(double) * nq * nq);
    sf_energy_eval(&q->e, &q->k, &q->par, NULL, HL, nq, NULL);
    const double *lam = y + nq;
    if (q->nloop) {
        sf_constraints(m, &q->k, q->g, q->J, lam, HL, nq);
        memcpy(C, q->J, sizeof(double) * q->nloop * nq);
    }
    for (int r = 0; r < q->nsup; r++) {
        double f[3] = {0, 0, 0};
        f[q->rowc[r]] = lam[q->nloop + r];
        sf_point_hess_add(m, &q->k, &q->rowpt[r], f, HL, nq);
        row_value(q, r, p, 1);
        memcpy(C + (size_t)(q->nloop + r) * nq, q->dx + q->rowc[r] * nq, sizeof(double) * nq);
    }
    /* the Hessian of a sum of smooth terms is symmetric; remove rounding */
    for (int i = 0; i < nq; i++)
        for (int j = 0; j < i; j++) {
            double v = 0.5 * (HL[(size_t)i * nq + j] + HL[(size_t)j * nq + i]);
            HL[(size_t)i * nq + j] = HL[(size_t)j * nq + i] = v;
        }
    return finite_all(HL, nq * nq) && finite_all(C, q->ncon * nq) ? 0 : 1;
}

void sf_equil_report(sf_equil *q, const double *y, double p, double *Pi,
                     double *res_rot, double *res_tra)
{
    if (q->pz) {
        sf_peq_report(q, y, p, Pi, res_rot, res_tra);
        return;
    }
    const sf_model *m = q->m;
    sf_equil_set_param(q, p);
    sf_kin_eval(m, y, 0, &q->k);
    *Pi = sf_energy_eval(&q->e, &q->k, &q->par, NULL, NULL, 0, NULL);
    sf_constraints(m, &q->k, q->g, NULL, NULL, NULL, 0);
    double rr = 0, rt = 0;
    for (int r = 0; r < m->ncon; r++) {
        if (r % 6 < 3) rr = fmax(rr, fabs(q->g[r]));
        else rt = fmax(rt, fabs(q->g[r]));
    }
    *res_rot = rr;
    *res_tra = rt;
}

int sf_equil_create_solver(sf_equil *q, cont_solver **out)
{
    if (q->pz) return sf_peq_create_solver(q, out);
    cont_problem prob;
    memset(&prob, 0, sizeof prob);
    prob.n = q->n;
    prob.residual = sf_equil_residual;
    prob.jacobian = sf_equil_jacobian;
    prob.jac_matrix = CONT_MATRIX_DENSE;
    prob.yscale = q->yscale;
    prob.fscale = q->fscale;
    prob.anchor = sf_equil_anchor;
    prob.user = q;
    if (q->sparse) {
        prob.jacobian = sf_equil_jacobian_sparse;
        prob.jac_matrix = CONT_MATRIX_SPARSE;
        prob.jac_nnz = (long)q->n * q->n;
    }
    *out = NULL;
    int rc = cont_create(&prob, q->sparse ? sf_equil_sparse_linsol(q) : CONT_LINSOL_DENSE, out);
    if (rc == CONT_OK && q->ncon > 0) {
        double *w = calloc((size_t)q->n, sizeof(double));
        if (!w) return CONT_ENOMEM;
        for (int j = 0; j < q->nq; j++) w[j] = 1.0;
        rc = cont_set_weights(*out, w);
        free(w);
    }
    return rc;
}

void sf_equil_use_sparse(sf_equil *q, int sparse)
{
    q->sparse = sparse != 0;
    q->linsol = sparse == CONT_LINSOL_KLU ? CONT_LINSOL_KLU : CONT_LINSOL_MUMPS;
}

int sf_equil_sparse_linsol(const sf_equil *q)
{
    return q->linsol == CONT_LINSOL_KLU ? CONT_LINSOL_KLU : CONT_LINSOL_MUMPS;
}

int sf_equil_jacobian_sparse(const double *y, double p, SUNMatrix Jy, double *Fp, void *user)
{
    sf_equil *q = user;
    if (q->pz) return sf_peq_jacobian(q, y, p, Jy, Fp);
    long n = q->n;
    if (q->Jd && SUNDenseMatrix_Columns(q->Jd) != n) {
        SUNMatDestroy(q->Jd);
        q->Jd = NULL;
        free(q->pattern);
        q->pattern = NULL;
    }
    if (!q->Jd) {
        q->Jd = SUNDenseMatrix(n, n, Jy->sunctx);
        q->pattern = calloc((size_t)(n * n) + 1, 1);
        if (!q->Jd || !q->pattern) return 1;
    }
    SUNMatZero(q->Jd);
    int rc = sf_equil_jacobian(y, p, q->Jd, Fp, q);
    if (rc) return rc;
    const sunrealtype *A = SUNDenseMatrix_Data(q->Jd);
    if (SUNSparseMatrix_NNZ(Jy) < n * n && SUNSparseMatrix_Reallocate(Jy, n * n) != 0) return 1;
    sunrealtype *v = SUNSparseMatrix_Data(Jy);
    sunindextype *ri = SUNSparseMatrix_IndexValues(Jy), *cp = SUNSparseMatrix_IndexPointers(Jy);
    long nz = 0;
    for (long j = 0; j < n; j++) {
        cp[j] = nz;
        for (long i = 0; i < n; i++) {
            double a = A[j * n + i];
            if (a != 0.0 || i == j) q->pattern[j * n + i] = 1;
            if (!q->pattern[j * n + i]) continue;
            ri[nz] = i;
            v[nz++] = a;
        }
    }
    cp[n] = nz;
    return 0;
}

int sf_equil_start_off_flat(sf_equil *q, double p1, double tol, double *y, sf_error *err)
{
    const sf_model *m = q->m;
    if (q->disp_row >= 0)
        return sf_fail(err, SF_EINPUT, "%s: a displacement parameter with exact loop constraints "
                       "cannot start at the flat state; start from p != 0", m->study->path);
    sf_equil pen;
    if (sf_equil_init(&pen, m, q->param, q->group, 0, 0, q->load, err)) return err->code;
    double *yp = calloc((size_t)pen.n + 1, sizeof(double));
    double *ytry = calloc((size_t)pen.n + 1, sizeof(double));
    cont_solver *ps = NULL;
    int levels = 0;
    int rc = (yp && ytry) ? SF_OK : sf_fail(err, SF_ENOMEM, "out of memory");
    double lR = 0, ld = 0;
    for (double k = 1e2; !rc && k <= 1e8 * 1.0001; k *= 100.0) {
        lR = k * q->kref;
        ld = k * q->kref / (q->lref * q->lref);
        sf_equil_use_penalty(&pen, lR, ld);
        if (ps) cont_free(ps);
        ps = NULL;
        if (sf_equil_create_solver(&pen, &ps) != CONT_OK) {
            rc = sf_fail(err, SF_ENOMEM, "continuation: cannot create the start solver");
            break;
        }
        cont_set_newton(ps, tol, 50, 1);
        cont_set_newton_init(ps, 200, 1);
        memcpy(ytry, yp, sizeof(double) * pen.n);
        if (cont_solve_fixed(ps, ytry, p1) != CONT_OK) {
            /* a stiffer penalty did not converge: keep the last solution */
            if (levels > 0) {
                lR /= 100.0;
                ld /= 100.0;
                break;
            }
            rc = sf_fail(err, SF_ENUMERIC, "%s: cannot start the path off the flat state: the "
                         "penalty problem at p = %g with lambda_R = %g J does not converge (%s)",
                         m->study->path, p1, lR, cont_errmsg(ps));
        } else {
            memcpy(yp, ytry, sizeof(double) * pen.n);
            levels++;
        }
    }
    if (!rc) {
        memcpy(y, yp, sizeof(double) * q->nq);
        sf_kin_eval(m, yp, 0, &q->k);
        sf_constraints(m, &q->k, q->g, NULL, NULL, NULL, 0);
        for (int c = 0; c < q->nloop; c++) y[q->nq + c] = (c % 6 < 3 ? lR : ld) * q->g[c];
        for (int c = 0; c < q->nsup; c++) y[q->nq + q->nloop + c] = yp[pen.nq + c];
    }
    if (ps) cont_free(ps);
    free(yp);
    free(ytry);
    sf_equil_free(&pen);
    return rc;
}
