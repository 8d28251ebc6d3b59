/* mobility.c - degrees of freedom left by the loop constraints (see
 * mobility.h for the method). */
#include "mobility.h"

#include "energy.h"
#include "flatstart.h"
#include "lmi.h"

#include <math.h>
#include <stdio.h>
#include <SuiteSparseQR_C.h>
#include <stdlib.h>
#include <string.h>

extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n,
                    double *a, const int *lda, double *s, double *u, const int *ldu,
                    double *vt, const int *ldvt, double *work, const int *lwork, int *info);
extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);
extern void dgelss_(const int *m, const int *n, const int *nrhs, double *a, const int *lda,
                    double *b, const int *ldb, double *s, const double *rcond, int *rank,
                    double *work, const int *lwork, int *info);

#ifndef MOB_RADIUS
#define MOB_RADIUS 0.02     /* rad: radius of the probe sphere about q0 */
#endif
#define MOB_TOL 1e-10       /* scaled residual of a state that closes the loops */
#define RANK_RTOL 1e-8      /* singular values below RANK_RTOL * sigma_max (and */
#define RANK_ATOL 1e-12     /* below RANK_ATOL) do not count */
#define MOB_MAXIT 40
#define MOB_FOUND 2         /* states on the constraint set sought (each with its neighbours) */
#define MOB_LIMIT_IT 400    /* Newton iterations of one limit problem */
#define MOB_CERT_TOL 1e-7   /* locked when lambda_min of the stress matrix exceeds this */
#define MOB_SOS_TOL 1e-8    /* second-order rigid when the sum of squares' gamma exceeds this */
#define MOB_RAY_IT 60      /* Gauss-Newton iterations of one cone ray */
#define MOB_RAY_TOL 1e-13   /* a cone ray's forms, relative to their size */
#define MOB_LOCAL_MAX 64    /* coordinates of one vertex (sf_constraints_vertex) */

/* Work space and the problem of one analysis: coordinates C (global
 * indices) and rows R of the loop constraints. */
typedef struct probe {
    const sf_model *m;
    sf_kin k;
    int nq, ncon;
    int vertex;               /* >= 0: the rows of this vertex alone, evaluated locally */
    int lcols[MOB_LOCAL_MAX]; /* its local columns (sf_constraints_vertex) */
    int nlfolds;              /* its distinct folds, the only folding maps */
    int lfolds[MOB_LOCAL_MAX];/* its rows need (sf_kin_eval_folds) */
    int nmodes;               /* a vertex's distinct second-order fold-angle */
    double *modes;            /* directions (nlfolds values each, up to
                                 SF_MOBILITY_MODES_MAX; NULL: not counted) */
    double *lJ, *lH;          /* 6 x MOB_LOCAL_MAX, MOB_LOCAL_MAX^2 */
    double lref;
    double *q, *g, *J;        /* full state, all rows, full Jacobian */
    int nc, nr;
    int *C, *R;
    double *A, *b, *S, *VT, *work;
    int lwork;
    double *Hs, *gs;          /* the study's: Hessian and gradient of Pi at q0,
                                 every load and actuation at full value, or NULL */
    double *states;           /* the whole sheet's: the states found (want x nq), or NULL */
    int nstates;
    int want;                 /* closed states sought (MOB_FOUND for check) */
    int branch_ranks;         /* 1: each state's branch rank from its neighbours (the dof) */
} probe;

static double row_scale(const probe *P, int r) { return r % 6 < 3 ? 1.0 : 1.0 / P->lref; }

/* Scaled rows R at P->q into out (nr), Jacobian (nr x nc, column-major
 * with leading dimension ld) into A when not NULL. */
static int local_col(const probe *P, int nl, int gcol)
{
    for (int a = 0; a < nl; a++)
        if (P->lcols[a] == gcol) return a;
    return -1;
}

/* The kinematics the rows need at P->q: a vertex's own folds, or the
 * whole sheet. */
static void eval_kin(probe *P, int order)
{
    if (P->vertex >= 0) sf_kin_eval_folds(P->m, P->q, order, P->nlfolds, P->lfolds, &P->k);
    else sf_kin_eval(P->m, P->q, order, &P->k);
}

/* dst = src on the probe's coordinates C.  Only those are read or changed
 * (all nq for the whole sheet; a vertex's own, so that its analysis costs
 * nothing of the size of the sheet). */
static void copy_coords(const probe *P, double *dst, const double *src)
{
    for (int j = 0; j < P->nc; j++) dst[P->C[j]] = src[P->C[j]];
}

static void eval_rows(probe *P, double *out, double *A, int ld)
{
    eval_kin(P, A ? 1 : 0);
    if (P->vertex >= 0) {
        /* one vertex: its six rows over its own columns, nothing of size nq */
        double g[6];
        int nl = 0;
        if (sf_constraints_vertex(P->m, &P->k, P->vertex, g, P->lcols, &nl, A ? P->lJ : NULL,
                                  NULL, NULL)) {
            for (int i = 0; i < P->nr; i++) out[i] = NAN;
            return;
        }
        for (int i = 0; i < P->nr; i++) {
            double f = row_scale(P, P->R[i]);
            out[i] = f * g[P->R[i] % 6];
            if (A)
                for (int j = 0; j < P->nc; j++) {
                    int a = local_col(P, nl, P->C[j]);
                    A[(size_t)j * ld + i] = a < 0 ? 0.0 : f * P->lJ[(size_t)(P->R[i] % 6) * nl + a];
                }
        }
        return;
    }
    sf_constraints(P->m, &P->k, P->g, A ? P->J : NULL, NULL, NULL, 0);
    for (int i = 0; i < P->nr; i++) {
        int r = P->R[i];
        double f = row_scale(P, r);
        out[i] = f * P->g[r];
        if (A)
            for (int j = 0; j < P->nc; j++) A[(size_t)j * ld + i] = f * P->J[(size_t)r * P->nq + P->C[j]];
    }
}

static int lapack_work(probe *P, int need)
{
    if (need <= P->lwork) return 0;
    double *w = realloc(P->work, sizeof(double) * (size_t)need);
    if (!w) return -1;
    P->work = w;
    P->lwork = need;
    return 0;
}

/* Singular values (and VT when want_vt) of the scaled rows' Jacobian at
 * P->q; returns the rank, -1 on failure. */
static int jacobian_rank(probe *P, int want_vt)
{
    int nr = P->nr, nc = P->nc, info, lw = -1, one = 1;
    double wq, du;
    double *tmp = P->b;   /* nr values, unused here */
    eval_rows(P, tmp, P->A, nr);
    const char *jv = want_vt ? "A" : "N";
    if (nr == 0) return 0;
    dgesvd_("N", jv, &nr, &nc, P->A, &nr, P->S, &du, &one, P->VT, &nc, &wq, &lw, &info);
    if (info != 0 || lapack_work(P, (int)wq + 1)) return -1;
    lw = P->lwork;
    dgesvd_("N", jv, &nr, &nc, P->A, &nr, P->S, &du, &one, P->VT, &nc, P->work, &lw, &info);
    if (info != 0) return -1;
    int kmax = nr < nc ? nr : nc, rank = 0;
    double tol = fmax(RANK_RTOL * P->S[0], RANK_ATOL);
    for (int i = 0; i < kmax; i++)
        if (P->S[i] > tol) rank++;
    return rank;
}

/* Gauss-Newton from P->q on r(q) = [scaled rows R; (|q - q0|^2 -
 * radius^2) / (2 radius)], minimum-norm steps (dgelss) with backtracking
 * on |r|.  Returns the final max-norm of r, -1 on failure. */
static double solve_on_sphere(probe *P, const double *q0, double radius)
{
    int nr = P->nr, nc = P->nc, m = nr + 1, one = 1, info, rank;
    double rcond = 1e-12;
    int ldb = m > nc ? m : nc;
    double *d = malloc(sizeof(double) * (size_t)ldb);
    double *rv = malloc(sizeof(double) * (size_t)m), *save = malloc(sizeof(double) * (size_t)P->nq);
    double res = -1.0;
    if (!d || !rv || !save) goto done;
    for (int it = 0;; it++) {
        eval_rows(P, rv, P->A, m);
        double h = 0.0;
        for (int j = 0; j < nc; j++) {
            double dx = P->q[P->C[j]] - q0[P->C[j]];
            h += dx * dx;
            P->A[(size_t)j * m + nr] = dx / radius;
        }
        rv[nr] = (h - radius * radius) / (2.0 * radius);
        double rinf = 0.0, r2 = 0.0;
        for (int i = 0; i < m; i++) {
            rinf = fmax(rinf, fabs(rv[i]));
            r2 += rv[i] * rv[i];
        }
        res = rinf;
        if (rinf <= 1e-2 * MOB_TOL || it >= MOB_MAXIT) break;
        for (int i = 0; i < ldb; i++) d[i] = i < m ? -rv[i] : 0.0;
        int lw = -1;
        double wq;
        dgelss_(&m, &nc, &one, P->A, &m, d, &ldb, P->S, &rcond, &rank, &wq, &lw, &info);
        if (info != 0 || lapack_work(P, (int)wq + 1)) { res = -1.0; break; }
        lw = P->lwork;
        dgelss_(&m, &nc, &one, P->A, &m, d, &ldb, P->S, &rcond, &rank, P->work, &lw, &info);
        if (info != 0) { res = -1.0; break; }
        copy_coords(P, save, P->q);
        double t = 1.0;
        int ok = 0;
        for (int bt = 0; bt < 30 && !ok; bt++, t *= 0.5) {
            for (int j = 0; j < nc; j++) P->q[P->C[j]] = save[P->C[j]] + t * d[j];
            eval_rows(P, rv, NULL, m);
            double hh = 0.0, t2 = 0.0;
            for (int j = 0; j < nc; j++) {
                double dx = P->q[P->C[j]] - q0[P->C[j]];
                hh += dx * dx;
            }
            rv[nr] = (hh - radius * radius) / (2.0 * radius);
            for (int i = 0; i < m; i++) t2 += rv[i] * rv[i];
            ok = t2 < r2;
        }
        if (!ok) {
            copy_coords(P, P->q, save);
            break;
        }
    }
done:
    free(d);
    free(rv);
    free(save);
    return res;
}

/* Second-order data of rows R and coordinates C at q0: the first-order
 * combinations J1 of the scaled rows, a basis Z of the first-order
 * motions (null space of J), and for each self-stress s (a combination of
 * the rows in the left null space of J, i.e. of second order) its Hessian
 * G_s and the projection Gh_s = Z^T G_s Z. */
typedef struct second_order {
    int n1, n2, nnull;
    double *J1;     /* n1 x nc */
    double *Z;      /* nnull x nc (row a = null vector a) */
    double *G;      /* n2 x nc x nc */
    double *Gh;     /* n2 x nnull x nnull */
} second_order;

static void so_free(second_order *so)
{
    free(so->J1);
    free(so->Z);
    free(so->G);
    free(so->Gh);
    memset(so, 0, sizeof *so);
}

static int so_build(probe *P, const double *q0, second_order *so)
{
    int nr = P->nr, nc = P->nc, nq = P->nq, info, lw = -1;
    memset(so, 0, sizeof *so);
    int local = P->vertex >= 0;
    double *U = malloc(sizeof(double) * ((size_t)nr * nr + 1));
    double *w = local ? NULL : calloc((size_t)P->ncon + 1, sizeof(double));
    /* the whole sheet (small sheets only): the Hessians in nq x nq */
    double *H = local ? NULL : malloc(sizeof(double) * ((size_t)nq * nq + 1));
    double *Jl = malloc(sizeof(double) * ((size_t)nr * nc + 1));
    int rc = -1;
    if (!U || (!local && (!w || !H)) || !Jl) goto done;
    copy_coords(P, P->q, q0);
    eval_rows(P, P->b, P->A, nr);
    memcpy(Jl, P->A, sizeof(double) * (size_t)nr * nc); /* dgesvd overwrites A */
    double wq;
    dgesvd_("A", "A", &nr, &nc, P->A, &nr, P->S, U, &nr, P->VT, &nc, &wq, &lw, &info);
    if (info != 0 || lapack_work(P, (int)wq + 1)) goto done;
    lw = P->lwork;
    dgesvd_("A", "A", &nr, &nc, P->A, &nr, P->S, U, &nr, P->VT, &nc, P->work, &lw, &info);
    if (info != 0) goto done;
    int kmax = nr < nc ? nr : nc, n1 = 0;
    double tol = fmax(RANK_RTOL * P->S[0], RANK_ATOL);
    for (int i = 0; i < kmax; i++)
        if (P->S[i] > tol) n1++;
    so->n1 = n1;
    so->n2 = nr - n1;
    so->nnull = nc - n1;
    int n2 = so->n2, nn = so->nnull;
    so->J1 = calloc((size_t)n1 * nc + 1, sizeof(double));
    so->Z = calloc((size_t)nn * nc + 1, sizeof(double));
    so->G = calloc((size_t)n2 * nc * nc + 1, sizeof(double));
    so->Gh = calloc((size_t)n2 * nn * nn + 1, sizeof(double));
    if (!so->J1 || !so->Z || !so->G || !so->Gh) goto done;
    for (int c = 0; c < n1; c++)
        for (int j = 0; j < nc; j++) {
            double v = 0.0;
            for (int i = 0; i < nr; i++) v += U[(size_t)c * nr + i] * Jl[(size_t)j * nr + i];
            so->J1[(size_t)c * nc + j] = v;
        }
    for (int a = 0; a < nn; a++)
        for (int j = 0; j < nc; j++) so->Z[(size_t)a * nc + j] = P->VT[(size_t)j * nc + n1 + a];
    eval_kin(P, 2);
    double *GZ = malloc(sizeof(double) * ((size_t)nc * nn + 1));
    if (!GZ) goto done;
    for (int s2 = 0; s2 < n2; s2++) {
        double *Gs = so->G + (size_t)s2 * nc * nc;
        if (local) {
            double w6[6] = {0};
            for (int i = 0; i < nr; i++)
                w6[P->R[i] % 6] = U[(size_t)(n1 + s2) * nr + i] * row_scale(P, P->R[i]);
            int nl = 0;
            memset(P->lH, 0, sizeof(double) * MOB_LOCAL_MAX * MOB_LOCAL_MAX);
            if (sf_constraints_vertex(P->m, &P->k, P->vertex, NULL, P->lcols, &nl, NULL, w6, P->lH)) {
                free(GZ);
                goto done;
            }
            for (int a = 0; a < nc; a++) {
                int la = local_col(P, nl, P->C[a]);
                for (int b = 0; b < nc; b++) {
                    int lb = local_col(P, nl, P->C[b]);
                    Gs[(size_t)a * nc + b] = la < 0 || lb < 0 ? 0.0 : P->lH[(size_t)la * nl + lb];
                }
            }
        } else {
            memset(w, 0, sizeof(double) * (size_t)P->ncon);
            for (int i = 0; i < nr; i++)
                w[P->R[i]] = U[(size_t)(n1 + s2) * nr + i] * row_scale(P, P->R[i]);
            memset(H, 0, sizeof(double) * (size_t)nq * nq);
            sf_constraints(P->m, &P->k, NULL, NULL, w, H, nq);
            for (int a = 0; a < nc; a++)
                for (int b = 0; b < nc; b++) Gs[(size_t)a * nc + b] = H[(size_t)P->C[a] * nq + P->C[b]];
        }
        for (int a = 0; a < nc; a++)
            for (int k2 = 0; k2 < nn; k2++) {
                double v = 0.0;
                for (int b = 0; b < nc; b++) v += Gs[(size_t)a * nc + b] * so->Z[(size_t)k2 * nc + b];
                GZ[(size_t)k2 * nc + a] = v;
            }
        double *Ghs = so->Gh + (size_t)s2 * nn * nn;
        for (int k1 = 0; k1 < nn; k1++)
            for (int k2 = 0; k2 < nn; k2++) {
                double v = 0.0;
                for (int a = 0; a < nc; a++) v += so->Z[(size_t)k1 * nc + a] * GZ[(size_t)k2 * nc + a];
                Ghs[(size_t)k1 * nn + k2] = v;
            }
    }
    free(GZ);
    rc = 0;
done:
    free(U);
    free(w);
    free(H);
    free(Jl);
    if (rc) so_free(so);
    return rc;
}

/* Prestress certificate (Connelly and Whiteley, "Second-order rigidity
 * and prestress stability for tensegrity frameworks", SIAM J. Discrete
 * Math. 9, 1996): if some self-stress nu makes M(nu) = sum_s nu_s Gh_s
 * positive definite, no first-order motion u = Z v can satisfy the
 * second-order conditions v^T Gh_s v = 0 for all s, so the rows lock C.
 * lambda_min(M(nu)) is concave in nu; its maximum over |nu| <= 1 (Gh
 * scaled by their largest Frobenius norm) is a semidefinite program,
 * solved by DSDP (lmi.h) and checked with LAPACK dsyev at the nu found.
 * Returns that lambda_min (> 0: locked; <= 0: no certificate), and in
 * dirs (nc each) up to two candidate second-order motions Z v, v the
 * eigenvectors of the two smallest eigenvalues there; *ndirs their
 * number.  -HUGE_VAL when DSDP fails or memory runs out. */
static double certificate(const probe *P, const second_order *so, double *dirs, int *ndirs)
{
    int nn = so->nnull, n2 = so->n2, nc = P->nc, info, lw = -1;
    size_t kk = (size_t)nn * nn;
    *ndirs = 0;
    if (nn == 0) return HUGE_VAL;          /* no first-order motion at all */
    if (n2 == 0) return -HUGE_VAL;         /* no self-stress: nothing to certify */
    double amax = 0.0;
    for (int s2 = 0; s2 < n2; s2++) {
        double f = 0.0;
        for (size_t i = 0; i < kk; i++) f += so->Gh[(size_t)s2 * kk + i] * so->Gh[(size_t)s2 * kk + i];
        amax = fmax(amax, sqrt(f));
    }
    if (!(amax > 0)) return -HUGE_VAL;
    double *M = malloc(sizeof(double) * (kk + 1));
    double *ev = malloc(sizeof(double) * ((size_t)nn + 1));
    double *nu = calloc((size_t)n2 + 1, sizeof(double));
    double wq, best = -HUGE_VAL, tlo;
    double *work = NULL;
    if (!M || !ev || !nu) goto done;
    dsyev_("V", "U", &nn, M, &nn, ev, &wq, &lw, &info);
    lw = (int)wq + 1;
    work = malloc(sizeof(double) * (size_t)lw);
    if (!work || sf_lmi_max_min_eig(nn, NULL, n2, so->Gh, 1.0, amax, 1.0, nu, &tlo, NULL))
        goto done;
    /* the check: lambda_min of M(nu) with the Gh in units of amax */
    memset(M, 0, sizeof(double) * kk);
    for (int s2 = 0; s2 < n2; s2++)
        for (size_t i = 0; i < kk; i++) M[i] += nu[s2] * so->Gh[(size_t)s2 * kk + i];
    dsyev_("V", "U", &nn, M, &nn, ev, work, &lw, &info);
    if (info != 0) goto done;
    best = ev[0];
    /* candidate motions: eigenvectors of the smallest eigenvalues */
    for (int k = 0; k < 2 && k < nn; k++) {
        for (int j = 0; j < nc; j++) {
            double v = 0.0;
            for (int a = 0; a < nn; a++) v += M[(size_t)k * nn + a] * so->Z[(size_t)a * nc + j];
            dirs[(size_t)k * nc + j] = v;
        }
        (*ndirs)++;
    }
done:
    free(M);
    free(ev);
    free(nu);
    free(work);
    return best;
}

/* A ray of the second-order cone: a unit v (nnull values) with
 * v^T Gh_s v = 0 for every self-stress s, by Gauss-Newton with
 * minimum-norm steps (dgelss) on [v^T Gh_s v / scale; (|v|^2 - 1) / 2]
 * from v (in: the start, out: the ray).  Returns 1 when the forms vanish
 * to MOB_RAY_TOL relative to their scale, 0 when not, -1 out of memory. */
static int cone_ray(const second_order *so, double *v)
{
    int nn = so->nnull, n2 = so->n2, m = n2 + 1, one = 1, info, rank;
    if (nn == 0 || n2 == 0) return 0;
    double scale = 0.0, rcond = 1e-12;
    for (size_t i = 0; i < (size_t)n2 * nn * nn; i++) scale = fmax(scale, fabs(so->Gh[i]));
    if (!(scale > 0)) return 0;
    int ldb = m > nn ? m : nn, lw = -1;
    double *A = malloc(sizeof(double) * ((size_t)m * nn + 1));
    double *d = malloc(sizeof(double) * ((size_t)ldb + 1));
    double *r = malloc(sizeof(double) * ((size_t)m + 1));
    double *t = malloc(sizeof(double) * ((size_t)nn + 1));
    double *sv = malloc(sizeof(double) * ((size_t)ldb + 1));
    double *w = NULL, wq;
    int ok = -1;
    if (!A || !d || !r || !t || !sv) goto done;
    dgelss_(&m, &nn, &one, A, &m, d, &ldb, sv, &rcond, &rank, &wq, &lw, &info);
    lw = (int)wq + 1;
    if (!(w = malloc(sizeof(double) * (size_t)lw))) goto done;
    ok = 0;
    /* the residual and Jacobian at x: the forms, scaled, and the norm */
#define RAY_EVAL(x, withA)                                                                   \
    do {                                                                                     \
        double h_ = 0.0;                                                                     \
        for (int s_ = 0; s_ < n2; s_++) {                                                    \
            const double *G_ = so->Gh + (size_t)s_ * nn * nn;                                \
            double q_ = 0.0;                                                                 \
            for (int a_ = 0; a_ < nn; a_++) {                                                \
                double g_ = 0.0;                                                             \
                for (int b_ = 0; b_ < nn; b_++) g_ += G_[(size_t)a_ * nn + b_] * (x)[b_];    \
                q_ += (x)[a_] * g_;                                                          \
                if (withA) A[(size_t)a_ * m + s_] = 2.0 * g_ / scale;                        \
            }                                                                                \
            r[s_] = q_ / scale;                                                              \
        }                                                                                    \
        for (int a_ = 0; a_ < nn; a_++) {                                                    \
            h_ += (x)[a_] * (x)[a_];                                                         \
            if (withA) A[(size_t)a_ * m + n2] = (x)[a_];                                     \
        }                                                                                    \
        r[n2] = 0.5 * (h_ - 1.0);                                                            \
    } while (0)
    for (int it = 0; it < MOB_RAY_IT; it++) {
        RAY_EVAL(v, 1);
        double r2 = 0.0, rinf = 0.0;
        for (int i = 0; i < m; i++) {
            r2 += r[i] * r[i];
            rinf = fmax(rinf, fabs(r[i]));
        }
        if (rinf <= MOB_RAY_TOL) { ok = 1; break; }
        for (int i = 0; i < ldb; i++) d[i] = i < m ? -r[i] : 0.0;
        dgelss_(&m, &nn, &one, A, &m, d, &ldb, sv, &rcond, &rank, w, &lw, &info);
        if (info != 0) break;
        double step = 1.0;
        int better = 0;
        for (int bt = 0; bt < 30 && !better; bt++, step *= 0.5) {
            for (int a = 0; a < nn; a++) t[a] = v[a] + step * d[a];
            RAY_EVAL(t, 0);
            double t2 = 0.0;
            for (int i = 0; i < m; i++) t2 += r[i] * r[i];
            better = t2 < r2;
        }
        if (!better) break;
        memcpy(v, t, sizeof(double) * (size_t)nn);
    }
#undef RAY_EVAL
done:
    free(A); free(d); free(r); free(t); free(sv); free(w);
    return ok;
}

/* The second-order motion the study's own driving selects: the limit
 * problem of flatstart.h with the study's stiffness H0 and its loads and
 * actuation gp at full value (a locked set has none: the homotopy does not
 * reach eps = 0).  Writes it as a unit direction into D (nc values);
 * returns 1, 0 when the study has no driving or the problem does not
 * converge, -1 when out of memory. */
static int driving_direction(const probe *P, const second_order *so, double *D)
{
    int nc = P->nc, found = -1;
    if (!P->Hs || !P->gs) return 0;
    sf_limit L;
    memset(&L, 0, sizeof L);
    L.nq = nc;
    L.n1 = so->n1;
    L.n2 = so->n2;
    L.n = nc + so->n1 + so->n2;
    L.J1 = so->J1;
    if (sf_limit_set_G_dense(&L, so->G)) return -1;
    L.H0 = calloc((size_t)nc * nc + 1, sizeof(double));
    L.gp = calloc((size_t)nc + 1, sizeof(double));
    L.c1 = calloc((size_t)so->n1 + 1, sizeof(double));
    double *z = calloc((size_t)L.n + 1, sizeof(double));
    if (!L.H0 || !L.gp || !L.c1 || !z) goto done;
    found = 0;
    double nf = 0.0, hmax = 0.0;
    for (int a = 0; a < nc; a++) {
        L.gp[a] = P->gs[P->C[a]];
        nf += L.gp[a] * L.gp[a];
        for (int b = 0; b < nc; b++) {
            L.H0[(size_t)a * nc + b] = P->Hs[(size_t)P->C[a] * P->nq + P->C[b]];
            hmax = fmax(hmax, fabs(L.H0[(size_t)a * nc + b]));
        }
    }
    if (!(nf > 0) || !(hmax > 0)) goto done;
    for (size_t i = 0; i < (size_t)nc * nc; i++) L.H0[i] /= hmax;
    for (int j = 0; j < nc; j++) L.gp[j] /= sqrt(nf);
    double res = sf_limit_solve(&L, z, MOB_LIMIT_IT, NULL);
    if (res < 0) { found = -1; goto done; }
    double nu = 0.0;
    for (int j = 0; j < nc; j++) nu += z[j] * z[j];
    nu = sqrt(nu);
    if (res <= 1e-9 && nu > 1e-8) {
        for (int j = 0; j < nc; j++) D[j] = z[j] / nu;
        found++;
    }
done:
    sf_limit_free_G(&L);
    free(L.H0);
    free(L.gp);
    free(L.c1);
    free(z);
    return found;
}

/* One start of the probe: direction v (nc values, any length).  A state
 * found counts with the rank of the branch it lies on; *minrank keeps the
 * smallest such rank over the states found (the largest branch). */
static int try_start(probe *P, const double *q0, const double *v, int *found, int *minrank,
                     double *best)
{
    int nc = P->nc;
    double nv = 0.0;
    for (int j = 0; j < nc; j++) nv += v[j] * v[j];
    nv = sqrt(nv);
    if (!(nv > 0)) return 0;
    copy_coords(P, P->q, q0);
    for (int j = 0; j < nc; j++) P->q[P->C[j]] += MOB_RADIUS * v[j] / nv;
    double res = solve_on_sphere(P, q0, MOB_RADIUS);
    if (res < 0) return -1;
    if (res <= MOB_TOL) {
        /* the rank there, and at states a step 0.5 r away along each
         * motion the rows leave free there (null vectors of J), back on
         * the set: where branches cross (e.g. one straight line folded
         * alone) the rows are redundant, and a step along a branch's own
         * tangent leaves the crossing; the largest rank is that of a
         * branch through it */
        if (P->states && P->nstates < P->want)
            memcpy(P->states + (size_t)P->nstates++ * P->nq, P->q, sizeof(double) * (size_t)P->nq);
        int rk = jacobian_rank(P, P->branch_ranks), branch = rk;   /* VT for the neighbours */
        if (rk < 0) return -1;
        /* all rows independent: no crossing, nothing to look for */
        int nfree = P->branch_ranks && rk < (P->nr < nc ? P->nr : nc) ? nc - rk : 0;
        double *x = malloc(sizeof(double) * (size_t)P->nq);
        double *T = malloc(sizeof(double) * ((size_t)nfree * nc + 1));
        if (!x || !T) { free(x); free(T); return -1; }
        copy_coords(P, x, P->q);
        for (int a = 0; a < nfree; a++)
            for (int j = 0; j < nc; j++) T[(size_t)a * nc + j] = P->VT[(size_t)j * nc + rk + a];
        for (int s = 0; s < 2 * nfree; s++) {
            copy_coords(P, P->q, x);
            for (int j = 0; j < nc; j++)
                P->q[P->C[j]] += (s % 2 ? -0.5 : 0.5) * MOB_RADIUS * T[(size_t)(s / 2) * nc + j];
            double rs = solve_on_sphere(P, q0, MOB_RADIUS);
            if (rs < 0) { free(x); free(T); return -1; }
            if (rs > MOB_TOL) continue;
            int rn = jacobian_rank(P, 0);
            if (rn < 0) { free(x); free(T); return -1; }
            if (rn > branch) branch = rn;
        }
        free(x);
        free(T);
        if (branch < *minrank) *minrank = branch;
        (*found)++;
    } else if (res < *best) {
        *best = res;
    }
    return 0;
}

/* A cone ray v (nc values) as a folding mode of a vertex: its fold
 * angles (each fold's first coordinate, in the order of P->lfolds), unit,
 * the largest one positive; a new mode unless parallel (to 1e-6 in
 * 1 - |cos|) to one recorded.  Rays that hardly fold (fold angles below
 * 1e-3 of the ray) are no mode: near the intersection of two modes'
 * planes a ray within the forms' tolerance (1e-13, so about 3e-7 off
 * each plane) has fold angles of no definite direction. */
static void record_mode(probe *P, const double *v)
{
    if (!P->modes || P->nmodes >= SF_MOBILITY_MODES_MAX) return;
    int nf = P->nlfolds;
    double p[MOB_LOCAL_MAX], nv = 0.0, np = 0.0, big = 0.0;
    for (int j = 0; j < P->nc; j++) nv += v[j] * v[j];
    for (int a = 0; a < nf; a++) {
        p[a] = 0.0;
        for (int j = 0; j < P->nc; j++)
            if (P->C[j] == P->m->qoff[P->lfolds[a]]) p[a] = v[j];
        np += p[a] * p[a];
        if (fabs(p[a]) > fabs(big)) big = p[a];
    }
    if (!(np > 1e-6 * nv)) return;
    np = copysign(sqrt(np), big);
    for (int a = 0; a < nf; a++) p[a] /= np;
    for (int k = 0; k < P->nmodes; k++) {
        double c = 0.0;
        for (int a = 0; a < nf; a++) c += p[a] * P->modes[(size_t)k * nf + a];
        if (1.0 - fabs(c) <= 1e-6) return;
    }
    memcpy(P->modes + (size_t)P->nmodes * nf, p, sizeof(double) * (size_t)nf);
    P->nmodes++;
}

/* The first-order motion nearest to sign e_ci (+ sj e_cj when cj >= 0),
 * Z^T Z (e_ci + sj e_cj), in Z's coordinates (nn values): the columns of
 * Z, which depend on the null space alone, unlike its rows (an arbitrary
 * basis that rounding rotates).  Returns its squared length. */
static double nearest_motion(const second_order *so, int nc, double sign, int ci, int cj,
                             double sj, double *ray)
{
    double len = 0.0;
    for (int a = 0; a < so->nnull; a++) {
        ray[a] = sign * so->Z[(size_t)a * nc + ci];
        if (cj >= 0) ray[a] += sj * so->Z[(size_t)a * nc + cj];
        len += ray[a] * ray[a];
    }
    return len;
}

/* Analyse coordinates C against rows R about q0: first-order count, dof
 * (0: locked, -1: undecided), gap and the certificate value. */
static int analyse(probe *P, const double *q0, int *first_order, int *dof, double *gap,
                   double *cert, int *kind)
{
    int nc = P->nc, rc = 0;
    second_order so;
    if (so_build(P, q0, &so)) return -1;
    *first_order = so.nnull;
    int nn = so.nnull;
    double *v = malloc(sizeof(double) * ((size_t)nc + 1));
    double *D = malloc(sizeof(double) * ((size_t)3 * nc + 1));
    if (!v || !D) { rc = -1; goto done; }
    int nd = 0, found = 0, minrank = nc + 1;
    double best = HUGE_VAL;
    *cert = certificate(P, &so, D, &nd);
    int locked = *cert > MOB_CERT_TOL;
    *kind = locked ? SF_CERT_PRESTRESS : 0;
    /* look for states on the constraint set at |q - q0| = r: along the
     * second-order motion the study's driving selects, then along the
     * cone's rays, then along first-order motions.  A locked set only
     * gets the certificate's candidates and the first-order motions (for
     * the gap). */
    if (locked) {
        for (int s = 0; s < 2 * nd && !rc; s++) {
            for (int j = 0; j < nc; j++) v[j] = (s % 2 ? -1.0 : 1.0) * D[(size_t)(s / 2) * nc + j];
            rc = try_start(P, q0, v, &found, &minrank, &best);
        }
    } else if (!rc) {
        int nl = driving_direction(P, &so, D);
        if (nl < 0) rc = -1;
        for (int s = 0; s < nl && found < P->want && !rc; s++)
            rc = try_start(P, q0, D + (size_t)s * nc, &found, &minrank, &best);
    }
    /* the rays of the second-order cone (no motion of the set leaves the
     * flat state except along one) nearest to the first-order motions
     * nearest to +-e_j, and at a degree-4 vertex to e_i +- e_j too; the
     * search for modes stops at two, since a degree-4 vertex's fold
     * angles lie on its rigid cone, at most two lines (a quadratic form
     * on the plane the in-plane rotation rows leave) */
    int nstart = 2 * nc + (P->modes ? nc * (nc - 1) : 0);
    for (int s = 0; s < nstart && !locked && !rc &&
                    (found < P->want || (P->modes && P->nmodes < 2)); s++) {
        double *ray = D + (size_t)2 * nc, len;
        if (s < 2 * nc) {
            len = nearest_motion(&so, nc, s % 2 ? -1.0 : 1.0, s / 2, -1, 0.0, ray);
        } else {
            int k = (s - 2 * nc) / 2, ci = 0;
            while (k >= nc - 1 - ci) k -= nc - 1 - ci++;
            len = nearest_motion(&so, nc, 1.0, ci, ci + 1 + k, (s - 2 * nc) % 2 ? -1.0 : 1.0, ray);
        }
        if (!(len > 1e-12)) continue;   /* a direction no first-order motion takes */
        int ok = cone_ray(&so, ray);
        if (ok < 0) { rc = -1; break; }
        if (!ok) continue;
        memset(v, 0, sizeof(double) * (size_t)nc);
        for (int a = 0; a < nn; a++)
            for (int j = 0; j < nc; j++) v[j] += ray[a] * so.Z[(size_t)a * nc + j];
        record_mode(P, v);
        if (found < P->want) rc = try_start(P, q0, v, &found, &minrank, &best);
    }
    for (int s = 0, tried = 0; s < 2 * nc && tried < 4 && !found && !rc; s++) {
        double *z = D + (size_t)2 * nc;
        if (!(nearest_motion(&so, nc, s % 2 ? -1.0 : 1.0, s / 2, -1, 0.0, z) > 1e-12)) continue;
        memset(v, 0, sizeof(double) * (size_t)nc);
        for (int a = 0; a < nn; a++)
            for (int j = 0; j < nc; j++) v[j] += z[a] * so.Z[(size_t)a * nc + j];
        tried++;
        rc = try_start(P, q0, v, &found, &minrank, &best);
    }
    /* no ray of the cone and no prestress: second-order rigidity, if the
     * forms have no common real zero (mobility_sos.c) */
    if (!rc && !found && !locked) {
        int st = 0;
        double gamma = sf_mobility_sos(nn, so.n2, so.Gh, &st);
        if (st < 0) rc = -1;
        else if (gamma > MOB_SOS_TOL) {
            locked = 1;
            *cert = gamma;
            *kind = SF_CERT_SECOND_ORDER;
        }
    }
    if (!rc) {
        *gap = found ? 0.0 : best;
        *dof = found ? nc - minrank : locked ? 0 : -1;
    }
done:
    so_free(&so);
    free(v);
    free(D);
    return rc;
}

void sf_mobility_free(sf_mobility *mb)
{
    for (int v = 0; mb->v && v < mb->nvertices; v++) free(mb->v[v].mode);
    free(mb->v);
    free(mb->states);
    memset(mb, 0, sizeof *mb);
}

/* The analysis (sf_mobility_analyse), the whole sheet's probe seeking
 * want closed states, with their branch ranks (the dof) or without. */
static int analyse_all(const sf_model *m, const double *q0in, int want, int branch_ranks,
                       sf_mobility *mb, sf_error *err)
{
    memset(mb, 0, sizeof *mb);
    const sf_topology *t = m->topo;
    int nq = m->nq, ncon = m->ncon, nv = t->nivertices;
    mb->nq = nq;
    mb->ncon = ncon;
    mb->radius = MOB_RADIUS;
    mb->nvertices = nv;
    mb->v = calloc((size_t)nv + 1, sizeof *mb->v);
    probe P;
    memset(&P, 0, sizeof P);
    P.want = MOB_FOUND;   /* each vertex: as check's */
    P.branch_ranks = 1;
    P.m = m;
    P.nq = nq;
    P.ncon = ncon;
    P.lref = 0.0;
    for (int i = 0; i < m->nfolds; i++) P.lref += m->study->folds[i].width / m->nfolds;
    if (!(P.lref > 0)) P.lref = 1.0;
    /* above SF_MOBILITY_DENSE_MAX: nothing of size nq^2 (each vertex is
     * analysed locally, the whole sheet to first order, sparse) */
    int dense = nq <= SF_MOBILITY_DENSE_MAX;
    mb->probed = dense || ncon == 0;
    size_t big = dense ? (size_t)(ncon + 1) * (nq + 1) + 1
                       : (size_t)(6 + 2) * (MOB_LOCAL_MAX + 1) + 1;
    double *q0 = calloc((size_t)nq + 1, sizeof(double));
    P.q = calloc((size_t)nq + 1, sizeof(double));
    P.g = calloc((size_t)ncon + 1, sizeof(double));
    P.J = calloc(dense ? big : 1, sizeof(double));
    P.lJ = calloc(6 * MOB_LOCAL_MAX, sizeof(double));
    P.lH = calloc(MOB_LOCAL_MAX * MOB_LOCAL_MAX, sizeof(double));
    P.C = malloc(sizeof(int) * ((size_t)nq + 1));
    P.R = malloc(sizeof(int) * ((size_t)ncon + 1));
    P.A = calloc(big, sizeof(double));
    P.b = calloc((size_t)ncon + nq + 2, sizeof(double));
    P.S = calloc((size_t)ncon + nq + 2, sizeof(double));
    P.VT = dense ? calloc((size_t)nq * nq + 1, sizeof(double))
                 : calloc(MOB_LOCAL_MAX * MOB_LOCAL_MAX + 1, sizeof(double));
    int rc = SF_OK;
    if (!mb->v || !q0 || !P.q || !P.g || !P.J || !P.C || !P.R || !P.A || !P.b || !P.S || !P.VT ||
        !P.lJ || !P.lH || sf_kin_alloc(m, &P.k)) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto done;
    }
    if (q0in) memcpy(q0, q0in, sizeof(double) * (size_t)nq);
    {
        /* the study's loads and actuation at full value, as one more
         * force to look for motions with (optional: skipped when the
         * energy cannot be set up) */
        sf_energy e;
        sf_params par;
        sf_error eerr;
        sf_error_clear(&eerr);
        if (dense && sf_energy_init(&e, m, &eerr) == SF_OK) {
            if (sf_params_alloc(&e, &par) == SF_OK) {
                P.Hs = calloc((size_t)nq * nq + 1, sizeof(double));
                P.gs = calloc((size_t)nq + 1, sizeof(double));
                if (P.Hs && P.gs) {
                    for (int k = 0; k < e.nstages; k++) par.stage[k] = 1.0;
                    for (int i = 0; i < m->nfolds; i++) {
                        const sf_fold_def *f = &m->study->folds[i];
                        par.rest[i] = f->group >= 0 ? m->study->groups[f->group].rest_angle
                                                    : f->rest_angle;
                    }
                    e.penalty = 0;
                    sf_kin_eval(m, q0, 2, &P.k);
                    sf_energy_eval(&e, &P.k, &par, P.gs, P.Hs, nq, NULL);
                }
                sf_params_free(&par);
            }
            sf_energy_free(&e);
        }
    }
    /* the base state must close the loops */
    sf_kin_eval(m, q0, 0, &P.k);
    sf_constraints(m, &P.k, P.g, NULL, NULL, NULL, 0);
    for (int r = 0; r < ncon; r++)
        if (!(fabs(row_scale(&P, r) * P.g[r]) <= 1e-9)) {
            rc = sf_fail(err, SF_EINPUT, "%s: mobility: the state does not close the loop of "
                         "vertex %s (residual %.3g)", m->study->path,
                         m->study->vertices[t->ivertices[r / 6].vertex].name, P.g[r]);
            goto done;
        }
    /* each vertex under its own rows */
    for (int v = 0; v < nv; v++) {
        const sf_ivertex *iv = &t->ivertices[v];
        P.nc = 0;
        P.nlfolds = 0;
        for (int a = 0; a < iv->degree; a++) {
            int f = iv->folds[a], dup = 0;
            for (int b = 0; b < a; b++) dup |= iv->folds[b] == f;
            if (dup) continue;
            if (P.nlfolds < MOB_LOCAL_MAX) P.lfolds[P.nlfolds++] = f;
            for (int j = 0; j < m->qn[f]; j++) P.C[P.nc++] = m->qoff[f] + j;
        }
        P.nr = 6;
        for (int e = 0; e < 6; e++) P.R[e] = 6 * v + e;
        P.vertex = v;
        if (P.nc > MOB_LOCAL_MAX) {
            rc = sf_fail(err, SF_EINPUT, "%s: mobility: vertex %s has %d coordinates, more than "
                         "%d", m->study->path, m->study->vertices[iv->vertex].name, P.nc,
                         MOB_LOCAL_MAX);
            goto done;
        }
        sf_mobility_vertex *mv = &mb->v[v];
        mv->ivertex = v;
        mv->coords = P.nc;
        mv->nfolds = P.nlfolds;
        /* folding modes at degree 4, where each is one line of fold
         * angles (at higher degree they come in families) */
        if (iv->degree == 4 && P.nlfolds == 4) {
            mv->mode = malloc(sizeof(double) * ((size_t)SF_MOBILITY_MODES_MAX * P.nlfolds + 1));
            if (!mv->mode) {
                rc = sf_fail(err, SF_ENOMEM, "out of memory");
                goto done;
            }
        }
        P.modes = mv->mode;
        P.nmodes = 0;
        if (analyse(&P, q0, &mv->first_order, &mv->dof, &mv->gap, &mv->certificate, &mv->cert_kind)) {
            rc = sf_fail(err, SF_ENUMERIC, "mobility: LAPACK failed");
            goto done;
        }
        /* modes count where the vertex moves (a locked or undecided
         * vertex's cone rays lead to no state) */
        mv->modes = mv->dof > 0 ? P.nmodes : 0;
        P.modes = NULL;
        mb->nlocked += mv->dof == 0;
    }
    /* the whole sheet */
    P.vertex = -1;
    if (!dense && ncon > 0) {
        mb->dof = -1;
        mb->gap = -1.0;
        rc = sf_mobility_first_order(m, q0, &mb->first_order, err);
        goto done;
    }
    P.nc = nq;
    for (int j = 0; j < nq; j++) P.C[j] = j;
    P.nr = ncon;
    for (int r = 0; r < ncon; r++) P.R[r] = r;
    if (ncon == 0) {
        mb->first_order = nq;
        mb->dof = nq;
    } else {
        P.states = mb->states = malloc(sizeof(double) * ((size_t)want * nq + 1));
        P.want = want;
        P.branch_ranks = branch_ranks;
        if (!mb->states) {
            rc = sf_fail(err, SF_ENOMEM, "out of memory");
            goto done;
        }
        if (analyse(&P, q0, &mb->first_order, &mb->dof, &mb->gap, &mb->certificate, &mb->cert_kind)) {
            rc = sf_fail(err, SF_ENUMERIC, "mobility: LAPACK failed");
            goto done;
        }
        mb->nstates = P.nstates;
    }
done:
    mb->fold_evals = P.k.fold_evals;
    sf_kin_free(&P.k);
    free(q0);
    free(P.q);
    free(P.g);
    free(P.J);
    free(P.C);
    free(P.R);
    free(P.A);
    free(P.b);
    free(P.S);
    free(P.VT);
    free(P.work);
    free(P.Hs);
    free(P.gs);
    free(P.lJ);
    free(P.lH);
    if (rc) sf_mobility_free(mb);
    return rc;
}

int sf_mobility_analyse(const sf_model *m, const double *q0, sf_mobility *mb, sf_error *err)
{
    return analyse_all(m, q0, MOB_FOUND, 1, mb, err);
}

int sf_mobility_states(const sf_model *m, int want, sf_mobility *mb, sf_error *err)
{
    return analyse_all(m, NULL, want > 0 ? want : 1, 0, mb, err);
}

int sf_mobility_locked(const sf_mobility *mb)
{
    return mb->dof == 0 || mb->nlocked > 0;
}

int sf_mobility_overcounted(const sf_model *m, int *rows, int *coords, int *coords2, int *k1)
{
    *rows = 6 * m->topo->nivertices;
    *coords = m->nq;
    *coords2 = *k1 = 0;
    for (int f = 0; f < m->nfolds; f++) {
        *coords2 += m->qn[f] > 3 ? m->qn[f] : 3;
        *k1 += m->qn[f] <= 2;
    }
    return *rows > *coords && *k1 > 0;
}

void sf_mobility_describe(const sf_model *m, const sf_mobility *mb, char *buf, size_t size)
{
    const sf_study *s = m->study;
    const sf_topology *t = m->topo;
    size_t n = 0;
    buf[0] = '\0';
#define ADD(...)                                                              \
    do {                                                                      \
        if (n < size) {                                                       \
            int k_ = snprintf(buf + n, size - n, __VA_ARGS__);                \
            n += k_ > 0 ? (size_t)k_ : 0;                                     \
        }                                                                     \
    } while (0)
    if (!sf_mobility_locked(mb)) return;
    if (mb->dof == 0)
        ADD("the loop constraints leave the sheet no motion (%d coordinates, %d loop equations)",
            mb->nq, mb->ncon);
    else
        ADD("the loop constraints leave the sheet %d degree%s of freedom, but not every vertex "
            "can move", mb->dof, mb->dof == 1 ? "" : "s");
    if (mb->nlocked > 0) {
        ADD(": ");
        int k = 0;
        for (int v = 0; v < mb->nvertices; v++) {
            const sf_mobility_vertex *mv = &mb->v[v];
            if (mv->dof) continue;
            ADD("%svertex %s (degree %d, %d coordinates for 6 loop equations, smallest loop "
                "residual %.2g at %.2g rad%s", k++ ? ", " : "",
                s->vertices[t->ivertices[v].vertex].name, t->ivertices[v].degree, mv->coords,
                mv->gap, mb->radius, mv->cert_kind ? "; " : ")");
            if (mv->cert_kind == SF_CERT_PRESTRESS)
                ADD("a prestress of its loops makes the second-order closure conditions positive "
                    "definite on its %d first-order motions, smallest eigenvalue %.3g)",
                    mv->first_order, mv->certificate);
            else if (mv->cert_kind == SF_CERT_SECOND_ORDER)
                ADD("its second-order closure conditions have no common real zero on its %d "
                    "first-order motions, sum-of-squares margin %.3g)", mv->first_order,
                    mv->certificate);
        }
        ADD(" lock%s %s folds", mb->nlocked == 1 ? "s" : "", mb->nlocked == 1 ? "its" : "their");
    } else {
        ADD(": each vertex alone can move, but together the loops of vertices ");
        for (int v = 0; v < mb->nvertices; v++)
            ADD("%s%s", v ? ", " : "", s->vertices[t->ivertices[v].vertex].name);
        ADD(" do not");
    }
    ADD("; to fold it: more shape modes (defaults.modes), the loop penalty "
        "(solver.constraints = \"penalty\") or bending faces (faces.bending)");
#undef ADD
}
