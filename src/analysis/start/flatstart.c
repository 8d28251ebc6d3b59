/* flatstart.c - the first point of an exact path off the flat state, from
 * the limit of the branch as the parameter goes to its start value.
 *
 * Why the flat state is hard.  At q = 0 the rotation about the normal and
 * the in-plane translations of every vertex loop (in general: every
 * combination of constraint rows in the left null space of J(0), e.g. also
 * in-plane point supports) have zero gradient; they are of second order in
 * q.  Near the flat state the branch behaves like an inextensible string
 * under a small transverse load: the coordinates grow like the parameter,
 * q = dp u + O(dp^2), but the multipliers of the second-order rows tend to
 * finite, non-zero values nu (a prestress of the flat sheet selected by
 * the load; waterbomb2: about -47 N and -41 N on the in-plane translation
 * rows of its two vertices under gravity), not to zero.  A start guess
 * with those multipliers near zero, or with the penalty forces k g of a
 * penalty solution (g being of second order, k g estimates them poorly,
 * and a stiff penalty can land on an unstable penalty equilibrium where a
 * vertex stays flat and its rows are degenerate), lies outside the region
 * where Newton converges: that is why exact closure did not start for
 * waterbomb2 and square4-corner.
 *
 * The limit problem.  Write y = (dp u, dp mu, nu) with mu the multipliers
 * of the first-order row combinations and nu those of the second-order
 * ones, and expand F(y; p0 + dp) in dp.  The leading terms, divided by dp
 * (gradient and first-order rows) and by dp^2 (second-order rows), give a
 * problem free of dp:
 *     (H0 + sum_s nu_s G_s) u + J1^T mu + gp = 0
 *      J1 u + c1 = 0
 *      u^T G_s u / 2 = 0                    (each second-order combination s)
 * with H0 the Hessian of Pi at the flat state, gp = d grad Pi / dp, J1 the
 * first-order combinations of the constraint rows, c1 their derivative in
 * p (a prescribed displacement) and G_s the Hessian of second-order
 * combination s.  Its Jacobian is a KKT matrix whose constraint rows are
 * J1 and (G_s u)^T: regular for a generic u, whatever dp is.  It is solved
 * by a short homotopy (the second-order equations relaxed by eps nu, eps
 * from 1 to 0) with Newton steps of minimum norm (LAPACK dgelss), then
 * scaled back to a guess of the exact problem at p0 + dp, which is off by
 * O(dp^2) only.
 */
#include "flatstart.h"

#include "flatcone.h"
#include "study.h"

#include "cont.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n,
                    double *a, const int *lda, double *s, double *u, const int *ldu,
                    double *vt, const int *ldvt, double *work, const int *lwork, int *info);
extern void dgesv_(const int *n, const int *nrhs, double *a, const int *lda, int *ipiv, double *b,
                   const int *ldb, int *info);
extern void dgelss_(const int *m, const int *n, const int *nrhs, double *a, const int *lda,
                    double *b, const int *ldb, double *s, const double *rcond, int *rank,
                    double *work, const int *lwork, int *info);

#define RANK_TOL 1e-8      /* relative singular value of a first-order row combination */
#define LS_RCOND 1e-12     /* minimum-norm Newton steps of the limit problem */
#define LIMIT_TOL 1e-12    /* scaled residual of the limit problem */
#define LIMIT_MAXIT 60

typedef sf_limit limit_problem;

void sf_limit_free(sf_limit *L)
{
    free(L->H0);
    free(L->gp);
    free(L->cp);
    free(L->U);
    free(L->J1);
    free(L->c1);
    sf_limit_free_G(L);
    memset(L, 0, sizeof *L);
}

void sf_limit_free_G(sf_limit *L)
{
    free(L->Gp);
    free(L->Gi);
    free(L->Gj);
    free(L->Gx);
    L->Gp = NULL;
    L->Gi = L->Gj = NULL;
    L->Gx = NULL;
}

/* Append the nonzeros of the dense nq x nq matrix H as G_s (s = the next
 * one; Gp[s] set by the caller); *cap grows the arrays. */
static int g_append(sf_limit *L, int s, const double *H, long *cap)
{
    int nq = L->nq;
    long k = L->Gp[s];
    for (int i = 0; i < nq; i++)
        for (int j = 0; j < nq; j++) {
            double v = H[(size_t)i * nq + j];
            if (v == 0.0) continue;
            if (k == *cap) {
                long nc = *cap ? 2 * *cap : 1024;
                int *gi = realloc(L->Gi, sizeof(int) * (size_t)nc);
                if (gi) L->Gi = gi;
                int *gj = realloc(L->Gj, sizeof(int) * (size_t)nc);
                if (gj) L->Gj = gj;
                double *gx = realloc(L->Gx, sizeof(double) * (size_t)nc);
                if (gx) L->Gx = gx;
                if (!gi || !gj || !gx) return -1;
                *cap = nc;
            }
            L->Gi[k] = i;
            L->Gj[k] = j;
            L->Gx[k++] = v;
        }
    L->Gp[s + 1] = k;
    return 0;
}

int sf_limit_set_G_dense(sf_limit *L, const double *G)
{
    long cap = 0;
    L->Gp = calloc((size_t)L->n2 + 1, sizeof(long));
    if (!L->Gp) return -1;
    for (int s = 0; s < L->n2; s++)
        if (g_append(L, s, G + (size_t)s * L->nq * L->nq, &cap)) {
            sf_limit_free_G(L);
            return -1;
        }
    return 0;
}

/* Residual of the limit problem at z = (u, mu, nu); Jacobian A (n x n,
 * column-major) when A is not NULL. */
static void limit_eval(const limit_problem *L, const double *z, double eps, double *E, double *A)
{
    int nq = L->nq, n1 = L->n1, n2 = L->n2, n = L->n;
    const double *u = z, *mu = z + nq, *nu = z + nq + n1;
    double *Gu = calloc((size_t)n2 * nq + 1, sizeof(double));
    for (int s = 0; s < n2; s++)
        for (long k = L->Gp[s]; k < L->Gp[s + 1]; k++)
            Gu[(size_t)s * nq + L->Gi[k]] += L->Gx[k] * u[L->Gj[k]];
    for (int i = 0; i < nq; i++) {
        double v = L->gp[i];
        for (int j = 0; j < nq; j++) v += L->H0[(size_t)i * nq + j] * u[j];
        for (int s = 0; s < n2; s++) v += nu[s] * Gu[(size_t)s * nq + i];
        for (int r = 0; r < n1; r++) v += L->J1[(size_t)r * nq + i] * mu[r];
        E[i] = v;
    }
    for (int r = 0; r < n1; r++) {
        double v = L->c1[r];
        for (int j = 0; j < nq; j++) v += L->J1[(size_t)r * nq + j] * u[j];
        E[nq + r] = v;
    }
    for (int s = 0; s < n2; s++) {
        double v = 0.0;
        for (int j = 0; j < nq; j++) v += u[j] * Gu[(size_t)s * nq + j];
        E[nq + n1 + s] = 0.5 * v - eps * nu[s];
    }
    if (A) {
        memset(A, 0, sizeof(double) * (size_t)n * n);
#define AT(i, j) A[(size_t)(j) * n + (i)]
        for (int i = 0; i < nq; i++)
            for (int j = 0; j < nq; j++) AT(i, j) = L->H0[(size_t)i * nq + j];
        for (int s = 0; s < n2; s++)
            for (long k = L->Gp[s]; k < L->Gp[s + 1]; k++) AT(L->Gi[k], L->Gj[k]) += nu[s] * L->Gx[k];
        for (int r = 0; r < n1; r++)
            for (int j = 0; j < nq; j++) {
                AT(j, nq + r) = L->J1[(size_t)r * nq + j];
                AT(nq + r, j) = L->J1[(size_t)r * nq + j];
            }
        for (int s = 0; s < n2; s++)
            for (int j = 0; j < nq; j++) {
                AT(j, nq + n1 + s) = Gu[(size_t)s * nq + j];
                AT(nq + n1 + s, j) = Gu[(size_t)s * nq + j];
            }
        for (int s = 0; s < n2; s++) AT(nq + n1 + s, nq + n1 + s) = -eps;
#undef AT
    }
    free(Gu);
}

static double maxabs(const double *v, int n)
{
    double m = 0.0;
    for (int i = 0; i < n; i++) m = fmax(m, fabs(v[i]));
    return m;
}

double sf_limit_residual(const sf_limit *L, const double *z)
{
    double *E = calloc((size_t)L->n + 1, sizeof(double));
    if (!E) return INFINITY;
    limit_eval(L, z, 0.0, E, NULL);
    double e = maxabs(E, L->n);
    free(E);
    return e;
}

/* Solution of A x = b by LU (LAPACK dgesv; A n x n column-major,
 * destroyed); nonzero when A is singular. */
static int lusolve(int n, double *A, double *b)
{
    int one = 1, info;
    int *ipiv = malloc(sizeof(int) * ((size_t)n + 1));
    if (!ipiv) return -1;
    dgesv_(&n, &one, A, &n, ipiv, b, &n, &info);
    free(ipiv);
    if (info != 0) return 1;
    for (int i = 0; i < n; i++)
        if (!isfinite(b[i])) return 1;
    return 0;
}

/* Minimum-norm solution of A x = b (A n x n column-major, destroyed). */
static int lstsq(int n, double *A, double *b)
{
    int one = 1, rank, info, lwork = -1;
    double rcond = LS_RCOND, wq;
    double *s = malloc(sizeof(double) * ((size_t)n + 1));
    if (!s) return -1;
    dgelss_(&n, &n, &one, A, &n, b, &n, s, &rcond, &rank, &wq, &lwork, &info);
    lwork = (int)wq + 1;
    double *w = malloc(sizeof(double) * (size_t)lwork);
    if (!w) { free(s); return -1; }
    dgelss_(&n, &n, &one, A, &n, b, &n, s, &rcond, &rank, w, &lwork, &info);
    free(w);
    free(s);
    return info;
}

/* Value scale of constraint row r (as in the equilibrium problem's
 * fscale): rotation rows 1, translation, support and displacement rows
 * 1 / lref. */
static double row_scale(const sf_equil *q, int r)
{
    return q->fscale[q->nq + r];
}

/* Gradient of constraint row r at the current kinematic state (order >= 1
 * in q->k; loop rows from q->J, which must be filled). */
static void row_gradient(sf_equil *q, int r, double *out)
{
    int nq = q->nq;
    if (r < q->nloop) {
        memcpy(out, q->J + (size_t)r * nq, sizeof(double) * (size_t)nq);
        return;
    }
    int sr = r - q->nloop;
    double x[3];
    sf_point_eval(q->m, &q->k, &q->rowpt[sr], x, q->dx);
    memcpy(out, q->dx + (size_t)q->rowc[sr] * nq, sizeof(double) * (size_t)nq);
}

/* Add sum_r w_r d2g_r/dq2 over all constraint rows to H (needs order 2). */
static void rows_hessian_add(sf_equil *q, const double *w, double *H)
{
    int nq = q->nq;
    if (q->nloop) sf_constraints(q->m, &q->k, NULL, NULL, w, H, nq);
    for (int sr = 0; sr < q->nsup; sr++) {
        double f[3] = {0, 0, 0};
        f[q->rowc[sr]] = w[q->nloop + sr];
        if (f[q->rowc[sr]] != 0.0) sf_point_hess_add(q->m, &q->k, &q->rowpt[sr], f, H, nq);
    }
}

/* Build the limit problem at the flat state q = 0, parameter p0 (flatstart.h). */
int sf_limit_build(sf_equil *q, double p0, sf_limit *L, sf_error *err)
{
    const sf_model *m = q->m;
    int nq = q->nq, nc = q->ncon;
    memset(L, 0, sizeof *L);
    L->nq = nq;
    L->ncon = nc;
    double *z0 = calloc((size_t)nq + 1, sizeof(double));
    double *Jr = malloc(sizeof(double) * ((size_t)nc * nq + 1));
    double *Js = malloc(sizeof(double) * ((size_t)nc * nq + 1));
    double *S = malloc(sizeof(double) * ((size_t)(nc < nq ? nq : nc) + 1));
    double *lam = malloc(sizeof(double) * ((size_t)nc + 1));
    double *grad = calloc((size_t)nq + 1, sizeof(double));
    double *Hs = NULL;
    long gcap = 0;
    L->H0 = calloc((size_t)nq * nq + 1, sizeof(double));
    L->gp = calloc((size_t)nq + 1, sizeof(double));
    L->cp = calloc((size_t)nc + 1, sizeof(double));
    L->U = malloc(sizeof(double) * ((size_t)nc * nc + 1));
    int rc = SF_OK;
    if (!z0 || !Jr || !Js || !S || !lam || !grad || !L->H0 || !L->gp || !L->cp || !L->U) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto done;
    }
    sf_equil_set_param(q, p0);
    sf_kin_eval(m, z0, 2, &q->k);
    sf_energy_eval(&q->e, &q->k, &q->par, grad, L->H0, nq, L->gp);
    for (size_t i = 0; i < (size_t)nq * nq; i++) L->H0[i] /= q->kref;
    for (int i = 0; i < nq; i++) L->gp[i] /= q->kref;
    if (q->nloop) sf_constraints(m, &q->k, q->g, q->J, NULL, NULL, 0);
    /* scaled rows, column-major for LAPACK: Js[j * nc + r] */
    for (int r = 0; r < nc; r++) {
        row_gradient(q, r, Jr + (size_t)r * nq);
        for (int j = 0; j < nq; j++) Js[(size_t)j * nc + r] = row_scale(q, r) * Jr[(size_t)r * nq + j];
    }
    /* d g / dp: the displacement row's target is p */
    if (q->disp_row >= 0) L->cp[q->nloop + q->disp_row] = -row_scale(q, q->nloop + q->disp_row);
    {
        int info, lwork = -1, ldvt = 1;
        double wq, vt;
        dgesvd_("A", "N", &nc, &nq, Js, &nc, S, L->U, &nc, &vt, &ldvt, &wq, &lwork, &info);
        lwork = (int)wq + 1;
        double *w = malloc(sizeof(double) * (size_t)lwork);
        if (!w) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); goto done; }
        dgesvd_("A", "N", &nc, &nq, Js, &nc, S, L->U, &nc, &vt, &ldvt, w, &lwork, &info);
        free(w);
        if (info != 0) { rc = sf_fail(err, SF_ENUMERIC, "flat start: SVD failed"); goto done; }
    }
    int kmax = nc < nq ? nc : nq, n1 = 0;
    for (int i = 0; i < kmax; i++)
        if (S[i] > RANK_TOL * S[0]) n1++;
    L->n1 = n1;
    L->n2 = nc - n1;
    L->n = nq + L->n1 + L->n2;
    /* the parameter must move the first-order combinations only: an
     * in-plane prescribed displacement (second order at the flat state)
     * has no limit of this form */
    for (int c = n1; c < nc; c++) {
        double v = 0.0;
        for (int r = 0; r < nc; r++) v += L->U[(size_t)c * nc + r] * L->cp[r];
        if (fabs(v) > 1e-8) {
            rc = sf_fail(err, SF_EINPUT, "%s: the prescribed displacement is of second order at "
                         "the flat state (in-plane): no linear start", m->study->path);
            goto done;
        }
    }
    L->J1 = calloc((size_t)n1 * nq + 1, sizeof(double));
    L->c1 = calloc((size_t)n1 + 1, sizeof(double));
    L->Gp = calloc((size_t)L->n2 + 1, sizeof(long));
    Hs = malloc(sizeof(double) * ((size_t)nq * nq + 1)); /* one G_s at a time */
    if (!L->J1 || !L->c1 || !L->Gp || !Hs) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); goto done; }
    /* combination c of the scaled rows: weights U[:, c] on the scaled rows,
     * i.e. U[r, c] * scale_r on the rows themselves */
    for (int c = 0; c < n1; c++) {
        for (int r = 0; r < nc; r++) L->c1[c] += L->U[(size_t)c * nc + r] * L->cp[r];
        for (int j = 0; j < nq; j++) {
            double v = 0.0;
            for (int r = 0; r < nc; r++)
                v += L->U[(size_t)c * nc + r] * row_scale(q, r) * Jr[(size_t)r * nq + j];
            L->J1[(size_t)c * nq + j] = v;
        }
    }
    for (int s = 0; s < L->n2; s++) {
        int c = n1 + s;
        for (int r = 0; r < nc; r++) lam[r] = L->U[(size_t)c * nc + r] * row_scale(q, r);
        memset(Hs, 0, sizeof(double) * (size_t)nq * nq);
        rows_hessian_add(q, lam, Hs);
        if (g_append(L, s, Hs, &gcap)) {
            rc = sf_fail(err, SF_ENOMEM, "out of memory");
            goto done;
        }
    }
done:
    free(z0);
    free(Jr);
    free(Js);
    free(S);
    free(lam);
    free(grad);
    free(Hs);
    if (rc) sf_limit_free(L);
    return rc;
}

/* The eps homotopy (sf_limit_solve); with stall > 0 it also stops when
 * stall levels in a row have failed since eps last fell by a factor of
 * 10, i.e. where the back-off only creeps (a degenerate ray of the cone,
 * whose multipliers grow as eps falls: the miura 2x2 sheet under gravity
 * and a tip load crept from eps = 1e-9 to about 1.7e-10 in 10961
 * iterations of its 20000; docs/flatstart.md);
 * *stalled (when not NULL) then receives the last eps that converged. */
static double limit_solve(const sf_limit *Lp, double *z, int maxit, int *iters, int stall,
                          double *stalled)
{
    const limit_problem L = *Lp;
    int n = L.n;
    double *E = calloc((size_t)n + 1, sizeof(double));
    double *A = malloc(sizeof(double) * ((size_t)n * n + 1));
    double *zt = calloc((size_t)n + 1, sizeof(double));
    double *Et = calloc((size_t)n + 1, sizeof(double));
    double *zn = calloc((size_t)n + 1, sizeof(double));
    double *As = malloc(sizeof(double) * ((size_t)n * n + 1));
    if (!E || !A || !zt || !Et || !zn || !As) {
        free(E); free(A); free(zt); free(Et); free(zn); free(As);
        return -1.0;
    }
    memset(z, 0, sizeof(double) * (size_t)n);
    /* Homotopy in eps: the second-order equations relaxed to
     * u^T G_s u / 2 = eps nu_s, a penalty of stiffness 1/eps (relative to
     * the mean fold stiffness).  For large eps the solution is the
     * first-order response (nu ~ 0, only J1 u = 0 enforced); eps is cut by
     * 10 per level down to 1e-12, then set to 0.  Newton with
     * minimum-norm steps and backtracking on the max-norm of the residual
     * at each level, from the previous level's solution. */
    int it = 0, total = 0, nfail = 0;
    double en = 0.0, eps = 1.0, eps_ok = -1.0, eps_mark = -1.0;
    if (stalled) *stalled = -1.0;
    for (int level = 0; level < 200 && total < maxit; level++) {
        memcpy(zt, z, sizeof(double) * (size_t)n);
        int conv = 0;
        for (it = 0; it < LIMIT_MAXIT && total < maxit; it++, total++) {
            limit_eval(&L, zt, eps, E, A);
            en = maxabs(E, n);
            if (en <= LIMIT_TOL) { conv = 1; break; }
            /* eps > 0 keeps the matrix regular: LU; at eps = 0 the
             * combinations that stay degenerate need the minimum-norm step */
            for (int i = 0; i < n; i++) Et[i] = -E[i];
            if (eps > 0.0) {
                memcpy(As, A, sizeof(double) * (size_t)n * n);
                if (lusolve(n, A, Et)) {
                    for (int i = 0; i < n; i++) Et[i] = -E[i];
                    if (lstsq(n, As, Et)) break;
                }
            } else if (lstsq(n, A, Et)) {
                break;
            }
            double t = 1.0, et = 0.0;
            for (int b = 0; b < 30; b++, t *= 0.5) {
                for (int i = 0; i < n; i++) zn[i] = zt[i] + t * Et[i];
                limit_eval(&L, zn, eps, E, NULL);
                et = maxabs(E, n);
                if (et < en) break;
            }
            if (!(et < en)) break;
            memcpy(zt, zn, sizeof(double) * (size_t)n);
        }
        if (conv) {
            memcpy(z, zt, sizeof(double) * (size_t)n);
            eps_ok = eps;
            if (eps_mark < 0.0 || eps_ok <= 0.1 * eps_mark) {
                eps_mark = eps_ok;
                nfail = 0;
            }
            if (eps == 0.0) break;
            eps = eps <= 1.001e-12 ? 0.0 : eps * 0.1;
        } else {
            /* back off towards the last level that converged */
            if (eps_ok < 0 || eps == eps_ok) break;
            if (stall > 0 && ++nfail >= stall) {
                if (stalled) *stalled = eps_ok;
                break;
            }
            if (eps == 0.0) eps = eps_ok * 1e-2;
            else eps = sqrt(eps * eps_ok);
            if (eps_ok / eps < 1.01) break;
        }
    }
    if (eps_ok != 0.0) en = fmax(en, 1.0);  /* did not reach eps = 0 */
    if (iters) *iters = total;
    free(E); free(A); free(zt); free(Et); free(zn); free(As);
    return en;
}

double sf_limit_solve(const sf_limit *Lp, double *z, int maxit, int *iters)
{
    return limit_solve(Lp, z, maxit, iters, 0, NULL);
}

#define CONE_STARTS 1      /* starts of the search on the tangent cone */
#define HOMOTOPY_SHORT 2000 /* Newton iterations of the homotopy as a candidate */
#define HOMOTOPY_STALL 5    /* failed levels without a decade of eps: the homotopy creeps */

/* Rays of the tangent cone selected by the crease assignment: the
 * branches of the limit problem driven towards fold angles +1 (valley
 * folds) and -1 (mountain folds), with L's cone.  *rays receives them (nq
 * values each, malloc'd; NULL when none).  Returns their number, -1 when
 * out of memory. */
static int assignment_rays(sf_equil *q, const sf_limit *L, double **rays)
{
    const sf_model *m = q->m;
    const sf_study *s = m->study;
    int nq = L->nq, any = 0;
    *rays = NULL;
    double *target = calloc((size_t)nq + 1, sizeof(double));
    double *gv = calloc((size_t)nq + 1, sizeof(double));
    double *zv = calloc((size_t)L->n + 1, sizeof(double));
    if (!target || !gv || !zv) { free(target); free(gv); free(zv); return -1; }
    for (int i = 0; i < m->nfolds && i < s->nfolds; i++) {
        double sg = sf_study_fold_sign(s, i);
        target[m->qoff[i]] = sg;
        any |= sg != 0.0;
    }
    int nr = 0;
    if (any) {
        for (int i = 0; i < nq; i++) {
            double v = 0.0;
            for (int j = 0; j < nq; j++) v -= L->H0[(size_t)i * nq + j] * target[j];
            gv[i] = v;
        }
        sf_limit Lv = *L;
        Lv.gp = gv;
        double ev = limit_solve(&Lv, zv, HOMOTOPY_SHORT, NULL, HOMOTOPY_STALL, NULL);
        sf_cone Cv;
        if (ev >= 0 && sf_cone_find(&Lv, CONE_STARTS, ev <= LIMIT_TOL * 1e3 ? zv : NULL, &Cv) == 0) {
            *rays = malloc(sizeof(double) * ((size_t)(Cv.nb + 1) * nq));
            if (*rays) {
                for (int b = 0; b < Cv.nb; b++)
                    memcpy(*rays + (size_t)nr++ * nq, Cv.z + (size_t)b * L->n, sizeof(double) * (size_t)nq);
                if (ev <= LIMIT_TOL * 1e3) memcpy(*rays + (size_t)nr++ * nq, zv, sizeof(double) * (size_t)nq);
            }
            sf_cone_free(&Cv);
            if (!*rays) nr = -1;
        }
    }
    free(target);
    free(gv);
    free(zv);
    return nr;
}
#define TIE_RTOL 1e-7      /* branches of equal energy: the driving selects none */

/* The branch from the tangent cone (flatcone.h): the stable solution of
 * the limit problem of lowest energy, or the pick-th stable one by
 * energy.  *en receives its residual (2 when there is none: the caller
 * falls back to the eps homotopy).  info->note says what was found and
 * what was chosen. */
static int cone_start(sf_equil *q, const sf_limit *L, int pick, double *z, double *en,
                      sf_flatstart_info *info, sf_error *err)
{
    const char *path = q->m->study->path;
    *en = 2.0;
    if (maxabs(L->c1, L->n1) != 0.0) return SF_OK;   /* a prescribed displacement: the homotopy */
    /* the eps homotopy (a short one) as a further candidate: it follows
     * the driving's response continuously and finds branches the descent
     * may miss (miura-2x2's lowest) */
    double *zh = calloc((size_t)L->n + 1, sizeof(double));
    if (!zh) return sf_fail(err, SF_ENOMEM, "out of memory");
    double eh = limit_solve(L, zh, HOMOTOPY_SHORT, NULL, HOMOTOPY_STALL, NULL);
    sf_cone C;
    const double *zx = eh >= 0 && eh <= LIMIT_TOL * 1e3 ? zh : NULL;
    int fr = sf_cone_find(L, CONE_STARTS, zx, &C);
    if (!fr && C.nb == 0) {
        /* nothing regular: the branches of the crease assignment's own
         * driving as further rays (the cone does not depend on the
         * driving; miura-2x2 under a tip load has its only ray, a
         * degenerate one, found from there) */
        double *rays = NULL;
        int nrays = assignment_rays(q, L, &rays);
        if (nrays > 0) {
            sf_cone_free(&C);
            fr = sf_cone_find_rays(L, CONE_STARTS, zx, rays, nrays, &C);
        }
        free(rays);
        if (nrays < 0) fr = -1;
    }
    free(zh);
    if (fr)
        return sf_fail(err, SF_ENOMEM, "%s: flat start: out of memory (or a LAPACK failure) on "
                       "the tangent cone", path);
    int ns = 0, first = -1, chosen = -1, nties = 0;
    for (int i = 0; i < C.nb; i++) {
        if (!C.stable[i] || !(C.resid[i] <= LIMIT_TOL * 1e3)) continue;
        if (first < 0) first = i;
        if (++ns == pick) chosen = i;
        if (fabs(C.energy[i] - C.energy[first]) <= TIE_RTOL * fabs(C.energy[first])) nties++;
    }
    char note[sizeof info->note];
    note[0] = 0;
    int rc = SF_OK;
    int deg = -1;
    if (C.nb == 0 && C.ndeg > 0) {
        deg = 0;
        for (int i = 1; i < C.ndeg; i++)
            if (C.degen[i] < C.degen[deg]) deg = i;
    }
    if (deg >= 0) {
        snprintf(note, sizeof note, "flat start: the driving's branch is a degenerate ray of the "
                 "tangent cone (%d first-order motions, %d second-order conditions; %d such "
                 "ray%s): the driving also pushes along a motion that loop closure blocks only "
                 "at third order, so the prestress of the flat sheet grows like 1/(p - p0) and "
                 "the branch has no regular limit; starting on the ray of lowest energy", C.k,
                 C.r, C.ndeg, C.ndeg == 1 ? "" : "s");
    } else if (C.k > 0 && C.ncone == 0) {
        snprintf(note, sizeof note, "flat start: no branch found on the tangent cone along the "
                 "driving (%d first-order motions, %d independent second-order loop conditions "
                 "on them; the search from the driving's response ends at the flat state): the "
                 "search is a local one, not a proof that exact closure locks the sheet (a start "
                 "that fails is followed by a mobility check that names a locked sheet); other "
                 "starts: solver.formulation = \"poses\" with analysis.flat_start = "
                 "\"sparse\", more fold modes (defaults.modes), solver.constraints = "
                 "\"penalty\"", C.k, C.r);
    } else if (C.nb == 0) {
        snprintf(note, sizeof note, "the driving does no first-order work on the %d-dimensional "
                 "tangent cone of the flat state (%d cone points found)", C.k, C.ncone);
    } else if (ns == 0) {
        chosen = 0;
        if (info) info->unstable = 1;
        int lower = 0;
        double emin = C.energy[0];
        for (int i = 0; i < C.ndeg; i++)
            if (C.degen[i] < C.energy[0]) {
                lower++;
                emin = fmin(emin, C.degen[i]);
            }
        int len = snprintf(note, sizeof note, "flat start: none of the %d branches of the "
                           "tangent cone is stable; following the one of lowest energy (%.4g)",
                           C.nb, C.energy[0]);
        if (lower && len > 0 && (size_t)len < sizeof note)
            snprintf(note + len, sizeof note - (size_t)len, "; %d degenerate ray%s of the cone "
                     "ha%s lower energy (down to %.4g) but no regular limit (the loops' prestress "
                     "grows like 1/(p - p0)): a stable branch may leave the flat state there, "
                     "which this start does not follow", lower, lower == 1 ? "" : "s",
                     lower == 1 ? "s" : "ve", emin);
    } else if (chosen < 0) {
        rc = sf_fail(err, SF_EINPUT, "%s: solver.flat_branch = %d, but the flat state has %d "
                     "stable branch%s (1..%d, by energy)", path, pick, ns, ns == 1 ? "" : "es", ns);
    } else if (nties > 1) {
        snprintf(note, sizeof note, "flat start: the driving selects no single branch: %d stable "
                 "branches leave the flat state with the same energy (a symmetric start); "
                 "following branch %d of %d, solver.flat_branch = 1..%d selects another", nties,
                 pick, ns, ns);
    } else {
        snprintf(note, sizeof note, "flat start: %d stable branch%s on the tangent cone "
                 "(%d first-order motions, %d second-order conditions); following branch %d "
                 "(%s energy)", ns, ns == 1 ? "" : "es", C.k, C.r, pick,
                 pick == 1 ? "lowest" : "by");
    }
    if (info) {
        snprintf(info->note, sizeof info->note, "%s", note);
        info->cone_dim = C.k;
        info->cone_forms = C.r;
        info->branches = ns;
        info->ties = nties;
        info->chosen = chosen >= 0 ? pick : 0;
    }
    if (rc == SF_OK && chosen >= 0) {
        memcpy(z, C.z + (size_t)chosen * L->n, sizeof(double) * (size_t)L->n);
        *en = C.resid[chosen];
    } else if (rc == SF_OK && deg >= 0) {
        /* the multipliers of the singular branch are left to Newton */
        memset(z, 0, sizeof(double) * (size_t)L->n);
        memcpy(z, C.degu + (size_t)deg * L->nq, sizeof(double) * (size_t)L->nq);
        *en = 0.0;
        if (info) {
            info->chosen = 1;
            info->degenerate = 1;
        }
    }
    sf_cone_free(&C);
    return rc;
}

/* (flatstart.h) */
void sf_limit_to_state(const sf_equil *q, const sf_limit *L, const double *z, double dp, double *y)
{
    int nq = L->nq, n1 = L->n1, nc = L->ncon;
    memset(y, 0, sizeof(double) * (size_t)q->n);
    for (int j = 0; j < nq; j++) y[j] = dp * z[j];
    for (int r = 0; r < nc; r++) {
        double f = row_scale(q, r), v = 0.0;
        for (int c = 0; c < n1; c++) v += L->U[(size_t)c * nc + r] * dp * z[nq + c];
        for (int s = 0; s < L->n2; s++) v += L->U[(size_t)(n1 + s) * nc + r] * z[nq + n1 + s];
        y[nq + r] = q->kref * f * v;
    }
}

int sf_equil_start_limit(sf_equil *q, double p0, double p1, double *y, sf_flatstart_info *info,
                         sf_error *err)
{
    return sf_equil_start_limit_branch(q, p0, p1, 1, y, info, err);
}

int sf_equil_start_limit_branch(sf_equil *q, double p0, double p1, int branch, double *y,
                                sf_flatstart_info *info, sf_error *err)
{
    const sf_model *m = q->m;
    int pick = branch > 0 ? branch : 1;
    if (info) memset(info, 0, sizeof *info);
    if (q->ncon == 0)
        return sf_fail(err, SF_EINPUT, "%s: the limit start needs constraint rows", m->study->path);
    limit_problem L;
    if (sf_limit_build(q, p0, &L, err)) return err->code;
    int n = L.n, n1 = L.n1;
    double *z = calloc((size_t)n + 1, sizeof(double));
    int rc = SF_OK;
    if (!z) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto done;
    }
    int it = 0;
    double en = 2.0, stall_eps = -1.0;
    rc = cone_start(q, &L, pick, z, &en, info, err);
    if (rc == SF_ENOMEM || rc == SF_EINPUT) goto done;
    rc = SF_OK;
    if (!(en <= LIMIT_TOL * 1e3)) {
        /* no branch on the cone (the driving acts at second order only,
         * e.g. in-plane loads): the eps homotopy */
        en = limit_solve(&L, z, 20000, &it, HOMOTOPY_STALL, &stall_eps);
        if (en < 0) {
            rc = sf_fail(err, SF_ENOMEM, "out of memory");
            goto done;
        }
    }
    if (info) {
        info->iterations = it;
        info->residual = en;
        info->first_order_rows = n1;
        info->second_order_rows = L.n2;
    }
    if (!(en <= LIMIT_TOL * 1e3)) {
        char stall[120] = "";
        if (stall_eps > 0.0)
            snprintf(stall, sizeof stall, "; its eps homotopy stalled below eps = %.2g", stall_eps);
        rc = sf_fail(err, SF_ENUMERIC, "%s: the limit problem of the flat state does not converge "
                     "(residual %.3g after %d iterations%s)%s%s", m->study->path, en, it, stall,
                     info && info->note[0] ? "; " : "", info ? info->note : "");
        goto done;
    }
    /* back to the unknowns of the exact problem at p1 */
    sf_limit_to_state(q, &L, z, p1 - p0, y);
    if (info)
        for (int j = 0; j < L.nq; j++) info->amplitude = fmax(info->amplitude, fabs(y[j]));
done:
    free(z);
    sf_limit_free(&L);
    return rc;
}

int sf_equil_start_flat(sf_equil *q, struct cont_solver *cs, double p0, double p1, int dir,
                        double tol, double *y, int branch, sf_flatstart_info *info, sf_error *err)
{
    sf_error lerr;
    sf_error_clear(&lerr);
    sf_flatstart_info own;
    if (!info) info = &own;
    int rc = sf_equil_start_limit_branch(q, p0, p1, branch, y, info, &lerr);
    if (rc == SF_EINPUT && lerr.code == SF_EINPUT && strstr(lerr.msg, "solver.flat_branch"))
        return sf_fail(err, rc, "%s", lerr.msg);
    if (rc == SF_OK && info->degenerate) {
        /* motions of the order of the Newton tolerance's square root:
         * the KKT regularisation relative to them (equilibrium.h) */
        q->reg_rel = SF_FLAT_REG_REL;
        q->reg_min = SF_FLAT_REG_MIN;
    }
    if (rc == SF_OK && cont_start(cs, y, p1, dir) == CONT_OK) {
        if (!info->unstable || q->pz) return SF_OK;
        return sf_flat_start_descend(q, cs, p1, dir, tol, y, branch, info, err);
    }
    /* the penalty homotopy (sf_equil_start_off_flat) as the fallback */
    char why[SF_MSG_SIZE];
    if (rc == SF_OK && info->degenerate)
        snprintf(why, sizeof why, "%s; on it the fold coordinates at p = %g are about %.2g, "
                 "so the second-order loop terms (about %.2g) that this branch turns on are "
                 "at the level of the Newton tolerance %g: %s", info->note, p1, info->amplitude,
                 info->amplitude * info->amplitude, tol, cont_errmsg(cs));
    else
        snprintf(why, sizeof why, "%s", rc ? lerr.msg : cont_errmsg(cs));
    memset(y, 0, sizeof(double) * (size_t)q->n);
    sf_error_clear(&lerr);
    /* the pose formulation's sparse start is a different computation
     * (docs/flatstart.md) and starts sheets where this one fails (the
     * Miura 2x2 sheet under gravity and a tip load): named first, so that
     * a long reason cannot cut it off */
    static const char other[] = "in the fold formulation" SF_FLAT_POSES_HINT;
    if (sf_equil_start_off_flat(q, p1, tol, y, &lerr))
        return sf_fail(err, lerr.code, "%s: no equilibrium at p = %g off the flat state %s "
                       "(limit start: %s; penalty start: %s)", q->m->study->path, p1, other, why,
                       lerr.msg);
    if (cont_start(cs, y, p1, dir) != CONT_OK)
        return sf_fail(err, SF_ENUMERIC, "%s: no equilibrium at p = %g off the flat state %s "
                       "(limit start: %s; from the penalty start: %s)", q->m->study->path, p1,
                       other, why, cont_errmsg(cs));
    return SF_OK;
}

int sf_equil_start_flat_solved(sf_equil *q, double p0, double p1, int dir, double tol, double *y,
                               sf_error *err)
{
    cont_solver *cs = NULL;
    if (sf_equil_create_solver(q, &cs) != CONT_OK) {
        if (cs) cont_free(cs);
        return sf_fail(err, SF_ENOMEM, "continuation: cannot create the start solver");
    }
    cont_set_newton(cs, tol, 12, 0);
    int rc = sf_equil_start_flat(q, cs, p0, p1, dir, tol, y, 1, NULL, err);
    if (rc == SF_OK) memcpy(y, cont_get_point(cs)->y, sizeof(double) * (size_t)q->n);
    cont_free(cs);
    return rc;
}
