/* run.c - `smoothfold run`: follow the study's equilibrium path with the
 * continuation engine and write DIR/branch.tsv, DIR/stats.csv,
 * DIR/special.tsv, DIR/shapes.pvd (with the VTK files in DIR/shapes/) and DIR/study.cfg
 * (docs/reference/output-files.md).  Every file is written to a temporary name and
 * renamed when complete.  This file: the command, the dispatch by
 * analysis.type, the end of the run; the path itself is run_equilibrium.c. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "flatstart.h"
#include "progress.h"
#include "run_boundary.h"
#include "run_dynamics.h"
#include "run_impl.h"
#include "study.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* Open the writers of a run in r->dir (shapes, folded.fold) and start
 * branch.tsv's header. */
static int run_open(run_ctx *r, sf_error *err)
{
    sf_scene *sc = r->sc;
    char pvd[1100];
    snprintf(pvd, sizeof pvd, "%s/shapes.pvd", r->dir);
    sf_pvd_init(&r->pvd, pvd);
    if (sf_foldrec_init(&r->foldrec, &sc->model, err)) return err->code;
    sf_outbuf_printf(&r->header, "# smoothfold %s: %s, analysis %s\n", PACKAGE_VERSION,
                     sc->study.name, sc->study.analysis_type);
    return SF_OK;
}

/* Free what run_open and run_equilibrium set up in r. */
static void run_release(run_ctx *r)
{
    if (r->solver) cont_free(r->solver);
    sf_bif_free(&r->bif);
    sf_equil_free(&r->eq);
    free(r->probes);
    free(r->flat_first);
    free(r->rows.s);
    free(r->stats.s);
    free(r->special.s);
    free(r->header.s);
    free(r->bnotes.s);
    if (r->do_stab) sf_stab_free(&r->stab);
    if (r->do_stab && r->step_bound) sf_stab_free(&r->stab2);
    sf_reactions_free(&r->reac);
    sf_pvd_free(&r->pvd);
    sf_foldrec_free(&r->foldrec);
    run_validity_free(&r->vt);
    free(r->held_y);
    r->held_y = NULL;
}

/* The start by the method of multipliers, chosen by "auto" for a small
 * sheet, found no first point, or the path could not go past it (the
 * branch of least energy it leaves on can run along nearly dependent loop
 * rows: the 2x2 Miura under a tip load of 1 N folds along its straight
 * crease line, docs/design/start.md): the same study again with the limit
 * start, which follows the branch the driving selects on the tangent cone
 * (docs/flatstart.md); branch.tsv's header says why. */
static int run_again_with_limit(run_ctx *r, sf_error *err)
{
    char why[700];
    snprintf(why, sizeof why, "%.690s", err->msg);
    int started = r->npoints > 1;
    sf_scene *sc = r->sc;
    const sf_options *opt = r->opt;
    sf_compare *cmp = r->cmp;
    char dir[sizeof r->dir];
    memcpy(dir, r->dir, sizeof dir);
    run_release(r);
    memset(r, 0, sizeof *r);   /* the context of a fresh run in the same directory */
    r->sc = sc;
    r->opt = opt;
    r->err = err;
    r->cmp = cmp;
    memcpy(r->dir, dir, sizeof dir);
    sf_error_clear(err);
    sf_study *s = &r->sc->study;
    if (sf_study_set_string(s, "analysis.flat_start", "limit", err) || run_open(r, err))
        return err->code;
    const char *line = started ? "auto: the path from the start by the method of multipliers stopped "
                                 "at its first point; run again with analysis.flat_start = \"limit\""
                               : "auto: the start by the method of multipliers found no first point; "
                                 "run again with analysis.flat_start = \"limit\"";
    sf_outbuf_printf(&r->header, "# %s (it said: %s)\n", line, why);
    if (!r->opt->quiet) fprintf(stderr, "smoothfold: %s\n", line);
    return run_equilibrium(r);
}

int sf_cmd_run(const sf_options *o, sf_error *err)
{
    if (!o->output) return sf_fail(err, SF_EINPUT, "run: give the output directory with -o DIR");
    double t0 = now();
    sf_scene sc;
    sf_progress_phase(o->progress, 0, "run: reading the study, building the sheet (faces, bands, model)");
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
        sf_progress_phase(o->progress, 0, "run: the trajectory in time (IDA)");
        int drc = sf_run_dynamics(&sc, o, err);
        sf_scene_close(&sc);
        return drc;
    }
    if (strcmp(sc.study.analysis_type, "boundary") == 0) {
        sf_progress_phase(o->progress, 0, "run: the stability boundary in two parameters");
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
    if (!rc) rc = run_open(&r, err);
    if (!rc) {
        rc = run_equilibrium(&r);
        if (rc == SF_ENUMERIC && r.auto_small && r.multipliers_start && r.npoints <= 2)
            rc = run_again_with_limit(&r, err);
        if (rc == SF_ENUMERIC && r.npoints > 0) {
            /* keep the path up to where it stopped: complete files whose
             * header says why it stopped; the exit status stays non-zero */
            sf_outbuf_printf(&r.header, "# STOPPED EARLY: %s\n", err->msg);
            sf_error keep = *err;
            sf_error_clear(err);
            if (run_write_outputs(&r) == SF_OK) *err = keep;
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
                sf_progress_phase(o->progress, 0, "run: solving at the reference values of p");
                rc = sf_compare_eval(r.cmp, &r.eq, r.probes, r.solver, err);
                r.compared = !rc;
            }
            sf_progress_phase(o->progress, 0, "run: writing the result files");
            if (!rc) rc = run_write_outputs(&r);
        }
    }
    if (!rc && !o->quiet) {
        printf("%s: %ld points, %ld Newton iterations, %.3g s; results in %s\n", sc.study.name,
               r.npoints, r.tot.newton_iters, now() - t0, r.dir);
        sf_compare_print(r.cmp, stdout);
    }
    if ((!rc || rc == SF_ENUMERIC) && r.npoints > 0) {
        /* said even with --quiet: a warning about the results */
        char vline[1500];
        run_validity_summary(&r, vline, sizeof vline);
        if (vline[0]) fprintf(stderr, "smoothfold: warning: %s\n", vline);
    }
    if (!rc && r.compared) rc = sf_compare_check(r.cmp, err);
    if (!rc && r.short_stop)
        rc = sf_fail(err, SF_ESHORT, "%s: stopped early: analysis.max_steps = %d reached on branch "
                     "%d at p = %.6g, short of the end of the range [%g, %g]; results so far in "
                     "%s (raise analysis.max_steps or analysis.step)", sc.study.path, r.max_steps,
                     r.short_branch, r.short_p, r.p_lo, r.p_hi, r.dir);
    sf_compare_free(r.cmp);
    run_release(&r);
    sf_scene_close(&sc);
    return rc;
}
