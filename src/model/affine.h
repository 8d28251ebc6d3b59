/* affine.h - rigid maps as 3x4 row-major arrays [R | t]. */
#ifndef SF_AFFINE_H
#define SF_AFFINE_H

void sf_affine_identity(double A[12]);
/* C = A B (C may alias A or B). */
void sf_affine_mul(const double A[12], const double B[12], double C[12]);
/* Ai = A^-1 for a rigid A (R^T, -R^T t); Ai may alias A. */
void sf_affine_inv(const double A[12], double Ai[12]);
/* y = R x + t (y may alias x). */
void sf_affine_apply(const double A[12], const double x[3], double y[3]);
/* R: rotation by angle about the unit axis, row-major 3x3. */
void sf_rotation(const double axis[3], double angle, double R[9]);

#endif
