/* equilibrium_poses.h - the equilibrium problem of equilibrium.h in the
 * face-pose formulation (MODEL.md 9, src/model/poses.h), behind the same
 * sf_equil: after sf_equil_use_poses the unknowns are
 *   y = (x, lambda),  x = (q, face poses) (nx = q->nq values, the fold
 *   coordinates first, see poses.h), lambda = the kept ones of the 6 rows
 *   per fold (rotation, translation; q->nloop of 6 N, in fold-row order:
 *   a maximal independent set, poses_rowsel.h), then the support and
 *   displacement rows,
 * and sf_equil_residual, sf_equil_jacobian(_sparse), sf_equil_kkt,
 * sf_equil_report and sf_equil_create_solver use the functions below.
 * The Jacobian [HL J^T; J -eps D] is assembled directly into CSC: its
 * pattern is recorded once (sf_equil_use_poses) as a fixed sequence of
 * additions, then values are refilled through the map (poses.h,
 * sf_triplets).  Nothing of size nx^2 is formed except by sf_equil_kkt,
 * whose callers (the dense stability analysis) ask for dense blocks; the
 * sparse stability analysis takes sf_peq_kkt_csc instead. */
#ifndef SF_EQUILIBRIUM_POSES_H
#define SF_EQUILIBRIUM_POSES_H

#include "equilibrium.h"
#include "sstab.h"

struct cont_solver;

/* Switch q (exact constraints, just initialised) to the pose formulation.
 * Fails with a message naming the study for penalty constraints. */
int sf_equil_use_poses(sf_equil *q, sf_error *err);

/* Complete a state whose first m->nq values are fold coordinates: the
 * poses from the tree maps (poses.h, sf_poses_from_folds), multipliers 0. */
int sf_equil_poses_lift(sf_equil *q, double *y);
/* Derivative of that lift at the fold coordinates of y along those of dy
 * (analytic, sf_poses_from_folds_dir): dx = (dq, d poses, 0). */
int sf_equil_poses_lift_dir(sf_equil *q, const double *y, const double *dy, double *dx);

/* Nonzeros of the Jacobian pattern. */
long sf_equil_poses_nnz(const sf_equil *q);

/* Start an exact path at p1 off the flat state (solving the problem at
 * p0): the fold formulation's start (flatstart.h) on a fold-coordinate
 * copy of the problem, lifted to poses, then cont_start of cs (created for
 * q) from there.  y receives the lifted guess. */
int sf_equil_poses_start_flat(sf_equil *q, struct cont_solver *cs, double p0, double p1,
                              int dir, double tol, double *y, sf_error *err);

/* The KKT blocks at (y, p) for the sparse stability analysis (sstab.h):
 * HL (nx x nx, lower triangle) and C (ncon x nx), pointing into storage
 * of q valid until the next call; patterns fixed for the study.  SF_OK,
 * SF_ENUMERIC on a non-finite value, SF_ENOMEM. */
int sf_peq_kkt_csc(sf_equil *q, const double *y, double p, sf_csc *HL, sf_csc *C);

/* The whole Jacobian dF/dy at (y, p) as CSC arrays of q (n = q->n
 * columns, pattern fixed for the study, both triangles; valid until the
 * next assembly) and dF/dp into Fp (q->n values).  For the sparse flat
 * start (flatstart_sparse.h).  SF_OK or SF_ENUMERIC (non-finite value). */
int sf_peq_jacobian_csc(sf_equil *q, const double *y, double p, const long **colptr,
                        const int **rowind, const double **val, double *Fp);

/* Fold rows dropped as dependent at a generic state (poses_rowsel.h,
 * solver.pose_rows), and the largest residual of those rows at y, scaled
 * as Newton scales the kept ones (rotation 1, translation 1 / lref):
 * after a solved point it must be at the Newton tolerance too. */
int sf_peq_rows_dropped(const sf_equil *q);
/* The rank of the 6 N fold rows at the generic state (-1 when
 * solver.pose_rows = "all"); equal to the unknowns q->nq: nothing dropped
 * (poses_rowsel.h). */
int sf_peq_rows_rank(const sf_equil *q);
double sf_peq_dropped_residual(sf_equil *q, const double *y);
/* Index among the constraint rows (multiplier nx + index) of fold row
 * 6 i + c, -1 when that row is dropped (flatlimit_sparse.c). */
int sf_peq_fold_row(const sf_equil *q, int fold_row);

/* The wrench that fold i exerts on its left face at the solved state y
 * (force F [N], moment M [N m] about the global origin), from the
 * multipliers of its kept rows (dropped rows carry none): minus the
 * rows' generalised force on the face's pose, turned into a wrench.  The
 * right face (with the band) receives -F, -M.  Where the sheet has closed
 * loops the distribution among folds is statically indeterminate: it is
 * the solver's, and only what statics fixes (e.g. the sum over the folds
 * of a face) is unique.  SF_OK or SF_ENUMERIC (non-finite). */
int sf_peq_fold_wrench(sf_equil *q, const double *y, int fold, double F[3], double M[3]);

/* Used by equilibrium.c when q->pz is set. */
int sf_peq_residual(sf_equil *q, const double *y, double p, double *F);
int sf_peq_jacobian(sf_equil *q, const double *y, double p, SUNMatrix Jy, double *Fp);
int sf_peq_kkt(sf_equil *q, const double *y, double p, double *HL, double *C);
void sf_peq_report(sf_equil *q, const double *y, double p, double *Pi, double *res_rot,
                   double *res_tra);
int sf_peq_create_solver(sf_equil *q, struct cont_solver **out);
void sf_peq_free(sf_equil *q);

#endif
