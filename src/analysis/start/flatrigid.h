/* flatrigid.h - a rigid-origami motion of the crease pattern at the flat
 * state, built from the closed form of its degree-4 vertices: the start
 * of the sparse limit problem (flatlimit_sparse.c) that is not the
 * first-order response (docs/flatstart.md, "Which limit state"). */
#ifndef SF_FLATRIGID_H
#define SF_FLATRIGID_H

#include "kinematics.h"

/* Fold angles x of a rigid folding motion of the crease pattern of m,
 * built vertex by vertex from the closed form of a degree-4 vertex at the
 * flat state; u (the first-order response) and b (the driving, dF/dp at
 * the flat state) give at least m->nq values, fold coordinates first.  At interior vertex v with outward crease
 * directions e_k (ccw) the fold angles rho_k turn the faces about e_k, so
 * the loop closes to first order when sum rho_k e_k = 0 (a plane of
 * solutions) and to second order when the normal rotation of the product,
 * sum_{i<j} rho_i rho_j (e_i x e_j) . n / 2, vanishes: a quadratic form on
 * that plane whose two null lines are the vertex's two rigid modes (for a
 * flat-foldable vertex the classical ones: one pair of opposite creases
 * equal, tan(rho_minor / 2) proportional to tan(rho_major / 2);
 * docs/design/crease-limit.md).  Each vertex takes the mode whose signs agree
 * best with the driving's, s = sgn(-b) (sgn u on folds b leaves alone):
 * largest |s . r| / |r|.  The first-order response u is not used for
 * that: on the 4x4 Miura sheet its signs already follow the branch with
 * flat edge columns.  The modes are chained across shared folds
 * breadth-first from the vertex where u is largest (a fold takes the
 * value of the first vertex reached: exact where the pattern folds
 * rigidly in these modes).  Folds at no degree-4 vertex keep u.  x (nq
 * fold coordinates, mode amplitudes 0) has u's largest fold angle, signed
 * so that the driving does work (s . x > 0); returns the number of
 * vertices used (0: none, no such start). */
int sf_flat_rigid_modes(const sf_model *m, const double *u, const double *b, double *x);

#endif
