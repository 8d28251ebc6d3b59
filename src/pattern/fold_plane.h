/* fold_plane.h - the plane of a FOLD frame's 3-D vertices, and the proper
 * rotation that lays it into the x-y plane (fold_plane.c).
 *
 * A frame is flat when every vertex lies within 1e-6 of its size (the
 * larger side of its bounding box) from the plane through the centroid.
 * The normal is the null vector of the points' covariance (the longest
 * cross product of two of its rows: exact for a plane, no eigensolver),
 * snapped to a coordinate axis when within 1e-12 of it.  Its side: the
 * one from which the faces (faces_vertices) turn counter-clockwise, as
 * FOLD's crease patterns do; without faces, the side whose largest
 * component is positive.  Origami Simulator's patterns (x-z plane, faces
 * counter-clockwise in (x, z)) so keep their x and z as x and y. */
#ifndef SF_FOLD_PLANE_H
#define SF_FOLD_PLANE_H

typedef struct sf_plane {
    double n[3];       /* unit normal, becomes +z */
    double u[3], v[3]; /* in-plane axes, become +x and +y (u x v = n) */
    int flat;          /* 1 when every vertex is within tolerance */
    int is_xy;         /* the plane is z = 0 with normal +z: nothing moves */
    int worst;         /* vertex farthest from the plane */
    double dev;        /* its distance */
    const char *how;   /* how the side was chosen (for a note) */
} sf_plane;

/* faces: nf faces in CSR (fs[nf + 1] offsets into fv), or nf = 0.
 * Returns 0, or -1 when out of memory (never: no allocation) */
int sf_plane_fit(int n, const double (*x)[3], const int *fs, const int *fv, int nf, sf_plane *pl);
/* p (3-D) to the plane's coordinates: out[0..1] in the plane, out[2] the
 * height above it; out may be p */
void sf_plane_map(const sf_plane *pl, const double p[3], double out[3]);

#endif
