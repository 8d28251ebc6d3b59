/* bifurcation.h - bifurcation bookkeeping along equilibrium paths: the
 * Morse index between consecutive points of a branch, crossings of
 * eigenvalues of H_c located at fixed p (regula falsi on the eigenvalue),
 * branch points the engine located poorly refined on the eigenvalue, and
 * the branch-switching driver (breadth first through the simple branch
 * points met, up to a depth).
 *
 * The continuation engine finds a branch point from a sign change of
 * det [Jy Fp; t^T] between two points, so it misses two eigenvalues of H_c
 * crossing zero in one step: a double eigenvalue of a symmetric sheet (the
 * buckling modes of square4 come in pairs), or two simple crossings close
 * together.  The Morse index sees them.  Between consecutive points a and b
 * of a branch, the index may change by the crossings at a or b themselves
 * (an LP or BP the engine located has one eigenvalue at zero, counted
 * either way); any further change is located here, eigenvalue by
 * eigenvalue, by regula falsi (Illinois) on p with fixed-p solves, and
 * handed to the caller as a point of its own: type BP for one eigenvalue,
 * BPk for k eigenvalues crossing together (a k-dimensional kernel: a
 * multiple branch point, whose branches, for k = 2, come from the reduced
 * bifurcation equations of multibp.h).  A change that
 * cannot be located is stated in a note.
 *
 * The caller (src/cli/run_point.c, run_stability.c) owns the output: located points go back to it
 * through hooks, as do notes.  Enters: the equilibrium problem and its
 * stability (equilibrium.h, stability.h), the path's points (cont.h).
 * Leaves: located points, notes, the branch numbering. */
#ifndef SF_BIFURCATION_H
#define SF_BIFURCATION_H

#include "cont.h"
#include "equilibrium.h"
#include "sf_error.h"
#include "stability.h"

/* Most branches followed in one run (the first one included). */
#define SF_BIF_MAX_BRANCHES 64

/* A branch point met along a branch, for switching. */
typedef struct sf_bif_bp {
    double *y, *ty;
    double p, tp;
    int depth;            /* depth of the branch it was found on */
    int branch;           /* that branch */
    long point;           /* its row in the output */
    int switched;         /* 1 once the branches through it were started */
    int mult;             /* kernel dimension: 1, or k for a "BPk" (multibp.h) */
} sf_bif_bp;

/* What the bookkeeping hands back to its caller.  ctx is passed to each;
 * a NULL hook does nothing. */
typedef struct sf_bif_hooks {
    void *ctx;
    /* A note on a branch: one line, no newline. */
    void (*note)(void *ctx, const char *line);
    /* Write the located point q (its stability in the sf_stab's res) as the
     * next row; 0 on success. */
    int (*emit)(void *ctx, const cont_point *q);
    /* A new branch, number branch, starts at bp: prepare its output and
     * the solver's parameter range; 0 or an SF_* status that ends the
     * switching. */
    int (*begin_branch)(void *ctx, const sf_bif_bp *bp, int branch);
    /* Non-zero when the caller's point callback has failed (its status is
     * in the sf_error given to sf_bif_switch). */
    int (*failed)(void *ctx);
} sf_bif_hooks;

typedef struct sf_bif {
    sf_equil *eq;
    sf_stab *stab;        /* stability of the points (NULL: no Morse check) */
    double tol;           /* Newton tolerance of the fixed-p solves */
    sf_bif_hooks h;
    const long *nrows;    /* rows the caller has written so far */
    /* branches: the one being followed, and the branch points still to
     * switch at (breadth first, up to depth max_depth) */
    int branch, nbranches, depth, max_depth;
    sf_bif_bp *bp;
    int nbp, capbp, nextbp;
    /* Morse-index check between consecutive points of a branch */
    cont_solver *aux;     /* fixed-p solves while locating (not the path's solver) */
    int prev_ok, prev_lo, prev_hi, prev_dim, prev_neig;
    long prev_row;
    double prev_p, prev_sarc;
    double *prev_y, *prev_eig, *ya, *yb, *yt;
    int in_check;         /* locating: the rows written are not path points */
} sf_bif;

/* Bookkeeping for the problem eq with stability st (or NULL), Newton
 * tolerance tol for the fixed-p solves, switching up to max_depth levels.
 * nrows: the caller's count of rows written.  The first branch is 1. */
void sf_bif_init(sf_bif *b, sf_equil *eq, sf_stab *st, double tol, int max_depth,
                 const long *nrows, const sf_bif_hooks *h);
void sf_bif_free(sf_bif *b);
/* A note on the run (one line, printf format), through the caller's hook
 * when there is one. */
void sf_bif_note(sf_bif *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Bounds lo..hi on the Morse index at a point with stability R: the
 * negative eigenvalues, allowing for the one at zero of an LP/BP the engine
 * located (pt's label) or of a branch point the point is (at_bp). */
void sf_bif_morse_bounds(const sf_stab_result *R, const cont_point *pt, int at_bp, int *lo,
                         int *hi);

/* Locate the zero of the j-th eigenvalue (1-based) between the points
 * a (ya, pa), where it is fa (its sign only unless known_a), and b (yb,
 * pb), where it has the other sign: regula falsi with the Illinois
 * modification on the eigenvalue where the method computed it, bisection
 * on the index otherwise.  Leaves the solution in b->yt (b->stab->res its
 * stability) and its p in *p_out; returns the final bracket width in p, or
 * -1 when the zero cannot be located.  Needs sf_bif_prepare. */
double sf_bif_locate_eig(sf_bif *b, const double *ya, double pa, double fa, int known_a,
                         const double *yb, double pb, int j, double *p_out);
/* The fixed-p solver and scratch of the locating functions; 0 or SF_ENOMEM
 * / SF_ENUMERIC. */
int sf_bif_prepare(sf_bif *b);

/* The point pt (stability in b->stab->res) was written as row *nrows - 1,
 * at arclength sarc: remember it for the next check (not while locating). */
void sf_bif_point_written(sf_bif *b, const cont_point *pt, double sarc);

/* Step bound near predicted eigenvalue crossings (docs/guides/stability.md,
 * "Step length near predicted crossings").  R: the stability at the
 * regular point pt (unit tangent pt->ty, pt->tp).  The slopes dmu_j/ds of
 * the eigenvalues R->eig come from a second evaluation with st2 at
 * (y + h ty, p + h tp), h = 1e-6 (the eigenvalues keep their order over so
 * short a distance); each mu_j moving towards zero is predicted to cross
 * it at d_j = -mu_j / (dmu_j/ds) beyond pt.  When two distinct predicted
 * crossings (d_b - d_a > 1e-3 d_b; equal ones are one multiple crossing)
 * both lie within the next step ds_next, the step is bounded to
 * (d_a + d_b) / 2, so that it ends between them.  Returns the bound, or 0
 * (none, or the second evaluation failed). */
double sf_bif_step_bound(const sf_stab_result *R, sf_stab *st2, sf_equil *eq, const cont_point *pt,
                         double ds_next);

/* Before pt is written (its stability in b->stab->res): locate the
 * eigenvalue crossings since the previous point that the engine's tests
 * cannot account for, emitting each as a row.  s_offset: arclength before
 * the engine's first point; first: pt starts a branch.  Leaves b->stab->res
 * at pt.  0, or an SF_* status (message in err). */
int sf_bif_check(sf_bif *b, const cont_point *pt, double s_offset, int first, sf_error *err);

/* A branch point the engine located poorly (its corrector left the branch
 * while bisecting on the determinant): locate the zero of the eigenvalue
 * nearest zero again, with fixed-p solves, between the previous point and
 * pt or, when the eigenvalue has not changed sign there, between pt and a
 * point one step beyond.  On success *q is the located point (state in
 * ybuf, n values) with b->stab->res its stability, and 1 is returned; 0
 * leaves pt as it is (with b->stab->res at pt). */
int sf_bif_refine(sf_bif *b, const cont_point *pt, double s_offset, int first, cont_point *q,
                  double *ybuf);

/* Remember the branch point pt (with its tangent) for switching, unless
 * it is one already known or the branch is at the largest depth.  A
 * multiple one (label "BPk", k >= 2) needs no tangent: its branches come
 * from the reduced equations (multibp.h).  0 or SF_ENOMEM. */
int sf_bif_add_bp(sf_bif *b, const cont_point *pt, sf_error *err);

/* Follow the branches through the branch points met so far, breadth
 * first, with the path's solver cs: at each simple branch point, the new
 * direction t2 from cont_branch_direction, then one branch along +t2 and
 * one along -t2 (hooks begin_branch, then the points through cs's
 * callback); at a multiple one (kernel dimension 2), one branch along each
 * solution of the reduced bifurcation equations (multibp.h), its first
 * point compared with the others' to recognise duplicates (same state:
 * not followed) and symmetric images (same p, energy and sorted |q|:
 * followed, and grouped in a note "classes of symmetric images").  A
 * branch that fails is kept up to where it stopped and noted; it does not
 * end the run. */
int sf_bif_switch(sf_bif *b, cont_solver *cs, sf_error *err);

#endif
