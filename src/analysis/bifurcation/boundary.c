/* boundary.c - two-parameter continuation of limit and branch points: the
 * family of problems over a second study key, and the minimally extended
 * systems of Govaerts (2000) for the continuation engine (boundary.h). */
#include "boundary.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sunmatrix/sunmatrix_dense.h>

#include "cont.h"
#include "study.h"

extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, double *a,
                    const int *lda, double *s, double *u, const int *ldu, double *vt,
                    const int *ldvt, double *work, const int *lwork, int *info);
extern void dgetrf_(const int *m, const int *n, double *a, const int *lda, int *ipiv, int *info);
extern void dgetrs_(const char *trans, const int *n, const int *nrhs, const double *a,
                    const int *lda, const int *ipiv, double *b, const int *ldb, int *info);

/* relative steps of the central differences (boundary.h, "Derivatives") */
#define BND_HDIR 1e-5
#define BND_HQ 1e-6

/* ---------------------------------------------------------------------- */
/* The family over the second parameter                                    */
/* ---------------------------------------------------------------------- */

static void entry_free(sf_family_entry *e)
{
    if (e->stamp) sf_equil_free(&e->eq);
    sf_scene_close(&e->sc);
    memset(e, 0, sizeof *e);
}

/* "key=value" for q: a number, or the whole vector with one component q.
 * %.17e keeps every digit and makes a float that libconfig reads as one. */
static void set_text(sf_family *f, double q)
{
    if (f->comp < 0) {
        snprintf(f->setbuf, sizeof f->setbuf, "%s=%.17e", f->key, q);
        return;
    }
    int n = snprintf(f->setbuf, sizeof f->setbuf, "%s=[", f->key);
    for (int i = 0; i < f->nvec && n > 0 && (size_t)n < sizeof f->setbuf; i++)
        n += snprintf(f->setbuf + n, sizeof f->setbuf - (size_t)n, "%s%.17e", i ? ", " : "",
                      i == f->comp ? q : f->vec[i]);
    if (n > 0 && (size_t)n < sizeof f->setbuf - 1) snprintf(f->setbuf + n, sizeof f->setbuf - (size_t)n, "]");
}

int sf_family_get(sf_family *f, double q, sf_equil **eq, sf_error *err)
{
    if (!isfinite(q)) return sf_fail(err, SF_ENUMERIC, "%s: not a finite value", f->shown);
    int lru = 0;
    for (int i = 0; i < SF_FAMILY_CACHE; i++) {
        sf_family_entry *e = &f->ent[i];
        if (e->stamp && e->q == q) {
            e->stamp = ++f->clock;
            *eq = &e->eq;
            return SF_OK;
        }
        if (e->stamp < f->ent[lru].stamp) lru = i;
    }
    sf_family_entry *e = &f->ent[lru];
    entry_free(e);
    set_text(f, q);
    f->sets[f->nset] = f->setbuf;
    if (sf_scene_open(&e->sc, f->path, f->nset + 1, f->sets, err)) {
        sf_scene_close(&e->sc);
        return err->code;
    }
    const sf_study *s = &e->sc.study;
    double load = 0.0;
    if (sf_study_double(s, "analysis.load", 0.0, &load, err) ||
        sf_equil_init(&e->eq, &e->sc.model, f->param, f->group, f->probe, f->component, load, err)) {
        sf_scene_close(&e->sc);
        return err->code;
    }
    e->stamp = ++f->clock;
    e->q = q;
    if (s->constraints == SF_CONSTRAINTS_PENALTY)
        sf_equil_use_penalty(&e->eq, s->penalty_rotation, s->penalty_translation);
    f->builds++;
    if (f->n && e->eq.n != f->n) {
        entry_free(e);
        return sf_fail(err, SF_EINPUT, "%s = %g changes the number of unknowns of the sheet; "
                       "the second parameter must leave the model's layout alone", f->shown, q);
    }
    *eq = &e->eq;
    return SF_OK;
}

/* Split "key[k]" into key and k when key is a vector key of the study. */
static int parse_second(sf_family *f, const sf_study *s, const char *second, sf_error *err)
{
    sf_error e;
    sf_error_clear(&e);
    snprintf(f->shown, sizeof f->shown, "%s", second);
    snprintf(f->key, sizeof f->key, "%s", second);
    f->comp = -1;
    size_t L = strlen(second);
    const char *lb = strrchr(second, '[');
    if (L > 3 && second[L - 1] == ']' && lb && lb[1] >= '0' && lb[1] <= '2' && lb + 3 == second + L) {
        char pre[256];
        snprintf(pre, sizeof pre, "%.*s", (int)(lb - second), second);
        if (sf_study_has(s, pre) && sf_study_doubles(s, pre, 2, 3, f->vec, &f->nvec, &e) == SF_OK &&
            f->nvec > lb[1] - '0') {
            snprintf(f->key, sizeof f->key, "%s", pre);
            f->comp = lb[1] - '0';
            f->q0 = f->vec[f->comp];
            return SF_OK;
        }
        sf_error_clear(&e);
    }
    if (sf_study_double(s, second, NAN, &f->q0, &e) != SF_OK || !isfinite(f->q0))
        return sf_study_fail(s, err, SF_EINPUT, "analysis.second",
                             "\"%s\" is not a numeric key of this study%s%s (give a number key such "
                             "as defaults.width, materials.fold.E, analysis.load, or a vector "
                             "component such as loads[0].force[0])", second,
                             e.code == SF_EINPUT ? ": " : "", e.code == SF_EINPUT ? e.msg : "");
    return SF_OK;
}

int sf_family_init(sf_family *f, const char *path, int nset, const char **sets,
                   const char *second, sf_error *err)
{
    memset(f, 0, sizeof *f);
    f->path = path;
    f->sets = calloc((size_t)nset + 2, sizeof *f->sets);
    if (!f->sets) return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int i = 0; i < nset; i++) f->sets[i] = sets[i];
    f->nset = nset;
    sf_scene sc;
    if (sf_scene_open(&sc, path, nset, sets, err)) {
        sf_scene_close(&sc);
        return err->code;
    }
    int rc = parse_second(f, &sc.study, second, err);
    if (!rc) rc = sf_equil_parse_param(&sc.study, &f->param, &f->group, &f->probe, &f->component, err);
    sf_scene_close(&sc);
    if (rc) return rc;
    f->qs = f->q0 != 0.0 ? fabs(f->q0) : 1.0;
    sf_equil *eq;
    if (sf_family_get(f, f->q0, &eq, err)) return err->code;
    f->n = eq->n;
    f->nq = eq->nq;
    f->ys = malloc(sizeof(double) * (size_t)(2 * f->n));
    if (!f->ys) return sf_fail(err, SF_ENOMEM, "out of memory");
    f->fs = f->ys + f->n;
    memcpy(f->ys, eq->yscale, sizeof(double) * (size_t)f->n);
    memcpy(f->fs, eq->fscale, sizeof(double) * (size_t)f->n);
    return SF_OK;
}

void sf_family_free(sf_family *f)
{
    for (int i = 0; i < SF_FAMILY_CACHE; i++) entry_free(&f->ent[i]);
    free(f->sets);
    free(f->ys);
    memset(f, 0, sizeof *f);
}

/* ---------------------------------------------------------------------- */
/* The extended system                                                     */
/* ---------------------------------------------------------------------- */

double sf_bnd_q(const sf_bnd *B, double s) { return B->fam->q0 + B->fam->qs * s; }

static sf_equil *at(sf_bnd *B, double s)
{
    sf_equil *eq = NULL;
    sf_error_clear(&B->err);
    if (sf_family_get(B->fam, sf_bnd_q(B, s), &eq, &B->err)) return NULL;
    return eq;
}

/* Scaled augmented Jacobian As = [diag(fs) Jy diag(1/ys), diag(fs) Fp]
 * (n x (n+1), column-major) of eq at (y, p). */
static int eval_A(sf_bnd *B, sf_equil *eq, const double *y, double p, double *A)
{
    int n = B->n;
    SUNMatZero(B->J);
    memset(B->Fp, 0, sizeof(double) * (size_t)n);
    if (sf_equil_jacobian(y, p, B->J, B->Fp, eq)) return 1;
    const double *J = SUNDenseMatrix_Data(B->J);
    const double *fs = B->fam->fs, *ys = B->fam->ys;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) A[i + (size_t)j * n] = fs[i] * J[i + (size_t)j * n] / ys[j];
    for (int i = 0; i < n; i++) A[i + (size_t)n * n] = fs[i] * B->Fp[i];
    for (size_t i = 0; i < (size_t)n * (n + 1); i++)
        if (!isfinite(A[i])) return 1;
    return 0;
}

/* The bordered matrix M = [A_m b; C^T 0] ((m+1) x (m+1)) factorised, its
 * solutions X = M^-1 [0; I_k] and u = M^-T e_m.  The test functions are
 * g_r = X[m + r (m+1)]. */
static int bordered(sf_bnd *B, const double *A)
{
    int n = B->n, m = B->m, k = B->k, ld = m + 1, info, one = 1;
    memset(B->M, 0, sizeof(double) * (size_t)ld * ld);
    for (int j = 0; j < m; j++)
        for (int i = 0; i < n; i++) B->M[i + (size_t)j * ld] = A[i + (size_t)j * n];
    for (int i = 0; i < n; i++) B->M[i + (size_t)m * ld] = B->b[i];
    for (int r = 0; r < k; r++)
        for (int j = 0; j < m; j++) B->M[n + r + (size_t)j * ld] = B->C[j + (size_t)r * m];
    dgetrf_(&ld, &ld, B->M, &ld, B->piv, &info);
    if (info != 0) return 1;
    memset(B->X, 0, sizeof(double) * (size_t)ld * k);
    for (int r = 0; r < k; r++) B->X[n + r + (size_t)r * ld] = 1.0;
    dgetrs_("N", &ld, &k, B->M, &ld, B->piv, B->X, &ld, &info);
    if (info != 0) return 1;
    memset(B->u, 0, sizeof(double) * (size_t)ld);
    B->u[m] = 1.0;
    dgetrs_("T", &ld, &one, B->M, &ld, B->piv, B->u, &ld, &info);
    return info != 0;
}

/* Direction r of the bordered solution, padded to the n+1 unknowns (y, p)
 * (scaled): V_r for a BP, (v, 0) for an LP. */
static void direction(sf_bnd *B, int r, double *Vt)
{
    int n = B->n, ld = B->m + 1;
    memset(Vt, 0, sizeof(double) * (size_t)(n + 1));
    for (int j = 0; j < B->m; j++) Vt[j] = B->X[j + (size_t)r * ld];
}

/* dA = derivative of As along the scaled direction Vt (central difference
 * of the analytic Jacobian, boundary.h). */
static int dir_deriv(sf_bnd *B, sf_equil *eq, const double *y, double p, const double *Vt, double *dA)
{
    int n = B->n;
    double nv = 0.0;
    for (int j = 0; j <= n; j++) nv += Vt[j] * Vt[j];
    nv = sqrt(nv);
    if (!(nv > 0)) return 1;
    double h = BND_HDIR / nv;
    double *yy = B->F1;
    for (int sg = 0; sg < 2; sg++) {
        double sgn = sg ? -1.0 : 1.0;
        for (int i = 0; i < n; i++) yy[i] = y[i] + sgn * h * Vt[i] / B->fam->ys[i];
        if (eval_A(B, eq, yy, p + sgn * h * Vt[n], sg ? B->Am : B->Ap)) return 1;
        B->njac_diff++;
    }
    for (size_t i = 0; i < (size_t)n * (n + 1); i++) dA[i] = (B->Ap[i] - B->Am[i]) / (2.0 * h);
    return 0;
}

int sf_bnd_residual(const double *Y, double s, double *G, void *user)
{
    sf_bnd *B = user;
    int n = B->n;
    double p = Y[n];
    sf_equil *eq = at(B, s);
    if (!eq || sf_equil_residual(Y, p, G, eq)) return 1;
    if (B->kind == SF_BND_BP)
        for (int i = 0; i < n; i++) G[i] += Y[n + 1] * B->b[i] / B->fam->fs[i];
    if (eval_A(B, eq, Y, p, B->A) || bordered(B, B->A)) return 1;
    for (int r = 0; r < B->k; r++) G[n + r] = B->X[B->m + (size_t)r * (B->m + 1)];
    for (int i = 0; i < B->N; i++)
        if (!isfinite(G[i])) return 1;
    return 0;
}

int sf_bnd_jacobian(const double *Y, double s, SUNMatrix JY, double *Gs, void *user)
{
    sf_bnd *B = user;
    int n = B->n, N = B->N;
    double p = Y[n];
    const double *ys = B->fam->ys, *fs = B->fam->fs;
    sf_equil *eq = at(B, s);
    if (!eq) return 1;
    double *JYd = SUNDenseMatrix_Data(JY);
    long ldJ = SUNDenseMatrix_LData(JY) / N;
    /* F rows: the analytic Jacobian, Fp, and the unfolding column */
    SUNMatZero(B->J);
    memset(B->Fp, 0, sizeof(double) * (size_t)n);
    if (sf_equil_jacobian(Y, p, B->J, B->Fp, eq)) return 1;
    const double *J = SUNDenseMatrix_Data(B->J);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) JYd[i + (size_t)j * ldJ] = J[i + (size_t)j * n];
    for (int i = 0; i < n; i++) JYd[i + (size_t)n * ldJ] = B->Fp[i];
    if (B->kind == SF_BND_BP)
        for (int i = 0; i < n; i++) JYd[i + (size_t)(n + 1) * ldJ] = B->b[i] / fs[i];
    /* g rows: -w^T (dAs . V_r) over (y, p) */
    if (eval_A(B, eq, Y, p, B->A) || bordered(B, B->A)) return 1;
    for (int r = 0; r < B->k; r++) {
        direction(B, r, B->V + (size_t)r * (n + 1));
        if (dir_deriv(B, eq, Y, p, B->V + (size_t)r * (n + 1), B->dA)) return 1;
        for (int j = 0; j <= n; j++) {
            double d = 0.0;
            for (int i = 0; i < n; i++) d -= B->u[i] * B->dA[i + (size_t)j * n];
            JYd[n + r + (size_t)j * ldJ] = j < n ? d * ys[j] : d;
        }
    }
    /* d/ds: differences between the problems at q +- hq */
    double hs = BND_HQ;
    sf_equil *ep = at(B, s + hs);
    if (!ep || sf_equil_residual(Y, p, B->F1, ep) || eval_A(B, ep, Y, p, B->Ap)) return 1;
    sf_equil *em = at(B, s - hs);
    if (!em || sf_equil_residual(Y, p, B->F2, em) || eval_A(B, em, Y, p, B->Am)) return 1;
    B->njac_diff += 2;
    for (int i = 0; i < n; i++) Gs[i] = (B->F1[i] - B->F2[i]) / (2.0 * hs);
    for (int r = 0; r < B->k; r++) {
        const double *Vt = B->V + (size_t)r * (n + 1);
        double d = 0.0;
        for (int j = 0; j <= n; j++) {
            double wa = 0.0;
            for (int i = 0; i < n; i++) wa += B->u[i] * (B->Ap[i + (size_t)j * n] - B->Am[i + (size_t)j * n]);
            d -= wa * Vt[j];
        }
        Gs[n + r] = d / (2.0 * hs);
    }
    for (int i = 0; i < N; i++) {
        if (!isfinite(Gs[i])) return 1;
        for (int j = 0; j < N; j++)
            if (!isfinite(JYd[i + (size_t)j * ldJ])) return 1;
    }
    return 0;
}

/* Cusp test of an LP curve: a = w^T (dJs . v) v / (|w| |v|^2). */
int sf_bnd_test(const double *Y, double s, const double *tY, double ts, double *out, void *user)
{
    (void)tY;
    (void)ts;
    sf_bnd *B = user;
    int n = B->n;
    out[0] = 0.0;
    if (B->kind != SF_BND_LP) return 0;
    sf_equil *eq = at(B, s);
    if (!eq || eval_A(B, eq, Y, Y[n], B->A) || bordered(B, B->A)) return 1;
    direction(B, 0, B->V);
    if (dir_deriv(B, eq, Y, Y[n], B->V, B->dA)) return 1;
    double a = 0.0, nw = 0.0, nv = 0.0;
    for (int i = 0; i < n; i++) {
        double Av = 0.0;
        for (int j = 0; j < n; j++) Av += B->dA[i + (size_t)j * n] * B->V[j];
        a += B->u[i] * Av;
        nw += B->u[i] * B->u[i];
        nv += B->V[i] * B->V[i];
    }
    out[0] = a / (sqrt(nw) * nv);
    return isfinite(out[0]) ? 0 : 1;
}

/* Borders from the SVD of A at a point: the right singular vectors of the
 * k smallest singular values of the bordered block (n x m), the left one
 * of the smallest.  With old borders given, oriented (and for k = 2
 * rotated) to follow them. */
static int svd_borders(sf_bnd *B, const double *A, int keep)
{
    int n = B->n, m = B->m, k = B->k, info, lw = -1;
    double *a = malloc(sizeof(double) * (size_t)(n * m + n * n + m * m + n + m + 2));
    if (!a) return 1;
    double *U = a + (size_t)n * m, *VT = U + (size_t)n * n, *S = VT + (size_t)m * m, wq;
    memcpy(a, A, sizeof(double) * (size_t)n * m);
    dgesvd_("A", "A", &n, &m, a, &n, S, U, &n, VT, &m, &wq, &lw, &info);
    lw = (int)wq + 1;
    double *wk = malloc(sizeof(double) * (size_t)lw);
    if (!wk) { free(a); return 1; }
    dgesvd_("A", "A", &n, &m, a, &n, S, U, &n, VT, &m, wk, &lw, &info);
    free(wk);
    if (info != 0) { free(a); return 1; }
    /* new null basis Nb (m x k): rows m-k .. m-1 of VT */
    double Nb[2 * 512], *Nbp = m * k <= 1024 ? Nb : malloc(sizeof(double) * (size_t)m * k);
    if (!Nbp) { free(a); return 1; }
    for (int r = 0; r < k; r++)
        for (int j = 0; j < m; j++) Nbp[j + (size_t)r * m] = VT[(m - k + r) + (size_t)j * m];
    double bs = 0.0;
    for (int i = 0; i < n; i++) bs += U[i + (size_t)(n - 1) * n] * (keep ? B->b[i] : 1.0);
    for (int i = 0; i < n; i++) B->b[i] = (bs < 0 ? -1.0 : 1.0) * U[i + (size_t)(n - 1) * n];
    if (keep) {
        /* C <- Nb Nb^T C, then Gram-Schmidt; fall back to Nb if degenerate */
        for (int r = 0; r < k; r++) {
            double *c = B->C + (size_t)r * m, pr[2];
            for (int t = 0; t < k; t++) {
                pr[t] = 0.0;
                for (int j = 0; j < m; j++) pr[t] += Nbp[j + (size_t)t * m] * c[j];
            }
            for (int j = 0; j < m; j++) {
                c[j] = 0.0;
                for (int t = 0; t < k; t++) c[j] += Nbp[j + (size_t)t * m] * pr[t];
            }
            for (int t = 0; t < r; t++) {
                double d = 0.0, *ct = B->C + (size_t)t * m;
                for (int j = 0; j < m; j++) d += ct[j] * c[j];
                for (int j = 0; j < m; j++) c[j] -= d * ct[j];
            }
            double nc = 0.0;
            for (int j = 0; j < m; j++) nc += c[j] * c[j];
            nc = sqrt(nc);
            if (nc < 1e-3) { keep = 0; break; }
            for (int j = 0; j < m; j++) c[j] /= nc;
        }
    }
    if (!keep) memcpy(B->C, Nbp, sizeof(double) * (size_t)m * k);
    if (Nbp != Nb) free(Nbp);
    free(a);
    return 0;
}

int sf_bnd_update(sf_bnd *B, const double *Y, double s)
{
    sf_equil *eq = at(B, s);
    if (!eq || eval_A(B, eq, Y, Y[B->n], B->A)) return 1;
    return svd_borders(B, B->A, 1);
}

int sf_bnd_init(sf_bnd *B, sf_family *f, int kind, const double *y, double p, double q,
                sf_error *err)
{
    memset(B, 0, sizeof *B);
    int n = f->n;
    B->fam = f;
    B->kind = kind;
    B->n = n;
    B->m = kind == SF_BND_LP ? n : n + 1;
    B->k = kind == SF_BND_LP ? 1 : 2;
    B->N = n + B->k;
    size_t na = (size_t)n * (n + 1), ld = (size_t)B->m + 1;
    B->b = calloc((size_t)n + 1, sizeof(double));
    B->C = calloc((size_t)B->m * B->k + 1, sizeof(double));
    B->A = calloc(4 * na + ld * ld + ld * 2 + ld + 4 * (size_t)(n + 1) + 3 * (size_t)n, sizeof(double));
    B->piv = calloc(ld, sizeof(int));
    if (!B->b || !B->C || !B->A || !B->piv) return sf_fail(err, SF_ENOMEM, "out of memory");
    B->Ap = B->A + na;
    B->Am = B->Ap + na;
    B->dA = B->Am + na;
    B->M = B->dA + na;
    B->X = B->M + ld * ld;
    B->u = B->X + ld * 2;
    B->V = B->u + ld;
    B->F1 = B->V + 4 * (size_t)(n + 1);
    B->F2 = B->F1 + n;
    B->Fp = B->F2 + n;
    if (SUNContext_Create(NULL, &B->ctx) || !B->ctx) return sf_fail(err, SF_ENOMEM, "no SUNDIALS context");
    B->J = SUNDenseMatrix(n, n, B->ctx);
    if (!B->J) return sf_fail(err, SF_ENOMEM, "out of memory");
    double s = (q - f->q0) / f->qs;
    sf_equil *eq = at(B, s);
    if (!eq) return sf_fail(err, B->err.code, "%s", B->err.msg);
    if (eval_A(B, eq, y, p, B->A) || svd_borders(B, B->A, 0))
        return sf_fail(err, SF_ENUMERIC, "boundary: no singular vectors at the start point "
                       "(non-finite Jacobian, or LAPACK dgesvd failed)");
    return SF_OK;
}

void sf_bnd_free(sf_bnd *B)
{
    if (B->J) SUNMatDestroy(B->J);
    if (B->ctx) SUNContext_Free(&B->ctx);
    free(B->b);
    free(B->C);
    free(B->A);
    free(B->piv);
    memset(B, 0, sizeof *B);
}

static const char *const bnd_labels[] = {"CP"};

void sf_bnd_problem(sf_bnd *B, double *yscale, double *fscale, cont_problem *prob)
{
    int n = B->n;
    for (int i = 0; i < B->N; i++) {
        yscale[i] = i < n ? B->fam->ys[i] : 1.0;
        fscale[i] = i < n ? B->fam->fs[i] : 1.0;
    }
    memset(prob, 0, sizeof *prob);
    prob->n = B->N;
    prob->residual = sf_bnd_residual;
    prob->jacobian = sf_bnd_jacobian;
    prob->jac_matrix = CONT_MATRIX_DENSE;
    prob->ntest = B->kind == SF_BND_LP ? 1 : 0;
    prob->test = sf_bnd_test;
    prob->test_labels = bnd_labels;
    prob->yscale = yscale;
    prob->fscale = fscale;
    prob->pscale = 1.0;
    prob->user = B;
}
