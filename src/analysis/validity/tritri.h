/* tritri.h - where two triangles of a folded sheet meet in space, and how
 * far apart in the flat sheet the material points are that meet there.
 *
 * Each triangle carries its vertices in space (x) and in the flat
 * reference sheet (X, 2-D); inside it the map between the two is affine.
 * The intersection of two triangles is a segment (or a point) when their
 * planes cross, a convex polygon when they are coplanar.  Along that set
 * the two material points that occupy one place, X_P(x) and X_Q(x), are
 * affine in x, so their distance |X_P - X_Q| is convex there and its
 * largest value, the "material separation" of the crossing, is attained
 * at a vertex of the set.  Neighbours of a continuous sheet meet where
 * they share material (separation 0: a common edge, a common corner);
 * two parts of the sheet pass through each other where material points
 * far apart in the sheet occupy one place.
 *
 * Method: signed distances of each triangle's vertices to the other's
 * plane (Moeller, J. Graphics Tools 2(2), 1997), the two triangles' pieces
 * on the planes' common line overlapped; coplanar triangles clipped
 * against each other (Sutherland-Hodgman).  Distances within eps of a
 * plane count as on it. */
#ifndef SF_TRITRI_H
#define SF_TRITRI_H

typedef struct sf_tri3 {
    double x[3][3];   /* vertices in space [m] */
    double X[3][2];   /* the same material points in the flat sheet [m] */
} sf_tri3;

/* The set where two triangles meet, by its vertices (two for a segment,
 * equal for a point, up to 6 for a coplanar overlap): each a place in
 * space and the material point of either triangle there. */
#define SF_TRI_MEET_MAX 12
typedef struct sf_tri_meet {
    int n;
    double x[SF_TRI_MEET_MAX][3];
    double XP[SF_TRI_MEET_MAX][2], XQ[SF_TRI_MEET_MAX][2];
} sf_tri_meet;

/* Do P and Q meet (within eps [m])?  1 with the set in *out; 0 when they
 * do not meet or one is degenerate (zero area). */
int sf_tritri(const sf_tri3 *P, const sf_tri3 *Q, double eps, sf_tri_meet *out);

/* The material separation of vertex k of a meeting set, |XP - XQ| [m],
 * and the largest over the set (-1 for an empty set); *k_max (may be
 * NULL) gets the vertex where the largest is attained. */
double sf_tri_meet_sep(const sf_tri_meet *M, int k);
double sf_tri_meet_max_sep(const sf_tri_meet *M, int *k_max);

#endif
