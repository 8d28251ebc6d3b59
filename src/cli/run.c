/* run.c - `smoothfold run`: follow the study's equilibrium path with the
 * continuation engine and write DIR/branch.tsv, DIR/stats.csv,
 * DIR/special.tsv, DIR/shapes.pvd (with the VTK files in DIR/shapes/) and DIR/study.cfg
 * (docs/output-format.md).  Every file is written to a temporary name and
 * renamed when complete. */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "bifurcation.h"
#include "commands.h"
#include "compare.h"
#include "cont.h"
#include "equilibrium.h"
#include "equilibrium_poses.h"
#include "outbuf.h"
#include "run_boundary.h"
#include "run_dynamics.h"
#include "flatstart.h"
#include "flatstart_sparse.h"
#include "flatswitch.h"
#include "mobility.h"
#include "reactions.h"
#include "scene.h"
#include "stability.h"
#include "study.h"
#include "fold.h"
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
} run_ctx;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* Probe displacements of a state. */
static void probe_disp(run_ctx *r, const double *y, int i, double u[3])
{
    double x[3];
    sf_point_eval(r->eq.m, &r->eq.k, &r->probes[i], x, NULL);
    u[0] = x[0] - r->probes[i].X[0];
    u[1] = x[1] - r->probes[i].X[1];
    u[2] = x[2];
    (void)y;
}

/* Note on a branch, for the headers of branch.tsv and on the terminal. */
static void branch_note(run_ctx *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void branch_note(run_ctx *r, const char *fmt, ...)
{
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    sf_outbuf_printf(&r->bnotes, "# %s\n", line);
    if (!r->opt->quiet) fprintf(stderr, "%s\n", line);
}

/* Stability columns (stable, morse, eig1..eigN) of a row; empty fields
 * where there is no value (stability off, or fewer eigenvalues). */
static void stab_fields(run_ctx *r, sf_outbuf *b)
{
    const sf_stab_result *R = &r->stab.res;
    if (!r->do_stab) {
        sf_outbuf_printf(b, "\t\t");
        for (int i = 0; i < r->nev; i++) sf_outbuf_printf(b, "\t");
        return;
    }
    if (R->stable < 0) sf_outbuf_printf(b, "\t\t%d", R->morse); /* unknown: empty */
    else sf_outbuf_printf(b, "\t%d\t%d", R->stable, R->morse);
    for (int i = 0; i < r->nev; i++) {
        if (i < R->neig && isfinite(R->eig[i])) sf_outbuf_printf(b, "\t%.13g", R->eig[i]);
        else sf_outbuf_printf(b, "\t");
    }
}

static int write_point(run_ctx *r, const cont_point *pt);

/* Every number of the point's rows is finite, checked before any of them is
 * written (outbuf.h, sf_need_finite); else SF_ENUMERIC naming the quantity,
 * the row and p, and the run stops with the rows before it. */
static int check_point(run_ctx *r, const cont_point *pt, double sarc, double load, const double e[3])
{
    sf_error *err = r->err;
    const sf_model *m = r->eq.m;
    const sf_study *s = m->study;
    long k = r->npoints;
    if (sf_need_finite(err, pt->p, "p at row %ld (branch %d)", k, r->bif.branch)) return err->code;
    const double *v[] = {&sarc, &load, &e[0], &e[1], &e[2], &pt->ds};
    const char *what[] = {"arclength s", "load", "energy", "residual (rotation)", "residual (translation)",
                          "step ds"};
    for (int j = 0; j < 6; j++)
        if (sf_need_finite(err, *v[j], "%s at row %ld (branch %d, p = %.10g)", what[j], k, r->bif.branch,
                           pt->p))
            return err->code;
    for (int i = 0; i < s->nprobes; i++) {
        double u[3];
        probe_disp(r, pt->y, i, u);
        for (int c = 0; c < 3; c++)
            if (sf_need_finite(err, u[c], "probe %s u%c at row %ld (branch %d, p = %.10g)",
                               s->probes[i].name, "xyz"[c], k, r->bif.branch, pt->p))
                return err->code;
    }
    for (int i = 0; i < m->nfolds; i++)
        if (sf_need_finite(err, pt->y[m->qoff[i]], "fold angle of fold %d at row %ld (branch %d, p = %.10g)",
                           i + 1, k, r->bif.branch, pt->p))
            return err->code;
    for (int j = 0; j < r->eq.n; j++)
        if (sf_need_finite(err, pt->y[j], "unknown %d of the state at row %ld (branch %d, p = %.10g)", j, k,
                           r->bif.branch, pt->p))
            return err->code;
    if (pt->label[0] && strcmp(pt->label, "EP") != 0 &&
        sf_need_finite(err, pt->loc_err, "location error of %s at row %ld (branch %d, p = %.10g)", pt->label,
                       k, r->bif.branch, pt->p))
        return err->code;
    return SF_OK;
}

static int on_point(const cont_point *pt, void *data)
{
    run_ctx *r = data;
    if (r->skip_start) {
        r->skip_start = 0;
        return 0;
    }
    cont_point relabel;
    int ends = strcmp(pt->label, "EP") == 0;   /* the last point of a branch */
    r->branch_end = ends;
    if (ends && fabs(pt->p - r->seg_end) <= 1e-9 && fabs(r->seg_end - r->p_end) > 1e-9) {
        /* the end of a load stage inside the path is a regular point */
        relabel = *pt;
        relabel.label[0] = '\0';
        pt = &relabel;
    } else if (ends && fabs(pt->p - r->p_lo) > 1e-9 * (1 + fabs(r->p_lo)) &&
               fabs(pt->p - r->p_hi) > 1e-9 * (1 + fabs(r->p_hi)) &&
               fabs(pt->p - r->seg_end) > 1e-9) {
        /* the engine ended the branch inside the range: analysis.max_steps
         * (the only other stop rule here), not an end point */
        relabel = *pt;
        relabel.label[0] = '\0';
        pt = &relabel;
        if (!r->short_stop) {
            r->short_stop = 1;
            r->short_p = pt->p;
            r->short_branch = r->bif.branch;
        }
    }
    sf_equil *eq = &r->eq;
    if (r->do_stab) {
        if (sf_stab_eval(&r->stab, eq, pt->y, pt->p, r->err)) {
            r->failed = 1;
            return 1;
        }
        r->neig_method[r->stab.res.method]++;
        r->neig_inertia += r->stab.res.method == SF_EIG_INERTIA && r->stab.res.neig > 0;
        const sf_stab_result *S = &r->stab.res;
        if (S->status != SF_SSTAB_OK)
            branch_note(r, "stability at row %ld (branch %d, p = %.10g): %s after %d ARPACK "
                        "attempt(s): %s", r->npoints, r->bif.branch, pt->p,
                        S->status == SF_SSTAB_RETRIED ? "retried, converged"
                        : S->stable < 0 ? "UNKNOWN" : "eigenvalues unknown, unstable by inertia",
                        S->attempts, S->reason);
        if (sf_bif_check(&r->bif, pt, r->s_offset, r->branch_first, r->err)) {
            r->failed = 1;
            return 1;
        }
        cont_point q;
        double *ybuf = malloc(sizeof(double) * (size_t)eq->n);
        if (ybuf && sf_bif_refine(&r->bif, pt, r->s_offset, r->branch_first, &q, ybuf)) {
            int rc = write_point(r, &q);
            free(ybuf);
            return rc;
        }
        free(ybuf);
        if (r->step_bound && pt->index >= 1 && pt->type == CONT_PT_REGULAR) {
            /* two eigenvalue crossings predicted within the next step: end
             * it between them (bifurcation.h, sf_bif_step_bound) */
            double bnd = sf_bif_step_bound(&r->stab.res, &r->stab2, eq, pt, cont_get_ds(r->solver));
            if (bnd > 0 && cont_set_next_step(r->solver, bnd) == CONT_OK) r->nbound++;
        }
    }
    return write_point(r, pt);
}

/* One row of branch.tsv (and of special.tsv, stats.csv, the shapes, the
 * comparison) for the solved point pt, whose stability is r->stab.res. */
static int write_point(run_ctx *r, const cont_point *pt)
{
    sf_equil *eq = &r->eq;
    const sf_model *m = eq->m;
    const sf_study *s = m->study;
    double Pi, rr, rt;
    sf_equil_report(eq, pt->y, pt->p, &Pi, &rr, &rt);
    if (eq->pz && sf_peq_rows_dropped(eq)) {
        double d = sf_peq_dropped_residual(eq, pt->y), tol = s->tolerance > 0 ? s->tolerance : 1e-10;
        r->drop_max = fmax(r->drop_max, d);
        if (!(d <= tol) && !r->drop_bad++)
            branch_note(r, "row %ld (branch %d, p = %.10g): a dropped pose constraint row has "
                        "residual %.3g, above the Newton tolerance %.3g: the kept rows do not "
                        "imply it here (docs/formulations.md; solver.pose_rows = \"all\" keeps "
                        "every row)", r->npoints, r->bif.branch, pt->p, d, tol);
    }
    double load = eq->param == SF_PARAM_LOAD ? pt->p : eq->load;
    if (r->s_offset < 0) {
        /* first point after a start off the flat state: the arclength
         * from the flat state, in the norm of the path (q and p) */
        double d2 = (pt->p - r->p_start) * (pt->p - r->p_start);
        for (int j = 0; j < m->nq; j++) d2 += pt->y[j] * pt->y[j];   /* fold coordinates */
        r->s_offset = sqrt(d2);
    }
    sf_outbuf *b = &r->rows;
    double sarc = pt->s + r->s_offset;
    const double e[3] = {Pi, rr, rt};
    if (check_point(r, pt, sarc, load, e) ||
        (eq->nsup && sf_reactions_add(&r->reac, eq, r->npoints, pt->y, pt->p, load, r->err))) {
        r->failed = 1;
        return 1;
    }
    sf_outbuf_printf(b, "%ld\t%d\t%.12g\t%.12g\t%.12g", r->npoints, r->bif.branch, sarc, pt->p, load);
    double u0[3] = {0, 0, 0};
    for (int i = 0; i < s->nprobes; i++) {
        double u[3];
        probe_disp(r, pt->y, i, u);
        if (i == 0) memcpy(u0, u, sizeof u);
        sf_outbuf_printf(b, "\t%.12g\t%.12g\t%.12g", u[0], u[1], u[2]);
    }
    sf_outbuf_printf(b, "\t%.12g\t%.3g\t%.3g\t%.3g\t%d", Pi, fmax(rr, rt), rr, rt, pt->newton_iters);
    stab_fields(r, b);
    sf_outbuf_printf(b, "\t%s", pt->label);
    for (int i = 0; i < m->nfolds; i++) sf_outbuf_printf(b, "\t%.12g", pt->y[m->qoff[i]]);
    sf_outbuf_printf(b, "\n");
    cont_stats last;
    memset(&last, 0, sizeof last);
    if (r->solver) cont_get_stats(r->solver, &last, NULL);
    sf_outbuf_printf(&r->stats, "%ld,%d,%.6g,%.6g,%d,%ld,%ld,%ld,%ld,%.6g,%ld\n", r->npoints, r->bif.branch,
              pt->p, pt->ds, pt->newton_iters, last.nres, last.njac, last.retries, last.nlocate,
              last.wall, last.nfactor);
    int special = pt->label[0] && strcmp(pt->label, "EP") != 0;
    if (special) {
        sf_outbuf_printf(&r->special, "%ld\t%d\t%s\t%.12g\t%.12g", r->npoints, r->bif.branch, pt->label,
                  pt->p, sarc);
        for (int i = 0; i < s->nprobes; i++) {
            double u[3];
            probe_disp(r, pt->y, i, u);
            sf_outbuf_printf(&r->special, "\t%.12g\t%.12g\t%.12g", u[0], u[1], u[2]);
        }
        stab_fields(r, &r->special);
        sf_outbuf_printf(&r->special, "\t%.3g\n", pt->loc_err);
        if (pt->index >= 0 && pt->loc_err > 1e-6 * (1.0 + fabs(pt->p)))
            branch_note(r, "%s at row %ld (branch %d, p = %.10g) located only to within %.3g in "
                        "arclength: the corrector left the branch while bisecting", pt->label,
                        r->npoints, r->bif.branch, pt->p, pt->loc_err);
        if (strncmp(pt->label, "BP", 2) == 0 && sf_bif_add_bp(&r->bif, pt, r->err)) {
            r->failed = 1;
            return 1;
        }
    }
    /* shapes: the first and last point of each branch, every special
     * point, every output.shape_every points, and whenever p has moved by
     * shape_dp since the last shape (so a snap segment, where p hardly
     * moves, still has its shapes) */
    int want = r->nshapes > 0 &&
               (r->branch_first || r->branch_end || special ||
                (r->shape_every > 0 && r->npoints - r->last_shape_pt >= r->shape_every) ||
                (r->shape_dp > 0 && fabs(pt->p - r->last_shape_p) >= r->shape_dp * (1 - 1e-9)));
    r->branch_first = 0;
    if (want) {
        char rel[64], path[1200];
        snprintf(rel, sizeof rel, "shapes/shape_%04ld.vtp", r->npoints);
        snprintf(path, sizeof path, "%s/%s", r->dir, rel);
        /* time in the .pvd: the row number (monotone along the branch,
         * also where p turns back); p and the row are field data */
        const char *fname[2] = {"p", "point"};
        double fval[2] = {pt->p, (double)r->npoints};
        if (sf_vtk_write_shape_fields(m, pt->y, s->samples, path, 2, fname, fval, r->err) ||
            sf_pvd_add(&r->pvd, (double)r->npoints, rel, r->err) ||
            sf_foldrec_add(&r->foldrec, pt->y, pt->p, load, r->do_stab ? r->stab.res.stable : -1,
                           r->bif.branch, r->err)) {
            r->failed = 1;
            return 1;
        }
        r->last_shape_p = pt->p;
        r->last_shape_pt = r->npoints;
    }
    if (r->cmp) {
        /* reference comparison: points of each branch form their own block */
        if (sf_compare_add(r->cmp, eq, r->probes, pt->y, pt->p, r->bif.branch, r->err)) {
            r->failed = 1;
            return 1;
        }
    }
    if (!r->opt->quiet) {
        fprintf(stderr, "point %4ld  p %-11.6g s %-10.4g newton %2d  |g| %-9.2g", r->npoints,
                pt->p, sarc, pt->newton_iters, fmax(rr, rt));
        if (s->nprobes) fprintf(stderr, "  %s uz %-11.5g", s->probes[0].name, u0[2]);
        if (r->do_stab)
            fprintf(stderr, "  %s", r->stab.res.stable < 0 ? "unknown "   /* see the note */
                                    : r->stab.res.stable ? "stable  " : "unstable");
        if (r->bif.nbranches > 1 || r->bif.max_depth > 0) fprintf(stderr, "  branch %d", r->bif.branch);
        fprintf(stderr, "%s%s\n", pt->label[0] ? "  " : "", pt->label);
    }
    r->npoints++;
    sf_bif_point_written(&r->bif, pt, sarc);
    return 0;
}

/* Hooks of the bifurcation bookkeeping (bifurcation.h). */
static void on_note(void *ctx, const char *line) { branch_note(ctx, "%s", line); }

static int on_located(void *ctx, const cont_point *q)
{
    run_ctx *r = ctx;
    r->neig_method[r->stab.res.method]++;
    return write_point(r, q);
}

static int on_failed(void *ctx) { return ((run_ctx *)ctx)->failed; }

/* A switched branch starts: its own series of shapes, the whole range of
 * p (it may run either way, all load stages together), a new block of
 * branch.tsv. */
static int on_branch(void *ctx, const sf_bif_bp *bp, int branch)
{
    run_ctx *r = ctx;
    (void)bp;
    if (r->nshapes > 0) {
        /* each branch has its own series of shapes */
        if (sf_pvd_write(&r->pvd, r->err)) return r->err->code;
        sf_pvd_free(&r->pvd);
        char pvd[1100];
        snprintf(pvd, sizeof pvd, "%s/shapes_branch%d.pvd", r->dir, branch);
        sf_pvd_init(&r->pvd, pvd);
    }
    /* a switched branch may run either way in p: the whole range,
     * all load stages together */
    r->eq.ramp_stage = -1;
    r->seg_end = r->p_end;
    cont_set_prange(r->solver, fmin(r->p_start, r->p_end), fmax(r->p_start, r->p_end));
    r->branch_first = 1;
    r->s_offset = 0.0;
    sf_outbuf_printf(&r->rows, "\n\n");
    return SF_OK;
}

/* The start failed: when the loop constraints leave no motion (the whole
 * sheet, or a vertex its own folds), say so instead (SF_ELOCKED). */
static int explain_start_failure(run_ctx *r)
{
    sf_error *err = r->err;
    if (r->eq.nloop == 0 || r->failed) return err->code;
    sf_mobility mb;
    sf_error merr;
    sf_error_clear(&merr);
    if (sf_mobility_analyse(r->eq.m, NULL, &mb, &merr)) return err->code;
    if (sf_mobility_locked(&mb)) {
        char what[1500];
        sf_mobility_describe(r->eq.m, &mb, what, sizeof what);
        sf_error_clear(err);
        sf_fail(err, SF_ELOCKED, "%s: no equilibrium at the start of the path: %s",
                r->eq.m->study->path, what);
    }
    sf_mobility_free(&mb);
    return err->code;
}

/* Follow the load stage that contains p in direction dir: the stage ramps
 * alone (sf_equil_set_param) and the parameter range ends where it ends
 * (or at the path's end). */
static void stage_segment(run_ctx *r, double p, int dir, double lo, double hi)
{
    int ns = r->eq.e.nstages;
    int k = dir > 0 ? (int)floor(p + 1e-9) : (int)ceil(p - 1e-9) - 1;
    k = k < 0 ? 0 : k > ns - 1 ? ns - 1 : k;
    double e = dir > 0 ? (k == ns - 1 ? hi : fmin(k + 1.0, hi)) : (k == 0 ? lo : fmax(k, lo));
    r->eq.ramp_stage = k;
    r->seg_end = (dir > 0 ? e >= hi : e <= lo) ? r->p_end : e;
    cont_set_prange(r->solver, dir > 0 ? lo : e, dir > 0 ? e : hi);
}

/* Every branch at the flat state (flatswitch.h): the solutions of the
 * reduced second-order equations on the tangent cone, each followed as a
 * branch; the path already followed from the flat state is not repeated. */
static int flat_switch(run_ctx *r)
{
    sf_flatsw F;
    sf_error e;
    sf_error_clear(&e);
    int nst = 400;
    if (sf_study_int(&r->sc->study, "analysis.flat_starts", 400, &nst, r->err)) return r->err->code;
    int rc = sf_flatsw_find(&r->eq, r->flat_p0, r->flat_dp, 0.02, r->p_lo, r->p_hi, nst, &F, &e);
    if (rc) {
        if (rc == SF_ENOMEM) return sf_fail(r->err, rc, "%s", e.msg);
        branch_note(r, "flat state: no switching: %s", e.msg);
        return SF_OK;
    }
    rc = sf_flatsw_follow(&r->bif, r->solver, &F, r->flat_p0, r->flat_first, r->flat_p1, r->err);
    sf_flatsw_free(&F);
    return rc;
}

/* Follow the path from its start point: one load stage after the other
 * when the loads come in stages (staged), then the branches through the
 * branch points met (bifurcation.h).  y0: scratch of n values, freed here. */
static int follow_path(run_ctx *r, double *y0, int staged, int dir, double lo, double hi)
{
    cont_solver *cs = r->solver;
    const sf_study *s = &r->sc->study;
    sf_equil *eq = &r->eq;
    sf_error *err = r->err;
    double end = r->p_end;
    int rc = cont_run(cs);
    while (staged && rc == CONT_DONE && !r->failed && r->seg_end != end &&
           cont_stop_reason(cs) == (dir > 0 ? CONT_STOP_PMAX : CONT_STOP_PMIN)) {
        /* next stage, from the last point */
        const cont_point *last = cont_get_point(cs);
        double pb = last->p;
        r->s_offset += last->s;
        memcpy(y0, last->y, (size_t)eq->n * sizeof *y0);
        stage_segment(r, pb, dir, lo, hi);
        r->skip_start = 1;
        if (cont_start(cs, y0, pb, dir) != CONT_OK) {
            r->skip_start = 0;
            if (r->failed) break;
            free(y0);
            return sf_fail(err, SF_ENUMERIC, "%s: path stopped after %ld points: no restart at "
                           "the end of load stage %d (p = %g): %s", s->path, r->npoints,
                           (int)lround(pb), pb, cont_errmsg(cs));
        }
        rc = cont_run(cs);
    }
    free(y0);
    if (r->failed) return err->code;
    if (rc == CONT_FAIL)
        return sf_fail(err, SF_ENUMERIC, "%s: path stopped after %ld points: %s%s", s->path, r->npoints,
                       cont_errmsg(cs), strstr(cont_errmsg(cs), "residual floor") ? " (solver.tolerance)" : "");
    if (r->flat_sw && flat_switch(r)) return err->code;
    return sf_bif_switch(&r->bif, cs, err);
}

/* analysis.stability and its keys: the eigensolver of each point, the
 * branch bookkeeping (bifurcation.h) and, through *depth, how deep
 * branches are switched.  After the equilibrium problem is set up. */
static int setup_stability(run_ctx *r, int *depth)
{
    sf_scene *sc = r->sc;
    const sf_study *s = &sc->study;
    sf_error *err = r->err;
    sf_equil *eq = &r->eq;
    int stab_on = 1, nev = 4;
    *depth = 0;
    const char *eigsolver = "auto";
    if (sf_study_bool(s, "analysis.stability", 1, &stab_on, err) ||
        sf_study_int(s, "analysis.eigenvalues", 4, &nev, err) ||
        sf_study_int(s, "analysis.branch_depth", 0, depth, err) ||
        sf_study_string(s, "analysis.eigensolver", "auto", &eigsolver, err) ||
        sf_study_bool(s, "analysis.step_bound", 1, &r->step_bound, err))
        return err->code;
    if (stab_on && nev > sc->model.nq) {
        /* bounded by the problem: no more eigenvalues exist than coordinates */
        sf_outbuf_printf(&r->header, "# note: analysis.eigenvalues = %d, but the sheet has %d "
                         "generalised coordinates: %d reported\n", nev, sc->model.nq, sc->model.nq);
        nev = sc->model.nq;
    }
    r->do_stab = stab_on;
    r->nev = stab_on ? nev : 0;
    sf_bif_hooks hooks = {r, on_note, on_located, on_branch, on_failed};
    sf_bif_init(&r->bif, &r->eq, r->do_stab ? &r->stab : NULL,
                s->tolerance > 0 ? s->tolerance : 1e-10, *depth, &r->npoints, &hooks);
    if (r->do_stab) {
        int meth = strcmp(eigsolver, "dense") == 0 ? SF_EIG_DENSE
                 : strcmp(eigsolver, "arpack") == 0  ? SF_EIG_ARPACK
                 : strcmp(eigsolver, "inertia") == 0 ? SF_EIG_INERTIA
                                                     : SF_EIG_AUTO;
        if (sf_stab_init(&r->stab, eq, meth, nev > 0 ? nev : 1, err)) return err->code;
        if (r->step_bound && sf_stab_init(&r->stab2, eq, meth, nev > 0 ? nev : 1, err)) {
            r->step_bound = 0;
            return err->code;
        }
        if (sf_stab_read_keys(&r->stab, s, err)) return err->code;
    }
    return SF_OK;
}

/* The path starts at the flat state of a sheet with loops: write that
 * point, then find the first point off it (flatstart.h, the pose and
 * sparse variants).  0: the engine holds the first point, *ret = CONT_OK;
 * 1: stop with *ret. */
static int start_at_flat(run_ctx *r, double *y0, double start, double end, double step,
                         int dir, int depth, int sparse, double flat_angle, int *ret)
{
    const sf_study *s = &r->sc->study;
    sf_error *err = r->err;
    sf_equil *eq = &r->eq;
    cont_solver *cs = r->solver;
    int rc;
    /* The flat state solves the exact problem at the start, but it is a
     * singular point of loop closure (multipliers of the second-order
     * rows are undetermined there).  Report it, then start the branch
     * one step further from the limit of the branch at the flat state
     * (src/analysis/flatstart.c; the penalty homotopy as the fallback). */
    cont_point p0;
    memset(&p0, 0, sizeof p0);
    p0.y = y0;
    p0.p = start;
    on_point(&p0, r);
    if (r->failed) return *ret = err->code, 1;
    double p1 = start + dir * fmin(step, 0.25 * fabs(end - start));
    if (r->seg_end != end) p1 = start + dir * fmin(fabs(p1 - start), 0.25 * fabs(r->seg_end - start));
    r->s_offset = -1.0;   /* set from the first point (on_point) */
    double tol = s->tolerance > 0 ? s->tolerance : 1e-10;
    sf_flatstart_info fi;
    memset(&fi, 0, sizeof fi);
    int fb = 1;
    if (sf_study_int(s, "solver.flat_branch", 1, &fb, err)) return *ret = err->code, 1;
    if (sparse)
        rc = sf_equil_poses_start_sparse(eq, cs, y0, start, 0.5 * fabs(r->seg_end - start), dir,
                                         flat_angle, tol, y0, &fi, err);
    else
        rc = eq->pz ? sf_equil_poses_start_flat(eq, cs, start, p1, dir, tol, y0, err)
                    : sf_equil_start_flat(eq, cs, start, p1, dir, tol, y0, fb, &fi, err);
    if (fi.note[0]) branch_note(r, "%s", fi.note);
    if (rc) return *ret = explain_start_failure(r), 1;
    if (depth >= 1 && !eq->pz && !r->failed) {
        /* every branch of the flat state, after the path (flat_switch) */
        r->flat_first = malloc(sizeof(double) * (size_t)eq->n);
        if (!r->flat_first) return *ret = sf_fail(err, SF_ENOMEM, "out of memory"), 1;
        memcpy(r->flat_first, cont_get_point(cs)->y, sizeof(double) * (size_t)eq->n);
        r->flat_sw = 1;
        r->flat_p0 = start;
        r->flat_p1 = cont_get_point(cs)->p;
        r->flat_dp = p1 - start;
    }
    *ret = CONT_OK;
    return 0;
}

static int run_equilibrium(run_ctx *r)
{
    sf_scene *sc = r->sc;
    const sf_study *s = &sc->study;
    sf_error *err = r->err;
    double start, end, step, min_step, max_step, load;
    int max_steps;
    if (sf_study_double(s, "analysis.start", 0.0, &start, err) ||
        sf_study_double(s, "analysis.end", (double)s->nstages, &end, err) ||
        sf_study_double(s, "analysis.step", 0.05, &step, err) ||
        sf_study_double(s, "analysis.min_step", 1e-6, &min_step, err) ||
        sf_study_double(s, "analysis.max_step", 0.2, &max_step, err) ||
        sf_study_int(s, "analysis.max_steps", 500, &max_steps, err) ||
        sf_study_double(s, "analysis.load", 0.0, &load, err))
        return err->code;
    int ptype, gi, pi, ci;
    if (sf_equil_parse_param(s, &ptype, &gi, &pi, &ci, err)) return err->code;
    if (sf_equil_init(&r->eq, &sc->model, ptype, gi, pi, ci, load, err))
        return err->code;
    sf_equil *eq = &r->eq;
    sf_reactions_init(&r->reac, ptype == SF_PARAM_DISPLACEMENT ? pi : -1);
    if (s->constraints == SF_CONSTRAINTS_PENALTY)
        sf_equil_use_penalty(eq, s->penalty_rotation, s->penalty_translation);
    const char *linsol;
    if (sf_study_string(s, "solver.linear_solver", "dense", &linsol, err)) return err->code;
    sf_equil_use_sparse(eq, strcmp(linsol, "klu") == 0    ? CONT_LINSOL_KLU
                            : strcmp(linsol, "dense") == 0 ? 0
                                                           : CONT_LINSOL_MUMPS);
    const char *formulation;
    if (sf_study_string(s, "solver.formulation", "folds", &formulation, err)) return err->code;
    if (strcmp(formulation, "poses") == 0 && sf_equil_use_poses(eq, err)) return err->code;
    r->probes = calloc((size_t)s->nprobes + 1, sizeof(sf_mpoint));
    if (!r->probes) return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int i = 0; i < s->nprobes; i++)
        if (sf_model_locate(&sc->model, s->probes[i].at, &r->probes[i], err)) {
            sf_error_prefix(err, "%s:%d: probe %d", s->path, s->probes[i].line, i + 1);
            return err->code;
        }
    int depth = 0;
    if (setup_stability(r, &depth)) return err->code;
    /* the continuation engine sees only this problem */
    if (sf_equil_create_solver(eq, &r->solver) != CONT_OK)
        return sf_fail(err, SF_ENOMEM, "continuation: %s",
                       r->solver ? cont_errmsg(r->solver) : "cannot create the solver");
    cont_solver *cs = r->solver;
    if (eq->pz)
        sf_outbuf_printf(&r->header, "# formulation: poses, %d unknowns (%d coordinates, %d "
                         "multipliers), %ld Jacobian nonzeros\n", eq->n, eq->nq, eq->ncon,
                         sf_equil_poses_nnz(eq));
    double lo = fmin(start, end), hi = fmax(start, end);
    cont_set_step(cs, step, min_step, max_step);
    cont_set_prange(cs, lo, hi);
    cont_set_max_steps(cs, max_steps);
    cont_set_newton(cs, s->tolerance > 0 ? s->tolerance : 1e-10, 12, 0);
    cont_set_callback(cs, on_point, r);
    cont_set_store(cs, 0);
    r->p_start = start;
    r->p_end = end;
    r->p_lo = lo;
    r->p_hi = hi;
    r->max_steps = max_steps;
    r->nshapes = s->shapes;
    if (sf_study_int(s, "output.shape_every", 0, &r->shape_every, err)) return err->code;
    r->shape_dp = s->shapes > 0 ? fabs(end - start) / s->shapes : 0.0;
    r->branch_first = 1;
    double *y0 = calloc((size_t)eq->n + 1, sizeof(double));
    if (!y0) return sf_fail(err, SF_ENOMEM, "out of memory");
    if (eq->pz) sf_equil_poses_lift(eq, y0);   /* the flat sheet in poses */
    int dir = end >= start ? +1 : -1, rc;
    /* Loads in several stages: the path has a corner where a stage ends
     * (the load changes direction), which the continuation takes for a
     * branch jump; follow it one stage at a time instead. */
    r->seg_end = end;
    int staged = ptype == SF_PARAM_LOAD && eq->e.nstages > 1;
    if (staged) stage_segment(r, start, dir, lo, hi);
    double F0norm = 0.0;
    {
        double *F0 = calloc((size_t)eq->n + 1, sizeof(double));
        if (!F0) { free(y0); return sf_fail(err, SF_ENOMEM, "out of memory"); }
        sf_equil_residual(y0, start, F0, eq);
        for (int i = 0; i < eq->n; i++) F0norm = fmax(F0norm, fabs(F0[i] * eq->fscale[i]));
        free(F0);
    }
    /* Without loads the sheet sits at its rest angles; with a rest angle
     * set, that state is a better first guess than the flat sheet (a
     * compressed strip folded by actuation has the flat state as an
     * unstable equilibrium nearby). */
    int rested = 0;
    /* the flat state solves the problem at the start when its residual is
     * rounding only (it grows with the number of loops: 1.4e-14 on a 3x3
     * Miura sheet) */
    double flat_tol = 1e-2 * (s->tolerance > 0 ? s->tolerance : 1e-10);
    {   /* face poses: the lift's rounding grows with the sheet (scaled
         * positions ~ size / band width; 1.7e-12 on an 8x8 Miura sheet) */
        double ym = 1.0;
        for (int i = 0; i < eq->n; i++) ym = fmax(ym, fabs(y0[i] * eq->yscale[i]));
        flat_tol = fmax(flat_tol, 1e3 * DBL_EPSILON * ym);
    }
    if (F0norm > flat_tol) {
        sf_equil_set_param(eq, start);
        for (int i = 0; i < sc->model.nfolds; i++)
            if (eq->par.rest[i] != 0.0) {
                y0[sc->model.qoff[i]] = eq->par.rest[i];
                rested = 1;
            }
        if (rested && eq->pz) sf_equil_poses_lift(eq, y0);
    }
    const char *flat_start;
    double flat_angle = 0.05;
    if (sf_study_string(s, "analysis.flat_start", "limit", &flat_start, err) ||
        sf_study_double(s, "analysis.flat_angle", 0.05, &flat_angle, err)) {
        free(y0);
        return err->code;
    }
    int direct = strcmp(flat_start, "direct") == 0;
    int sparse = strcmp(flat_start, "sparse") == 0;   /* flatstart_sparse.h */
    if (!direct && (eq->pz ? sc->topo.nivertices > 0 : eq->nloop > 0) && F0norm <= flat_tol) {
        if (start_at_flat(r, y0, start, end, step, dir, depth, sparse, flat_angle, &rc)) {
            free(y0);
            return rc;
        }
        rc = CONT_OK;
    } else {
        rc = cont_start(cs, y0, start, dir);
        if (rc != CONT_OK && rested && !r->failed) {
            /* the rest state did not lead Newton anywhere: try the flat sheet */
            memset(y0, 0, (size_t)eq->n * sizeof *y0);
            if (eq->pz) sf_equil_poses_lift(eq, y0);
            rc = cont_start(cs, y0, start, dir);
        }
    }
    if (rc != CONT_OK) {
        free(y0);
        if (r->failed) return err->code;
        sf_fail(err, SF_ENUMERIC, "%s: no equilibrium at the start of the path: %s%s",
                s->path, cont_errmsg(cs),
                eq->nloop ? " (exact loop closure: the KKT matrix may be singular here; "
                            "solver.constraints = \"penalty\" is the paper's method)" : "");
        return explain_start_failure(r);
    }
    return follow_path(r, y0, staged, dir, lo, hi);
}

static int write_outputs(run_ctx *r)
{
    const sf_study *s = &r->sc->study;
    sf_error *err = r->err;
    char path[1200];
    sf_outbuf out = {0};
#define WRITE(name, buf)                                                           \
    do {                                                                           \
        if ((buf).oom) return sf_fail(err, SF_ENOMEM, "out of memory");            \
        snprintf(path, sizeof path, "%s/%s", r->dir, name);                        \
        if (sf_write_atomic(path, sf_outbuf_fill, &(buf), err)) return err->code;       \
    } while (0)
    /* branch.tsv: comments, column names, rows */
    sf_outbuf_printf(&out, "%s", r->header.s ? r->header.s : "");
    if (r->bnotes.n) sf_outbuf_printf(&out, "%.*s", (int)r->bnotes.n, r->bnotes.s);
    if (r->do_stab)
        sf_outbuf_printf(&out, "# stability: %ld points by the dense LAPACK method, %ld by ARPACK, "
                         "%ld by the MUMPS inertia (eigenvalues at %ld of them) "
                         "(analysis.eigensolver)\n", r->neig_method[SF_EIG_DENSE],
                         r->neig_method[SF_EIG_ARPACK], r->neig_method[SF_EIG_INERTIA],
                         r->neig_inertia);
    if (r->eq.pz && sf_peq_rows_dropped(&r->eq))
        sf_outbuf_printf(&out, "# pose rows: %d of %d fold rows kept, %d dropped as identities "
                         "(dependent at a generic state, solver.pose_rows); largest residual of a "
                         "dropped row %.3g over the points written, %ld point%s above the Newton "
                         "tolerance\n", r->eq.nloop, 6 * r->eq.m->nfolds,
                         sf_peq_rows_dropped(&r->eq), r->drop_max, r->drop_bad,
                         r->drop_bad == 1 ? "" : "s");
    else if (r->eq.pz && sf_peq_rows_rank(&r->eq) >= 0 && sf_peq_rows_rank(&r->eq) < 6 * r->eq.m->nfolds)
        sf_outbuf_printf(&out, "# pose rows: all %d fold rows kept: at a generic state they have "
                         "rank %d = the unknowns, so the dependent ones are equations of their own "
                         "(more rows than unknowns), not identities (docs/formulations.md)\n",
                         6 * r->eq.m->nfolds, sf_peq_rows_rank(&r->eq));
    if (r->do_stab && r->step_bound)
        sf_outbuf_printf(&out, "# step bound: %ld steps shortened to end between two predicted "
                         "eigenvalue crossings (analysis.step_bound)\n", r->nbound);
    sf_outbuf_printf(&out, "# units: s, p, load: as the parameter (load factor, actuation factor, or m); "
                    "probe*: m; energy: J; residual_rot: 1; residual_tra: m; eig*: J per unit "
                    "of the coordinates (rad, mode amplitude); theta*: rad\n");
    if (r->bif.nbranches > 1)
        sf_outbuf_printf(&out, "# %d branches, each a block after two blank lines (gnuplot index 0..%d)\n",
                  r->bif.nbranches, r->bif.nbranches - 1);
    sf_outbuf_printf(&out, "point\tbranch\ts\tp\tload");
    sf_outbuf_probe_columns(&out, s->nprobes);
    sf_outbuf_printf(&out, "\tenergy\tresidual\tresidual_rot\tresidual_tra\tnewton\tstable\tmorse");
    sf_outbuf_numbered_columns(&out, "eig", r->nev);
    sf_outbuf_printf(&out, "\ttype");
    sf_outbuf_numbered_columns(&out, "theta", s->nfolds);
    sf_outbuf_printf(&out, "\n");
    if (r->rows.n) sf_outbuf_printf(&out, "%.*s", (int)r->rows.n, r->rows.s);
    WRITE("branch.tsv", out);
    out.n = 0;
    sf_outbuf_printf(&out, "# smoothfold %s per-step solver statistics for %s\n", PACKAGE_VERSION, s->name);
    sf_outbuf_printf(&out, "point,branch,p,ds,newton,residual_evals,jacobian_evals,retries,locate_points,wall_s,factorisations\n");
    if (r->stats.n) sf_outbuf_printf(&out, "%.*s", (int)r->stats.n, r->stats.s);
    WRITE("stats.csv", out);
    out.n = 0;
    sf_outbuf_printf(&out, "%s", r->header.s ? r->header.s : "");
    sf_outbuf_printf(&out, "point\tbranch\ttype\tp\ts");
    sf_outbuf_probe_columns(&out, s->nprobes);
    sf_outbuf_printf(&out, "\tstable\tmorse");
    sf_outbuf_numbered_columns(&out, "eig", r->nev);
    sf_outbuf_printf(&out, "\tloc_err\n");
    if (r->special.n) sf_outbuf_printf(&out, "%.*s", (int)r->special.n, r->special.s);
    WRITE("special.tsv", out);
    free(out.s);
#undef WRITE
    if (r->eq.nsup) {
        snprintf(path, sizeof path, "%s/reactions.tsv", r->dir);
        if (sf_reactions_write(&r->reac, &r->eq, path, r->header.s, err)) return err->code;
    }
    if (r->nshapes > 0 && sf_pvd_write(&r->pvd, err)) return err->code;
    snprintf(path, sizeof path, "%s/folded.fold", r->dir);
    if (sf_foldrec_write(&r->foldrec, path, err)) return err->code;
    snprintf(path, sizeof path, "%s/study.cfg", r->dir);
    char hdr[256];
    snprintf(hdr, sizeof hdr, "merged study run by smoothfold %s (after --set overrides)",
             PACKAGE_VERSION);
    if (sf_study_write(s, path, hdr, err)) return err->code;
    if (r->compared && sf_compare_write(r->cmp, r->dir, r->header.s, err)) return err->code;
    return SF_OK;
}

int sf_cmd_run(const sf_options *o, sf_error *err)
{
    if (!o->output) return sf_fail(err, SF_EINPUT, "run: give the output directory with -o DIR");
    double t0 = now();
    sf_scene sc;
    if (sf_scene_open(&sc, o->study_path, o->nset, o->sets, err)) {
        sf_scene_close(&sc);
        return err->code;
    }
    sf_cli_warn(&sc.study);
    if (strcmp(sc.study.analysis_type, "dynamics") == 0) {
        /* reference data are compared with equilibrium paths only: say so
         * rather than ignore a declared tolerance silently */
        if (sf_study_count(&sc.study, "references") > 0 && !o->quiet)
            fprintf(stderr, "smoothfold: note: the study's references are compared with "
                            "equilibrium paths only, not with this trajectory\n");
        int drc = sf_run_dynamics(&sc, o, err);
        sf_scene_close(&sc);
        return drc;
    }
    if (strcmp(sc.study.analysis_type, "boundary") == 0) {
        int brc = sf_run_boundary(&sc, o, err);   /* run_boundary.c */
        sf_scene_close(&sc);
        return brc;
    }
    run_ctx r;
    memset(&r, 0, sizeof r);
    r.sc = &sc;
    r.opt = o;
    r.err = err;
    snprintf(r.dir, sizeof r.dir, "%s", o->output);
    int rc = SF_OK;
    if (strcmp(sc.study.analysis_type, "equilibrium") != 0) {
        rc = sf_fail(err, SF_EINPUT, "%s: analysis.type \"%s\" is not available in this version "
                     "(only \"equilibrium\" and \"dynamics\")", sc.study.path, sc.study.analysis_type);
    }
    char shapes[1100];
    snprintf(shapes, sizeof shapes, "%s/shapes", r.dir);
    if (!rc) rc = sf_compare_open(&r.cmp, &sc.study, err);   /* bad reference files: before any output */
    if (!rc) rc = sf_cli_outdir(o, r.dir, err);   /* earlier results removed */
    if (!rc && sc.study.shapes > 0) rc = sf_mkdir_p(shapes, err);
    if (!rc) {
        char pvd[1100];
        snprintf(pvd, sizeof pvd, "%s/shapes.pvd", r.dir);
        sf_pvd_init(&r.pvd, pvd);
        rc = sf_foldrec_init(&r.foldrec, &sc.model, err);
    }
    if (!rc) {
        sf_outbuf_printf(&r.header, "# smoothfold %s: %s, analysis %s\n", PACKAGE_VERSION,
                  sc.study.name, sc.study.analysis_type);
        rc = run_equilibrium(&r);
        if (rc == SF_ENUMERIC && r.npoints > 0) {
            /* keep the path up to where it stopped: complete files whose
             * header says why it stopped; the exit status stays non-zero */
            sf_outbuf_printf(&r.header, "# STOPPED EARLY: %s\n", err->msg);
            sf_error keep = *err;
            sf_error_clear(err);
            if (write_outputs(&r) == SF_OK) *err = keep;
            rc = err->code;
        } else if (!rc) {
            cont_get_stats(r.solver, NULL, &r.tot);
            if (r.short_stop)   /* complete files, an honest header and status */
                sf_outbuf_printf(&r.header, "# STOPPED EARLY: analysis.max_steps = %d reached on "
                                 "branch %d at p = %.10g, inside the range [%g, %g]\n", r.max_steps,
                                 r.short_branch, r.short_p, r.p_lo, r.p_hi);
            if (r.cmp) {
                /* solve at fixed p in the whole path's parametrisation
                 * (every stage ramps over its own interval), not in the
                 * one-stage ramp the last segment was followed in */
                r.eq.ramp_stage = -1;
                rc = sf_compare_eval(r.cmp, &r.eq, r.probes, r.solver, err);
                r.compared = !rc;
            }
            if (!rc) rc = write_outputs(&r);
        }
    }
    if (!rc && !o->quiet) {
        printf("%s: %ld points, %ld Newton iterations, %.3g s; results in %s\n", sc.study.name,
               r.npoints, r.tot.newton_iters, now() - t0, r.dir);
        sf_compare_print(r.cmp, stdout);
    }
    if (!rc && r.compared) rc = sf_compare_check(r.cmp, err);
    if (!rc && r.short_stop)
        rc = sf_fail(err, SF_ESHORT, "%s: stopped early: analysis.max_steps = %d reached on branch "
                     "%d at p = %.6g, short of the end of the range [%g, %g]; results so far in "
                     "%s (raise analysis.max_steps or analysis.step)", sc.study.path, r.max_steps,
                     r.short_branch, r.short_p, r.p_lo, r.p_hi, r.dir);
    sf_compare_free(r.cmp);
    if (r.solver) cont_free(r.solver);
    sf_bif_free(&r.bif);
    sf_equil_free(&r.eq);
    free(r.probes);
    free(r.flat_first);
    free(r.rows.s);
    free(r.stats.s);
    free(r.special.s);
    free(r.header.s);
    free(r.bnotes.s);
    if (r.do_stab) sf_stab_free(&r.stab);
    if (r.do_stab && r.step_bound) sf_stab_free(&r.stab2);
    sf_reactions_free(&r.reac);
    sf_pvd_free(&r.pvd);
    sf_foldrec_free(&r.foldrec);
    sf_scene_close(&sc);
    return rc;
}
