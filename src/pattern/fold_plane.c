/* fold_plane.c - a FOLD frame's plane and its rotation into x-y
 * (fold_plane.h). */
#include "fold_plane.h"

#include <math.h>
#include <string.h>

static void cross(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

int sf_plane_fit(int n, const double (*x)[3], const int *fs, const int *fv, int nf, sf_plane *pl)
{
    memset(pl, 0, sizeof *pl);
    double c[3] = {0, 0, 0}, lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            c[k] += x[i][k] / n;
            lo[k] = fmin(lo[k], x[i][k]);
            hi[k] = fmax(hi[k], x[i][k]);
        }
    double size = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    if (!(size > 0)) size = 1;
    /* covariance, in units of the size to keep it well scaled */
    double C[3][3] = {{0}};
    for (int i = 0; i < n; i++) {
        double d[3] = {(x[i][0] - c[0]) / size, (x[i][1] - c[1]) / size, (x[i][2] - c[2]) / size};
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) C[a][b] += d[a] * d[b];
    }
    double best = -1, nn[3] = {0, 0, 1};
    for (int a = 0; a < 3; a++) {
        double t[3];
        cross(C[a], C[(a + 1) % 3], t);
        double l = sqrt(dot(t, t));
        if (l > best) { best = l; nn[0] = t[0]; nn[1] = t[1]; nn[2] = t[2]; }
    }
    double l = sqrt(dot(nn, nn));
    if (!(l > 0)) { nn[0] = nn[1] = 0; nn[2] = 1; l = 1; }   /* collinear or a point */
    for (int k = 0; k < 3; k++) nn[k] /= l;
    for (int k = 0; k < 3; k++)
        if (fabs(nn[k]) > 1 - 1e-12) {
            double s = nn[k] > 0 ? 1 : -1;
            nn[0] = nn[1] = nn[2] = 0;
            nn[k] = s;
        }
    /* the side: the faces' vector area */
    double A[3] = {0, 0, 0};
    for (int f = 0; f < nf; f++)
        for (int k = fs[f]; k < fs[f + 1]; k++) {
            int p = fv[k], q = fv[k + 1 < fs[f + 1] ? k + 1 : fs[f]];
            double t[3];
            cross(x[p], x[q], t);
            for (int j = 0; j < 3; j++) A[j] += 0.5 * t[j];
        }
    double an = dot(A, nn);
    if (nf > 0 && fabs(an) > 1e-12 * size * size) {
        pl->how = "faces_vertices turn counter-clockwise";
        if (an < 0) for (int k = 0; k < 3; k++) nn[k] = -nn[k];
    } else {
        pl->how = "the normal's largest component is positive (no faces_vertices)";
        int m = 0;
        for (int k = 1; k < 3; k++)
            if (fabs(nn[k]) > fabs(nn[m]) + 1e-12) m = k;
        if (nn[m] < 0) for (int k = 0; k < 3; k++) nn[k] = -nn[k];
    }
    memcpy(pl->n, nn, sizeof nn);
    /* u: the coordinate axis most nearly in the plane (the first of equals) */
    int m = 0;
    for (int k = 1; k < 3; k++)
        if (fabs(nn[k]) < fabs(nn[m]) - 1e-12) m = k;
    double e[3] = {0, 0, 0};
    e[m] = 1;
    double en = dot(e, nn);
    for (int k = 0; k < 3; k++) pl->u[k] = e[k] - en * nn[k];
    double ul = sqrt(dot(pl->u, pl->u));
    for (int k = 0; k < 3; k++) pl->u[k] /= ul;
    for (int k = 0; k < 3; k++)
        if (fabs(pl->u[k]) > 1 - 1e-12) { double s = pl->u[k] > 0 ? 1 : -1; pl->u[0] = pl->u[1] = pl->u[2] = 0; pl->u[k] = s; }
    cross(pl->n, pl->u, pl->v);
    pl->is_xy = nn[2] == 1;
    pl->flat = 1;
    pl->worst = 0;
    for (int i = 0; i < n; i++) {
        double d[3] = {x[i][0] - c[0], x[i][1] - c[1], x[i][2] - c[2]};
        double h = fabs(dot(d, nn));
        if (h > pl->dev) { pl->dev = h; pl->worst = i; }
    }
    pl->flat = pl->dev <= 1e-6 * size;
    return 0;
}

void sf_plane_map(const sf_plane *pl, const double p[3], double out[3])
{
    if (pl->is_xy) { double z = p[2]; out[0] = p[0]; out[1] = p[1]; out[2] = z; return; }
    double r[3] = {dot(p, pl->u), dot(p, pl->v), dot(p, pl->n)};
    out[0] = r[0];
    out[1] = r[1];
    out[2] = r[2];
}
