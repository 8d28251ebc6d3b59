/* tritri.c - the intersection of two triangles and the material
 * separation along it (tritri.h). */
#include "tritri.h"

#include <math.h>
#include <string.h>

static void sub(const double a[3], const double b[3], double c[3])
{
    for (int i = 0; i < 3; i++) c[i] = a[i] - b[i];
}
static double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Unit normal of a triangle; 0 when it has no area. */
static int unit_normal(const sf_tri3 *T, double n[3])
{
    double e1[3], e2[3];
    sub(T->x[1], T->x[0], e1);
    sub(T->x[2], T->x[0], e2);
    cross(e1, e2, n);
    double a = sqrt(dot(n, n)), l = fmax(dot(e1, e1), dot(e2, e2));
    if (!(a > 1e-14 * l)) return 0;   /* zero area, also relative to its size */
    for (int i = 0; i < 3; i++) n[i] /= a;
    return 1;
}

/* A point of the intersection with its barycentric coordinates in either
 * triangle. */
typedef struct ipt {
    double x[3];
    double bp[3], bq[3];
} ipt;

/* Barycentric coordinates of x (in T's plane, unit normal n) in T. */
static void bary(const sf_tri3 *T, const double n[3], const double x[3], double b[3])
{
    double e1[3], e2[3], c[3];
    sub(T->x[1], T->x[0], e1);
    sub(T->x[2], T->x[0], e2);
    cross(e1, e2, c);
    double area2 = dot(c, n);
    double a[3], d[3], e[3];
    sub(T->x[1], x, a);
    sub(T->x[2], x, d);
    cross(a, d, e);
    b[0] = dot(e, n) / area2;
    sub(T->x[2], x, a);
    sub(T->x[0], x, d);
    cross(a, d, e);
    b[1] = dot(e, n) / area2;
    b[2] = 1.0 - b[0] - b[1];
}

/* Append p to the meeting set, as places and material points. */
static void meet_add(const sf_tri3 *P, const sf_tri3 *Q, const ipt *p, sf_tri_meet *M)
{
    if (M->n >= SF_TRI_MEET_MAX) return;
    int k = M->n++;
    memcpy(M->x[k], p->x, sizeof p->x);
    for (int c = 0; c < 2; c++) {
        double xp = 0, xq = 0;
        for (int i = 0; i < 3; i++) {
            xp += p->bp[i] * P->X[i][c];
            xq += p->bq[i] * Q->X[i][c];
        }
        M->XP[k][c] = xp;
        M->XQ[k][c] = xq;
    }
}

double sf_tri_meet_sep(const sf_tri_meet *M, int k)
{
    return hypot(M->XP[k][0] - M->XQ[k][0], M->XP[k][1] - M->XQ[k][1]);
}

double sf_tri_meet_max_sep(const sf_tri_meet *M, int *k_max)
{
    double best = -1;
    int kb = -1;
    for (int k = 0; k < M->n; k++) {
        double s = sf_tri_meet_sep(M, k);
        if (s > best) {
            best = s;
            kb = k;
        }
    }
    if (k_max) *k_max = kb;
    return best;
}

/* The piece of T on the plane its signed distances d refer to: up to two
 * points ordered along the direction D, with T's barycentric coordinates
 * in b.  Returns the number of points (1 or 2), 0 when T misses the plane. */
static int plane_piece(const sf_tri3 *T, const double d[3], const double D[3], double x[2][3],
                       double b[2][3])
{
    double px[4][3], pb[4][3];
    int n = 0;
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3;
        if (d[i] == 0) {
            memcpy(px[n], T->x[i], sizeof px[n]);
            memset(pb[n], 0, sizeof pb[n]);
            pb[n][i] = 1;
            n++;
        }
        if ((d[i] < 0 && d[j] > 0) || (d[i] > 0 && d[j] < 0)) {
            double t = d[i] / (d[i] - d[j]);
            for (int c = 0; c < 3; c++) px[n][c] = T->x[i][c] + t * (T->x[j][c] - T->x[i][c]);
            memset(pb[n], 0, sizeof pb[n]);
            pb[n][i] = 1 - t;
            pb[n][j] = t;
            n++;
        }
    }
    if (n == 0) return 0;
    int lo = 0, hi = 0;
    for (int k = 1; k < n; k++) {
        if (dot(px[k], D) < dot(px[lo], D)) lo = k;
        if (dot(px[k], D) > dot(px[hi], D)) hi = k;
    }
    memcpy(x[0], px[lo], sizeof x[0]);
    memcpy(b[0], pb[lo], sizeof b[0]);
    memcpy(x[1], px[hi], sizeof x[1]);
    memcpy(b[1], pb[hi], sizeof b[1]);
    return lo == hi ? 1 : 2;
}

/* Interpolate along a piece [x0, x1] (barycentric b0, b1) at the line
 * parameter t (dot with D). */
static void along(const double x[2][3], const double b[2][3], const double D[3], double t,
                  double xo[3], double bo[3])
{
    double t0 = dot(x[0], D), t1 = dot(x[1], D);
    double s = t1 > t0 ? (t - t0) / (t1 - t0) : 0.0;
    s = fmin(1.0, fmax(0.0, s));
    for (int c = 0; c < 3; c++) {
        xo[c] = x[0][c] + s * (x[1][c] - x[0][c]);
        bo[c] = b[0][c] + s * (b[1][c] - b[0][c]);
    }
}

/* Planes that cross: the overlap of the two triangles' pieces on the
 * common line. */
static int crossing(const sf_tri3 *P, const sf_tri3 *Q, const double nP[3], const double nQ[3],
                    const double dP[3], const double dQ[3], double eps, sf_tri_meet *M)
{
    double D[3];
    cross(nP, nQ, D);
    double xp[2][3], bp[2][3], xq[2][3], bq[2][3];
    int np = plane_piece(P, dP, D, xp, bp), nq = plane_piece(Q, dQ, D, xq, bq);
    if (!np || !nq) return 0;
    if (np == 1) { memcpy(xp[1], xp[0], sizeof xp[0]); memcpy(bp[1], bp[0], sizeof bp[0]); }
    if (nq == 1) { memcpy(xq[1], xq[0], sizeof xq[0]); memcpy(bq[1], bq[0], sizeof bq[0]); }
    double lD = sqrt(dot(D, D));
    double lo = fmax(dot(xp[0], D), dot(xq[0], D)), hi = fmin(dot(xp[1], D), dot(xq[1], D));
    if (lo > hi + eps * lD) return 0;
    if (lo > hi) lo = hi = 0.5 * (lo + hi);   /* touching within eps */
    for (int e = 0; e < (hi > lo ? 2 : 1); e++) {
        ipt p;
        double xa[3], xb[3];
        along(xp, bp, D, e ? hi : lo, xa, p.bp);
        along(xq, bq, D, e ? hi : lo, xb, p.bq);
        for (int c = 0; c < 3; c++) p.x[c] = 0.5 * (xa[c] + xb[c]);
        meet_add(P, Q, &p, M);
    }
    return 1;
}

/* Coplanar triangles: Q clipped by the three inner half-planes of P (the
 * vertices carry Q's barycentric coordinates, exact under interpolation),
 * the separation at the vertices of what is left. */
static int coplanar(const sf_tri3 *P, const sf_tri3 *Q, const double nP[3], double eps,
                    sf_tri_meet *M)
{
    ipt poly[2][12];
    int n = 3, cur = 0;
    double nQ[3];
    if (!unit_normal(Q, nQ)) return 0;
    for (int i = 0; i < 3; i++) {
        memcpy(poly[0][i].x, Q->x[i], sizeof poly[0][i].x);
        memset(poly[0][i].bq, 0, sizeof poly[0][i].bq);
        poly[0][i].bq[i] = 1;
    }
    /* orientation of P about nP: its inner normals point into it */
    for (int e = 0; e < 3 && n > 0; e++) {
        const double *a = P->x[e], *b = P->x[(e + 1) % 3];
        double ab[3], m[3];
        sub(b, a, ab);
        cross(nP, ab, m);
        double lm = sqrt(dot(m, m));
        if (!(lm > 0)) return 0;
        for (int c = 0; c < 3; c++) m[c] /= lm;
        int nn = 0;
        ipt *in = poly[cur], *out = poly[1 - cur];
        for (int k = 0; k < n; k++) {
            const ipt *s = &in[k], *t = &in[(k + 1) % n];
            double xs[3], xt[3];
            sub(s->x, a, xs);
            sub(t->x, a, xt);
            double hs = dot(m, xs) + eps, ht = dot(m, xt) + eps;
            if (hs >= 0) out[nn++] = *s;
            if ((hs >= 0) != (ht >= 0) && nn < 12) {
                double u = hs / (hs - ht);
                ipt *o = &out[nn++];
                for (int c = 0; c < 3; c++) {
                    o->x[c] = s->x[c] + u * (t->x[c] - s->x[c]);
                    o->bq[c] = s->bq[c] + u * (t->bq[c] - s->bq[c]);
                }
            }
        }
        n = nn;
        cur = 1 - cur;
    }
    if (n == 0) return 0;
    for (int k = 0; k < n; k++) {
        ipt *p = &poly[cur][k];
        bary(P, nP, p->x, p->bp);
        meet_add(P, Q, p, M);
    }
    return 1;
}

int sf_tritri(const sf_tri3 *P, const sf_tri3 *Q, double eps, sf_tri_meet *M)
{
    M->n = 0;
    double nP[3], nQ[3];
    if (!unit_normal(P, nP) || !unit_normal(Q, nQ)) return 0;
    double dP[3], dQ[3], r[3];
    int posP = 0, negP = 0, posQ = 0, negQ = 0;
    for (int i = 0; i < 3; i++) {
        sub(P->x[i], Q->x[0], r);
        dP[i] = dot(nQ, r);
        if (fabs(dP[i]) <= eps) dP[i] = 0;
        posP += dP[i] > 0;
        negP += dP[i] < 0;
        sub(Q->x[i], P->x[0], r);
        dQ[i] = dot(nP, r);
        if (fabs(dQ[i]) <= eps) dQ[i] = 0;
        posQ += dQ[i] > 0;
        negQ += dQ[i] < 0;
    }
    if (posP == 3 || negP == 3 || posQ == 3 || negQ == 3) return 0;
    if ((posP == 0 && negP == 0) || (posQ == 0 && negQ == 0)) return coplanar(P, Q, nP, eps, M);
    return crossing(P, Q, nP, nQ, dP, dQ, eps, M);
}
