/* start_impl.h - private to src/analysis/start/: the bordered KKT systems
 * of the start (start_kkt.c) and the method of multipliers that solves
 * them (start_alm.c).  Prefix fs_ ("flat start"). */
#ifndef SF_START_IMPL_H
#define SF_START_IMPL_H

#include <sundials/sundials_context.h>
#include <sundials/sundials_matrix.h>

#include "equilibrium.h"
#include "ldlt.h"

/* The symmetric matrix K0 = S J S of the equilibrium problem (J its
 * Jacobian, with the block -eps D of the proximal rows, in physical units;
 * S = sqrt(fscale / yscale), which makes S J S symmetric and of order one
 * in every block), factorised with a shift on its coordinate block:
 * K0 + shift [I 0; 0 0].  Dense LAPACK (Bunch-Kaufman) up to FS_DENSE_MAX
 * unknowns, MUMPS LDL^T (ldlt.h) above; both give the inertia. */
#define FS_DENSE_MAX 600

typedef struct fs_kkt {
    sf_equil *q;
    int n, nx, m;           /* unknowns, coordinates, constraint rows */
    double *S;              /* n: the symmetric scaling */
    double *Fp;             /* n: dF/dp at the last evaluation (physical) */
    int dense;
    /* dense: the scaled matrix (column-major, lower triangle used) and its factors */
    SUNContext ctx;
    SUNMatrix Jd;
    double *K, *LD, *work;
    int *ipiv, lwork;
    /* sparse: the scaled lower triangle as triplets, MUMPS */
    sf_ldlt *ld;
    int *ti, *tj;
    double *tv;
    long tnnz, tcap;
    int *diag;              /* n: index of each diagonal triplet (-1: none) */
    int neg;                /* negative pivots of the last factorisation */
    long nfact, neval;
} fs_kkt;

int fs_kkt_init(fs_kkt *k, sf_equil *q, sf_error *err);
void fs_kkt_free(fs_kkt *k);
/* Evaluate J and dF/dp at (y, p) (q's proximal weight and anchor as set). */
int fs_kkt_eval(fs_kkt *k, const double *y, double p, sf_error *err);
/* Factorise K0 + shift on the coordinates; k->neg receives its negative
 * pivots.  SF_OK, SF_ENUMERIC when singular (a zero pivot), SF_ENOMEM. */
int fs_kkt_factor(fs_kkt *k, double shift, sf_error *err);
/* Solve (K0 + shift) x = b in place, b in scaled units (n values). */
int fs_kkt_solve(fs_kkt *k, double *b, sf_error *err);
/* w = K0 v (unshifted, scaled; n values each). */
void fs_kkt_matvec(const fs_kkt *k, const double *v, double *w);

/* The control of a minimisation (start_alm.c): one linear condition
 * row . x = target on the coordinates x, whose multiplier mu is the
 * change of the path parameter (FS_PARAM: the equations are evaluated at
 * p0 + mu, row = dF/dp at the flat state), or a generalised force along
 * row (FS_PIN: p stays p0, row a unit fold coordinate); FS_FIXED: no
 * condition (a prescribed displacement parameter holds the amount of
 * folding), p = p0. */
enum { FS_PARAM = 0, FS_PIN = 1, FS_FIXED = 2 };
typedef struct fs_control {
    int kind;
    const double *row;      /* nx values (physical); NULL for FS_FIXED */
    double target;
    double p0;
    double eps0;            /* first proximal weight (scaled); 0: the default */
} fs_control;

typedef struct fs_alm_result {
    int closed;             /* constraint rows within the tolerance at a minimum */
    int blocked;            /* eps fell to its floor with the rows still open */
    int saddle;             /* a saddle was left along negative curvature */
    int outer, newton;      /* outer iterations, Newton steps */
    double gres;            /* final constraint residual (scaled rows) */
    double eps;             /* final proximal weight */
} fs_alm_result;

/* Minimise from y (n values, physical; its multipliers are the first
 * anchor) and *mu; branch 2 takes the mirror image where a saddle is
 * left.  y and *mu receive the result; res what happened.  SF_OK also
 * when not closed (res says why); an error for numerical failures. */
int fs_alm(fs_kkt *k, const fs_control *c, double *y, double *mu, int branch, double tol,
           fs_alm_result *res, sf_error *err);

#endif
