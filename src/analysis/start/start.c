/* start.c - the first point off the flat sheet (start.h): the driving's
 * control and amount of folding, the minimisation of start_alm.c, the
 * sheet's own branches where the driving is blocked, and what the output
 * says about them. */
#include "start.h"
#include "start_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "equilibrium_poses.h"
#include "mobility.h"
#include "study.h"

/* Two branches are the same when their unit fold-angle directions (sign
 * fixed) differ by less than this. */
#define SAME_BRANCH 1e-3

typedef struct start_ctx {
    sf_equil *q;
    fs_kkt k;
    const sf_start_opts *o;
    const double *y0;
    double p0;
    int dir;
    double *row;             /* the driving's control: dF/dp at the flat state */
    sf_start_info *info;
    int nbr;                 /* distinct branches found, their directions */
    double *dirs;            /* nbr x nfolds */
    unsigned char *rot;      /* ncon: 1 for the rotation rows of the loops */
} start_ctx;

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void add_stats(start_ctx *c, const fs_alm_result *r)
{
    c->info->outer += r->outer;
    c->info->newton += r->newton;
}

/* Largest |fold angle| of y. */
static double fold_amplitude(const sf_model *m, const double *y)
{
    double a = 0.0;
    for (int f = 0; f < m->nfolds; f++) a = fmax(a, fabs(y[m->qoff[f]]));
    return a;
}

/* Record the branch of the closed state y if its fold-angle direction is
 * new.  Returns its index. */
static int note_branch(start_ctx *c, const double *y)
{
    const sf_model *m = c->q->m;
    int nf = m->nfolds;
    double *v = malloc(sizeof(double) * ((size_t)nf + 1));
    if (!v) return -1;
    double big = fold_amplitude(m, y), sg = 0.0;
    for (int f = 0; f < nf; f++) {
        v[f] = big > 0.0 ? y[m->qoff[f]] / big : 0.0;
        if (sg == 0.0 && fabs(v[f]) >= 1e-2) sg = v[f] > 0.0 ? 1.0 : -1.0;
    }
    for (int f = 0; f < nf; f++) v[f] *= sg;
    for (int b = 0; b < c->nbr; b++) {
        double d = 0.0;
        for (int f = 0; f < nf; f++) d = fmax(d, fabs(v[f] - c->dirs[(size_t)b * nf + f]));
        if (d < SAME_BRANCH) { free(v); return b; }
    }
    double *nd = realloc(c->dirs, sizeof(double) * (size_t)(c->nbr + 1) * (size_t)nf);
    if (!nd) { free(v); return -1; }
    c->dirs = nd;
    memcpy(c->dirs + (size_t)c->nbr * nf, v, sizeof(double) * (size_t)nf);
    free(v);
    return c->nbr++;
}

/* Folds of y that turn against their crease assignment (valley positive). */
static int against_assignment(const sf_model *m, const double *y)
{
    const sf_study *s = m->study;
    int n = 0;
    double big = fold_amplitude(m, y);
    for (int i = 0; i < m->nfolds && i < s->nfolds; i++) {
        double sg = sf_study_fold_sign(s, i);
        double th = y[m->qoff[i]];
        if (sg != 0.0 && fabs(th) > 1e-3 * big && th * sg < 0.0) n++;
    }
    return n;
}

/* The rows' compliances in the method of multipliers (q->anchor_w, a
 * factor on each row's weight in the equilibrium problem; freed by
 * sf_start_flat).  The rotation rows of the loops are those of rigid
 * origami (the rotation part of a smooth fold's map is the rigid one,
 * MODEL.md 3), independent of band widths and shape modes; the
 * translation rows are the bands' own.  The minimisation runs in two
 * phases, a homotopy from rigid origami to smooth folds: first with the
 * rotation rows ROT_STIFF_* times stiffer than the translation rows, so
 * that the compliant sheet folds as rigid origami and only its bands'
 * translations give; then, from there, with every row at its own scale,
 * where the fold angles may leave rigid origami's ratios as much as the
 * bands need.  With equal weights from the start the shape modes close
 * the translations first and the sheet can end where its rotations cannot
 * close (Miura sheets of 4 x 4 and 8 x 8 cells in face poses); with stiff
 * rotations alone the translations cannot close where the bands need the
 * fold angles off rigid origami's (a 2 x 2 Miura sheet).  The factors
 * are measured, not derived: in fold coordinates 1e2 (1e4 and more left
 * the 4 x 4 Miura sheet's actuation unclosed), in face poses, where every
 * fold's rows are of first order at the flat state, 1e6 (1e2 left the
 * 8 x 8 sheet's unclosed). */
#define ROT_STIFF_FOLDS 1e2
#define ROT_STIFF_POSES 1e6
static int row_weights(start_ctx *c, sf_error *err)
{
    sf_equil *q = c->q;
    const sf_model *m = q->m;
    free(q->anchor_w);
    q->anchor_w = malloc(sizeof(double) * ((size_t)q->ncon + 1));
    c->rot = calloc((size_t)q->ncon + 1, 1);
    if (!q->anchor_w || !c->rot) return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int r = 0; r < q->ncon; r++) q->anchor_w[r] = 1.0;
    if (q->pz) {
        for (int k = 0; k < 6 * m->nfolds; k++) {
            int r = sf_peq_fold_row(q, k);   /* the constraint row of fold row k, or -1 */
            if (r >= 0 && k % 6 < 3) c->rot[r] = 1;
        }
    } else {
        for (int r = 0; r < q->nloop; r++) c->rot[r] = r % 6 < 3;
    }
    return SF_OK;
}

static void row_phase(start_ctx *c, int phase)
{
    sf_equil *q = c->q;
    double stiff = q->pz ? ROT_STIFF_POSES : ROT_STIFF_FOLDS;
    for (int r = 0; r < q->ncon; r++) q->anchor_w[r] = phase == 1 && c->rot[r] ? 1.0 / stiff : 1.0;
}

/* The first-order response to a unit amount of the control at the flat
 * state: its
 * largest fold angle per unit (*amp) and the sign of its multiplier
 * (*musign).  For FS_FIXED the response to a unit change of p. */
static int unit_response(start_ctx *c, const fs_control *ctl, double *amp, double *musign,
                         sf_error *err)
{
    fs_kkt *k = &c->k;
    sf_equil *q = c->q;
    int n = k->n, nx = k->nx;
    double *b = calloc((size_t)n + 1, sizeof(double));
    double *a = calloc((size_t)n + 1, sizeof(double));
    if (!b || !a) { free(b); free(a); return sf_fail(err, SF_ENOMEM, "out of memory"); }
    if (!q->lam_anchor) q->lam_anchor = calloc((size_t)q->ncon + 1, sizeof(double));
    memset(q->lam_anchor, 0, sizeof(double) * (size_t)q->ncon);
    /* the rows with a gradient at the flat state enforced (the others have
     * none there): the same response in either formulation */
    q->eps_anchor = 1e-10;
    int rc = fs_kkt_eval(k, c->y0, c->p0, err);
    if (!rc) rc = fs_kkt_factor(k, 0.0, err);
    if (!rc && ctl->kind == FS_FIXED) {
        for (int i = 0; i < n; i++) b[i] = -k->S[i] * k->Fp[i];
        rc = fs_kkt_solve(k, b, err);
        *musign = 1.0;
    } else if (!rc) {
        /* [K0 l; l^T 0] [x; nu] = [0; 1] */
        for (int i = 0; i < nx; i++) a[i] = ctl->row[i] * k->S[i];
        rc = fs_kkt_solve(k, a, err);
        double la = 0.0;
        for (int i = 0; i < nx; i++) la += ctl->row[i] * k->S[i] * a[i];
        if (!rc && la != 0.0) {
            for (int i = 0; i < n; i++) b[i] = a[i] / la;   /* x = K0^-1 l / (l . K0^-1 l) */
            *musign = la > 0.0 ? -1.0 : 1.0;                /* mu = -1 / la */
        } else if (!rc) {
            rc = SF_ENUMERIC;
        }
    }
    q->eps_anchor = 0.0;
    *amp = 0.0;
    for (int f = 0; !rc && f < q->m->nfolds; f++) {
        int i = q->m->qoff[f];
        *amp = fmax(*amp, fabs(b[i] * k->S[i]));
    }
    free(a);
    free(b);
    if (rc && rc != SF_ENOMEM)
        return sf_fail(err, SF_ENUMERIC, "flat start: the first-order response is singular");
    return rc;
}

/* Minimise under control ctl from y (in/out) and *mu, counting. */
static int minimise(start_ctx *c, const fs_control *ctl, double *y, double *mu, fs_alm_result *r,
                    sf_error *err)
{
    int rc = fs_alm(&c->k, ctl, y, mu, c->o->branch, c->o->tol, r, err);
    add_stats(c, r);
    return rc;
}

/* The driving's own minimisation from y (the flat state or a branch):
 * the amount of folding rel (row . (x - x0), or dp for a displacement
 * parameter), reduced where |p1 - p0| would exceed dp_max.  y, *mu
 * in/out. */
/* The driving's work function Psi(y) = Pi(y; p0 + 1) - Pi(y; p0)
 * (start_alm.c), and *pi = Pi(y; p0) when pi is not NULL. */
static double work_function(const start_ctx *c, const double *y, double *pi)
{
    double a, b, rr, rt;
    sf_equil_report(c->q, y, c->p0 + 1.0, &a, &rr, &rt);
    sf_equil_report(c->q, y, c->p0, &b, &rr, &rt);
    if (pi) *pi = b;
    return a - b;
}

static int drive(start_ctx *c, double *y, double *mu, double *relp, double eps_first,
                 fs_alm_result *r, sf_error *err)
{
    sf_equil *q = c->q;
    /* the amount of folding is measured from the flat state's Psi */
    double r0 = work_function(c, c->y0, NULL);
    int fixed = q->disp_row >= 0;
    double rel = *relp;
    double eps0 = eps_first;   /* 0: the first run starts compliant; a rerun as stiff as it ended */
    for (int tries = 0; tries < 4; tries++) {
        fs_control ctl = {fixed ? FS_FIXED : FS_PARAM, fixed ? NULL : c->row, r0 + rel,
                          fixed ? c->p0 + rel : c->p0, eps0};
        /* first as rigid origami (rotation rows stiff), then with the
         * bands' own weights (row_weights) */
        row_phase(c, 1);
        int rc = minimise(c, &ctl, y, mu, r, err);
        if (!rc && !r->closed) {
            row_phase(c, 2);
            /* phase 1's multipliers held its rotations against the bands:
             * phase 2 starts compliant from its state */
            memset(y + c->k.nx, 0, sizeof(double) * (size_t)c->k.m);
            ctl.eps0 = eps_first;
            rc = minimise(c, &ctl, y, mu, r, err);
        }
        *relp = rel;
        if (rc || !r->closed) return rc;
        double dp = fixed ? rel : *mu;
        if (fabs(dp) <= c->o->dp_max * (1.0 + 1e-12) || dp * c->dir <= 0.0) return SF_OK;
        /* too far along the path: less folding, from the state scaled back */
        double f = 0.9 * c->o->dp_max / fabs(dp);
        for (int i = 0; i < c->k.nx; i++) y[i] = c->y0[i] + f * (y[i] - c->y0[i]);
        *mu *= f;
        rel *= f;
        eps0 = r->eps;
    }
    return SF_OK;
}

/* The first proximal weight of a minimisation that starts from a closed
 * state: the loops nearly rigid from the start (a compliant first step
 * would leave the branch for the driving's unconstrained response). */
#define CLOSED_EPS 1e-8

/* Closed states the census asks the mobility analysis for (their
 * mirror images are tried too): the two `check` finds.  More find more
 * branches, but which ones depends on rounding: with 6, the windmill's
 * folding branch is among them under OpenBLAS's SkylakeX and Haswell
 * kernels, not under Prescott (its probe closes 4 states there, 8
 * otherwise). */
#define CENSUS_STATES 2

/* The census of the sheet's branches (start.h): the closed states that
 * `check`'s mobility analysis finds at a small distance from the flat
 * sheet (mobility.h: rays of the second-order cone, the first along the
 * driving's own second-order motion) and their mirror images, on the side
 * where the driving does work.  Each is scaled to the first point's
 * largest fold angle and taken by the driving's own minimisation at its
 * own amount of folding, with the loops rigid from the outset.
 *
 * The branch followed is the one of least energy at a given parameter.
 * On branch b, near the flat state, the bending energy is U = k_b a^2 / 2
 * and the driving's work -Psi = c_b a at amplitude a, so its equilibria
 * have a = (p - p0) c_b / k_b and energy -(p - p0)^2 c_b^2 / (2 k_b): the
 * branch with the largest c_b^2 / (2 k_b) = Psi^2 / (2 U), a ratio that
 * does not depend on the amplitude at which it is measured.  (The least
 * energy at equal amplitude would pick the stiffest branch.)
 *
 * best (q->n) and *mu get the state followed, *followed its index + 1; mb
 * the analysis (its verdict and certificate where none closes).  A seed
 * that is not closed does not serve: the rigid-origami motion of
 * flatrigid.h, with the bands' mode amplitudes zero, leaves the
 * windmill's loops open by 9e-5 however stiff they are made (K = 1:
 * closure needs a definite pattern of amplitudes). */
static int census(start_ctx *c, double *yb, double *best, double *mu, double *best_score,
                  int *followed, sf_mobility *mb, sf_error *err)
{
    sf_equil *q = c->q;
    const sf_model *m = q->m;
    int n = q->n, nq = m->nq, nx = q->nq;
    int rc = sf_mobility_states(m, CENSUS_STATES, mb, err);
    if (rc) return rc;
    double pi0, psi0 = work_function(c, c->y0, &pi0);   /* at the flat state */
    for (int s = 0; s < 2 * mb->nstates && !rc; s++) {
        const double *st = mb->states + (size_t)(s / 2) * nq;
        double big = 0.0;
        for (int g = 0; g < m->nfolds; g++) big = fmax(big, fabs(st[m->qoff[g]]));
        if (!(big > 0.0)) continue;
        memcpy(yb, c->y0, sizeof(double) * (size_t)n);
        double f = (s % 2 ? -1.0 : 1.0) * c->o->flat_angle / big;
        for (int j = 0; j < nq; j++) yb[j] = c->y0[j] + f * st[j];
        if (q->pz) sf_equil_poses_lift(q, yb);
        /* the side on which the driving does work: -dF/dp . dx > 0 */
        double w = 0.0;
        for (int i = 0; i < nx; i++) w += c->row[i] * (yb[i] - c->y0[i]);
        if (w * c->dir > 0.0) continue;
        c->info->singles++;
        double mc = 0.0, rel = work_function(c, yb, NULL) - psi0;
        fs_alm_result r;
        rc = drive(c, yb, &mc, &rel, CLOSED_EPS, &r, err);
        if (rc == SF_ENUMERIC) { sf_error_clear(err); rc = SF_OK; continue; }
        if (rc || !r.closed || mc * c->dir <= 0.0) continue;
        note_branch(c, yb);
        double Pi;
        work_function(c, yb, &Pi);
        double U = Pi - pi0, score = U > 0.0 ? rel * rel / (2.0 * U) : 0.0;
        if (score > *best_score * (1.0 + 1e-9)) {
            *best_score = score;
            *followed = s / 2 + 1;
            *mu = mc;
            memcpy(best, yb, sizeof(double) * (size_t)n);
        }
    }
    return rc;
}

int sf_start_flat(sf_equil *q, const double *y0, double p0, int dir, const sf_start_opts *o,
                  double *y1, double *p1, sf_start_info *info, sf_error *err)
{
    memset(info, 0, sizeof *info);
    double t0 = now();
    start_ctx c;
    memset(&c, 0, sizeof c);
    sf_mobility mb;   /* the census's (`check`'s) analysis of the flat sheet */
    memset(&mb, 0, sizeof mb);
    c.q = q;
    c.o = o;
    c.y0 = y0;
    c.p0 = p0;
    c.dir = dir >= 0 ? 1 : -1;
    c.info = info;
    const sf_model *m = q->m;
    const char *path = m->study->path;
    int n = q->n, nx = q->nq;
    int rc = fs_kkt_init(&c.k, q, err);
    double *yb = malloc(sizeof(double) * ((size_t)n + 1));
    double *best = malloc(sizeof(double) * ((size_t)n + 1));
    double *pin = calloc((size_t)nx + 1, sizeof(double));
    c.row = calloc((size_t)nx + 1, sizeof(double));
    if (!rc && (!yb || !best || !pin || !c.row)) rc = sf_fail(err, SF_ENOMEM, "out of memory");
    if (!rc) rc = row_weights(&c, err);
    /* the driving's control: dF/dp at the flat state */
    if (!rc) {
        q->eps_anchor = 0.0;
        rc = fs_kkt_eval(&c.k, y0, p0, err);
    }
    double rowmax = 0.0, r0 = 0.0;
    if (!rc) {
        for (int i = 0; i < nx; i++) {
            c.row[i] = c.k.Fp[i];
            rowmax = fmax(rowmax, fabs(c.row[i] * c.k.S[i]));
            r0 += c.row[i] * y0[i];
        }
    }
    if (!rc && q->disp_row < 0 && !(rowmax > 1e-12)) {
        /* in-plane loads: no first-order work, the flat sheet carries them */
        info->verdict = SF_FOLD_FLAT;
        memcpy(y1, y0, sizeof(double) * (size_t)n);
        *p1 = p0;
        snprintf(info->note, sizeof info->note, "flat start: the driving does no work on the "
                 "fold angles at first order (in-plane loads): the path starts along the flat "
                 "sheet");
        goto done;
    }
    double mu = 0.0, amp = 0.0, musign = 1.0;
    fs_alm_result r;
    memset(&r, 0, sizeof r);
    if (!rc) {
        fs_control ctl = {q->disp_row >= 0 ? FS_FIXED : FS_PARAM, c.row, 1.0, p0, 0.0};
        rc = unit_response(&c, &ctl, &amp, &musign, err);
    }
    if (!rc && !(amp > 0.0))
        rc = sf_fail(err, SF_EINPUT, "%s: the driving does not fold the sheet at first order "
                     "(its response keeps every fold flat)", path);
    double target = 0.0;
    if (!rc) {
        target = c.dir * musign * o->flat_angle / amp;
        memcpy(yb, y0, sizeof(double) * (size_t)n);
        rc = drive(&c, yb, &mu, &target, 0.0, &r, err);
    }
    int followed = -1;   /* 0: the driving's, f + 1: fold f's */
    if (!rc && r.closed) {
        followed = 0;
        info->symmetric = r.saddle;
        memcpy(best, yb, sizeof(double) * (size_t)n);
        note_branch(&c, best);
    } else if (!rc) {
        info->blocked = 1;
    }
    /* the sheet's own branches: the closed states of the mobility
     * analysis, each taken by the driving's own minimisation (census) */
    double best_score = 0.0;
    int censused = !rc && info->blocked && q->disp_row < 0;
    if (censused)
        rc = census(&c, yb, best, &mu, &best_score, &followed, &mb, err);
    info->branches = c.nbr;
    info->factorisations = c.k.nfact;
    if (rc) goto done;
    if (followed < 0 && censused && sf_mobility_locked(&mb)) {
        char what[1500];
        info->verdict = SF_FOLD_LOCKED;
        sf_mobility_describe(m, &mb, what, sizeof what);
        rc = sf_fail(err, SF_ELOCKED, "%s: flat start: locked: %s", path, what);
        goto done;
    }
    if (followed < 0) {
        info->verdict = SF_FOLD_UNDECIDED;
        char how[160];
        if (isfinite(r.gres))
            snprintf(how, sizeof how, "loop residual %.2g after %d Newton steps", r.gres, info->newton);
        else
            snprintf(how, sizeof how, "after %d Newton steps its state left the range where the "
                     "equations are defined", info->newton);
        rc = sf_fail(err, SF_ENUMERIC, "%s: flat start: no closed state near the flat sheet along "
                     "the driving's response (%s)%s; the "
                     "sheet may not fold with rigid faces and exact loop closure: try "
                     "`smoothfold check` and solver.constraints = \"penalty\" (compliant loops)",
                     path, how, !censused ? "" : mb.probed ?
                     ", nor from the closed states that `check`'s mobility analysis finds" :
                     " (the sheet is too large for the whole sheet's second-order analysis)");
        goto done;
    }
    double dp = mu;
    if (q->disp_row >= 0) dp = target;
    if (dp * c.dir <= 0.0) {
        info->verdict = SF_FOLD_UNDECIDED;
        rc = sf_fail(err, SF_ENUMERIC, "%s: flat start: the closed state the driving reaches needs "
                     "the parameter to move against the path's direction (dp = %.3g)", path, dp);
        goto done;
    }
    info->verdict = SF_FOLD_FOLDABLE;
    info->from_fold = followed;
    memcpy(y1, best, sizeof(double) * (size_t)n);
    *p1 = p0 + dp;
    info->p1 = *p1;
    info->amplitude = fold_amplitude(m, y1);
    info->residual = r.gres;
    info->against = against_assignment(m, y1);
    {
        char buf[600];
        int o2 = 0;
        if (followed == 0)
            o2 += snprintf(buf + o2, sizeof buf - (size_t)o2, "the driving's own branch");
        else
            o2 += snprintf(buf + o2, sizeof buf - (size_t)o2, "the branch of least energy at "
                           "a given parameter among those through the closed states of "
                           "`check`'s mobility analysis (state %d; the driving's own response "
                           "is blocked: no closed state near it)", followed);
        if (info->symmetric)
            o2 += snprintf(buf + o2, sizeof buf - (size_t)o2, "; symmetric driving: the state it "
                           "selects is a saddle, left along its direction of negative curvature "
                           "(branch %d of 2 mirror images, solver.flat_branch)", o->branch);
        if (info->against)
            snprintf(buf + o2, sizeof buf - (size_t)o2, "; %d folds turn against their "
                     "assignment", info->against);
        snprintf(info->note, sizeof info->note, "flat start: foldable: %d branch%s found%s; "
                 "following %s: first point at p = %.6g, largest fold angle %.4g rad (%d Newton "
                 "steps, %d outer iterations)", c.nbr, c.nbr == 1 ? "" : "es",
                 info->singles ? " (with the mobility analysis's closed states)" : "", buf, *p1,
                 info->amplitude, info->newton, info->outer);
    }
done:
    sf_mobility_free(&mb);
    info->seconds = now() - t0;
    q->eps_anchor = 0.0;
    free(q->anchor_w);
    q->anchor_w = NULL;
    fs_kkt_free(&c.k);
    free(c.row);
    free(c.dirs);
    free(c.rot);
    free(yb);
    free(best);
    free(pin);
    return rc;
}
