/* multibp.c - branch directions at a multiple branch point by
 * Lyapunov-Schmidt reduction onto a two-dimensional kernel (multibp.h). */
#include "multibp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_dense.h>

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

#define MBP_H1 1e-5      /* first differences along the branch */
#define MBP_H2 1e-3      /* differences along kernel directions */
#define MBP_SAMPLES 2000 /* samples of the angle function on [0, pi] */
#define MBP_SAME_RTOL 1e-6  /* step coordinates equal to this (relative): the same */

typedef struct mbp_ws {
    sf_equil *eq;
    int n;
    SUNContext ctx;
    SUNMatrix Jm;
    double *Fp, *J0, *Jp, *Jn, *V, *w, *Phi, *ty0, *yy, *u, *v, *q, *t;
    int k0, k1;           /* kernel eigenpairs */
    double A[4], B[3][2], C[4][2];   /* A (row-major), B11 B12 B22, c111 c112 c122 c222 */
} mbp_ws;

/* Jy at (y, p), unsymmetrised, column-major, into J. */
static int jac(mbp_ws *W, const double *y, double p, double *J)
{
    int n = W->n;
    SUNMatZero(W->Jm);
    memset(W->Fp, 0, sizeof(double) * (size_t)n);
    if (sf_equil_jacobian(y, p, W->Jm, W->Fp, W->eq)) return 1;
    memcpy(J, SUNDenseMatrix_Data(W->Jm), sizeof(double) * (size_t)n * n);
    for (size_t i = 0; i < (size_t)n * n; i++)
        if (!isfinite(J[i])) return 1;
    return 0;
}

static void matvec(int n, const double *M, const double *x, double *out)
{
    for (int i = 0; i < n; i++) out[i] = 0.0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) out[i] += M[i + (size_t)j * n] * x[j];
}

/* out = -Jy^+ (I - P) x over the eigenpairs outside the kernel */
static void minus_pinv(const mbp_ws *W, const double *x, double *out)
{
    int n = W->n;
    memset(out, 0, sizeof(double) * (size_t)n);
    for (int k = 0; k < n; k++) {
        if (k == W->k0 || k == W->k1) continue;
        const double *vk = W->V + (size_t)k * n;
        double c = 0.0;
        for (int i = 0; i < n; i++) c += vk[i] * x[i];
        c /= W->w[k];
        for (int i = 0; i < n; i++) out[i] -= c * vk[i];
    }
}

static void proj(const mbp_ws *W, const double *x, double out[2])
{
    for (int a = 0; a < 2; a++) {
        out[a] = 0.0;
        for (int i = 0; i < W->n; i++) out[a] += W->Phi[i + (size_t)a * W->n] * x[i];
    }
}

/* Phi^T F_yy[u, u] (into b) and the cubic form C(u, u, u) (into c) for u
 * in kernel coordinates. */
static int forms(mbp_ws *W, const double *y0, double p0, const double uk[2], double b[2], double c[2])
{
    int n = W->n;
    double h = MBP_H2;
    for (int i = 0; i < n; i++) W->u[i] = uk[0] * W->Phi[i] + uk[1] * W->Phi[i + n];
    for (int i = 0; i < n; i++) W->yy[i] = y0[i] + h * W->u[i];
    if (jac(W, W->yy, p0, W->Jp)) return 1;
    for (int i = 0; i < n; i++) W->yy[i] = y0[i] - h * W->u[i];
    if (jac(W, W->yy, p0, W->Jn)) return 1;
    /* Q = F_yy[u, u] = dJ(u) u, T = F_yyy[u, u, u] */
    for (size_t i = 0; i < (size_t)n * n; i++) {
        double jp = W->Jp[i], jn = W->Jn[i];
        W->Jp[i] = (jp - jn) / (2 * h);                  /* dJ(u) */
        W->Jn[i] = (jp - 2 * W->J0[i] + jn) / (h * h);   /* d2J(u, u) */
    }
    matvec(n, W->Jp, W->u, W->q);
    matvec(n, W->Jn, W->u, W->t);
    proj(W, W->q, b);
    minus_pinv(W, W->q, W->v);              /* w2 = -Jy^+ (I - P) Q */
    matvec(n, W->Jp, W->v, W->q);           /* F_yy[u, w2] */
    for (int i = 0; i < n; i++) W->t[i] += 3.0 * W->q[i];
    proj(W, W->t, c);
    return 0;
}

/* A u and G_r(u) = B(u, u) / 2 + (r / 6) C(u, u, u): the reduced equations
 * on the ray xi = r u read lam A u + r G_r(u) = 0 (the terms a kernel
 * direction meets at amplitude r; B = 0 leaves the cubic equations, C
 * negligible the quadratic ones). */
static void eval_forms(const mbp_ws *W, double r, const double u[2], double Au[2], double G[2])
{
    for (int a = 0; a < 2; a++) {
        Au[a] = W->A[2 * a] * u[0] + W->A[2 * a + 1] * u[1];
        double b = u[0] * u[0] * W->B[0][a] + 2 * u[0] * u[1] * W->B[1][a] + u[1] * u[1] * W->B[2][a];
        double c = u[0] * u[0] * u[0] * W->C[0][a] + 3 * u[0] * u[0] * u[1] * W->C[1][a] +
                   3 * u[0] * u[1] * u[1] * W->C[2][a] + u[1] * u[1] * u[1] * W->C[3][a];
        G[a] = 0.5 * b + r / 6.0 * c;
    }
}

static double angle_fn(const mbp_ws *W, double r, double th)
{
    double u[2] = {cos(th), sin(th)}, Au[2], G[2];
    eval_forms(W, r, u, Au, G);
    return Au[0] * G[1] - Au[1] * G[0];
}

/* lam on the ray u at amplitude r (NAN when A u = 0) */
static double ray_lam(const mbp_ws *W, double r, const double u[2])
{
    double Au[2], G[2];
    eval_forms(W, r, u, Au, G);
    double aa = Au[0] * Au[0] + Au[1] * Au[1];
    return aa > 0 ? -r * (G[0] * Au[0] + G[1] * Au[1]) / aa : NAN;
}

static void ws_free(mbp_ws *W)
{
    if (W->Jm) SUNMatDestroy(W->Jm);
    if (W->ctx) SUNContext_Free(&W->ctx);
    free(W->J0);
}

/* Kernel, known branch tangent and the coefficients A, B, C. */
static int reduce(mbp_ws *W, const double *y0, double p0, sf_mbp *res, sf_error *err)
{
    int n = W->n, info, lw = -1;
    if (jac(W, y0, p0, W->J0)) return sf_fail(err, SF_ENUMERIC, "multiple branch point: non-finite Jacobian");
    double *Fp0 = W->q;
    memcpy(Fp0, W->Fp, sizeof(double) * (size_t)n);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            W->V[i + (size_t)j * n] = 0.5 * (W->J0[i + (size_t)j * n] + W->J0[j + (size_t)i * n]);
    double wq;
    dsyev_("V", "U", &n, W->V, &n, W->w, &wq, &lw, &info);
    lw = (int)wq + 1;
    double *wk = malloc(sizeof(double) * (size_t)lw);
    if (!wk) return sf_fail(err, SF_ENOMEM, "out of memory");
    dsyev_("V", "U", &n, W->V, &n, W->w, wk, &lw, &info);
    free(wk);
    if (info != 0) return sf_fail(err, SF_ENUMERIC, "multiple branch point: dsyev failed (info %d)", info);
    /* the two eigenvalues nearest zero, and the next */
    int k0 = -1, k1 = -1, k2 = -1;
    for (int k = 0; k < n; k++) {
        double a = fabs(W->w[k]);
        if (k0 < 0 || a < fabs(W->w[k0])) { k2 = k1; k1 = k0; k0 = k; }
        else if (k1 < 0 || a < fabs(W->w[k1])) { k2 = k1; k1 = k; }
        else if (k2 < 0 || a < fabs(W->w[k2])) k2 = k;
    }
    if (k1 < 0 || k2 < 0) return sf_fail(err, SF_ENUMERIC, "multiple branch point: too few unknowns");
    res->eig[0] = W->w[k0];
    res->eig[1] = W->w[k1];
    res->eig[2] = W->w[k2];
    if (!(fabs(W->w[k1]) <= 1e-3 * fabs(W->w[k2])))
        return sf_fail(err, SF_ENUMERIC, "the kernel is not two-dimensional here (eigenvalues of Jy "
                       "nearest zero %.3g, %.3g, then %.3g)", W->w[k0], W->w[k1], W->w[k2]);
    W->k0 = k0;
    W->k1 = k1;
    memcpy(W->Phi, W->V + (size_t)k0 * n, sizeof(double) * (size_t)n);
    memcpy(W->Phi + n, W->V + (size_t)k1 * n, sizeof(double) * (size_t)n);
    /* known branch: ty0 = -Jy^+ Fp, then A = Phi^T dJ/dp Phi along it */
    minus_pinv(W, Fp0, W->ty0);
    double nt = 1.0;
    for (int i = 0; i < n; i++) nt += W->ty0[i] * W->ty0[i];
    double h = MBP_H1 / sqrt(nt);
    for (int i = 0; i < n; i++) W->yy[i] = y0[i] + h * W->ty0[i];
    if (jac(W, W->yy, p0 + h, W->Jp)) return sf_fail(err, SF_ENUMERIC, "multiple branch point: non-finite Jacobian");
    for (int i = 0; i < n; i++) W->yy[i] = y0[i] - h * W->ty0[i];
    if (jac(W, W->yy, p0 - h, W->Jn)) return sf_fail(err, SF_ENUMERIC, "multiple branch point: non-finite Jacobian");
    for (size_t i = 0; i < (size_t)n * n; i++) W->Jp[i] = (W->Jp[i] - W->Jn[i]) / (2 * h);
    for (int b = 0; b < 2; b++) {
        matvec(n, W->Jp, W->Phi + (size_t)b * n, W->t);
        double pr[2];
        proj(W, W->t, pr);
        W->A[b] = pr[0];       /* column b of A: A[a][b] at A[2a + b] */
        W->A[2 + b] = pr[1];
    }
    /* B and C by polarisation */
    const double S[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
    double bs[4][2], cs[4][2];
    for (int s = 0; s < 4; s++)
        if (forms(W, y0, p0, S[s], bs[s], cs[s]))
            return sf_fail(err, SF_ENUMERIC, "multiple branch point: non-finite Jacobian");
    for (int a = 0; a < 2; a++) {
        W->B[0][a] = bs[0][a];
        W->B[2][a] = bs[1][a];
        W->B[1][a] = 0.5 * (bs[2][a] - bs[0][a] - bs[1][a]);
        W->C[0][a] = cs[0][a];
        W->C[3][a] = cs[1][a];
        W->C[2][a] = (0.5 * (cs[2][a] + cs[3][a]) - cs[0][a]) / 3.0;
        W->C[1][a] = (0.5 * (cs[2][a] - cs[3][a]) - cs[1][a]) / 3.0;
    }
    res->bnorm = res->cnorm = 0.0;
    for (int a = 0; a < 2; a++) {
        for (int k = 0; k < 3; k++) res->bnorm = fmax(res->bnorm, fabs(W->B[k][a]));
        for (int k = 0; k < 4; k++) res->cnorm = fmax(res->cnorm, fabs(W->C[k][a]));
    }
    res->order = res->bnorm <= 1e-6 * res->cnorm ? 3 : 2;   /* 2: the quadratic part counts */
    return SF_OK;
}

/* Whether direction a comes before direction b: by the first coordinate of
 * the predicted step y - y0 that differs by more than MBP_SAME_RTOL of the
 * largest, smaller first.  The kernel basis (dsyev's eigenvectors of a
 * nearly double eigenvalue) turns and changes sign with rounding, and with
 * it the angles theta; the steps themselves do not. */
static int dir_before(const sf_mbp *res, const double *y0, int a, int b)
{
    int n = res->n;
    const double *ya = res->y + (size_t)a * n, *yb = res->y + (size_t)b * n;
    double big = 0.0;
    for (int j = 0; j < n; j++) big = fmax(big, fmax(fabs(ya[j] - y0[j]), fabs(yb[j] - y0[j])));
    for (int j = 0; j < n; j++)
        if (fabs(ya[j] - yb[j]) > MBP_SAME_RTOL * big) return ya[j] < yb[j];
    return 0;
}

static void swap_dir(sf_mbp *res, int a, int b)
{
    int n = res->n;
    double *arrs[] = {res->theta, res->lam, res->p, res->tp};
    for (int k = 0; k < 4; k++) {
        double t = arrs[k][a]; arrs[k][a] = arrs[k][b]; arrs[k][b] = t;
    }
    double *vs[] = {res->y, res->ty};
    for (int k = 0; k < 2; k++)
        for (int j = 0; j < n; j++) {
            double t = vs[k][(size_t)a * n + j];
            vs[k][(size_t)a * n + j] = vs[k][(size_t)b * n + j];
            vs[k][(size_t)b * n + j] = t;
        }
}

/* The directions in an order that does not depend on rounding, so that the
 * branches leaving the point are numbered the same under every kernel. */
static void order_directions(sf_mbp *res, const double *y0)
{
    for (int i = 1; i < res->ndir; i++)
        for (int j = i; j > 0 && dir_before(res, y0, j, j - 1); j--) swap_dir(res, j, j - 1);
}

int sf_mbp_directions(sf_equil *eq, const double *y0, double p0, int d, double r,
                      double lam_max, sf_mbp *res, sf_error *err)
{
    memset(res, 0, sizeof *res);
    int n = eq->n;
    res->n = n;
    if (d != 2)
        return sf_fail(err, SF_ENUMERIC, "branch switching at a multiple branch point needs a "
                       "two-dimensional kernel (this one has %d)", d);
    mbp_ws W;
    memset(&W, 0, sizeof W);
    W.eq = eq;
    W.n = n;
    size_t nn = (size_t)n * n;
    W.J0 = malloc(sizeof(double) * (4 * nn + 12 * (size_t)n + 8));
    if (!W.J0 || SUNContext_Create(NULL, &W.ctx) || !(W.Jm = SUNDenseMatrix(n, n, W.ctx))) {
        ws_free(&W);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    W.Jp = W.J0 + nn;
    W.Jn = W.Jp + nn;
    W.V = W.Jn + nn;
    W.w = W.V + nn;
    W.Phi = W.w + n;
    W.ty0 = W.Phi + 2 * (size_t)n;
    W.yy = W.ty0 + n;
    W.u = W.yy + n;
    W.v = W.u + n;
    W.q = W.v + n;
    W.t = W.q + n;
    W.Fp = W.t + n;
    int rc = reduce(&W, y0, p0, res, err);
    if (rc) { ws_free(&W); return rc; }
    int order = res->order;
    /* zeros of the angle function on [0, 2 pi): each a ray (u and -u are
     * different rays unless the equations are purely cubic, where they
     * are mirror images; both are followed) */
    double roots[SF_MBP_MAXDIR];
    int nr = 0, ns = 2 * MBP_SAMPLES;
    double th0 = 0.0, f0 = angle_fn(&W, r, 0.0);
    for (int k = 1; k <= ns && nr < SF_MBP_MAXDIR; k++) {
        double th1 = 2 * M_PI * k / ns, f1 = angle_fn(&W, r, th1);
        if (f0 == 0.0) {
            roots[nr++] = th0;
        } else if ((f0 > 0) != (f1 > 0) && f1 != 0.0 && k < ns) {
            double a = th0, b = th1, fa = f0;
            for (int it = 0; it < 100 && b - a > 1e-15; it++) {
                double m = 0.5 * (a + b), fm = angle_fn(&W, r, m);
                if (fm == 0.0) { a = b = m; break; }
                if ((fm > 0) == (fa > 0)) { a = m; fa = fm; } else b = m;
            }
            roots[nr++] = 0.5 * (a + b);
        } else if ((f0 > 0) != (f1 > 0) && k == ns) {
            /* the last interval ends at 2 pi = 0: a zero there is the first sample's */
            double a = th0, b = th1, fa = f0;
            for (int it = 0; it < 100 && b - a > 1e-15; it++) {
                double m = 0.5 * (a + b), fm = angle_fn(&W, r, m);
                if (fm == 0.0) { a = b = m; break; }
                if ((fm > 0) == (fa > 0)) { a = m; fa = fm; } else b = m;
            }
            if (2 * M_PI - 0.5 * (a + b) > 1e-9 || !(nr > 0 && roots[0] < 1e-9)) roots[nr++] = 0.5 * (a + b);
        }
        th0 = th1;
        f0 = f1;
    }
    res->y = malloc(sizeof(double) * (size_t)(2 * SF_MBP_MAXDIR) * n);
    if (!res->y) { ws_free(&W); return sf_fail(err, SF_ENOMEM, "out of memory"); }
    res->ty = res->y + (size_t)SF_MBP_MAXDIR * n;
    for (int i = 0; i < nr && res->ndir < SF_MBP_MAXDIR; i++) {
        double u[2] = {cos(roots[i]), sin(roots[i])}, rr = r;
        double lam = ray_lam(&W, rr, u);
        if (!isfinite(lam)) continue;
        for (int it = 0; it < 40 && fabs(lam) > lam_max; it++) {
            rr *= 0.5;
            lam = ray_lam(&W, rr, u);
        }
        /* dlam/dr on the ray, for the tangent */
        double dl = (ray_lam(&W, rr * 1.001, u) - ray_lam(&W, rr * 0.999, u)) / (0.002 * rr);
        int k = res->ndir++;
        double *y = res->y + (size_t)k * n, *ty = res->ty + (size_t)k * n;
        for (int j = 0; j < n; j++) {
            double uf = u[0] * W.Phi[j] + u[1] * W.Phi[j + n];
            y[j] = y0[j] + lam * W.ty0[j] + rr * uf;
            ty[j] = uf + dl * W.ty0[j];
        }
        res->p[k] = p0 + lam;
        res->tp[k] = dl;
        res->lam[k] = lam;
        res->theta[k] = roots[i];
    }
    ws_free(&W);
    order_directions(res, y0);
    if (res->ndir == 0)
        return sf_fail(err, SF_ENUMERIC, "the reduced bifurcation equations (order %d) have no "
                       "isolated solution", order);
    return SF_OK;
}

void sf_mbp_free(sf_mbp *res)
{
    free(res->y);
    memset(res, 0, sizeof *res);
}
