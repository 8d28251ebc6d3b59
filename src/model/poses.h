/* poses.h - the face-pose formulation of MODEL.md 9: kinematics, local
 * derivative blocks and the sparse pattern they fill.
 *
 * Unknowns x (nx values), in this order:
 *   x[0 .. nq)         the fold coordinates q_i = (theta_i, a_ik), laid out
 *                      exactly as in the fold formulation (m->qoff), so
 *                      that the first nq values of a pose state are a valid
 *                      fold state for every writer (probes, angles, shapes);
 *   x[nq + 6 k ..]     pose of the k-th free face (every face but the fixed
 *                      one, in face order): phi (3, rotation vector) then
 *                      xf (3, position of the face's reference point o_f).
 * The face map is X_f(y) = xf + R_f (y - o_f), R_f = exp([phi]x) (the
 * reference rotation Rbar_f is the identity, see docs/design/model.md), o_f
 * the centroid of the face body.  The fixed face has R = I, xf = o_f.
 *
 * Constraints: 6 per fold i (right face r, left face l), rows 6 i .. 6 i + 5:
 *   rotation     axial vector of M = (R_r Rot(m_i, theta_i))^T R_l,
 *                (M32 - M23, M13 - M31, M21 - M12) / 2;
 *   translation  X_l(p_L) - X_r(p_R) - R_r (c_n n_i + c_3 e3),
 *                p_R = a_i - (w/2) n_i, p_L = a_i + (w/2) n_i.
 *
 * Local blocks: a fold's rows depend on its local variables
 *   v = (q_i (K_i + 1), phi_r, xf_r, phi_l, xf_l)          (nv = K_i + 13),
 * a material point on face f (or on the band of fold i, whose right face is
 * f) on v = (q_i (band only), phi_f, xf_f).  sf_poses_*_vars give the
 * global column of each local variable (-1 for the fixed face's pose).
 */
#ifndef SF_POSES_H
#define SF_POSES_H

#include "kinematics.h"
#include "sf_error.h"

typedef struct sf_poses {
    const sf_model *m;
    int nq;            /* fold coordinates (= m->nq) */
    int nfree;         /* faces with a pose */
    int nx;            /* nq + 6 nfree */
    int nrows;         /* 6 per fold */
    int *pose_of;      /* [nfaces]: index of the face's pose, -1 for the fixed face */
    double *o;         /* [nfaces][3]: reference point o_f of each face */
    int maxnv;         /* largest local block */
} sf_poses;

int sf_poses_init(sf_poses *P, const sf_model *m, sf_error *err);
void sf_poses_free(sf_poses *P);

/* Rotation R = exp([phi]x) (row-major 3x3) with dR[a] = dR/dphi_a and
 * d2R[3 a + b] = d2R/dphi_a dphi_b (each 9 values), when not NULL. */
void sf_rodrigues(const double phi[3], double R[9], double dR[3][9], double d2R[9][9]);

/* Rotation and position of face f at state x. */
void sf_poses_face(const sf_poses *P, const double *x, int f, double R[9], double t[3]);

/* Global columns of a fold's local variables (nv = qn + 12 values). */
int sf_poses_fold_vars(const sf_poses *P, int fold, int *col);
/* Global columns of a point's local variables (attached to face f, and to
 * the band of `fold` when fold >= 0); returns nv. */
int sf_poses_point_vars(const sf_poses *P, int f, int fold, int *col);

/* The six rows of fold i: g[6]; dg (6 x nv, row-major) when not NULL;
 * when lam (6 values) and H (nv x nv, row-major) are not NULL, H receives
 * sum_c lam_c d2g_c (overwritten).  work: scratch of
 * sf_poses_work_size(P) doubles. */
void sf_poses_fold_rows(const sf_poses *P, const double *x, int fold, double g[6],
                        double *dg, const double *lam, double *H, double *work);

/* A material point attached to face f (reference position Xr, fold < 0)
 * or to the band of fold (kind SF_SEC_CHORD at arclength s, or
 * SF_SEC_CENTROID, tpos along m), f being the band's right face:
 * position x[3]; dx (3 x nv) when not NULL; when w and H are not NULL, H
 * (nv x nv) receives sum_c w_c d2x_c (overwritten). */
void sf_poses_point(const sf_poses *P, const double *x, int f, int fold, int kind,
                    const double Xr[2], double tpos, double s, double xo[3], double *dx,
                    const double *w, double *H, double *work);

/* Same for a located material point (sf_mpoint). */
void sf_poses_mpoint(const sf_poses *P, const double *x, const sf_mpoint *p, double xo[3],
                     double *dx, const double *w, double *H, double *work);

size_t sf_poses_work_size(const sf_poses *P);

/* Pose state from a fold state q (nq values): x = (q, poses of the tree
 * maps at q).  Exact when the fold state closes its loops. */
int sf_poses_from_folds(const sf_poses *P, const double *q, double *x);
/* Its derivative along dq at q (analytic: the tree's spatial twists):
 * dx = (dq, d poses).  SF_OK or SF_ENOMEM. */
int sf_poses_from_folds_dir(const sf_poses *P, const double *q, const double *dq, double *dx);

/* Rotation vector of a rotation matrix (angle in [0, pi]). */
void sf_rotation_log(const double R[9], double phi[3]);

/* ------------------------------------------------------------------ */
/* Sparse assembly: a fixed sequence of (row, column, value) additions,
 * recorded once (pattern), then replayed into the values of a CSC matrix
 * through a map computed once. */
typedef struct sf_triplets {
    int n;               /* square matrix order */
    int recording;       /* 1: recording the pattern, 0: adding values */
    long ncalls, cap;    /* additions per assembly */
    int *ri, *ci;        /* recorded positions (recording only) */
    long *map;           /* call -> index in val */
    long k;              /* next call */
    long nnz;
    long *colptr;        /* n + 1 */
    int *rowind;         /* nnz */
    double *val;         /* nnz */
    int oom;
} sf_triplets;

void sf_trip_begin(sf_triplets *t, int n);       /* start recording */
int sf_trip_finish(sf_triplets *t);              /* build the CSC pattern and map */
void sf_trip_zero(sf_triplets *t);               /* start a numeric assembly */
void sf_trip_add(sf_triplets *t, int i, int j, double v);
void sf_trip_free(sf_triplets *t);

#endif
