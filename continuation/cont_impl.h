/* cont_impl.h - private to the engine's source files in continuation/:
 * the solver structure, points, bordered matrices, and the functions the
 * files share (prefix ci_).  Not installed, not included outside continuation/;
 * the public face is cont.h.
 *
 * Files of the engine
 *   cont.c            life cycle (cont_create, cont_free), options
 *                     (cont_set_*), getters, small helpers, errors, timing,
 *                     allocation of points
 *   cont_bordered.c   the user's residual and Jacobian wrapped (counting,
 *                     non-finite and pattern checks); bordered matrices
 *                     [Jy Fp; c^T]: assembly, factorisation, determinant
 *                     sign, solves
 *   cont_corrector.c  the KINSOL corrector on the bordered system, Newton at
 *                     fixed p (cont_solve_fixed)
 *   cont_special.c    evaluation of a corrected point (tangent, determinant,
 *                     test functions) and location of test-function zeros
 *                     (LP, BP, user tests, p = p_b)
 *   cont_step.c       start (cont_start, cont_start_tangent), one step with
 *                     step-size control and stop rules (cont_step,
 *                     cont_run), delivery of points
 *   cont_switch.c     the new direction at a simple branch point
 *                     (cont_branch_direction)
 *   cont_blockelim.c  the bordered factorisation and solves by block
 *                     elimination on the LDL^T of a symmetric Jy, with the
 *                     checks that fall back to the LU of cont_bordered.c
 */
#ifndef CONT_IMPL_H
#define CONT_IMPL_H

#include "cont.h"
#include "cont_lapack.h"
#include "cont_mumps.h"

#include <kinsol/kinsol.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sundials/sundials_context.h>

#include <math.h>
#include <time.h>

/* Constants documented in cont.h */
#define SKIP_START_RATIO 1e-4   /* negligible test value at a start point */
#define BP_NULL_TOL 1e-6        /* null-space check in cont_branch_direction */
#define LOC_MAXIT 100
#define GUARD_ANGLE 0.05       /* rad, branch-jump guard in locate() */
#define MERGE_FRAC 1e-3        /* LP and BP this close (fraction of the step) are one BP */

enum { TEST_LP = -1, TEST_BP = -2, TEST_PB = -3 };  /* >= 0: user test k */
enum { ST_IDLE = 0, ST_RUN, ST_DONE, ST_FAIL };

typedef struct cont_bmat {
    long m;                   /* order */
    int sparse;               /* CSC storage (KLU or MUMPS) */
    int mumps;                /* factorised by MUMPS (cont_mumps.h), else KLU */
    SUNMatrix A;
    SUNLinearSolver LS;
    sunindextype *pat_ptr, *pat_idx;  /* last pattern analysed */
    sunindextype pat_cap;
    int pat_valid;
    long gen;                 /* factorisations made so far (ci_bm_factor) */
    /* block elimination on the LDL^T of a symmetric Jy (cont_blockelim.c):
     * NULL unless the problem says Jy is symmetric and the solver is MUMPS */
    struct cont_blk *blk;
    int blk_active;           /* the current factors are blk's, not LS's */
} cont_bmat;

typedef struct cpt {
    cont_point pub;
    double *x;       /* n+1: y, p */
    double *t;       /* n+1: ty, tp */
    double *test;    /* ntest */
    int det_valid;
    double h;        /* arclength offset from the step base */
    int terminal;
    int stop_reason;
} cpt;

struct cont_solver {
    cont_problem prob;
    long n, m;
    int linsol;
    double *yscale_copy, *fscale_copy;
    double *wy;              /* norm weights of y (cont_set_weights), NULL: all 1 */
    double arc2;             /* their factor in the arclength only (cont_set_arc_scale), a^2 */
    double *ulast;           /* with wy: the Newton iterate at the last Jacobian, m */
    char (*labels)[16];

    /* options */
    double ds0, ds_min, ds_max, grow, shrink, max_angle;
    double p_min, p_max, s_max, theta, ftol, xtol, loc_tol;
    long max_steps;
    int max_newton, strategy, fast_iters, init_maxit, init_strategy;
    unsigned detect;
    int store;
    cont_point_fn cb;
    void *cb_data;

    /* SUNDIALS objects */
    SUNContext ctx;
    SUNMatrix Jy;
    double *Fp;
    N_Vector u, uscale, fscale, vx, vb;
    void *kmem;
    cont_bmat bk, bt;        /* KINSOL's matrix; tangent/determinant matrix */

    /* corrector border: c.(x - xa) - sig = 0 */
    double *bc, *bxa, bsig;

    /* the reusing corrector (cont_corrector.c): the factors it left in
     * s->bt, made at an iterate near its solution with border rc */
    int corrector;           /* CONT_CORRECTOR_* */
    int point_inertia;       /* cont_set_point_inertia */
    double *rc;              /* m */
    double *rw;              /* work, 2m */
    long rgen;               /* s->bt.gen of those factors, -1: none */
    double *cw, *w1;         /* work, m each */
    char *mark;              /* permutation parity work, m+1 */
    long *stamp;             /* duplicate check of sparse Jy, n */

    /* run state */
    int state, stop_reason, first_step;
    cpt *base;               /* last regular point: the next step starts here */
    double s_arc, ds;
    long steps, index;
    cpt *queue[64];
    int nq, q0;
    cpt *cur;                /* last delivered point */
    int cur_owned;           /* cur not in hist: free it when replaced */
    cpt **hist;
    long nhist, hcap;
    cpt **spec;
    long nspec, scap;
    cpt *lw[3];              /* location scratch */
    struct timespec t_start;

    cont_stats stp, last, total;
    double last_fnorm;       /* residual norm at the last residual call */
    double kin_fs;           /* scaled max residual at KINSOL's last call */
    double fail_fs;          /* the same where the last corrector attempt
                              * failed (NAN: not known, or converged) */
    double anchor_fs;        /* lowest plain residual of this attempt's
                              * anchored solves (INFINITY: none) */
    double att_fsmin;        /* lowest scaled residual of the plain Newton
                              * iterates of the last step attempt, its
                              * predictor included (INFINITY: none) */
    int att_track;           /* a plain Newton of a step attempt is running */
    double att_afs;          /* lowest scaled residual of the Newton iterates of
                              * the last step attempt's anchored reusing
                              * corrector, where a level of it ended at its
                              * iteration limit (INFINITY: none did) */
    int att_anch;            /* that corrector of a step attempt is running */
    struct {                 /* failed step attempts in a row, across steps,
                              * whose anchored corrector stagnated at the
                              * tolerance (cont_step.c, afloor_count) */
        int n;
        long pts;            /* points accepted since the first of them */
        double lo, hi, p, ds;
    } afl;
    int anchor_first;        /* cont_set_anchor_first */
    int predictor;           /* cont_set_predictor: 1 or 2 */
    double *tprev, hprev;    /* the tangent of the point before the step base and
                              * the arclength between them (m; hprev 0: none) */
    int reuse_level;         /* its anchor level that last succeeded; 0: none */
    int polish_iters;        /* of the last ci_correct_step: its re-anchoring
                              * iterations (not a measure of the step's difficulty) */
    int anchor_level;        /* the anchor level (cont_anchor_fn) of the last
                              * anchored solve that met the tolerance in this
                              * run; 0: none yet.  Nonzero: the corrector tries
                              * the anchored system first, from that level */
    char why[400];           /* reason the last attempt failed */
    char kin_msg[256];       /* last message from KINSOL */
    char msg[2048];          /* first error (with a diagnosis about 1000 characters) */
    int err;
};

#define NEED(s) do { if (!(s)) return CONT_EINPUT; } while (0)

static inline int ci_differ(double a, double b) { return signbit(a) != signbit(b); }

/* cont.c: helpers, errors, timing; points; life cycle, options, getters */
int ci_all_finite(const double *v, long len);
double ci_fscaled_max(const cont_solver *s, const double *f, long len);
void ci_clear_run(cont_solver *s);
double ci_dotw(const cont_solver *s, const double *a, const double *b);
int ci_fail(cont_solver *s, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
double ci_norm_inf(const double *v, long len);
double ci_now_sec(void);
void ci_pt_copy(const cont_solver *s, cpt *dst, const cpt *src);
cpt *ci_pt_dup(cont_solver *s, const cpt *src);
void ci_pt_free(cpt *q);
cpt *ci_pt_new(cont_solver *s);
void ci_pt_sync(const cont_solver *s, cpt *q);
void ci_set_label(cpt *q, int type, const char *label);
double ci_since(const struct timespec *t0);
void ci_weigh(const cont_solver *s, const double *t, double *c);
void ci_why(cont_solver *s, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* cont_bordered.c: user callbacks wrapped; bordered matrices */
int ci_bm_build(cont_solver *s, cont_bmat *bm, const double *c);
void ci_bm_apply(const cont_solver *s, const double *c, const double *v, double *out);
int ci_bm_det(cont_solver *s, cont_bmat *bm, int *sign, double *logdet);
int ci_bm_factor(cont_solver *s, cont_bmat *bm, int *sign, double *logdet);
void ci_bm_free(cont_bmat *bm);
void ci_blk_factor_stats(const cont_bmat *bm, cont_factor_stats *fs);
void ci_blk_inertia(const cont_bmat *bm, long *neg, long *nnull);
int ci_bm_init(cont_solver *s, cont_bmat *bm, long m, int linsol,
               sunindextype nnz, N_Vector tmpl);
int ci_bm_solve(cont_solver *s, cont_bmat *bm, N_Vector x, N_Vector b);
int ci_bm_solve_as(cont_solver *s, cont_bmat *bm, N_Vector x, N_Vector b, int raw);
int ci_call_jacobian(cont_solver *s, const double *y, double p);
int ci_call_residual(cont_solver *s, const double *y, double p, double *F);
sunindextype ci_jy_nnz(const cont_solver *s);
void ci_jy_dense(const cont_solver *s, double *A, long ld);
sunindextype ci_jy_column(const cont_solver *s, long j, sunindextype *bi, double *bx,
                          sunindextype k, double *norm2);

/* cont_blockelim.c: block elimination on the LDL^T of a symmetric Jy */
int ci_blk_init(cont_solver *s, cont_bmat *bm);
void ci_blk_free(cont_bmat *bm);
void ci_blk_new_pattern(cont_bmat *bm);
int ci_blk_factor(cont_solver *s, cont_bmat *bm);
int ci_blk_det(const cont_bmat *bm, int *sign, double *logdet);
int ci_blk_solve(cont_solver *s, cont_bmat *bm, double *x, const double *b, int raw);

/* cont_corrector.c: KINSOL corrector, Newton at fixed p */
int ci_correct(cont_solver *s, double *x, const double *c, const double *xa,
               double sig, int maxit, int strategy, int *nit, double *fnorm);
int ci_correct_reuse(cont_solver *s, double *x, const double *c, const double *xa,
                     double sig, int maxit, int monotone, int *nit, double *fnorm);
/* one step's corrector: the anchored reusing one first (cont_set_anchor_first),
 * the reusing one, then KINSOL's (ci_correct) */
int ci_correct_step(cont_solver *s, double *x, const double *c, const double *xa, double sig,
                    int *nit, double *fnorm);
int ci_tangent_reuse(cont_solver *s, const double *c, int *sign, double *logdet);
void ci_kin_err(int code, const char *module, const char *function,
                char *msg, void *data);
int ci_kin_jac(N_Vector uv, N_Vector fv, SUNMatrix J, void *data,
               N_Vector t1, N_Vector t2);
int ci_kin_sys(N_Vector uv, N_Vector fv, void *data);
int ci_solve_fixed(cont_solver *s, double *x, int *nit, double *fnorm);

/* cont_special.c: points evaluated (tangent, determinant, test functions); special-point location; landing on p = pb */
int ci_eval_point(cont_solver *s, cpt *q, const double *c, int dir, int keep_t);
int ci_land(cont_solver *s, const cpt *b, const cpt *x1, double pb, cpt **res);
int ci_locate(cont_solver *s, int id, const cpt *b, const cpt *xe, double he,
              double pb, cpt **res);
double ci_test_value(const cont_solver *s, int id, const cpt *q, double ref, double pb);

/* cont_step.c: start, step control and stop rules, run */
void ci_flush_stats(cont_solver *s, double t0, int is_step);

#endif
