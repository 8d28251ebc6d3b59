/* start.h - leaving the flat sheet with exact loop closure (docs/design/start.md).
 *
 * At the flat state the loop rows that turn about the sheet's normal or
 * translate in its plane have no gradient: the flat state of a foldable
 * sheet is a singular point where several branches meet, and Newton's
 * method cannot start there.  The first point of a path is instead the
 * closed state of a small, given amount of folding with the least energy:
 * the equilibrium at the parameter p1 at which the driving's first-order
 * work reaches the amount that folds the sheet by analysis.flat_angle.  It
 * is found by the method of multipliers from the flat sheet (start_alm.c):
 * the loops start compliant and are made rigid, the inner minimisations
 * keep the inertia of a minimum, so the state reached is one the driving
 * pushes the sheet into.  Where that state is a saddle (a symmetric
 * driving), the two mirror branches leave it along its direction of
 * negative curvature: the first is followed, solver.flat_branch = 2
 * follows the other.
 *
 * Where no closed state lies near the driving's response (its response is
 * blocked: the loops resist it at second order), the sheet's own branches
 * are taken from `check`'s mobility analysis of the flat sheet
 * (mobility.h): each closed state it finds near the flat sheet, scaled to
 * the first point's amplitude, starts the same minimisation with the loops
 * rigid from the outset, and the branch of least energy at a given
 * parameter is followed (start.c, census).
 * Where none closes, the verdict is the mobility analysis's: locked with
 * its certificate (a prestress or second-order rigidity, naming the
 * vertices), or undecided. */
#ifndef SF_START_H
#define SF_START_H

#include "equilibrium.h"

typedef struct sf_start_opts {
    double flat_angle;   /* largest fold angle of the first point [rad] */
    double dp_max;       /* |p1 - p0| at most (the first step of the path) */
    double tol;          /* Newton tolerance (scaled residual) */
    int branch;          /* 1; 2: the mirror image where the driving is symmetric */
} sf_start_opts;

enum { SF_FOLD_UNKNOWN = 0, SF_FOLD_FOLDABLE = 1, SF_FOLD_LOCKED = 2, SF_FOLD_UNDECIDED = 3,
       SF_FOLD_FLAT = 4 /* the driving does no first-order work: the flat sheet is the branch */ };

typedef struct sf_start_info {
    int verdict;         /* SF_FOLD_* */
    int branches;        /* distinct branches found (by their fold-angle directions) */
    int singles;         /* the mobility analysis's closed states tried (census) */
    int blocked;         /* the driving's response has no closed state near it */
    int symmetric;       /* the state the driving selects is a saddle: mirror branches */
    int from_fold;       /* the branch followed: 0 the driving's own, s + 1 through the
                            mobility analysis's closed state s */
    int against;         /* folds of the first point that turn against their assignment */
    int outer, newton;   /* outer iterations and Newton steps, all minimisations */
    long factorisations;
    double p1;           /* the first point's parameter */
    double amplitude;    /* its largest |fold angle| [rad] */
    double residual;     /* its constraint residual (scaled rows) */
    double seconds;
    char note[1200];     /* one paragraph for the output: what was found and followed */
} sf_start_info;

/* The first point off the flat state y0 (q->n values, solving the
 * problem at p0) in direction dir (+1, -1): y1 (q->n values) and *p1.
 * SF_OK with info->verdict SF_FOLD_FOLDABLE (y1, p1 set) or SF_FOLD_FLAT
 * (y1 = y0, p1 = p0: start the path at the flat state itself); otherwise
 * an error whose message says what was found and what to try
 * (SF_ELOCKED with the certificate when the sheet is locked). */
int sf_start_flat(sf_equil *q, const double *y0, double p0, int dir, const sf_start_opts *o,
                  double *y1, double *p1, sf_start_info *info, sf_error *err);

#endif
