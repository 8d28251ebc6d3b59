/* flatswitch.h - branch switching at the flat state with exact loop
 * closure: every branch of the tangent cone, not only the one the driving
 * selects (flatcone.h), prefix sf_flatsw_.
 *
 * At the flat state the loop rows split into first-order rows J1 and
 * second-order rows with Hessians G_s (flatstart.h).  On the kernel of J1,
 * u = N x, with A(p) = N^T H0(p) N, b = N^T gp and the independent forms
 * Q_t (flatcone.h, sf_cone_reduce), a branch leaving the flat state
 * solves the reduced second-order equations
 *   driven (b != 0, the parameter does first-order work, e.g. actuation or
 *   a transverse load): at the start p0, q = dp u + O(dp^2),
 *       (A + sum_t nu_t Q_t) x + b = 0,   x^T Q_t x / 2 = 0;
 *   homogeneous (b = 0, in-plane loads: the flat state is an equilibrium
 *   at every p): a branch leaves at p*, q = eps u + O(eps^2),
 *       (A(p*) + sum_t nu_t Q_t) x = 0,   x^T Q_t x / 2 = 0,   |x| = 1,
 *   the critical points of the Rayleigh quotient of the stiffness on the
 *   cone; A(p) is affine in p (dead loads), A(p) = A0 + (p - p0) Ap.
 * The unknowns (x, nu[, p*]) are as many as the equations; solutions
 * (stable or not) are sought by Newton (Levenberg-Marquardt steps where its
 * line search stalls; deflation of the solutions already found, Farrell,
 * Birkisson & Funke 2015) from nstarts pseudo-random starts (fixed seed,
 * reproducible; first the driving's response, or the modes of the pencil
 * -Ap x = mu A x with sums and differences within multiple ones).  The
 * search is not exhaustive.  Kept
 * when new (x differs by more than 1e-4 relative, up to sign in the
 * homogeneous case) and, homogeneous, when p* lies in [plo, phi].
 * Distinct solutions are grouped into classes of symmetric images (same
 * p*, energy and sorted |u|: the sheet's symmetries permute the folds and
 * may flip all signs).
 *
 * Each solution gives its predicted branches for the continuation engine
 * (cont_start_tangent): driven, one at p0 + dp (the limit guess, as the
 * flat start makes it); homogeneous, two, at p* with q = +-eps u and the
 * second-order multipliers nu (the pitchfork's two halves), tangent
 * (u, mu, 0; 0).  Needs fold coordinates (not poses), exact loop rows,
 * no support rows and no prescribed displacement. */
#ifndef SF_FLATSWITCH_H
#define SF_FLATSWITCH_H

#include "bifurcation.h"
#include "cont.h"
#include "equilibrium.h"
#include "sf_error.h"

/* A solution is isolated (followed) when the smallest over the largest
 * singular value of the reduced Jacobian is at least this. */
#define SF_FLATSW_ISOL_MIN 1e-6

typedef struct sf_flatsw {
    int homogeneous;      /* 1: b = 0, branches leave at p*; 0: driven, at p0 */
    int k, r;             /* first-order motions, independent second-order forms */
    int nstarts;          /* Newton starts tried */
    int nconv;            /* starts that converged (any solution) */
    int nsym;             /* isometries of the crease pattern used (identity included) */
    int nsol;             /* distinct solutions kept */
    int ncls;             /* classes of symmetric images among them */
    int n, nq;            /* unknowns of the equilibrium problem, coordinates */
    double *pstar;        /* nsol: p where the branch leaves the flat state */
    double *energy;       /* nsol: driven: x^T A x / 2 + b . x; homogeneous: 0 */
    double *resid;        /* nsol: max-norm residual of the reduced equations */
    double *isol;         /* nsol: smallest / largest singular value of their
                           * Jacobian (isolated solution: not small) */
    double *u;            /* nsol x nq: the branch direction (full coordinates) */
    int *cls;             /* nsol: class (0-based: index of its first member) */
    int ndir;             /* predicted branches */
    int *sol;             /* ndir: the solution each belongs to */
    double *y, *ty;       /* ndir x n: predicted points, tangents */
    double *p, *tp;       /* ndir */
} sf_flatsw;

/* Solve the reduced equations at the flat state of eq (parameter p0) and
 * predict the branches: dp (driven: signed first step from p0), eps
 * (homogeneous: amplitude in the coordinates), [plo, phi] (homogeneous:
 * the range of p*).  SF_OK (possibly with nsol = 0), SF_EINPUT when the
 * problem is not of this kind, SF_ENOMEM / SF_ENUMERIC. */
int sf_flatsw_find(sf_equil *eq, double p0, double dp, double eps, double plo, double phi,
                   int nstarts, sf_flatsw *F, sf_error *err);
void sf_flatsw_free(sf_flatsw *F);

/* Follow every predicted branch of F with the path's solver cs and b's
 * hooks (a new branch each, like sf_bif_switch): the first point of each
 * is compared with known (the state of the path already followed, NULL:
 * none) at pknown and with the others': the same state (1e-6) is a
 * duplicate and not followed.  Notes say what was found and followed. */
int sf_flatsw_follow(sf_bif *b, cont_solver *cs, const sf_flatsw *F, double p0,
                     const double *known, double pknown, sf_error *err);

#endif
