/* start_cone.c - the tangent cone of the flat state in fold coordinates
 * (start_impl.h): the first-order motions, the second-order conditions on
 * them, rays of the cone nearest to a given motion, and the certificate
 * that the cone is the origin alone.
 *
 * At q = 0 the loop rows g split into combinations with a gradient (their
 * kernel, N, holds the first-order motions) and combinations w . g with
 * none (w in the left null space of J(0)); a motion q = t N x + O(t^2)
 * closes the loops to second order only if x^T Q_w x = 0 for every w, with
 * Q_w = N^T hess(w . g) N.  A point x of that cone where the rows' second-
 * order terms leave the sheet a motion is a direction in which it folds;
 * if some combination sum_w nu_w Q_w is positive definite, no x != 0 is in
 * the cone and the sheet cannot leave the flat state with rigid faces (a
 * prestress of the loops locks it, Connelly and Whiteley, "Second-order
 * rigidity and prestress stability", SIAM J. Discrete Math. 9, 1996).
 * Dense LAPACK throughout: for sheets of up to FS_CONE_MAXQ fold
 * coordinates. */
#include "start_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lmi.h"

extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, double *a,
                    const int *lda, double *s, double *u, const int *ldu, double *vt,
                    const int *ldvt, double *work, const int *lwork, int *info);
extern void dposv_(const char *uplo, const int *n, const int *nrhs, double *a, const int *lda,
                   double *b, const int *ldb, int *info);
extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

#define RANK_TOL 1e-8      /* relative singular value of a row combination with a gradient */

void fs_cone_free(fs_cone *C)
{
    free(C->N);
    free(C->A);
    free(C->c);
    free(C->Q);
    memset(C, 0, sizeof *C);
}

/* SVD of the m x n column-major matrix M (destroyed): singular values s,
 * U (m x m) and VT (n x n) when asked ("A"/"N"). */
static int svd(int m, int n, double *M, double *s, double *U, double *VT)
{
    int info, lw = -1, ldu = U ? m : 1, ldv = VT ? n : 1;
    double wq, du, dv;
    const char *ju = U ? "A" : "N", *jv = VT ? "A" : "N";
    dgesvd_(ju, jv, &m, &n, M, &m, s, U ? U : &du, &ldu, VT ? VT : &dv, &ldv, &wq, &lw, &info);
    lw = (int)wq + 1;
    double *w = malloc(sizeof(double) * (size_t)lw);
    if (!w) return -1;
    dgesvd_(ju, jv, &m, &n, M, &m, s, U ? U : &du, &ldu, VT ? VT : &dv, &ldv, w, &lw, &info);
    free(w);
    return info;
}

/* N^T M N (k x k) of the nq x nq row-major symmetric M. */
static void project(int nq, int k, const double *N, const double *M, double *out, double *tmp)
{
    for (int b = 0; b < k; b++)
        for (int i = 0; i < nq; i++) {
            double s = 0.0;
            for (int j = 0; j < nq; j++) s += M[(size_t)i * nq + j] * N[(size_t)b * nq + j];
            tmp[(size_t)b * nq + i] = s;
        }
    for (int a = 0; a < k; a++)
        for (int b = 0; b < k; b++) {
            double s = 0.0;
            for (int i = 0; i < nq; i++) s += N[(size_t)a * nq + i] * tmp[(size_t)b * nq + i];
            out[(size_t)a * k + b] = s;
        }
    for (int a = 0; a < k; a++)
        for (int b = 0; b < a; b++)
            out[(size_t)a * k + b] = out[(size_t)b * k + a] =
                0.5 * (out[(size_t)a * k + b] + out[(size_t)b * k + a]);
}

int fs_cone_build(const sf_equil *q, double p0, fs_cone *C, sf_error *err)
{
    const sf_model *m = q->m;
    memset(C, 0, sizeof *C);
    int nq = m->nq, nc = m->ncon;
    if (nq > FS_CONE_MAXQ || nc == 0) return SF_EINPUT;
    sf_equil f;
    int rc = sf_equil_init(&f, m, q->param == SF_PARAM_DISPLACEMENT ? SF_PARAM_LOAD : q->param,
                           q->group, 0, 0, q->load, err);
    if (rc) return rc;
    size_t qq = (size_t)nq * nq;
    double *z = calloc((size_t)nq + 1, sizeof(double));
    double *H = calloc(qq + 1, sizeof(double));
    double *grad = calloc((size_t)nq + 1, sizeof(double));
    double *gp = calloc((size_t)nq + 1, sizeof(double));
    double *g = calloc((size_t)nc + 1, sizeof(double));
    double *J = calloc((size_t)nc * nq + 1, sizeof(double));
    double *Js = malloc(sizeof(double) * ((size_t)nc * nq + 1));
    double *s = malloc(sizeof(double) * ((size_t)(nc > nq ? nc : nq) + 1));
    double *U = malloc(sizeof(double) * ((size_t)nc * nc + 1));
    double *VT = malloc(sizeof(double) * (qq + 1));
    double *G = malloc(sizeof(double) * (qq + 1));
    double *w = malloc(sizeof(double) * ((size_t)nc + 1));
    double *tmp = NULL, *Qall = NULL;
    if (!z || !H || !grad || !gp || !g || !J || !Js || !s || !U || !VT || !G || !w) {
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
        goto done;
    }
    sf_equil_set_param(&f, p0);
    sf_kin_eval(m, z, 2, &f.k);
    sf_energy_eval(&f.e, &f.k, &f.par, grad, H, nq, gp);
    sf_constraints(m, &f.k, g, J, NULL, NULL, 0);
    /* rows scaled as the equilibrium problem scales them: rotations 1,
     * translations in band widths */
    for (int r = 0; r < nc; r++) {
        double sc = r % 6 < 3 ? 1.0 : 1.0 / f.lref;
        for (int j = 0; j < nq; j++) Js[(size_t)j * nc + r] = sc * J[(size_t)r * nq + j];
    }
    if (svd(nc, nq, Js, s, U, VT)) { rc = sf_fail(err, SF_ENUMERIC, "flat start: SVD failed"); goto done; }
    int kmax = nc < nq ? nc : nq, r1 = 0;
    for (int i = 0; i < kmax; i++)
        if (s[i] > RANK_TOL * s[0]) r1++;
    int k = nq - r1, n2 = nc - r1;
    C->nq = nq;
    C->k = k;
    if (k == 0) goto done;   /* no first-order motion: locked at first order */
    C->N = malloc(sizeof(double) * ((size_t)nq * k + 1));
    C->A = malloc(sizeof(double) * ((size_t)k * k + 1));
    C->c = calloc((size_t)k + 1, sizeof(double));
    tmp = malloc(sizeof(double) * ((size_t)nq * k + 1));
    Qall = malloc(sizeof(double) * ((size_t)(n2 > 0 ? n2 : 1) * k * k + 1));
    if (!C->N || !C->A || !C->c || !tmp || !Qall) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); goto done; }
    /* N: the last k right singular vectors (rows of VT) */
    for (int b = 0; b < k; b++)
        for (int j = 0; j < nq; j++) C->N[(size_t)b * nq + j] = VT[(size_t)j * nq + r1 + b];
    for (size_t i = 0; i < qq; i++) H[i] /= f.kref;
    project(nq, k, C->N, H, C->A, tmp);
    for (int b = 0; b < k; b++) {
        double v = 0.0;
        for (int j = 0; j < nq; j++) v += C->N[(size_t)b * nq + j] * gp[j] / f.kref;
        C->c[b] = v;
    }
    /* the forms of the combinations without gradient */
    for (int t = 0; t < n2; t++) {
        for (int r = 0; r < nc; r++) w[r] = U[(size_t)(r1 + t) * nc + r] * (r % 6 < 3 ? 1.0 : 1.0 / f.lref);
        memset(G, 0, sizeof(double) * qq);
        sf_constraints(m, &f.k, NULL, NULL, w, G, nq);
        project(nq, k, C->N, G, Qall + (size_t)t * k * k, tmp);
    }
    /* an orthonormal basis of their span */
    if (n2 > 0) {
        int kk = k * k;
        double *M = malloc(sizeof(double) * ((size_t)n2 * kk + 1));
        double *sv = malloc(sizeof(double) * ((size_t)(n2 < kk ? n2 : kk) + 1));
        double *V = malloc(sizeof(double) * ((size_t)kk * kk + 1));
        if (!M || !sv || !V) {
            free(M); free(sv); free(V);
            rc = sf_fail(err, SF_ENOMEM, "out of memory");
            goto done;
        }
        /* rows t, columns the entries: column-major n2 x kk */
        for (int t = 0; t < n2; t++)
            for (int e = 0; e < kk; e++) M[(size_t)e * n2 + t] = Qall[(size_t)t * kk + e];
        int mn = n2 < kk ? n2 : kk, nr = 0;
        if (svd(n2, kk, M, sv, NULL, V) == 0) {
            for (int i = 0; i < mn; i++)
                if (sv[i] > RANK_TOL * sv[0]) nr++;
            C->Q = malloc(sizeof(double) * ((size_t)(nr > 0 ? nr : 1) * kk + 1));
            if (C->Q) {
                for (int i = 0; i < nr; i++)
                    for (int e = 0; e < kk; e++) C->Q[(size_t)i * kk + e] = V[(size_t)e * kk + i];
                C->r = nr;
            }
        }
        free(M); free(sv); free(V);
        if (!C->Q && nr > 0) rc = sf_fail(err, SF_ENOMEM, "out of memory");
    }
done:
    free(z); free(H); free(grad); free(gp); free(g); free(J); free(Js); free(s); free(U);
    free(VT); free(G); free(w); free(tmp); free(Qall);
    sf_equil_free(&f);
    if (rc) fs_cone_free(C);
    return rc;
}

/* Levenberg-Marquardt on x^T Q_t x = 0, x^T A x = 1 from x0. */
int fs_cone_ray(const fs_cone *C, const double *x0, double *x, double *res)
{
    int k = C->k, r = C->r, m = r + 1;
    size_t kk = (size_t)k * k;
    double *Jr = malloc(sizeof(double) * ((size_t)m * k + 1));
    double *F = malloc(sizeof(double) * ((size_t)m + 1));
    double *M = malloc(sizeof(double) * (kk + 1));
    double *d = malloc(sizeof(double) * ((size_t)k + 1));
    double *xt = malloc(sizeof(double) * ((size_t)k + 1));
    if (!Jr || !F || !M || !d || !xt) {
        free(Jr); free(F); free(M); free(d); free(xt);
        return -1;
    }
    double n0 = sqrt(fmax(sf_quad_form(k, C->A, x0), 1e-300));
    for (int i = 0; i < k; i++) x[i] = x0[i] / n0;
    double mu = 1e-3, f = INFINITY;
    for (int it = 0; it < 300; it++) {
        f = 0.0;
        for (int t = 0; t <= r; t++) {
            const double *Q = t < r ? C->Q + (size_t)t * kk : C->A;
            double v = sf_quad_form(k, Q, x) - (t < r ? 0.0 : 1.0);
            F[t] = v;
            f += v * v;
            for (int a = 0; a < k; a++) {
                double s = 0.0;
                for (int b = 0; b < k; b++) s += Q[(size_t)a * k + b] * x[b];
                Jr[(size_t)a * m + t] = 2.0 * s;
            }
        }
        double fmax_ = 0.0;
        for (int t = 0; t <= r; t++) fmax_ = fmax(fmax_, fabs(F[t]));
        if (fmax_ <= 1e-13) break;
        for (;;) {
            /* (Jr^T Jr + mu I) d = -Jr^T F */
            for (int a = 0; a < k; a++) {
                double g = 0.0;
                for (int t = 0; t < m; t++) g += Jr[(size_t)a * m + t] * F[t];
                d[a] = -g;
                for (int b = 0; b <= a; b++) {
                    double s = 0.0;
                    for (int t = 0; t < m; t++) s += Jr[(size_t)a * m + t] * Jr[(size_t)b * m + t];
                    M[(size_t)a * k + b] = M[(size_t)b * k + a] = s + (a == b ? mu : 0.0);
                }
            }
            int one = 1, info;
            dposv_("L", &k, &one, M, &k, d, &k, &info);
            if (info) { mu *= 10.0; if (mu > 1e20) break; continue; }
            for (int a = 0; a < k; a++) xt[a] = x[a] + d[a];
            double ft = 0.0;
            for (int t = 0; t <= r; t++) {
                double v = sf_quad_form(k, t < r ? C->Q + (size_t)t * kk : C->A, xt) - (t < r ? 0.0 : 1.0);
                ft += v * v;
            }
            if (ft < f) {
                memcpy(x, xt, sizeof(double) * (size_t)k);
                mu = fmax(mu * 0.3, 1e-15);
                break;
            }
            mu *= 10.0;
            if (mu > 1e20) break;
        }
        if (mu > 1e20) break;
    }
    *res = 0.0;
    for (int t = 0; t < r; t++) *res = fmax(*res, fabs(sf_quad_form(k, C->Q + (size_t)t * kk, x)));
    free(Jr); free(F); free(M); free(d); free(xt);
    return 0;
}

/* The prestress certificate: the largest smallest eigenvalue of
 * sum nu_t Q_t relative to A over |nu| <= 1 (lmi.h), checked with LAPACK at
 * the nu found.  *lmin receives that eigenvalue (> 0: locked), nu (r
 * values) the stress.  0 when it ran. */
int fs_cone_certify(const fs_cone *C, double *lmin, double *nu)
{
    int k = C->k, r = C->r;
    *lmin = -INFINITY;
    if (r == 0) return 0;
    size_t kk = (size_t)k * k;
    /* in the metric of A: L^-1 Q L^-T with A = L L^T, so that the
     * eigenvalues are those of the pencil (sum nu Q, A) */
    double *L = malloc(sizeof(double) * (kk + 1));
    double *B = malloc(sizeof(double) * ((size_t)r * kk + 1));
    double *S = malloc(sizeof(double) * (kk + 1));
    double *ev = malloc(sizeof(double) * ((size_t)k + 1));
    double *wk = malloc(sizeof(double) * (kk + 3 * (size_t)k + 1));
    int rc = (!L || !B || !S || !ev || !wk) ? -1 : 0;
    if (!rc) {
        memcpy(L, C->A, sizeof(double) * kk);
        int info;
        extern void dpotrf_(const char *, const int *, double *, const int *, int *);
        extern void dtrsm_(const char *, const char *, const char *, const char *, const int *,
                           const int *, const double *, const double *, const int *, double *,
                           const int *);
        dpotrf_("L", &k, L, &k, &info);
        if (info) rc = -1;
        double one = 1.0;
        for (int t = 0; !rc && t < r; t++) {
            double *Bt = B + (size_t)t * kk;
            memcpy(Bt, C->Q + (size_t)t * kk, sizeof(double) * kk);
            dtrsm_("L", "L", "N", "N", &k, &k, &one, L, &k, Bt, &k);
            dtrsm_("R", "L", "T", "N", &k, &k, &one, L, &k, Bt, &k);
        }
    }
    double tlo = -INFINITY, amax = 0.0;
    for (int t = 0; !rc && t < r; t++) {
        double f = 0.0;
        for (size_t i = 0; i < kk; i++) f += B[(size_t)t * kk + i] * B[(size_t)t * kk + i];
        amax = fmax(amax, sqrt(f));
    }
    if (!rc) rc = sf_lmi_max_min_eig(k, NULL, r, B, 1.0, amax, 1.0, nu, &tlo, NULL);
    if (!rc) {
        memset(S, 0, sizeof(double) * kk);
        for (int t = 0; t < r; t++)
            for (size_t i = 0; i < kk; i++) S[i] += nu[t] * B[(size_t)t * kk + i];
        int info, lw = (int)(kk + 3 * (size_t)k);
        dsyev_("N", "L", &k, S, &k, ev, wk, &lw, &info);
        if (!info) *lmin = ev[0];
    }
    free(L); free(B); free(S); free(ev); free(wk);
    return rc;
}
