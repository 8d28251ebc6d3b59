/* boundary.h - two-parameter continuation of limit points and branch
 * points (stability boundaries), prefix sf_bnd_ / sf_family_.
 *
 * A study's equilibrium problem F(y, p) = 0 (equilibrium.h) depends on a
 * second parameter q: any numeric key of the study (defaults.width,
 * materials.fold.E, analysis.load, folds[f1].rest_angle, or one component
 * of a vector key, loads[0].force[0]).  sf_family builds the problem at a
 * value of q by re-reading the study with the override "key=q" (the same
 * path as --set), so every key the study format knows can be the second
 * parameter; the last few values of q are cached.
 *
 * The special points of F(., .; q) form curves in (p, q).  sf_bnd is the
 * minimally extended system (Govaerts 2000, ch. 3-4; the bordered test
 * functions of MatCont) whose solutions are those curves, as a
 * cont_problem for the continuation engine, whose parameter is q
 * (normalised: s = (q - q0) / qs):
 *
 *   LP (limit point, fold): unknowns (y, p), n + 1 equations
 *       F(y, p; q) = 0,   g(y, p; q) = 0,
 *     g from the bordered system  [Js b; c^T 0] [v; g] = [0; 1],
 *     Js = diag(fs) Jy diag(1/ys) the scaled Jacobian, b, c borders close
 *     to its left and right null vectors: g = 0 iff Jy is singular.
 *   BP (branch point): unknowns (y, p, mu), n + 2 equations
 *       F(y, p; q) + mu b / fs = 0,   g1 = g2 = 0,
 *     (g1 g2) from  [As b; C^T 0] [V; g] = [0; I2],  As = [Js  fs Fp]
 *     (n x (n+1)), C two columns close to the null space of As: g1 = g2 =
 *     0 iff As has a two-dimensional null space.  mu (zero on the curve at
 *     a symmetry-breaking pitchfork, which is the branch point that
 *     persists under a second parameter) unfolds the system so that its
 *     Jacobian is regular there (Govaerts 2000, sec. 4.3; MatCont's BP
 *     curves).
 *
 * Derivatives.  Jy and Fp are the analytic ones of equilibrium.c.  The
 * rows of g need second derivatives of F; with u, w the right and left
 * bordered solutions (M^T u = e_last),
 *     dg_j = -w^T (dAs . V_j),
 * and by the symmetry of second derivatives the row of dg_j over all
 * unknowns is -w^T times the derivative of As in the direction V_j: ONE
 * directional derivative of the analytic Jacobian per g_j, taken by a
 * central difference with step 1e-5 (relative to |V| = 1 in the scaled
 * unknowns; error ~1e-10 relative), since the model has no third
 * derivatives of the energy.  The derivatives with respect to q are
 * central differences of F and of the analytic Jacobian between the
 * problems rebuilt at q +- 1e-6 qs: a study key enters the model through
 * the reader (widths change the faces, E the stiffnesses), so no analytic
 * dF/dq exists for every key.  These differences only enter the Newton
 * matrix: the points of the curve satisfy F = 0 and g = 0 to the Newton
 * tolerance whatever the accuracy of the Jacobian.
 *
 * Borders are refreshed at every point of the curve (sf_bnd_update): the
 * null vectors of the new point, oriented like the old ones (for a BP, the
 * old C projected onto the new null space and orthonormalised).
 *
 * Cusp test (LP curves): the quadratic coefficient of the fold,
 *   a = w^T (dJs . v) v / (|w| |v|^2),
 * vanishes at a cusp (two folds meet; the curve of folds has a cusp in the
 * (q, p) plane).  It is the engine's user test 0, labelled "CP".
 */
#ifndef SF_BOUNDARY_H
#define SF_BOUNDARY_H

#include <sundials/sundials_context.h>
#include <sundials/sundials_matrix.h>

#include "equilibrium.h"
#include "scene.h"
#include "sf_error.h"

#define SF_FAMILY_CACHE 4

typedef struct sf_family_entry {
    double q;
    long stamp;            /* last use, 0: empty */
    sf_scene sc;
    sf_equil eq;
} sf_family_entry;

typedef struct sf_family {
    const char *path;      /* the study file */
    int nset;              /* the user's --set overrides, then ours */
    const char **sets;
    char key[256];         /* the key set to q (a vector key when comp >= 0) */
    char shown[256];       /* the second parameter as the study names it */
    int comp, nvec;        /* component of a vector key (-1: a number) */
    double vec[3];
    double q0, qs;         /* value in the study; scale (|q0|, or 1) */
    int param, group, probe, component;   /* the path parameter p */
    int n, nq;
    double *ys, *fs;       /* Newton scales of y and F, fixed at q0 */
    long builds;           /* problems built */
    long clock;
    sf_family_entry ent[SF_FAMILY_CACHE];
    char setbuf[512];
} sf_family;

/* Family of the study at path (with the user's overrides) over the key
 * named by second.  Fails with a one-line message when the key is not a
 * numeric key of the study.  *f must be freed with sf_family_free. */
int sf_family_init(sf_family *f, const char *path, int nset, const char **sets,
                   const char *second, sf_error *err);
void sf_family_free(sf_family *f);
/* The equilibrium problem at second parameter q (cached; valid until the
 * next call that builds another). */
int sf_family_get(sf_family *f, double q, sf_equil **eq, sf_error *err);

enum { SF_BND_LP = 1, SF_BND_BP = 2 };

typedef struct sf_bnd {
    sf_family *fam;
    int kind;              /* SF_BND_LP or SF_BND_BP */
    int n, N;              /* equilibrium unknowns; extended unknowns */
    int m, k;              /* columns of the bordered block (n or n+1), borders (1 or 2) */
    double *b, *C;         /* borders: b[n], C[m * k] (column j at C + j*m) */
    /* scratch */
    double *A, *Ap, *Am, *M, *X, *u, *dA, *F1, *F2, *V;
    int *piv;
    SUNContext ctx;
    SUNMatrix J;
    double *Fp;
    long njac_diff;        /* Jacobian evaluations spent on differences */
    sf_error err;          /* last failure inside a callback */
} sf_bnd;

/* Extended system of the given kind for the family; borders from the SVD
 * at the special point (y, p) of F(., .; q).  */
int sf_bnd_init(sf_bnd *B, sf_family *f, int kind, const double *y, double p, double q,
                sf_error *err);
void sf_bnd_free(sf_bnd *B);
/* A cont_problem (user = B) on the unknowns Y = (y, p[, mu]), parameter
 * s = (q - q0) / qs. */
struct cont_problem;
void sf_bnd_problem(sf_bnd *B, double *yscale, double *fscale, struct cont_problem *prob);
/* New borders at the point (Y, s) of the curve. */
int sf_bnd_update(sf_bnd *B, const double *Y, double s);
/* q of the engine's parameter s, and back. */
double sf_bnd_q(const sf_bnd *B, double s);

/* Engine callbacks (user = sf_bnd *). */
int sf_bnd_residual(const double *Y, double s, double *G, void *user);
int sf_bnd_jacobian(const double *Y, double s, SUNMatrix JY, double *Gs, void *user);
int sf_bnd_test(const double *Y, double s, const double *tY, double ts, double *out, void *user);

#endif
