/* topology_geom.c - 2-D geometry for the topology (topology_impl.h):
 * orientation of a point against a segment, point-segment and
 * segment-segment distances, proper crossings, polygon area, centroid and
 * point classification (sf_polygon_contains). */
#include "topology_impl.h"

#include <math.h>

void tp_sub2(const double a[2], const double b[2], double r[2])
{
    r[0] = a[0] - b[0];
    r[1] = a[1] - b[1];
}

/* Signed distance of r from the line through p, q (positive on the left). */
double tp_side(const double p[2], const double q[2], const double r[2])
{
    double d[2], e[2];
    tp_sub2(q, p, d);
    tp_sub2(r, p, e);
    double len = hypot(d[0], d[1]);
    return len > 0.0 ? cross2(d, e) / len : hypot(e[0], e[1]);
}

/* Distance from r to segment pq; *s gets the parameter of the nearest point
 * (0 at p, 1 at q) when s is not NULL. */
double tp_point_seg(const double p[2], const double q[2], const double r[2], double *s)
{
    double d[2], e[2];
    tp_sub2(q, p, d);
    tp_sub2(r, p, e);
    double dd = dot2(d, d), u = dd > 0.0 ? dot2(e, d) / dd : 0.0;
    if (u < 0.0) u = 0.0;
    if (u > 1.0) u = 1.0;
    if (s) *s = u;
    double c[2] = {p[0] + u * d[0] - r[0], p[1] + u * d[1] - r[1]};
    return hypot(c[0], c[1]);
}

/* Do segments pq and rs cross properly: each one's ends strictly (beyond
 * tol) on opposite sides of the other's line? */
int tp_proper_cross(const double p[2], const double q[2], const double r[2],
                    const double s[2], double tol)
{
    double a = tp_side(p, q, r), b = tp_side(p, q, s), c = tp_side(r, s, p), d = tp_side(r, s, q);
    return ((a > tol && b < -tol) || (a < -tol && b > tol)) &&
           ((c > tol && d < -tol) || (c < -tol && d > tol));
}

/* Smallest distance between segments pq and rs (0 when they cross). */
double tp_seg_seg(const double p[2], const double q[2], const double r[2], const double s[2])
{
    if (tp_proper_cross(p, q, r, s, 0.0)) return 0.0;
    double m = tp_point_seg(p, q, r, NULL), v;
    if ((v = tp_point_seg(p, q, s, NULL)) < m) m = v;
    if ((v = tp_point_seg(r, s, p, NULL)) < m) m = v;
    if ((v = tp_point_seg(r, s, q, NULL)) < m) m = v;
    return m;
}

double tp_poly_area(int n, double (*p)[2])
{
    double a = 0.0;
    for (int i = 0; i < n; i++) {
        const double *u = p[i], *v = p[(i + 1) % n];
        a += u[0] * v[1] - v[0] * u[1];
    }
    return 0.5 * a;
}

/* Area and centroid of a simple polygon (shoelace, relative to the first
 * vertex to keep the sums well conditioned). */
double tp_poly_centroid(int n, double (*p)[2], double c[2])
{
    double a = 0.0, cx = 0.0, cy = 0.0, o[2] = {p[0][0], p[0][1]};
    for (int i = 0; i < n; i++) {
        double u[2] = {p[i][0] - o[0], p[i][1] - o[1]};
        double v[2] = {p[(i + 1) % n][0] - o[0], p[(i + 1) % n][1] - o[1]};
        double w = u[0] * v[1] - v[0] * u[1];
        a += w;
        cx += (u[0] + v[0]) * w;
        cy += (u[1] + v[1]) * w;
    }
    a *= 0.5;
    if (a != 0.0) {
        c[0] = o[0] + cx / (6.0 * a);
        c[1] = o[1] + cy / (6.0 * a);
    } else {
        c[0] = o[0];
        c[1] = o[1];
    }
    return a;
}

/* 1 when x is strictly inside (farther than tol from the boundary), 0 when
 * within tol of the boundary, -1 outside.  *margin (if not NULL) gets the
 * distance to the boundary, signed positive inside. */
int tp_poly_classify(int n, double (*p)[2], const double x[2], double tol, double *margin)
{
    double dmin = INFINITY;
    int inside = 0;
    for (int i = 0, j = n - 1; i < n; j = i++) {
        double d = tp_point_seg(p[j], p[i], x, NULL);
        if (d < dmin) dmin = d;
        /* even-odd ray casting towards +x */
        if ((p[i][1] > x[1]) != (p[j][1] > x[1])) {
            double xc = p[j][0] + (x[1] - p[j][1]) * (p[i][0] - p[j][0]) / (p[i][1] - p[j][1]);
            if (x[0] < xc) inside = !inside;
        }
    }
    if (margin) *margin = inside ? dmin : -dmin;
    if (dmin <= tol) return 0;
    return inside ? 1 : -1;
}

int sf_polygon_contains(const sf_polygon *poly, const double x[2], double tol)
{
    if (!poly || poly->n < 3 || !poly->p) return 0;
    return tp_poly_classify(poly->n, poly->p, x, tol, NULL) >= 0;
}
