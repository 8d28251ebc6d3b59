/* run_dynamics.c - `smoothfold run` with analysis.type = "dynamics": the
 * trajectory of dynamics.h, one row per integrator step, written as
 * DIR/trajectory.tsv, DIR/stats.csv, DIR/shapes.pvd with DIR/shapes/ (one .vtp per shape)
 * and DIR/study.cfg (each to a temporary name, then renamed), then the
 * plot of probes and fold angles against time (plots/trajectory.gp). */
#include "run_dynamics.h"

#include "outbuf.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "dynamics.h"
#include "study.h"
#include "run_validity.h"
#include "vtk.h"

#ifndef PACKAGE_VERSION
#define PACKAGE_VERSION "0.1.0"
#endif

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

typedef struct traj_ctx {
    sf_dyn d;
    const sf_options *opt;
    sf_error *err;
    char dir[1024];
    sf_mpoint *probes;
    sf_outbuf rows, stats, header;
    sf_pvd pvd;
    int nshapes, ishape;
    long nrows;
    double max_drift, next_print;
    run_validity vt;      /* the physical validity of every row */
} traj_ctx;

/* One row of trajectory.tsv (and stats.csv) for the current state; the
 * shape when the time has reached the next one due. */
static int record(traj_ctx *r)
{
    sf_dyn *d = &r->d;
    const sf_model *m = d->m;
    const sf_study *s = m->study;
    double Pi, T, drift, speed;
    sf_dyn_report(d, &Pi, &T, &drift, &speed);
    if (drift > r->max_drift) r->max_drift = drift;
    const sf_dyn_stats *st = &d->stats;
    sf_kin_eval(m, d->y, 0, &d->eq.k);
    /* every number of the row finite before any of it is written */
    sf_error *err = r->err;
    const double v[] = {d->t, d->p, d->load, Pi, T, drift, speed, st->h};
    const char *what[] = {"time t", "p", "load", "energy", "kinetic energy", "energy drift", "speed",
                          "step size h"};
    for (int j = 0; j < 8; j++)
        if (sf_need_finite(err, v[j], "%s at trajectory step %ld (t = %.10g)", what[j], st->steps, d->t))
            return err->code;
    for (int i = 0; i < s->nprobes; i++) {
        double x[3];
        sf_point_eval(m, &d->eq.k, &r->probes[i], x, NULL);
        for (int c = 0; c < 3; c++)
            if (sf_need_finite(err, x[c], "probe %s u%c at trajectory step %ld (t = %.10g)", s->probes[i].name,
                               "xyz"[c], st->steps, d->t))
                return err->code;
    }
    for (int i = 0; i < m->nfolds; i++)
        if (sf_need_finite(err, d->y[m->qoff[i]], "fold angle of fold %d at trajectory step %ld (t = %.10g)",
                           i + 1, st->steps, d->t))
            return err->code;
    char warning[40];
    if (run_validity_row(&r->vt, m, d->y, r->nrows, d->t, warning, sizeof warning, err)) {
        sf_error_prefix(err, "trajectory step %ld (t = %.10g)", st->steps, d->t);
        return err->code;
    }
    sf_outbuf_printf(&r->rows, "%ld\t%.12g\t%.12g\t%.12g", st->steps, d->t, d->p, d->load);
    double uz0 = 0.0;
    for (int i = 0; i < s->nprobes; i++) {
        double x[3];
        sf_point_eval(m, &d->eq.k, &r->probes[i], x, NULL);
        double u[3] = {x[0] - r->probes[i].X[0], x[1] - r->probes[i].X[1], x[2]};
        if (i == 0) uz0 = u[2];
        sf_outbuf_printf(&r->rows, "\t%.12g\t%.12g\t%.12g", u[0], u[1], u[2]);
    }
    sf_outbuf_printf(&r->rows, "\t%.12g\t%.12g\t%.3g\t%.6g", Pi, T, drift, speed);
    for (int i = 0; i < m->nfolds; i++) sf_outbuf_printf(&r->rows, "\t%.12g", d->y[m->qoff[i]]);
    sf_outbuf_printf(&r->rows, "\t%s\n", warning);
    sf_outbuf_printf(&r->stats, "%ld,%.9g,%.6g,%d,%ld,%ld,%ld,%ld,%ld,%.6g\n", st->steps, d->t, st->h,
              st->order, st->nres + st->nchecks, st->njac, st->nni, st->netf, st->ncfn, st->wall);
    /* shapes at k duration / N, k = 0..N, each at the first step at or
     * past its time, and the last state */
    double due = r->nshapes > 0 ? d->duration * r->ishape / r->nshapes : INFINITY;
    if (r->nshapes > 0 && (d->t >= due * (1 - 1e-12) || d->done)) {
        char rel[64], path[1200];
        snprintf(rel, sizeof rel, "shapes/shape_%04ld.vtp", r->nrows);
        snprintf(path, sizeof path, "%s/%s", r->dir, rel);
        if (sf_vtk_write_shape(m, d->y, s->samples, path, r->err) ||
            sf_pvd_add(&r->pvd, d->t, rel, r->err))
            return r->err->code;
        while (r->ishape <= r->nshapes && d->duration * r->ishape / r->nshapes <= d->t * (1 + 1e-12))
            r->ishape++;
    }
    if (!r->opt->quiet && (d->t >= r->next_print || d->done)) {
        fprintf(stderr, "t %-10.5g p %-10.5g steps %6ld  h %-9.3g drift %-9.2g speed %-9.3g",
                d->t, d->p, st->steps, st->h, drift, speed);
        if (s->nprobes) fprintf(stderr, "  %s uz %-11.5g", s->probes[0].name, uz0);
        fprintf(stderr, "%s\n", d->done == 2 ? "  settled" : "");
        while (r->next_print <= d->t) r->next_print += 0.05 * d->duration;
    }
    r->nrows++;
    return SF_OK;
}

static int write_outputs(traj_ctx *r)
{
    const sf_study *s = r->d.m->study;
    sf_error *err = r->err;
    char path[1200];
    sf_outbuf out = {0};
#define WRITE(name, buf)                                                           \
    do {                                                                           \
        if ((buf).oom) { free(out.s); return sf_fail(err, SF_ENOMEM, "out of memory"); } \
        snprintf(path, sizeof path, "%s/%s", r->dir, name);                        \
        if (sf_write_atomic(path, sf_outbuf_fill, &(buf), err)) { free(out.s); return err->code; } \
    } while (0)
    sf_outbuf_printf(&out, "%s", r->header.s ? r->header.s : "");
    char vline[1500];
    run_validity_line(&r->vt, r->d.m, "t", "trajectory.tsv", vline, sizeof vline);
    if (vline[0]) sf_outbuf_printf(&out, "# warning: %s\n", vline);
    sf_outbuf_printf(&out, "# units: t: s; p, load: as the parameter; probe*: m; energy, kinetic: J; "
                    "drift: 1 (rotation rows) or m; speed: rad/s; theta*: rad\n");
    sf_outbuf_printf(&out, "step\tt\tp\tload");
    sf_outbuf_probe_columns(&out, s->nprobes);
    sf_outbuf_printf(&out, "\tenergy\tkinetic\tdrift\tspeed");
    sf_outbuf_numbered_columns(&out, "theta", s->nfolds);
    sf_outbuf_printf(&out, "\twarning\n");
    if (r->rows.n) sf_outbuf_printf(&out, "%.*s", (int)r->rows.n, r->rows.s);
    WRITE("trajectory.tsv", out);
    out.n = 0;
    sf_outbuf_printf(&out, "# smoothfold %s integrator statistics for %s (counts cumulative, "
                    "including IDACalcIC)\n", PACKAGE_VERSION, s->name);
    sf_outbuf_printf(&out, "step,t,h,order,residual_evals,jacobian_evals,newton_iters,"
                    "error_test_fails,convergence_fails,wall_s\n");
    if (r->stats.n) sf_outbuf_printf(&out, "%.*s", (int)r->stats.n, r->stats.s);
    WRITE("stats.csv", out);
    free(out.s);
#undef WRITE
    if (r->nshapes > 0 && sf_pvd_write(&r->pvd, err)) return err->code;
    snprintf(path, sizeof path, "%s/study.cfg", r->dir);
    char hdr[256];
    snprintf(hdr, sizeof hdr, "merged study run by smoothfold %s (after --set overrides)",
             PACKAGE_VERSION);
    if (sf_study_write(s, path, hdr, err)) return err->code;
    return SF_OK;
}

static int integrate(traj_ctx *r, sf_scene *sc)
{
    sf_error *err = r->err;
    if (sf_dyn_init(&r->d, &sc->model, err)) return err->code;
    if (sf_scene_locate_probes(sc, &r->probes, err)) return err->code;
    if (sf_dyn_start(&r->d, err)) return err->code;
    /* the directory only once the trajectory has started */
    char shapes[1100];
    snprintf(shapes, sizeof shapes, "%s/shapes", r->dir);
    if (sf_cli_outdir(r->opt, r->dir, err) || (r->nshapes > 0 && sf_mkdir_p(shapes, err)))
        return err->code;
    if (record(r)) return err->code;
    while (!r->d.done) {
        if (sf_dyn_step(&r->d, err)) return err->code;
        if (record(r)) return err->code;
    }
    return SF_OK;
}

int sf_run_dynamics(sf_scene *sc, const sf_options *o, sf_error *err)
{
    double t0 = now();
    traj_ctx r;
    memset(&r, 0, sizeof r);
    r.opt = o;
    r.err = err;
    snprintf(r.dir, sizeof r.dir, "%s", o->output);
    r.nshapes = sc->study.shapes;
    char pvd[1100];
    snprintf(pvd, sizeof pvd, "%s/shapes.pvd", r.dir);
    sf_pvd_init(&r.pvd, pvd);
    int rc = SF_OK;
    {
        sf_outbuf_printf(&r.header, "# smoothfold %s: %s, analysis dynamics\n", PACKAGE_VERSION,
                  sc->study.name);
        rc = integrate(&r, sc);
        if (rc == SF_ENUMERIC && r.nrows > 0) {
            /* keep the trajectory up to where it stopped; status stays non-zero */
            sf_outbuf_printf(&r.header, "# STOPPED EARLY: %s\n", err->msg);
            sf_error keep = *err;
            sf_error_clear(err);
            if (write_outputs(&r) == SF_OK) *err = keep;
            rc = err->code;
        } else if (!rc) {
            rc = write_outputs(&r);
        }
    }
    if ((!rc || rc == SF_ENUMERIC) && r.nrows > 0) {
        /* said even with --quiet: a warning about the results */
        char vline[1500];
        run_validity_line(&r.vt, r.d.m, "t", "trajectory.tsv", vline, sizeof vline);
        if (vline[0]) fprintf(stderr, "smoothfold: warning: %s\n", vline);
    }
    if (!rc) {
        const sf_dyn_stats *st = &r.d.stats;
        if (!o->quiet)
            printf("%s: %ld IDA steps to t = %.6g s (%s), %ld residual and %ld Jacobian "
                   "evaluations, %ld Newton iterations (%ld for the constraint rows), %ld "
                   "error-test and %ld convergence failures, max drift %.3g, %.3g s; results "
                   "in %s\n",
                   sc->study.name, st->steps, r.d.t, r.d.done == 2 ? "settled" : "final time",
                   st->nres + st->nchecks, st->njac, st->nni, st->nextra, st->netf, st->ncfn,
                   r.max_drift, now() - t0, r.dir);
        sf_error perr;
        sf_error_clear(&perr);
        int want = o->plot;
        if (want < 0 && sf_study_bool(&sc->study, "output.plots", 1, &want, NULL)) want = 1;
        if (!want)
            ;   /* --no-plot, output.plots = false */
        else if (sf_plot_trajectory(r.dir, &perr) != SF_OK)
            fprintf(stderr, "smoothfold: warning: no plot: %s\n", perr.msg);
        else if (!o->quiet)
            printf("wrote %s/trajectory.png, trajectory.pdf\n", r.dir);
    }
    run_validity_free(&r.vt);
    sf_dyn_free(&r.d);
    free(r.probes);
    free(r.rows.s);
    free(r.stats.s);
    free(r.header.s);
    sf_pvd_free(&r.pvd);
    return rc;
}
