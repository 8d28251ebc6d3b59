/* kinematics.h - folding maps, face maps, material points and loop
 * constraints with analytic first and second derivatives (MODEL.md 3-4).
 *
 * Generalised coordinates: q[qoff[i] + 0] = theta_i, q[qoff[i] + k] = a_ik
 * (k = 1..K_i) for fold i; nq in all.
 *
 * Rigid transforms are 3x4 affine matrices A (row-major, A[r*4 + c]):
 * x -> A[:, 0:3] x + A[:, 3].  A twist (omega, v) acts as x -> omega x x + v.
 */
#ifndef SF_KINEMATICS_H
#define SF_KINEMATICS_H

#include "affine.h"
#include "pattern.h"
#include "shape.h"
#include "sf_error.h"
#include "topology.h"

typedef struct sf_model {
    const sf_study *study;
    const sf_topology *topo;
    int nfolds, nfaces, nq;
    int *qoff, *qn;            /* per fold: offset and count of coordinates */
    sf_section *sec;           /* per fold cross-section */
    int maxqn;
    /* per face: folds on the tree path from the root and the sign of each
     * crossing (+1: from the fold's right face to its left face) */
    int *pathlen;
    int **path, **pathsign;
    /* constraints: 6 per interior vertex (rotation axial vector, then
     * translation), in topology order */
    int ncon;
} sf_model;

/* Per-state cache: everything that depends on q.  Filled by sf_kin_eval. */
typedef struct sf_kin {
    int order;                 /* derivatives available: 0, 1 or 2 */
    double *q;                 /* copy of the state */
    /* per fold i (local frame of its right face) */
    double *T;                 /* [nfolds][12] folding map T_i */
    double *chord;             /* [nfolds][2] */
    double *xi;                /* [nq][6]: twist dT T^-1 (omega, v), local */
    double *xi2;               /* [nfolds][maxqn][maxqn][12]: d2T T^-1, local */
    /* per face: global rigid map */
    double *X;                 /* [nfaces][12] */
    long fold_evals;           /* folding maps evaluated into this cache so
                                  far (each one quadrature of its section) */
} sf_kin;

/* A material point of the sheet, located once. */
typedef struct sf_mpoint {
    double X[2];     /* reference position */
    int face;        /* face it moves with (crease-pattern face), or -1 */
    int fold;        /* fold band it lies in, or -1 (then face >= 0) */
    double s;        /* band: arclength from the right edge, in [0, w] */
    double tpos;     /* band: position along m from vertex a */
} sf_mpoint;

int sf_model_init(sf_model *m, const sf_study *s, const sf_topology *t,
                  sf_error *err);
void sf_model_free(sf_model *m);

int sf_kin_alloc(const sf_model *m, sf_kin *k);
void sf_kin_free(sf_kin *k);
/* Evaluate maps at q with derivatives up to order (0, 1, 2). */
void sf_kin_eval(const sf_model *m, const double *q, int order, sf_kin *k);
/* The folding maps of the nf listed folds alone, with derivatives up to
 * order, from their coordinates in q (copied into k->q); every other
 * fold's data and the face maps keep what they held.  Enough for the loop
 * rows of a vertex whose folds are listed (sf_constraints_vertex), at a
 * cost independent of the size of the sheet; the same values as
 * sf_kin_eval for those folds. */
void sf_kin_eval_folds(const sf_model *m, const double *q, int order, int nf, const int *folds,
                       sf_kin *k);

/* Locate a material point (band first, then face).  Fails when outside. */
int sf_model_locate(const sf_model *m, const double X[2], sf_mpoint *p,
                    sf_error *err);

/* Current position x[3] of a material point; dx (3 x nq, row-major
 * dx[c*nq + j]) when not NULL (needs order >= 1). */
void sf_point_eval(const sf_model *m, const sf_kin *k, const sf_mpoint *p,
                   double x[3], double *dx);
/* Add sum_c f[c] d2x_c/dq dq to H (nq x nq, H[j*ld + l]); needs order 2. */
void sf_point_hess_add(const sf_model *m, const sf_kin *k,
                       const sf_mpoint *p, const double f[3], double *H,
                       int ld);

/* Centroid of a fold band (for its weight): x, dx, and f . d2x added to H. */
void sf_fold_centroid(const sf_model *m, const sf_kin *k, int fold,
                      double x[3], double *dx, const double *f, double *H,
                      int ld);

/* Loop constraints, 6 per interior vertex: the axial vector of (R - R^T)/2
 * and the translation of the loop product, measured about the vertex (so
 * that a translation mismatch does not depend on where the origin is):
 * g[ncon]; J (ncon x nq,
 * row-major J[c*nq + j]) when not NULL; when lambda and H are not NULL,
 * adds sum_c lambda_c d2g_c/dq dq to H.  Needs the order asked for. */
void sf_constraints(const sf_model *m, const sf_kin *k, double *g, double *J,
                    const double *lambda, double *H, int ld);

/* The six loop rows of interior vertex v alone, local to its folds (no
 * array of size ncon x nq): g[6]; the distinct coordinates its rows depend
 * on in cols (at most 64; *ncols of them); J (6 x ncols, row-major
 * J[e * ncols + j]) when not NULL; with lambda (6) and H (ncols x ncols,
 * H[a * ncols + b]) adds sum_e lambda_e d2g_e/dq dq over those columns.
 * The same values as sf_constraints.  SF_OK, or SF_ENOMEM (also for a
 * vertex with more than 64 coordinates). */
int sf_constraints_vertex(const sf_model *m, const sf_kin *k, int v, double g[6], int *cols,
                          int *ncols, double *J, const double *lambda, double *H);

/* The paper's penalty: sum over interior vertices of
 * (lR/2)(R23^2 + R31^2 + R12^2) + (ld/2)|t|^2 of the loop product.
 * Returns the energy; adds gradient and Hessian when not NULL. */
double sf_penalty(const sf_model *m, const sf_kin *k, double lR, double ld,
                  double *grad, double *H, int ldh);

#endif
