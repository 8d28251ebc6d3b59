/* poses.c - face-pose kinematics (MODEL.md 9): rotations by rotation
 * vector, the six rows of each fold, material points, and the fixed-order
 * sparse assembly (see poses.h). */
#include "poses.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "shape.h"

int sf_poses_init(sf_poses *P, const sf_model *m, sf_error *err)
{
    memset(P, 0, sizeof *P);
    const sf_topology *t = m->topo;
    P->m = m;
    P->nq = m->nq;
    P->pose_of = malloc(sizeof(int) * ((size_t)t->nfaces + 1));
    P->o = calloc(3 * ((size_t)t->nfaces + 1), sizeof(double));
    if (!P->pose_of || !P->o) {
        sf_poses_free(P);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int f = 0; f < t->nfaces; f++) {
        P->pose_of[f] = f == t->root ? -1 : P->nfree++;
        P->o[3 * f] = t->faces[f].centroid[0];
        P->o[3 * f + 1] = t->faces[f].centroid[1];
    }
    P->nx = P->nq + 6 * P->nfree;
    P->nrows = 6 * m->nfolds;
    P->maxnv = m->maxqn + 12;
    return SF_OK;
}

void sf_poses_free(sf_poses *P)
{
    free(P->pose_of);
    free(P->o);
    memset(P, 0, sizeof *P);
}

size_t sf_poses_work_size(const sf_poses *P)
{
    size_t q = (size_t)P->m->maxqn;
    return 6 * q * q + 8 * q + 16;
}

/* ------------------------------------------------------------ rotations */

/* A = sin t / t, B = (1 - cos t) / t^2 as functions of s = t^2, with their
 * first and second derivatives in s: c = (A, A', A'', B, B', B'').  For
 * s < 4 (t < 2) by their power series, A = sum (-s)^k / (2k+1)!,
 * B = sum (-s)^k / (2k+2)!, ROD_TERMS terms summed upwards.  The
 * coefficients are the values of the recurrence fa /= (2k+2)(2k+3),
 * fb /= (2k+3)(2k+4) from fa = 1, fb = 1/2, bit for bit (hexadecimal
 * literals): a table instead of two divisions per term. */
#define ROD_TERMS 26
static const double rod_ca[ROD_TERMS] = {   /* (-1)^k / (2k+1)! */
    0x1p+0, -0x1.5555555555555p-3, 0x1.1111111111111p-7, -0x1.a01a01a01a01ap-13,
    0x1.71de3a556c734p-19, -0x1.ae64567f544e4p-26, 0x1.6124613a86d0ap-33, -0x1.ae7f3e733b82p-41,
    0x1.952c77030ad4bp-49, -0x1.2f49b46814158p-57, 0x1.71b8ef6dcf573p-66, -0x1.761b41316381bp-75,
    0x1.3f3ccdd165faap-84, -0x1.d1ab1c2dccea5p-94, 0x1.259f98b4358afp-103, -0x1.434d2e783f5bep-113,
    0x1.3981254dd0d53p-123, -0x1.0dc59c716d92p-133, 0x1.9ec8d1c94e85cp-144, -0x1.1e99449a4bacfp-154,
    0x1.65e61c39d0242p-165, -0x1.95db45257e514p-176, 0x1.a3cb872220649p-187, -0x1.8da8e0a127ebbp-198,
    0x1.5a42f0dfeb087p-209, -0x1.161872bf7b824p-220
};
static const double rod_cb[ROD_TERMS] = {   /* (-1)^k / (2k+2)! */
    0x1p-1, -0x1.5555555555555p-5, 0x1.6c16c16c16c16p-10, -0x1.a01a01a01a019p-16,
    0x1.27e4fb7789f5cp-22, -0x1.1eed8eff8d897p-29, 0x1.93974a8c07c9cp-37, -0x1.ae7f3e733b81ep-45,
    0x1.6827863b97d97p-53, -0x1.e542ba4020224p-62, 0x1.0ce396db7f852p-70, -0x1.f2cf01972f577p-80,
    0x1.88e85fc6a4e59p-89, -0x1.0a18a2635085dp-98, 0x1.3932c5047d60ep-108, -0x1.434d2e783f5bcp-118,
    0x1.2710231c0fd7ap-128, -0x1.df983290c2ca9p-139, 0x1.5d4acb9c0c3abp-149, -0x1.ca8ed42a12ae3p-160,
    0x1.10af527530de8p-170, -0x1.272b1b03fec6ap-181, 0x1.240804f65951p-192, -0x1.091b406b6ff26p-203,
    0x1.bb36f6e12cd77p-215, -0x1.56457989358c8p-226
};

static void rod_coef(double s, double c[6])
{
    if (s < 4.0) {
        double A = 0, A1 = 0, A2 = 0, B = 0, B1 = 0, B2 = 0;
        double pk = 1.0, pk1 = 0.0, pk2 = 0.0;   /* s^k, s^(k-1), s^(k-2) */
        for (int k = 0; k < ROD_TERMS; k++) {
            double ca = rod_ca[k], cb = rod_cb[k];
            A += ca * pk;
            A1 += ca * k * pk1;
            A2 += ca * k * (k - 1) * pk2;
            B += cb * pk;
            B1 += cb * k * pk1;
            B2 += cb * k * (k - 1) * pk2;
            pk2 = pk1;
            pk1 = pk;
            pk *= s;
        }
        c[0] = A; c[1] = A1; c[2] = A2; c[3] = B; c[4] = B1; c[5] = B2;
        return;
    }
    double t = sqrt(s), st = sin(t), ct = cos(t), t3 = s * t;
    double A = st / t, Ad = (t * ct - st) / s, Add = -st / t - 2.0 * ct / s + 2.0 * st / t3;
    double B = (1.0 - ct) / s, Bd = st / s - 2.0 * (1.0 - ct) / t3,
           Bdd = ct / s - 4.0 * st / t3 + 6.0 * (1.0 - ct) / (s * s);
    c[0] = A;
    c[1] = Ad / (2.0 * t);
    c[2] = (Add - Ad / t) / (4.0 * s);
    c[3] = B;
    c[4] = Bd / (2.0 * t);
    c[5] = (Bdd - Bd / t) / (4.0 * s);
}

static void skew(const double v[3], double K[9])
{
    K[0] = 0.0;   K[1] = -v[2]; K[2] = v[1];
    K[3] = v[2];  K[4] = 0.0;   K[5] = -v[0];
    K[6] = -v[1]; K[7] = v[0];  K[8] = 0.0;
}

static void mat_mul(const double A[9], const double B[9], double C[9])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = A[3 * r] * B[c] + A[3 * r + 1] * B[3 + c] + A[3 * r + 2] * B[6 + c];
}

/* C = A^T B */
static void mat_tmul(const double A[9], const double B[9], double C[9])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            C[3 * r + c] = A[r] * B[c] + A[3 + r] * B[3 + c] + A[6 + r] * B[6 + c];
}

static void mat_vec(const double A[9], const double x[3], double y[3])
{
    for (int r = 0; r < 3; r++) y[r] = A[3 * r] * x[0] + A[3 * r + 1] * x[1] + A[3 * r + 2] * x[2];
}

void sf_rodrigues(const double phi[3], double R[9], double dR[3][9], double d2R[9][9])
{
    double s = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2], c[6];
    rod_coef(s, c);
    double K[9], K2[9];
    skew(phi, K);
    mat_mul(K, K, K2);
    for (int i = 0; i < 9; i++) R[i] = (i % 4 == 0 ? 1.0 : 0.0) + c[0] * K[i] + c[3] * K2[i];
    if (!dR) return;
    /* E_a = [e_a]x; with [u]x [v]x = v u^T - (u.v) I:
     * EK_a = E_a K + K E_a = phi e_a^T + e_a phi^T - 2 phi_a I and
     * E_a E_b + E_b E_a = e_b e_a^T + e_a e_b^T - 2 delta_ab I */
    double E[3][9], EK[3][9];
    for (int a = 0; a < 3; a++) {
        double e[3] = {0, 0, 0};
        e[a] = 1.0;
        skew(e, E[a]);
        for (int r = 0; r < 3; r++)
            for (int q = 0; q < 3; q++)
                EK[a][3 * r + q] = (q == a ? phi[r] : 0.0) + (r == a ? phi[q] : 0.0) -
                                   (r == q ? 2.0 * phi[a] : 0.0);
    }
    for (int a = 0; a < 3; a++)
        for (int i = 0; i < 9; i++)
            dR[a][i] = 2.0 * c[1] * phi[a] * K[i] + c[0] * E[a][i] + 2.0 * c[4] * phi[a] * K2[i] +
                       c[3] * EK[a][i];
    if (!d2R) return;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double EE[9], d = a == b ? 1.0 : 0.0;
            for (int r = 0; r < 3; r++)
                for (int q = 0; q < 3; q++)
                    EE[3 * r + q] = (r == b && q == a ? 1.0 : 0.0) + (r == a && q == b ? 1.0 : 0.0) -
                                    (r == q ? 2.0 * d : 0.0);
            for (int i = 0; i < 9; i++)
                d2R[3 * a + b][i] =
                    (4.0 * c[2] * phi[a] * phi[b] + 2.0 * c[1] * d) * K[i] +
                    2.0 * c[1] * (phi[a] * E[b][i] + phi[b] * E[a][i]) +
                    (4.0 * c[5] * phi[a] * phi[b] + 2.0 * c[4] * d) * K2[i] +
                    2.0 * c[4] * (phi[a] * EK[b][i] + phi[b] * EK[a][i]) + c[3] * EE[i];
        }
}

void sf_rotation_log(const double R[9], double phi[3])
{
    double tr = R[0] + R[4] + R[8];
    double ca = fmax(-1.0, fmin(1.0, 0.5 * (tr - 1.0)));
    double ang = acos(ca);
    double v[3] = {0.5 * (R[7] - R[5]), 0.5 * (R[2] - R[6]), 0.5 * (R[3] - R[1])};
    if (ang < 1e-6) {
        /* R = I + [phi]x + O(phi^2): the axial vector, corrected to third order */
        for (int i = 0; i < 3; i++) phi[i] = v[i] * (1.0 + ang * ang / 6.0);
        return;
    }
    if (ang < M_PI - 1e-4) {
        double f = ang / sin(ang);
        for (int i = 0; i < 3; i++) phi[i] = f * v[i];
        return;
    }
    /* near pi: axis from the symmetric part (R + I)/2 = u u^T */
    int k = 0;
    for (int i = 1; i < 3; i++)
        if (R[4 * i] > R[4 * k]) k = i;
    double u[3];
    for (int i = 0; i < 3; i++) u[i] = 0.5 * (R[3 * i + k] + R[3 * k + i]) + (i == k ? 0.5 * (1.0 - tr) : 0.0);
    double nu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    double sgn = (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) < 0 ? -1.0 : 1.0;
    for (int i = 0; i < 3; i++) phi[i] = sgn * ang * u[i] / nu;
}

void sf_poses_face(const sf_poses *P, const double *x, int f, double R[9], double t[3])
{
    int k = P->pose_of[f];
    if (k < 0) {
        for (int i = 0; i < 9; i++) R[i] = i % 4 == 0 ? 1.0 : 0.0;
        memcpy(t, P->o + 3 * f, sizeof(double) * 3);
        return;
    }
    const double *v = x + P->nq + 6 * k;
    sf_rodrigues(v, R, NULL, NULL);
    memcpy(t, v + 3, sizeof(double) * 3);
}

/* Pose variables of face f: phi (3), then xf (3); identity for the fixed face. */
static void face_pose(const sf_poses *P, const double *x, int f, double phi[3], double xf[3])
{
    int k = P->pose_of[f];
    if (k < 0) {
        phi[0] = phi[1] = phi[2] = 0.0;
        memcpy(xf, P->o + 3 * f, sizeof(double) * 3);
        return;
    }
    memcpy(phi, x + P->nq + 6 * k, sizeof(double) * 3);
    memcpy(xf, x + P->nq + 6 * k + 3, sizeof(double) * 3);
}

static void pose_cols(const sf_poses *P, int f, int *col)
{
    int k = P->pose_of[f];
    for (int a = 0; a < 6; a++) col[a] = k < 0 ? -1 : P->nq + 6 * k + a;
}

int sf_poses_fold_vars(const sf_poses *P, int fold, int *col)
{
    const sf_model *m = P->m;
    int qn = m->qn[fold];
    for (int j = 0; j < qn; j++) col[j] = m->qoff[fold] + j;
    pose_cols(P, m->topo->folds[fold].right, col + qn);
    pose_cols(P, m->topo->folds[fold].left, col + qn + 6);
    return qn + 12;
}

int sf_poses_point_vars(const sf_poses *P, int f, int fold, int *col)
{
    const sf_model *m = P->m;
    int qn = fold >= 0 ? m->qn[fold] : 0;
    for (int j = 0; j < qn; j++) col[j] = m->qoff[fold] + j;
    pose_cols(P, f, col + qn);
    return qn + 6;
}

/* ------------------------------------------------------------ fold rows */

/* lam . axial(M), axial(M) = (M32 - M23, M13 - M31, M21 - M12) / 2 */
static double lin_axial(const double lam[3], const double M[9])
{
    return 0.5 * (lam[0] * (M[7] - M[5]) + lam[1] * (M[2] - M[6]) + lam[2] * (M[3] - M[1]));
}

static void axial(const double M[9], double g[3])
{
    g[0] = 0.5 * (M[7] - M[5]);
    g[1] = 0.5 * (M[2] - M[6]);
    g[2] = 0.5 * (M[3] - M[1]);
}

/* Rot^T A^T B for the rotation rows */
static void rtab(const double Rot[9], const double A[9], const double B[9], double M[9])
{
    double t[9];
    mat_tmul(A, B, t);
    mat_tmul(Rot, t, M);
}

void sf_poses_fold_rows(const sf_poses *P, const double *x, int fold, double g[6],
                        double *dg, const double *lam, double *H, double *work)
{
    const sf_model *m = P->m;
    const sf_fold_geom *G = &m->topo->folds[fold];
    const sf_section *sec = &m->sec[fold];
    int qn = sec->nq, nv = qn + 12, r = G->right, l = G->left;
    const double *q = x + m->qoff[fold];
    int order = H && lam ? 2 : dg ? 1 : 0;
    double w = sec->w;
    double mm[3] = {G->m[0], G->m[1], 0.0}, nn[3] = {G->n[0], G->n[1], 0.0};
    double phir[3], xr[3], phil[3], xl[3];
    face_pose(P, x, r, phir, xr);
    face_pose(P, x, l, phil, xl);
    double Rr[9], dRr[3][9], d2Rr[9][9], Rl[9], dRl[3][9], d2Rl[9][9];
    sf_rodrigues(phir, Rr, order >= 1 ? dRr : NULL, order >= 2 ? d2Rr : NULL);
    sf_rodrigues(phil, Rl, order >= 1 ? dRl : NULL, order >= 2 ? d2Rl : NULL);
    double Rot[9], Km[9], dRot[9], d2Rot[9];
    sf_rotation(mm, q[0], Rot);
    skew(mm, Km);
    mat_mul(Km, Rot, dRot);
    mat_mul(Km, dRot, d2Rot);
    double *dc = work, *d2c = work + 2 * qn, c[2];
    sf_section_integral(sec, SF_SEC_CHORD, q, c, order >= 1 ? dc : NULL, order >= 2 ? d2c : NULL);
    double pR[3], pL[3], c3[3], uR[3], uL[3];
    for (int i = 0; i < 3; i++) {
        double a = i < 2 ? G->a[i] : 0.0;
        pR[i] = a - 0.5 * w * nn[i];
        pL[i] = a + 0.5 * w * nn[i];
        c3[i] = c[0] * nn[i] + (i == 2 ? c[1] : 0.0);
        uR[i] = pR[i] - P->o[3 * r + i] + c3[i];
        uL[i] = pL[i] - P->o[3 * l + i];
    }
    /* rotation rows */
    double M[9];
    rtab(Rot, Rr, Rl, M);
    axial(M, g);
    /* translation rows */
    double a1[3], a2[3];
    mat_vec(Rl, uL, a1);
    mat_vec(Rr, uR, a2);
    for (int i = 0; i < 3; i++) g[3 + i] = xl[i] + a1[i] - xr[i] - a2[i];
    if (order < 1) return;
    int ir = qn, il = qn + 6;     /* local offsets of phi_r, phi_l (x follows at +3) */
    if (dg) {
        memset(dg, 0, sizeof(double) * 6 * (size_t)nv);
        double D[9], gg[3], v[3];
        rtab(dRot, Rr, Rl, D);     /* d/dtheta: dRot^T Rr^T Rl */
        axial(D, gg);
        for (int c2 = 0; c2 < 3; c2++) dg[c2 * nv] = gg[c2];
        for (int a = 0; a < 3; a++) {
            rtab(Rot, dRr[a], Rl, D);
            axial(D, gg);
            for (int c2 = 0; c2 < 3; c2++) dg[c2 * nv + ir + a] = gg[c2];
            rtab(Rot, Rr, dRl[a], D);
            axial(D, gg);
            for (int c2 = 0; c2 < 3; c2++) dg[c2 * nv + il + a] = gg[c2];
        }
        for (int j = 0; j < qn; j++) {
            double dc3[3] = {dc[j] * nn[0], dc[j] * nn[1], dc[qn + j]};
            mat_vec(Rr, dc3, v);
            for (int i = 0; i < 3; i++) dg[(3 + i) * nv + j] = -v[i];
        }
        for (int a = 0; a < 3; a++) {
            mat_vec(dRr[a], uR, v);
            for (int i = 0; i < 3; i++) dg[(3 + i) * nv + ir + a] = -v[i];
            mat_vec(dRl[a], uL, v);
            for (int i = 0; i < 3; i++) dg[(3 + i) * nv + il + a] = v[i];
        }
        for (int i = 0; i < 3; i++) {
            dg[(3 + i) * nv + ir + 3 + i] = -1.0;
            dg[(3 + i) * nv + il + 3 + i] = 1.0;
        }
    }
    if (order < 2) return;
    memset(H, 0, sizeof(double) * (size_t)nv * nv);
    const double *lr = lam, *lt = lam + 3;
    double D[9], v[3];
#define HS(i, j, val) do { double hv_ = (val); H[(size_t)(i) * nv + (j)] += hv_; \
        if ((i) != (j)) H[(size_t)(j) * nv + (i)] += hv_; } while (0)
    /* rotation rows */
    rtab(d2Rot, Rr, Rl, D);
    HS(0, 0, lin_axial(lr, D));
    for (int a = 0; a < 3; a++) {
        rtab(dRot, dRr[a], Rl, D);
        HS(0, ir + a, lin_axial(lr, D));
        rtab(dRot, Rr, dRl[a], D);
        HS(0, il + a, lin_axial(lr, D));
        for (int b = 0; b < 3; b++) {
            if (b >= a) {
                rtab(Rot, d2Rr[3 * a + b], Rl, D);
                HS(ir + a, ir + b, lin_axial(lr, D));
                rtab(Rot, Rr, d2Rl[3 * a + b], D);
                HS(il + a, il + b, lin_axial(lr, D));
            }
            rtab(Rot, dRr[a], dRl[b], D);
            HS(ir + a, il + b, lin_axial(lr, D));
        }
    }
    /* translation rows */
    for (int j = 0; j < qn; j++) {
        for (int k = j; k < qn; k++) {
            double d2c3[3] = {d2c[j * qn + k] * nn[0], d2c[j * qn + k] * nn[1],
                              d2c[(qn + j) * qn + k]};
            mat_vec(Rr, d2c3, v);
            HS(j, k, -(lt[0] * v[0] + lt[1] * v[1] + lt[2] * v[2]));
        }
        double dc3[3] = {dc[j] * nn[0], dc[j] * nn[1], dc[qn + j]};
        for (int a = 0; a < 3; a++) {
            mat_vec(dRr[a], dc3, v);
            HS(j, ir + a, -(lt[0] * v[0] + lt[1] * v[1] + lt[2] * v[2]));
        }
    }
    for (int a = 0; a < 3; a++)
        for (int b = a; b < 3; b++) {
            mat_vec(d2Rr[3 * a + b], uR, v);
            HS(ir + a, ir + b, -(lt[0] * v[0] + lt[1] * v[1] + lt[2] * v[2]));
            mat_vec(d2Rl[3 * a + b], uL, v);
            HS(il + a, il + b, lt[0] * v[0] + lt[1] * v[1] + lt[2] * v[2]);
        }
#undef HS
}

/* ------------------------------------------------------------ points */

void sf_poses_point(const sf_poses *P, const double *x, int f, int fold, int kind,
                    const double Xr[2], double tpos, double s, double xo[3], double *dx,
                    const double *w, double *H, double *work)
{
    const sf_model *m = P->m;
    int qn = fold >= 0 ? m->qn[fold] : 0, nv = qn + 6;
    int order = H && w ? 2 : dx ? 1 : 0;
    double phi[3], xf[3], R[9], dR[3][9], d2R[9][9];
    face_pose(P, x, f, phi, xf);
    sf_rodrigues(phi, R, order >= 1 ? dR : NULL, order >= 2 ? d2R : NULL);
    double y[3];
    double *dy = work, *d2y = work + 3 * (size_t)qn;   /* 3 x qn, 3 x qn x qn */
    if (fold >= 0) {
        const sf_fold_geom *g = &m->topo->folds[fold];
        const sf_section *sec = &m->sec[fold];
        const double *qi = x + m->qoff[fold];
        double rr[2], *dr = d2y + 3 * (size_t)qn * qn, *d2r = dr + 2 * qn;
        if (kind == SF_SEC_CENTROID)
            sf_section_integral(sec, SF_SEC_CENTROID, qi, rr, order >= 1 ? dr : NULL,
                                order >= 2 ? d2r : NULL);
        else
            sf_section_point(sec, qi, s, rr, order >= 1 ? dr : NULL, order >= 2 ? d2r : NULL);
        for (int c = 0; c < 2; c++)
            y[c] = g->a[c] + tpos * g->m[c] - 0.5 * sec->w * g->n[c] + rr[0] * g->n[c];
        y[2] = rr[1];
        if (order >= 1)
            for (int j = 0; j < qn; j++) {
                dy[j] = dr[j] * g->n[0];
                dy[qn + j] = dr[j] * g->n[1];
                dy[2 * qn + j] = dr[qn + j];
            }
        if (order >= 2)
            for (int j = 0; j < qn; j++)
                for (int k = 0; k < qn; k++) {
                    d2y[(0 * qn + j) * qn + k] = d2r[j * qn + k] * g->n[0];
                    d2y[(1 * qn + j) * qn + k] = d2r[j * qn + k] * g->n[1];
                    d2y[(2 * qn + j) * qn + k] = d2r[(qn + j) * qn + k];
                }
    } else {
        y[0] = Xr[0];
        y[1] = Xr[1];
        y[2] = 0.0;
    }
    double u[3] = {y[0] - P->o[3 * f], y[1] - P->o[3 * f + 1], y[2] - P->o[3 * f + 2]}, v[3];
    mat_vec(R, u, v);
    for (int i = 0; i < 3; i++) xo[i] = xf[i] + v[i];
    if (dx) {
        memset(dx, 0, sizeof(double) * 3 * (size_t)nv);
        for (int j = 0; j < qn; j++) {
            double dyj[3] = {dy[j], dy[qn + j], dy[2 * qn + j]};
            mat_vec(R, dyj, v);
            for (int i = 0; i < 3; i++) dx[i * nv + j] = v[i];
        }
        for (int a = 0; a < 3; a++) {
            mat_vec(dR[a], u, v);
            for (int i = 0; i < 3; i++) dx[i * nv + qn + a] = v[i];
        }
        for (int i = 0; i < 3; i++) dx[i * nv + qn + 3 + i] = 1.0;
    }
    if (order < 2) return;
    memset(H, 0, sizeof(double) * (size_t)nv * nv);
    for (int j = 0; j < qn; j++) {
        for (int k = 0; k < qn; k++) {
            double d[3] = {d2y[(0 * qn + j) * qn + k], d2y[(1 * qn + j) * qn + k],
                           d2y[(2 * qn + j) * qn + k]};
            mat_vec(R, d, v);
            H[j * nv + k] = w[0] * v[0] + w[1] * v[1] + w[2] * v[2];
        }
        double dyj[3] = {dy[j], dy[qn + j], dy[2 * qn + j]};
        for (int a = 0; a < 3; a++) {
            mat_vec(dR[a], dyj, v);
            double h = w[0] * v[0] + w[1] * v[1] + w[2] * v[2];
            H[j * nv + qn + a] = h;
            H[(qn + a) * nv + j] = h;
        }
    }
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            mat_vec(d2R[3 * a + b], u, v);
            H[(qn + a) * nv + qn + b] = w[0] * v[0] + w[1] * v[1] + w[2] * v[2];
        }
}

void sf_poses_mpoint(const sf_poses *P, const double *x, const sf_mpoint *p, double xo[3],
                     double *dx, const double *w, double *H, double *work)
{
    sf_poses_point(P, x, p->face, p->fold, SF_SEC_CHORD, p->X, p->tpos, p->s, xo, dx, w, H, work);
}

int sf_poses_from_folds(const sf_poses *P, const double *q, double *x)
{
    const sf_model *m = P->m;
    sf_kin k;
    if (sf_kin_alloc(m, &k)) return SF_ENOMEM;
    sf_kin_eval(m, q, 0, &k);
    if (x != q) memcpy(x, q, sizeof(double) * (size_t)P->nq);
    for (int f = 0; f < m->nfaces; f++) {
        int kk = P->pose_of[f];
        if (kk < 0) continue;
        const double *A = k.X + 12 * f;
        double R[9];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) R[3 * r + c] = A[4 * r + c];
        double *v = x + P->nq + 6 * kk;
        sf_rotation_log(R, v);
        sf_affine_apply(A, P->o + 3 * f, v + 3);
    }
    sf_kin_free(&k);
    return SF_OK;
}

/* d(log R) = Jl^-1(phi) omega for a spatial angular velocity omega
 * (dR = [omega]x R), R = exp([phi]x): Jl^-1 = I - [phi]x / 2 + c [phi]x^2,
 * c = 1/t^2 - (1 + cos t) / (2 t sin t) (series below t = 1e-3). */
static void dlog_left(const double phi[3], const double w[3], double out[3])
{
    double t2 = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2], t = sqrt(t2);
    double c = t < 1e-3 ? 1.0 / 12.0 + t2 / 720.0
                        : 1.0 / t2 - (1.0 + cos(t)) / (2.0 * t * sin(t));
    double pw[3] = {phi[1] * w[2] - phi[2] * w[1], phi[2] * w[0] - phi[0] * w[2],
                    phi[0] * w[1] - phi[1] * w[0]};
    double ppw[3] = {phi[1] * pw[2] - phi[2] * pw[1], phi[2] * pw[0] - phi[0] * pw[2],
                     phi[0] * pw[1] - phi[1] * pw[0]};
    for (int a = 0; a < 3; a++) out[a] = w[a] - 0.5 * pw[a] + c * ppw[a];
}

/* Ad_X xi for X = (R, t) (12 values, row-major 3 x 4) and xi = (omega, v):
 * (R omega, R v + t x R omega). */
static void adjoint_apply(const double X[12], const double xi[6], double out[6])
{
    double w[3], v[3];
    for (int r = 0; r < 3; r++) {
        w[r] = X[4 * r] * xi[0] + X[4 * r + 1] * xi[1] + X[4 * r + 2] * xi[2];
        v[r] = X[4 * r] * xi[3] + X[4 * r + 1] * xi[4] + X[4 * r + 2] * xi[5];
    }
    double t[3] = {X[3], X[7], X[11]};
    out[0] = w[0];
    out[1] = w[1];
    out[2] = w[2];
    out[3] = v[0] + t[1] * w[2] - t[2] * w[1];
    out[4] = v[1] + t[2] * w[0] - t[0] * w[2];
    out[5] = v[2] + t[0] * w[1] - t[1] * w[0];
}

int sf_poses_from_folds_dir(const sf_poses *P, const double *q, const double *dq, double *dx)
{
    const sf_model *m = P->m;
    const sf_topology *t = m->topo;
    sf_kin k;
    if (sf_kin_alloc(m, &k)) return SF_ENOMEM;
    double *V = calloc((size_t)m->nfaces * 6 + 1, sizeof(double));
    if (!V) {
        sf_kin_free(&k);
        return SF_ENOMEM;
    }
    sf_kin_eval(m, q, 1, &k);
    memcpy(dx, dq, sizeof(double) * (size_t)P->nq);
    /* spatial twists V_f = dX_f X_f^-1 down the tree: X_f = X_p T gives
     * V_f = V_p + Ad_{X_p} xi, X_f = X_p T^-1 gives V_f = V_p - Ad_{X_f} xi,
     * xi = sum_j (dT/dq_j T^-1) dq_j over the parent fold's coordinates */
    for (int n = 0; n < t->nfaces; n++) {
        int f = t->order[n], p = t->faces[f].parent;
        if (p < 0) continue;
        int fold = t->faces[f].parent_fold;
        double xi[6] = {0}, ad[6];
        for (int j = m->qoff[fold]; j < m->qoff[fold] + m->qn[fold]; j++)
            for (int a = 0; a < 6; a++) xi[a] += k.xi[6 * j + a] * dq[j];
        int left = t->folds[fold].left == f;
        adjoint_apply(left ? k.X + 12 * p : k.X + 12 * f, xi, ad);
        for (int a = 0; a < 6; a++) V[6 * f + a] = V[6 * p + a] + (left ? ad[a] : -ad[a]);
    }
    /* pose (phi, xf): dphi = Jl^-1 omega, dxf = omega x xf + v */
    for (int f = 0; f < m->nfaces; f++) {
        int kk = P->pose_of[f];
        if (kk < 0) continue;
        const double *A = k.X + 12 * f, *w = V + 6 * f;
        double R[9], phi[3], xf[3];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) R[3 * r + c] = A[4 * r + c];
        sf_rotation_log(R, phi);
        sf_affine_apply(A, P->o + 3 * f, xf);
        double *d = dx + P->nq + 6 * kk;
        dlog_left(phi, w, d);
        d[3] = w[1] * xf[2] - w[2] * xf[1] + w[3];
        d[4] = w[2] * xf[0] - w[0] * xf[2] + w[4];
        d[5] = w[0] * xf[1] - w[1] * xf[0] + w[5];
    }
    free(V);
    sf_kin_free(&k);
    return SF_OK;
}

/* ------------------------------------------------------------ triplets */

void sf_trip_begin(sf_triplets *t, int n)
{
    sf_trip_free(t);
    t->n = n;
    t->recording = 1;
}

void sf_trip_add(sf_triplets *t, int i, int j, double v)
{
    if (i < 0 || j < 0) return;
    if (!t->recording) {
        t->val[t->map[t->k++]] += v;
        return;
    }
    if (t->ncalls == t->cap) {
        long cap = t->cap ? 2 * t->cap : 1024;
        int *ri = realloc(t->ri, sizeof(int) * (size_t)cap);
        if (ri) t->ri = ri;
        int *ci = realloc(t->ci, sizeof(int) * (size_t)cap);
        if (ci) t->ci = ci;
        if (!ri || !ci) { t->oom = 1; return; }
        t->cap = cap;
    }
    t->ri[t->ncalls] = i;
    t->ci[t->ncalls] = j;
    t->ncalls++;
}

/* CSC from the recorded positions: counting sort by column, then by row
 * within each column (a second counting pass), duplicates merged. */
int sf_trip_finish(sf_triplets *t)
{
    if (t->oom) return SF_ENOMEM;
    long nc = t->ncalls;
    int n = t->n;
    long *cnt = calloc((size_t)n + 1, sizeof(long));
    long *byrow = malloc(sizeof(long) * ((size_t)nc + 1));
    long *bycol = malloc(sizeof(long) * ((size_t)nc + 1));
    t->map = malloc(sizeof(long) * ((size_t)nc + 1));
    t->colptr = calloc((size_t)n + 1, sizeof(long));
    t->rowind = malloc(sizeof(int) * ((size_t)nc + 1));
    if (!cnt || !byrow || !bycol || !t->map || !t->colptr || !t->rowind) {
        free(cnt); free(byrow); free(bycol);
        return SF_ENOMEM;
    }
    /* sort calls by row */
    for (long k = 0; k < nc; k++) cnt[t->ri[k] + 1]++;
    for (int i = 0; i < n; i++) cnt[i + 1] += cnt[i];
    for (long k = 0; k < nc; k++) byrow[cnt[t->ri[k]]++] = k;
    /* stable sort by column: rows stay ascending within a column */
    memset(cnt, 0, sizeof(long) * ((size_t)n + 1));
    for (long k = 0; k < nc; k++) cnt[t->ci[k] + 1]++;
    for (int j = 0; j < n; j++) cnt[j + 1] += cnt[j];
    for (long kk = 0; kk < nc; kk++) {
        long k = byrow[kk];
        bycol[cnt[t->ci[k]]++] = k;
    }
    long nnz = 0;
    int lastc = -1, lastr = -1;
    for (long kk = 0; kk < nc; kk++) {
        long k = bycol[kk];
        int c = t->ci[k], r = t->ri[k];
        if (c != lastc || r != lastr) {
            t->rowind[nnz] = r;
            t->colptr[c + 1]++;
            nnz++;
            lastc = c;
            lastr = r;
        }
        t->map[k] = nnz - 1;
    }
    for (int j = 0; j < n; j++) t->colptr[j + 1] += t->colptr[j];
    t->nnz = nnz;
    free(cnt); free(byrow); free(bycol);
    free(t->ri); free(t->ci);
    t->ri = t->ci = NULL;
    t->val = calloc((size_t)nnz + 1, sizeof(double));
    if (!t->val) return SF_ENOMEM;
    t->recording = 0;
    return SF_OK;
}

void sf_trip_zero(sf_triplets *t)
{
    t->k = 0;
    if (t->val) memset(t->val, 0, sizeof(double) * (size_t)t->nnz);
}

void sf_trip_free(sf_triplets *t)
{
    free(t->ri); free(t->ci); free(t->map); free(t->colptr); free(t->rowind); free(t->val);
    memset(t, 0, sizeof *t);
}
