/* run_point.c - `smoothfold run`, one solved point of the equilibrium path:
 * its stability, the Morse-index check and branch-point refinement
 * (bifurcation.h), and its rows of branch.tsv, special.tsv and stats.csv, its
 * shape, its physical validity (validity.h), its reference comparison and
 * its progress line. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "equilibrium_poses.h"
#include "progress.h"
#include "run_impl.h"

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
void run_branch_note(run_ctx *r, const char *fmt, ...)
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
    /* unknown: empty (a # note names the row and the reason) */
    if (R->stable < 0) sf_outbuf_printf(b, "\t");
    else sf_outbuf_printf(b, "\t%d", R->stable);
    if (R->morse_unknown) sf_outbuf_printf(b, "\t");
    else sf_outbuf_printf(b, "\t%d", R->morse);
    for (int i = 0; i < r->nev; i++) {
        if (i < R->neig && isfinite(R->eig[i])) sf_outbuf_printf(b, "\t%.13g", R->eig[i]);
        else sf_outbuf_printf(b, "\t");
    }
}

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

/* The physical validity of a point (validity.h) and its warning field:
 * "" or a comma-separated list of "beyond180" (a fold beyond +-180
 * degrees) and "crossing" (parts of the sheet through each other). */
static int validity_field(run_ctx *r, const cont_point *pt, char *field, size_t size)
{
    if (run_validity_row(&r->vt, r->eq.m, pt->y, r->npoints, pt->p, field, size, r->err)) {
        sf_error_prefix(r->err, "row %ld (branch %d, p = %.10g)", r->npoints, r->bif.branch, pt->p);
        return r->err->code;
    }
    return SF_OK;
}

void run_validity_summary(const run_ctx *r, char *buf, size_t size)
{
    run_validity_line(&r->vt, r->eq.m, "p", "branch.tsv", buf, size);
}

/* Swap r->stab.res with the held point's (the eigenvalues by value: both
 * results point into the solver's array). */
static void swap_held_res(run_ctx *r)
{
    sf_stab_result cur = r->stab.res;
    int nev = r->stab.nev;
    for (int i = 0; i < nev; i++) {
        double t = cur.eig[i];
        cur.eig[i] = r->held_eig[i];
        r->held_eig[i] = t;
    }
    double *eig = cur.eig;
    r->stab.res = r->held_res;
    r->stab.res.eig = eig;
    r->held_res = cur;
}

/* The held point through the bookkeeping a point takes (the Morse-index
 * check against the row before, then its row), with its own stability. */
static int write_held(run_ctx *r)
{
    r->held = 0;
    swap_held_res(r);
    int rc = 0;
    if (sf_bif_check(&r->bif, &r->held_pt, r->s_offset, 0, r->err)) {
        r->failed = 1;
        rc = 1;
    }
    if (!rc) {   /* as run_on_point: located again on its eigenvalue where that is closer */
        cont_point q;
        double *ybuf = malloc(sizeof(double) * (size_t)r->eq.n);
        if (ybuf && sf_bif_refine(&r->bif, &r->held_pt, r->s_offset, 0, &q, ybuf)) rc = run_write_point(r, &q);
        else rc = run_write_point(r, &r->held_pt);
        free(ybuf);
    }
    swap_held_res(r);
    return rc;
}

int run_flush_held(run_ctx *r) { return r->held ? write_held(r) : 0; }

/* A branch point of the engine's test is a sign change of det [Jy Fp;
 * t^T]; on the branch that is an odd number of eigenvalues of the
 * constrained Hessian crossing zero, so the Morse index differs on its two
 * sides.  Where nearly dependent constraint rows are regularised
 * (docs/design/linear-algebra.md, "Weak rows"), rounding can flip the
 * determinant's sign with no eigenvalue near zero.  So a BP whose Morse
 * index is the row before's is held (1) until the next point: the same
 * index there means no eigenvalue crossed, and the BP is dropped with a
 * note; another index, and it is written first. */
static int hold_bp(run_ctx *r, const cont_point *pt)
{
    const sf_stab_result *S = &r->stab.res;
    const sf_bif *b = &r->bif;
    if (pt->type != CONT_PT_BP || S->morse_unknown || !b->prev_ok || S->morse != b->prev_lo ||
        S->morse != b->prev_hi)
        return 0;
    int n = r->eq.n, nev = r->stab.nev;
    if (!r->held_y) {
        r->held_y = malloc(sizeof(double) * (size_t)(2 * n + nev + 1));
        if (!r->held_y) return 0;   /* no memory to hold it: written as it is */
        r->held_ty = r->held_y + n;
        r->held_eig = r->held_ty + n;
    }
    memcpy(r->held_y, pt->y, sizeof(double) * (size_t)n);
    r->held_pt = *pt;
    r->held_pt.y = r->held_y;
    if (pt->ty) memcpy(r->held_ty, pt->ty, sizeof(double) * (size_t)n);
    r->held_pt.ty = pt->ty ? r->held_ty : NULL;
    r->held_pt.test = NULL;
    r->held_res = *S;
    for (int i = 0; i < nev; i++) r->held_eig[i] = S->eig[i];
    r->held_morse = S->morse;
    r->held = 1;
    return 1;
}

/* The next point after a held BP: drop it or write it (nonzero: failed).
 * Only a regular point or the end point decides: another special point
 * (an LP in the same step) has an eigenvalue at zero itself, so the held
 * BP is written. */
static int settle_held(run_ctx *r, const cont_point *pt)
{
    const sf_stab_result *S = &r->stab.res;
    int decides = pt->type == CONT_PT_REGULAR || pt->type == CONT_PT_EP;
    if (decides && !S->morse_unknown && S->morse == r->held_morse) {
        r->held = 0;
        run_branch_note(r, "branch %d, p = %.10g: the extended Jacobian's determinant changed sign, "
                        "but the Morse index is %d before and after (next point p = %.10g): no eigenvalue "
                        "crossed zero, not a branch point, not written (nearly dependent constraint rows; "
                        "docs/design/linear-algebra.md, \"Weak rows\")", r->bif.branch, r->held_pt.p,
                        S->morse, pt->p);
        return 0;
    }
    return write_held(r);
}

int run_on_point(const cont_point *pt, void *data)
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
        sf_progress_phase(r->opt->progress, 0, "run: stability of point %ld (p = %.6g, %d unknowns)",
                          r->npoints, pt->p, eq->n);
        /* the engine's LDL^T of the corrector's Jacobian at this point */
        if (pt->jy_inertia) sf_stab_give_inertia(&r->stab, pt->jy_neg, pt->jy_null);
        if (sf_stab_eval(&r->stab, eq, pt->y, pt->p, r->err)) {
            r->failed = 1;
            return 1;
        }
        long evals_here = r->stab.nevals; /* the evaluation of this point */
        r->neig_method[r->stab.res.method]++;
        r->neig_inertia += r->stab.res.method == SF_EIG_INERTIA && r->stab.res.neig > 0;
        const sf_stab_result *S = &r->stab.res;
        if (S->status != SF_SSTAB_OK) {
            char how[80];
            if (S->method == SF_EIG_DENSE)   /* no ARPACK: stab_cert.c's unknown */
                snprintf(how, sizeof how, "UNKNOWN (dense method)");
            else
                snprintf(how, sizeof how, "%s after %d ARPACK attempt(s)",
                         S->status == SF_SSTAB_RETRIED ? "retried, converged"
                         : S->stable < 0 ? "UNKNOWN" : "eigenvalues unknown, unstable by inertia",
                         S->attempts);
            run_branch_note(r, "stability at row %ld (branch %d, p = %.10g): %s: %s", r->npoints,
                            r->bif.branch, pt->p, how, S->reason);
        }
        if (r->held && settle_held(r, pt)) return 1;
        if (hold_bp(r, pt)) return 0;
        if (sf_bif_check(&r->bif, pt, r->s_offset, r->branch_first, r->err)) {
            r->failed = 1;
            return 1;
        }
        cont_point q;
        double *ybuf = malloc(sizeof(double) * (size_t)eq->n);
        if (ybuf && sf_bif_refine(&r->bif, pt, r->s_offset, r->branch_first, &q, ybuf)) {
            int rc = run_write_point(r, &q);
            free(ybuf);
            return rc;
        }
        free(ybuf);
        if (r->step_bound && pt->index >= 1 && pt->type == CONT_PT_REGULAR) {
            /* two eigenvalue crossings predicted within the next step: end
             * it between them (bifurcation.h, sf_bif_step_bound).  The
             * second evaluation, h = 1e-6 along the tangent, takes the
             * independent constraint rows of this point's (unless the
             * Morse-index check evaluated elsewhere since): no check or QR
             * of its own, the same constraint set at both */
            sf_stab_follow(&r->stab2, r->stab.nevals == evals_here ? &r->stab : NULL);
            double bnd = sf_bif_step_bound(&r->stab.res, &r->stab2, eq, pt, cont_get_ds(r->solver));
            if (bnd > 0 && cont_set_next_step(r->solver, bnd) == CONT_OK) r->nbound++;
        }
    }
    return run_write_point(r, pt);
}

/* One row of branch.tsv (and of special.tsv, stats.csv, the shapes, the
 * comparison) for the solved point pt, whose stability is r->stab.res. */
int run_write_point(run_ctx *r, const cont_point *pt)
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
            run_branch_note(r, "row %ld (branch %d, p = %.10g): a dropped pose constraint row has "
                        "residual %.3g, above the Newton tolerance %.3g: the kept rows do not "
                        "imply it here (docs/design/model.md; solver.pose_rows = \"all\" keeps "
                        "every row)", r->npoints, r->bif.branch, pt->p, d, tol);
    }
    double load = eq->param == SF_PARAM_LOAD ? pt->p : eq->load;
    if (r->s_offset < 0) {
        /* first point after a start off the flat state: the arclength
         * from the flat state in the norm of the path (its fold
         * coordinates are zero there, the other unknowns weigh nothing) */
        r->s_offset = cont_arc_norm(r->solver, pt->y, pt->p - r->p_start);
    }
    sf_outbuf *b = &r->rows;
    double sarc = pt->s + r->s_offset;
    const double e[3] = {Pi, rr, rt};
    char warning[40];
    if (check_point(r, pt, sarc, load, e) || validity_field(r, pt, warning, sizeof warning) ||
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
    sf_outbuf_printf(b, "\t%s\n", warning);
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
            run_branch_note(r, "%s at row %ld (branch %d, p = %.10g) located only to within %.3g in "
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
        fprintf(stderr, "%s%s%s%s\n", pt->label[0] ? "  " : "", pt->label, warning[0] ? "  " : "",
                warning);
    }
    r->npoints++;
    sf_bif_point_written(&r->bif, pt, sarc);
    sf_progress_phase(r->opt->progress, 0, "run: following the path: point %ld, from p = %.6g",
                      r->npoints, pt->p);
    if (!r->opt->quiet) sf_progress_printed(r->opt->progress);
    return 0;
}
