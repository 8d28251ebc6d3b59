/* run_equilibrium.c - `smoothfold run`: the equilibrium path.  Sets up the
 * problem and the continuation engine from the study, finds the start (at the
 * flat state of a sheet with loops: flatstart.h), follows the load stages one
 * after the other and the branches met, and explains a start that fails. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "equilibrium_poses.h"
#include "flatstart.h"
#include "flatstart_sparse.h"
#include "progress.h"
#include "flatswitch.h"
#include "mobility.h"
#include "run_impl.h"
#include "start.h"
#include "study.h"

/* A start that found no closed state (SF_ENUMERIC) on a sheet whose loop
 * rows outnumber its fold coordinates because folds have one shape mode
 * (sf_mobility_overcounted): the remedy, appended to the error's line. */
static void hint_modes(run_ctx *r)
{
    sf_error *err = r->err;
    const sf_model *m = r->eq.m;
    int rows, coords, coords2, k1;
    if (err->code != SF_ENUMERIC || !m || !m->topo ||
        !sf_mobility_overcounted(m, &rows, &coords, &coords2, &k1))
        return;
    size_t n = strlen(err->msg);
    snprintf(err->msg + n, sizeof err->msg - n, "; the loops have %d rows for %d fold coordinates "
             "(%d folds with at most 1 shape mode): with defaults.modes = 2 (%d coordinates) they "
             "may close, try --set defaults.modes=2", rows, coords, k1, coords2);
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
    hint_modes(r);
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
        run_branch_note(r, "flat state: no switching: %s", e.msg);
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
    if (!(r->cpu_path0 > 0)) r->cpu_path0 = run_cpu_seconds();
    /* stability from the corrector's own LDL^T at each point (stability.h) */
    if (r->do_stab && sf_stab_wants_inertia(&r->stab, eq)) cont_set_point_inertia(cs, 1);
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
    if (run_flush_held(r)) return err->code;   /* the branch ended after a held BP */
    if (rc == CONT_FAIL) {
        /* the keys of the remedies a diagnosis names */
        const char *m = cont_errmsg(cs);
        return sf_fail(err, SF_ENUMERIC, "%s: path stopped after %ld points: %s%s", s->path, r->npoints,
                       m, strstr(m, "then diverged") ? " (solver.constraints)"
                          : strstr(m, "e.g. a penalty") ? " (solver.tolerance, solver.constraints)"
                          : strstr(m, "residual floor") ? " (solver.tolerance)" : "");
    }
    if (r->flat_sw && flat_switch(r)) return err->code;
    rc = sf_bif_switch(&r->bif, cs, err);
    if (!rc && run_flush_held(r)) return err->code;
    return rc;
}
/* The flat state as the path's first written point; nonzero when the
 * point callback stopped the run. */
static int write_flat_point(run_ctx *r, double *y0, double start)
{
    cont_point p0;
    memset(&p0, 0, sizeof p0);
    p0.y = y0;
    p0.p = start;
    run_on_point(&p0, r);
    return r->failed;
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
     * (src/analysis/start/flatstart.c; the penalty homotopy as the fallback). */
    if (write_flat_point(r, y0, start)) return *ret = err->code, 1;
    double p1 = start + dir * fmin(step, 0.25 * fabs(end - start));
    if (r->seg_end != end) p1 = start + dir * fmin(fabs(p1 - start), 0.25 * fabs(r->seg_end - start));
    r->s_offset = -1.0;   /* set from the first point (run_on_point) */
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
    if (fi.note[0]) run_branch_note(r, "%s", fi.note);
    if (rc) {
        *ret = explain_start_failure(r);
        return 1;
    }
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

/* analysis.flat_start = "multipliers" (start.h, docs/design/start.md): write the
 * flat state, find the closed state of least energy at a given amount of
 * folding by the method of multipliers, and hand it to the engine with
 * the chord from the flat state as its tangent (the Jacobian may be
 * nearly singular there; the start's point meets the Newton tolerance
 * already).  0: the engine holds the first point, *ret = CONT_OK; 1:
 * stop with *ret. */
static int start_by_multipliers(run_ctx *r, double *y0, double start, double end, int dir,
                                double flat_angle, int *ret)
{
    const sf_study *s = &r->sc->study;
    sf_error *err = r->err;
    sf_equil *eq = &r->eq;
    cont_solver *cs = r->solver;
    if (write_flat_point(r, y0, start)) return *ret = err->code, 1;
    r->s_offset = -1.0;   /* set from the first point (run_on_point) */
    r->multipliers_start = 1;
    int fb = 1;
    if (sf_study_int(s, "solver.flat_branch", 1, &fb, err)) return *ret = err->code, 1;
    if (fb > 2)
        return *ret = sf_fail(err, SF_EINPUT, "%s: solver.flat_branch = %d: with analysis.flat_start "
                              "= \"multipliers\", a symmetric driving gives two mirror branches "
                              "(1 or 2)", s->path, fb), 1;
    sf_start_opts o;
    o.flat_angle = flat_angle;
    o.dp_max = 0.25 * fabs((r->seg_end != end ? r->seg_end : end) - start);
    o.tol = s->tolerance > 0 ? s->tolerance : 1e-10;
    o.branch = fb;
    sf_start_info si;
    double p1 = start;
    double *y1 = malloc(sizeof(double) * ((size_t)eq->n + 1));
    double *t1 = malloc(sizeof(double) * ((size_t)eq->n + 1));
    if (!y1 || !t1) {
        free(y1);
        free(t1);
        return *ret = sf_fail(err, SF_ENOMEM, "out of memory"), 1;
    }
    int rc = sf_start_flat(eq, y0, start, dir, &o, y1, &p1, &si, err);
    if (si.note[0]) run_branch_note(r, "%s", si.note);
    if (!rc) {
        for (int i = 0; i < eq->n; i++) t1[i] = y1[i] - y0[i];
        if (cont_start_tangent(cs, y1, p1, t1, p1 - start) != CONT_OK) {
            if (!r->failed)
                sf_fail(err, SF_ENUMERIC, "%s: the first point off the flat state (p = %.6g) does "
                        "not converge in the path's corrector: %s", s->path, p1, cont_errmsg(cs));
            rc = err->code;
        }
    }
    free(y1);
    free(t1);
    if (rc) {
        /* every failure of the start carries its line; an empty one would
         * end the run as a success after the flat point */
        if (!err->code)
            sf_fail(err, rc, "%s: flat start: failed without a diagnosis (please report the study)",
                    s->path);
        hint_modes(r);
        return *ret = rc, 1;
    }
    *ret = CONT_OK;
    return 0;
}

/* The defaults of solver.formulation, analysis.flat_start and
 * analysis.step_norm, "auto" (docs/reference/study-keys.md, "Large sheets"): by
 * the size of the problem in fold coordinates (eq->n, before any switch to
 * poses).  Above solver.auto_unknowns, on a sheet with loops (exact
 * closure, interior vertices), with none of the three keys set and no
 * feature of the fold formulation only in use (the loop penalty; every
 * branch at the flat state, analysis.branch_depth >= 1), they are
 * "poses", "sparse", "rms"; otherwise "folds", "multipliers" ("limit"
 * above the threshold and with branch_depth >= 1), "sum", so that a study
 * or command that sets any of them runs as before (and an explicit
 * combination that does not work, such as "sparse" with "folds", gives
 * the same error).  The choices are written back into the study
 * (DIR/study.cfg records what was run; the K+1 run of
 * analysis.convergence, a larger problem, keeps them), and a sheet above
 * the threshold gets one header line saying what auto chose and why.
 * Where all three were "auto" and the sheet is small, r->auto_small lets
 * run.c run the study again with the limit start if the start by the
 * method of multipliers fails or its path stops at its first point.
 * *form, *fs, *norm: string literals or the study's values. */
static int choose_keys(run_ctx *r, const char **form, const char **fs, const char **norm)
{
    sf_study *s = &r->sc->study;
    sf_error *err = r->err;
    const sf_equil *eq = &r->eq;
    int lim = 0, depth = 0;
    if (sf_study_string(s, "solver.formulation", "auto", form, err) ||
        sf_study_string(s, "analysis.flat_start", "auto", fs, err) ||
        sf_study_string(s, "analysis.step_norm", "auto", norm, err) ||
        sf_study_int(s, "solver.auto_unknowns", 0, &lim, err) ||
        sf_study_int(s, "analysis.branch_depth", 0, &depth, err))
        return err->code;
    int af = strcmp(*form, "auto") == 0, as = strcmp(*fs, "auto") == 0, an = strcmp(*norm, "auto") == 0;
    int large = eq->n > lim;
    const char *why = !eq->exact ? "solver.constraints = \"penalty\" exists in the fold formulation only"
                      : depth >= 1 && eq->nloop > 0
                          ? "analysis.branch_depth >= 1 follows every branch at the flat state in the "
                            "fold formulation only"
                      : eq->nloop == 0 ? "the sheet has no interior vertex (no loop rows: the fold "
                                         "formulation is the smaller one)"
                      : !af ? "solver.formulation is set"
                      : !as && strcmp(*fs, "multipliers") != 0 ? "analysis.flat_start is set"
                      : !an ? "analysis.step_norm is set"
                            : NULL;
    int big = large && !why;
    r->auto_small = af && as && an && !why && !large;   /* run.c may retry with "limit" */
    if (af) *form = big ? "poses" : "folds";
    /* below the threshold the method of multipliers (start.h); above it,
     * where a key keeps the fold formulation's defaults, and for every
     * branch at the flat state (branch_depth >= 1, the tangent cone of
     * flatswitch.h), the limit start */
    if (as) *fs = big ? "sparse" : large || (depth >= 1 && eq->nloop > 0) ? "limit" : "multipliers";
    if (an) *norm = big ? "rms" : "sum";
    if ((af && sf_study_set_string(s, "solver.formulation", *form, err)) ||
        (as && sf_study_set_string(s, "analysis.flat_start", *fs, err)) ||
        (an && sf_study_set_string(s, "analysis.step_norm", *norm, err)))
        return err->code;
    if (!large || !(af || as || an)) return SF_OK;
    char line[1024], keys[256];
    int o = 0;
    keys[0] = '\0';
    if (af) o += snprintf(keys + o, sizeof keys - (size_t)o, "solver.formulation = \"%s\"", *form);
    if (as) o += snprintf(keys + o, sizeof keys - (size_t)o, "%sanalysis.flat_start = \"%s\"", o ? ", " : "", *fs);
    if (an) snprintf(keys + o, sizeof keys - (size_t)o, "%sanalysis.step_norm = \"%s\"", o ? ", " : "", *norm);
    if (big)
        snprintf(line, sizeof line, "auto: %d unknowns in fold coordinates, above solver.auto_unknowns = %d: "
                 "%s (setting any of the three keys keeps \"folds\", \"limit\", \"sum\" for the others)",
                 eq->n, lim, keys);
    else
        snprintf(line, sizeof line, "auto: %d unknowns in fold coordinates, above solver.auto_unknowns = %d, "
                 "but %s: %s (the fold formulation's)", eq->n, lim, why, keys);
    sf_outbuf_printf(&r->header, "# %s\n", line);
    if (!r->opt->quiet) fprintf(stderr, "%s\n", line);
    return SF_OK;
}

/* Every evaluation of the equations counts as progress (the param hook
 * is called by each residual, Jacobian and report). */
static void count_eval(sf_equil *q, double p, void *data)
{
    (void)q;
    (void)p;
    sf_progress_eval(data);
}

int run_equilibrium(run_ctx *r)
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
    if (r->opt->progress && !eq->param_hook) {
        eq->param_hook = count_eval;
        eq->param_hook_data = r->opt->progress;
    }
    sf_reactions_init(&r->reac, ptype == SF_PARAM_DISPLACEMENT ? pi : -1);
    if (s->constraints == SF_CONSTRAINTS_PENALTY)
        sf_equil_use_penalty(eq, s->penalty_rotation, s->penalty_translation);
    const char *linsol;
    if (sf_study_string(s, "solver.linear_solver", "dense", &linsol, err)) return err->code;
    sf_equil_use_sparse(eq, strcmp(linsol, "klu") == 0    ? CONT_LINSOL_KLU
                            : strcmp(linsol, "dense") == 0 ? 0
                                                           : CONT_LINSOL_MUMPS);
    const char *formulation, *flat_start, *step_norm;
    if (choose_keys(r, &formulation, &flat_start, &step_norm)) return err->code;
    if (strcmp(flat_start, "sparse") == 0 && strcmp(formulation, "poses") != 0)
        return sf_fail(err, SF_EINPUT, "%s: analysis.flat_start = \"sparse\" needs "
                       "solver.formulation = \"poses\" (it is \"%s\")", s->path, formulation);
    if (strcmp(formulation, "poses") == 0 && sf_equil_use_poses(eq, err)) return err->code;
    if (sf_scene_locate_probes(sc, &r->probes, err)) return err->code;
    int depth = 0;
    if (run_setup_stability(r, &depth)) return err->code;
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
    if (strcmp(step_norm, "rms") == 0) {
        /* steps in the RMS change of the fold coordinates (and p): the
         * same number of points on a small and a large sheet; such steps
         * need the anchored corrector (continuation/README.md, "Larger
         * steps") */
        cont_set_arc_scale(cs, 1.0 / sqrt((double)sc->model.nq));   /* the weighted ones */
        cont_set_anchor_first(cs, 1);
        cont_set_predictor(cs, 2);
    }
    cont_set_step(cs, step, min_step, max_step);
    cont_set_prange(cs, lo, hi);
    cont_set_max_steps(cs, max_steps);
    cont_set_newton(cs, s->tolerance > 0 ? s->tolerance : 1e-10, 12, 0);
    cont_set_callback(cs, run_on_point, r);
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
    double flat_angle = 0.05;
    if (sf_study_double(s, "analysis.flat_angle", 0.05, &flat_angle, err)) {
        free(y0);
        return err->code;
    }
    sf_progress_phase(r->opt->progress, 0, "run: the first point of the path, from p = %g%s", start,
                      F0norm <= flat_tol ? " (the flat state)" : "");
    int direct = strcmp(flat_start, "direct") == 0;
    int sparse = strcmp(flat_start, "sparse") == 0;   /* flatstart_sparse.h */
    int multipliers = strcmp(flat_start, "multipliers") == 0;   /* start.h */
    if (!direct && (eq->pz ? sc->topo.nivertices > 0 : eq->nloop > 0) && F0norm <= flat_tol) {
        if (multipliers ? start_by_multipliers(r, y0, start, end, dir, flat_angle, &rc)
                        : start_at_flat(r, y0, start, end, step, dir, depth, sparse, flat_angle, &rc)) {
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
