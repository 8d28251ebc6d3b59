/* poses_rowsel.h - which of the pose formulation's fold rows to keep
 * (docs/design/model.md, "Redundant rows removed"): the 6 N fold rows have
 * left null vectors at every state (the self-stress identities of the
 * faces ringed by folds, and with K = 1 more rows than unknowns), which
 * make the KKT matrix singular.  A maximal independent set of rows is
 * found once per study by SuiteSparseQR's rank-revealing QR of C^T at a
 * generic state; the others are dropped from the equations and checked
 * after each solved point. */
#ifndef SF_POSES_ROWSEL_H
#define SF_POSES_ROWSEL_H

#include "poses.h"
#include "sf_error.h"

/* A generic state x (P->nx values): fold coordinates uniform in
 * [-0.5, 0.5), the poses of their tree maps, then every pose entry moved
 * by up to amp / 2 (rotation) or amp lref / 2 (position); reproducible
 * from seed.  SF_OK or SF_ENOMEM. */
int sf_rowsel_generic_state(const sf_poses *P, double lref, double amp, unsigned seed, double *x);

/* The rank of the fold rows at x into *rank (rows scaled as Newton sees
 * them: translations by 1 / lref, positions by lref; a column of the QR
 * whose remaining norm is below rtol times the longest row is
 * dependent).  When it is below the number of unknowns P->nx, the
 * dependent rows are identities (self-stresses) and keep[r] (6 N values)
 * = 1 marks the rows of a maximal independent set, 0 the others, *nkeep
 * their number.  When the rank equals
 * P->nx the rows may outnumber the unknowns (K = 1): the surplus is then
 * made of equations of their own, not identities, and every row is kept
 * (keep[] = 1, *nkeep = 6 N).  SF_OK, SF_ENOMEM, SF_ENUMERIC (SuiteSparseQR failed). */
int sf_rowsel_select(const sf_poses *P, const double *x, double lref, double rtol, int *keep,
                     int *nkeep, int *rank, sf_error *err);

#endif
