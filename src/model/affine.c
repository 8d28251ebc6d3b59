/* affine.c - rigid maps as 3x4 row-major arrays [R | t] (rotation R,
 * translation t): identity, product, inverse, application, and the
 * rotation about a unit axis (Rodrigues). */
#include "affine.h"

#include <math.h>
#include <string.h>

void sf_affine_identity(double A[12])
{
    memset(A, 0, sizeof(double) * 12);
    A[0] = A[5] = A[10] = 1.0;
}

void sf_affine_mul(const double A[12], const double B[12], double C[12])
{
    double T[12];
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 4; c++) {
            double v = c == 3 ? A[r * 4 + 3] : 0.0;
            for (int k = 0; k < 3; k++) v += A[r * 4 + k] * B[k * 4 + c];
            T[r * 4 + c] = v;
        }
    }
    memcpy(C, T, sizeof T);
}

void sf_affine_inv(const double A[12], double Ai[12])
{
    double T[12];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) T[r * 4 + c] = A[c * 4 + r];
    for (int r = 0; r < 3; r++)
        T[r * 4 + 3] = -(T[r * 4] * A[3] + T[r * 4 + 1] * A[7] + T[r * 4 + 2] * A[11]);
    memcpy(Ai, T, sizeof T);
}

void sf_affine_apply(const double A[12], const double x[3], double y[3])
{
    double t[3];
    for (int r = 0; r < 3; r++)
        t[r] = A[r * 4] * x[0] + A[r * 4 + 1] * x[1] + A[r * 4 + 2] * x[2] + A[r * 4 + 3];
    memcpy(y, t, sizeof t);
}

void sf_rotation(const double u[3], double a, double R[9])
{
    double c = cos(a), s = sin(a), C = 1.0 - c;
    R[0] = c + u[0] * u[0] * C;
    R[1] = u[0] * u[1] * C - u[2] * s;
    R[2] = u[0] * u[2] * C + u[1] * s;
    R[3] = u[1] * u[0] * C + u[2] * s;
    R[4] = c + u[1] * u[1] * C;
    R[5] = u[1] * u[2] * C - u[0] * s;
    R[6] = u[2] * u[0] * C - u[1] * s;
    R[7] = u[2] * u[1] * C + u[0] * s;
    R[8] = c + u[2] * u[2] * C;
}
