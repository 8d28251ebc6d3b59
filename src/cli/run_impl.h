/* run_impl.h - private to `smoothfold run` for equilibrium paths: the state
 * the files run.c, run_equilibrium.c, run_stability.c, run_point.c and
 * run_output.c share. */
#ifndef SF_RUN_IMPL_H
#define SF_RUN_IMPL_H

#include "bifurcation.h"
#include "commands.h"
#include "compare.h"
#include "cont.h"
#include "equilibrium.h"
#include "fold.h"
#include "kinematics.h"
#include "outbuf.h"
#include "reactions.h"
#include "scene.h"
#include "stability.h"
#include "run_validity.h"
#include "vtk.h"

#ifndef PACKAGE_VERSION
#define PACKAGE_VERSION "0.1.0"
#endif

typedef struct run_ctx {
    sf_scene *sc;
    sf_equil eq;
    const sf_options *opt;
    sf_error *err;
    char dir[1024];
    sf_mpoint *probes;
    sf_outbuf rows, stats, special, header;
    sf_pvd pvd;
    sf_foldrec foldrec;   /* DIR/folded.fold: one frame per shape (fold.h) */
    int nshapes;
    double p_start, p_end, last_shape_p, shape_dp;
    int branch_first;     /* the next point starts a branch */
    long npoints;
    int failed;
    double s_offset;      /* arclength before the engine's first point */
    double cpu_path0;     /* process CPU seconds when the path after its start began (0: not yet) */
    cont_solver *solver;
    /* stability */
    int do_stab, nev;
    int step_bound;       /* analysis.step_bound: steps bounded near predicted crossings */
    long nbound;          /* steps so bounded */
    sf_stab stab2;        /* the second evaluation of the step bound */
    sf_stab stab;
    long neig_method[4];  /* points analysed by each SF_EIG_* method */
    long neig_inertia;    /* of those by the inertia method: with eigenvalues */
    /* branches (numbering, branch points, switching) and the Morse-index
     * check between consecutive points (bifurcation.h) */
    sf_bif bif;
    sf_outbuf bnotes;
    int skip_start;       /* the next point repeats the last one (stage restart) */
    /* a branch point of the engine's determinant test, held back until
     * the next point's Morse index says whether an eigenvalue crossed
     * (run_point.c, hold_bp) */
    int held;
    int held_morse;       /* the index of the row before it */
    cont_point held_pt;
    double *held_y, *held_ty, *held_eig;
    sf_stab_result held_res;
    double seg_end;       /* end of the stage being followed (multi-stage loads) */
    double p_lo, p_hi;    /* the parameter range of the path */
    int max_steps;        /* analysis.max_steps */
    int short_stop;       /* a branch stopped at max_steps inside the range */
    double short_p;       /* where (the first one) */
    int short_branch;
    int branch_end;       /* the point being written ends its branch */
    int shape_every;      /* output.shape_every: a shape every N points */
    long last_shape_pt;   /* row of the last shape */
    sf_reactions reac;    /* reactions.tsv rows (supports, prescribed displacement) */
    sf_compare *cmp;      /* reference data of the study (compare.h), or NULL */
    int compared;         /* comparison done */
    cont_stats tot;       /* solver totals of the path (before the comparison) */
    /* switching at the flat state with exact closure (flatswitch.h) */
    int flat_sw;          /* the path started at the flat state, branch_depth >= 1 */
    double flat_p0, flat_dp, flat_p1;
    double *flat_first;   /* the first point of the path off the flat state */
    /* face poses: the fold rows dropped as dependent (poses_rowsel.h),
     * checked at every written point */
    double drop_max;      /* largest scaled residual of a dropped row */
    long drop_bad;        /* points where it exceeded the Newton tolerance */
    /* physical validity of every point written (validity.h): the warning
     * column of branch.tsv, and the summary at the end of the run */
    run_validity vt;
    /* "auto" chose the start by the method of multipliers for a small
     * sheet with loops (choose_keys); multipliers_start: that start ran.
     * If it found no first point, or the path stopped before its second,
     * run.c runs the study again with the limit start */
    int auto_small;
    int multipliers_start;
} run_ctx;

/* run_equilibrium.c: set up the equilibrium problem and the continuation
 * engine from the study, then follow the whole path (all stages, branches). */
int run_equilibrium(run_ctx *r);

/* run_stability.c: analysis.stability keys, eigensolver and branch bookkeeping;
 * *depth gets analysis.branch_depth. */
int run_setup_stability(run_ctx *r, int *depth);

/* run_point.c: the engine's callback for each solved point (cont.h). */
int run_on_point(const cont_point *pt, void *data);
/* A held branch point written as it is (the branch ended before the next
 * point decided it); nonzero when writing failed. */
int run_flush_held(run_ctx *r);
/* run_point.c: write the rows, shapes and progress line of one solved point. */
int run_write_point(run_ctx *r, const cont_point *pt);
/* run_point.c: a note on a branch, for branch.tsv's header and the terminal. */
void run_branch_note(run_ctx *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* run_point.c: the physical-validity summary of the run (validity.h):
 * one line, "" when every point is valid. */
void run_validity_summary(const run_ctx *r, char *buf, size_t size);

/* run_output.c: write DIR/branch.tsv, stats.csv, special.tsv and the rest. */
int run_write_outputs(run_ctx *r);

/* CPU seconds of the process so far (user + system, every thread). */
double run_cpu_seconds(void);

#endif
