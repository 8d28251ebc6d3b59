/* equilibrium.h - the equilibrium problem F(y; p) = 0 of MODEL.md 6 for the
 * continuation engine.
 *
 * Unknowns y = (q, lambda): generalised coordinates, then one multiplier
 * per constraint row: the loop rows (6 per interior vertex, exact mode
 * only), the support rows, and the prescribed-displacement row when the
 * parameter is a displacement.
 *   F = [ grad Pi(q; p) + J^T lambda ;  g(q; p) ]
 *   dF/dy = [ H + sum_c lambda_c hess g_c ,  J^T ;  J , -eps D ]
 * The -eps D block (eps = 1e-10, D the row scales) only enters the
 * Jacobian, never the residual, so solutions satisfy g = 0 exactly: it
 * keeps the Newton matrix regular where loop rows are redundant (at the
 * flat state the rotation about the normal and the in-plane translation
 * of every vertex loop are of second order in the fold angles).
 *
 * Parameter p: "load" (load factor; stage k of the study ramps over
 * p in [k-1, k]), "actuation" (factor on the rest angles of the driven
 * groups: theta0 = p * rest_angle of the group; group -1 drives all),
 * "displacement" (prescribed displacement [m] of one component of a probe
 * point).
 */
#ifndef SF_EQUILIBRIUM_H
#define SF_EQUILIBRIUM_H

#include <sundials/sundials_matrix.h>

#include "energy.h"
#include "kinematics.h"
#include "sf_error.h"

enum { SF_PARAM_LOAD = 0, SF_PARAM_ACTUATION = 1, SF_PARAM_DISPLACEMENT = 2 };

typedef struct sf_equil {
    const sf_model *m;
    sf_energy e;
    sf_params par;
    sf_kin k;
    int param;            /* SF_PARAM_* */
    int group;            /* actuated group (actuation) */
    double load;          /* load parameter value when p is not the load */
    int ramp_stage;       /* load stage (0-based) followed alone, -1: all (see
                             sf_equil_set_param) */
    int exact;            /* loop rows enforced by multipliers */
    int nq, nloop, nsup, ncon, n;
    /* support and displacement rows: point, component, prescribed value */
    sf_mpoint *rowpt;
    int *rowc;
    double *rowval;
    int disp_row;         /* index among the support rows, -1 if none */
    double kref, lref;    /* reference stiffness [J] and length [m] */
    double reg_rel, reg_min;  /* sf_equil_reg_eps; 0: the fixed eps */
    double *lam_anchor;   /* sf_equil_anchor: multipliers of the anchor, ncon */
    double eps_anchor;    /* its eps; 0: no anchor (the plain residual) */
    double *anchor_w;     /* NULL, or a factor on eps_anchor per constraint row (ncon) */
    double *yscale, *fscale;
    /* scratch */
    double *grad, *H, *gp, *g, *J, *dx;
    long nres, njac;
    /* sparse linear algebra (sf_equil_use_sparse): dense assembly, then
     * compressed to CSC over the union of the nonzero patterns seen */
    int sparse;
    int linsol;           /* sparse solver: CONT_LINSOL_KLU or _MUMPS (0: MUMPS) */
    SUNMatrix Jd;
    unsigned char *pattern;
    /* Optional: called at the end of sf_equil_set_param (so also inside
     * the residual, Jacobian and report), e.g. by the dynamics module to
     * apply the time histories of other actuation groups. */
    void (*param_hook)(struct sf_equil *q, double p, void *data);
    void *param_hook_data;
    /* the face-pose formulation (equilibrium_poses.h), NULL for fold
     * coordinates: set by sf_equil_use_poses */
    struct sf_peq *pz;
} sf_equil;

int sf_equil_init(sf_equil *q, const sf_model *m, int param, int group,
                  int probe, int component, double load, sf_error *err);
void sf_equil_free(sf_equil *q);

/* The path parameter of the study's analysis block, shared by equilibrium
 * paths and trajectories: analysis.parameter ("load", "actuation",
 * "displacement"), analysis.group, analysis.probe and analysis.component
 * as the arguments of sf_equil_init.  Fails (naming the study's line) when
 * a displacement parameter has no probe. */
int sf_equil_parse_param(const sf_study *s, int *param, int *group, int *probe,
                         int *component, sf_error *err);

/* Switch the loop rows to the paper's penalty (weights lR [J], ld [J/m^2]):
 * the unknowns become (q, support multipliers).  Used for penalty studies
 * and for the penalty homotopy that starts exact paths off the flat state. */
void sf_equil_use_penalty(sf_equil *q, double lR, double ld);

/* Solve the Newton systems with a sparse LU on a compressed sparse (CSC)
 * Jacobian instead of dense LU (solver.linear_solver = "sparse", "mumps"
 * or "klu"): sparse is 0 (dense), or the engine's solver CONT_LINSOL_MUMPS
 * or CONT_LINSOL_KLU (any other nonzero value: MUMPS).  The Jacobian is
 * assembled densely, then compressed: what changes is the factorisation.
 * The pose formulation is always sparse; this chooses its solver too
 * (MUMPS unless KLU is asked for). */
void sf_equil_use_sparse(sf_equil *q, int sparse);
int sf_equil_jacobian_sparse(const double *y, double p, SUNMatrix Jy, double *Fp, void *user);
/* The sparse solver chosen by sf_equil_use_sparse (CONT_LINSOL_MUMPS or _KLU). */
int sf_equil_sparse_linsol(const sf_equil *q);


/* A continuation solver for this problem: dense LU, or the sparse solver of
 * sf_equil_use_sparse.  When there are
 * multipliers, the arclength norm weighs the coordinates q and p only
 * (cont_set_weights: multipliers weigh 0): the multipliers of loop rows
 * that are nearly redundant (second order near the flat state) are large
 * and change fast, and would otherwise dominate the step length. */
struct cont_solver;
int sf_equil_create_solver(sf_equil *q, struct cont_solver **out);

/* Start of an exact path off the flat state, which is a singular point of
 * loop closure: solve the penalty problem at p1 with stiffness raised by
 * 100 per stage from 1e2 to 1e8 times the fold stiffness (keeping the last
 * level that converged), then estimate the multipliers as penalty forces
 * (lambda = k g).  Writes y = (q, lambda) for the exact problem. */
int sf_equil_start_off_flat(sf_equil *q, double p1, double tol, double *y, sf_error *err);

/* Parameter values for p (load factors, rest angles and their derivatives).
 * With q->ramp_stage = k >= 0 (load parameter), stage k ramps linearly on
 * both sides of [k, k + 1] and every other stage keeps its value there
 * (0 before, 1 after): a path followed one stage at a time then has no
 * corner where the continuation may step past the stage's end. */
void sf_equil_set_param(sf_equil *q, double p);

/* The regularisation eps of the multiplier block (in the scaled system)
 * at the state y: 1e-10, or with q->reg_rel > 0, reg_rel a^2 with a the
 * largest fold coordinate (the first m->nq values of y), between
 * q->reg_min and 1e-10.  Near the flat state the gradients of the
 * second-order loop rows are of the order of a, and a fixed eps swamps
 * them: the flat start sets reg_rel on a degenerate ray of the tangent
 * cone (flatstart.h, docs/flatstart.md "Small motions on a degenerate
 * ray"). */
double sf_equil_reg_eps(const sf_equil *q, const double *y);

/* The proximal anchor of the continuation engine (cont_anchor_fn): with
 * on = 1 the residual's constraint rows become g - eps D (lambda -
 * lambda_a), lambda_a the multipliers of y and eps = sf_equil_reg_eps(y),
 * which makes the Jacobian's regularisation -eps D exact; on = 0 restores
 * g.  For where Newton stagnates at a residual floor because nearly
 * dependent rows (singular values below sqrt(eps)) keep part of g
 * (docs/design/model.md, "Gravity and a tip load").  0 or 1 (no memory). */
int sf_equil_anchor(const double *y, double p, int on, void *user);

/* The weight of constraint row r in the multiplier block: eps, times
 * q->anchor_w[r] while an anchor with row factors is on. */
double sf_equil_row_eps(const sf_equil *q, double eps, int r);

/* Adds the anchor's term to the constraint rows of F (nothing if off). */
void sf_equil_anchor_rows(const sf_equil *q, const double *y, double *F);
/* Callbacks for cont_problem (user = sf_equil *). */
int sf_equil_residual(const double *y, double p, double *F, void *user);
int sf_equil_jacobian(const double *y, double p, SUNMatrix Jy, double *Fp, void *user);

/* The blocks of the KKT matrix at (y, p), without the regularisation:
 * HL (nq x nq, row-major) = hess Pi + sum_c lambda_c hess g_c (symmetric),
 * C (ncon x nq, row-major) = the constraint rows (loop rows in exact mode,
 * then supports and the displacement row).  For the stability analysis.
 * Returns nonzero on a non-finite value. */
int sf_equil_kkt(sf_equil *q, const double *y, double p, double *HL, double *C);

/* Quantities of a solved point: energy Pi, max |loop residual| (rotation
 * rows and translation rows [m] separately). */
void sf_equil_report(sf_equil *q, const double *y, double p, double *Pi,
                     double *res_rot, double *res_tra);

#endif
