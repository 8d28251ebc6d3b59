/* run.c - `smoothfold run`: follow the study's equilibrium path with the
 * continuation engine and write DIR/branch.tsv, DIR/stats.csv,
 * DIR/special.tsv, DIR/shapes.pvd (with the VTK files in DIR/shapes/) and DIR/study.cfg
 * (docs/output-format.md).  Every file is written to a temporary name and
 * renamed when complete. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "commands.h"
#include "compare.h"
#include "cont.h"
#include "equilibrium.h"
#include "scene.h"
#include "study.h"
#include "vtk.h"

#ifndef PACKAGE_VERSION
#define PACKAGE_VERSION "0.1.0"
#endif

/* A growing text buffer. */
typedef struct sbuf {
    char *s;
    size_t n, cap;
    int oom;
} sbuf;

static void sb_printf(sbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void sb_printf(sbuf *b, const char *fmt, ...)
{
    if (b->oom) return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        size_t room = b->cap - b->n;
        int k = vsnprintf(b->s ? b->s + b->n : NULL, b->s ? room : 0, fmt, ap);
        va_end(ap);
        if (k < 0) { b->oom = 1; return; }
        if (b->s && (size_t)k < room) { b->n += (size_t)k; return; }
        size_t cap = b->cap ? 2 * b->cap : 4096;
        while (cap < b->n + (size_t)k + 1) cap *= 2;
        char *ns = realloc(b->s, cap);
        if (!ns) { b->oom = 1; return; }
        b->s = ns;
        b->cap = cap;
    }
}

static int fill_sbuf(void *ctx, void *f)
{
    const sbuf *b = ctx;
    if (b->n && fwrite(b->s, 1, b->n, (FILE *)f) != b->n) return SF_EIO;
    return SF_OK;
}

/* Finite numbers only: a non-finite value never reaches an output file. */
static double fin(double v) { return isfinite(v) ? v : 0.0; }

typedef struct run_ctx {
    sf_scene *sc;
    sf_equil eq;
    const sf_options *opt;
    sf_error *err;
    char dir[1024];
    sf_mpoint *probes;
    sbuf branch, stats, special, header;
    sf_pvd pvd;
    int nshapes;
    double p_start, p_end, next_shape, shape_dp;
    long npoints;
    int failed;
    double s_offset;      /* arclength before the engine's first point */
    cont_solver *solver;
    sf_compare *cmp;      /* reference data of the study (compare.h), or NULL */
    int block, compared;  /* branch block of the points; comparison done */
    long last_index;
    cont_stats tot;       /* solver totals of the path (before the comparison) */
} run_ctx;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int make_dir(const char *d, sf_error *err)
{
    char tmp[1024];
    snprintf(tmp, sizeof tmp, "%s", d);
    for (char *p = tmp + 1; *p; p++)
        if (*p == '/') {
            *p = '\0';
            if (mkdir(tmp, 0777) != 0 && errno != EEXIST)
                return sf_fail(err, SF_EIO, "%s: cannot create directory: %s", tmp, strerror(errno));
            *p = '/';
        }
    if (mkdir(tmp, 0777) != 0 && errno != EEXIST)
        return sf_fail(err, SF_EIO, "%s: cannot create directory: %s", tmp, strerror(errno));
    return SF_OK;
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

static int on_point(const cont_point *pt, void *data)
{
    run_ctx *r = data;
    sf_equil *eq = &r->eq;
    const sf_model *m = eq->m;
    const sf_study *s = m->study;
    double Pi, rr, rt;
    sf_equil_report(eq, pt->y, pt->p, &Pi, &rr, &rt);
    double load = eq->param == SF_PARAM_LOAD ? pt->p : eq->load;
    sbuf *b = &r->branch;
    double sarc = pt->s + r->s_offset;
    sb_printf(b, "%ld\t%.12g\t%.12g\t%.12g", r->npoints, fin(sarc), fin(pt->p), fin(load));
    double u0[3] = {0, 0, 0};
    for (int i = 0; i < s->nprobes; i++) {
        double u[3];
        probe_disp(r, pt->y, i, u);
        if (i == 0) memcpy(u0, u, sizeof u);
        sb_printf(b, "\t%.12g\t%.12g\t%.12g", fin(u[0]), fin(u[1]), fin(u[2]));
    }
    sb_printf(b, "\t%.12g\t%.3g\t%.3g\t%.3g\t%d\t%s", fin(Pi), fin(fmax(rr, rt)), fin(rr), fin(rt),
              pt->newton_iters, pt->label[0] ? pt->label : "-");
    for (int i = 0; i < m->nfolds; i++) sb_printf(b, "\t%.12g", fin(pt->y[m->qoff[i]]));
    sb_printf(b, "\n");
    cont_stats last;
    memset(&last, 0, sizeof last);
    if (r->solver) cont_get_stats(r->solver, &last, NULL);
    sb_printf(&r->stats, "%ld,%.6g,%.6g,%d,%ld,%ld,%ld,%ld,%.6g\n", r->npoints, fin(pt->p),
              fin(pt->ds), pt->newton_iters, last.nres, last.njac, last.retries, last.nlocate,
              fin(last.wall));
    if (pt->label[0] && strcmp(pt->label, "EP") != 0) {
        sb_printf(&r->special, "%ld\t%s\t%.12g\t%.12g", r->npoints, pt->label, fin(pt->p), fin(sarc));
        for (int i = 0; i < s->nprobes; i++) {
            double u[3];
            probe_disp(r, pt->y, i, u);
            sb_printf(&r->special, "\t%.12g\t%.12g\t%.12g", fin(u[0]), fin(u[1]), fin(u[2]));
        }
        sb_printf(&r->special, "\n");
    }
    /* shapes: the first point, then every shape_dp in p, and the last */
    int want = r->nshapes > 0 &&
               (r->npoints == 0 ||
                (r->shape_dp > 0 && (pt->p - r->next_shape) * (r->p_end >= r->p_start ? 1 : -1) >= -1e-12) ||
                strcmp(pt->label, "EP") == 0);
    if (want) {
        char rel[64], path[1200];
        snprintf(rel, sizeof rel, "shapes/shape_%04ld.vtp", r->npoints);
        snprintf(path, sizeof path, "%s/%s", r->dir, rel);
        if (sf_vtk_write_shape(m, pt->y, s->samples, path, r->err) ||
            sf_pvd_add(&r->pvd, pt->p, rel, r->err)) {
            r->failed = 1;
            return 1;
        }
        while (r->shape_dp > 0 &&
               (pt->p - r->next_shape) * (r->p_end >= r->p_start ? 1 : -1) >= -1e-12)
            r->next_shape += (r->p_end >= r->p_start ? 1 : -1) * r->shape_dp;
    }
    if (r->cmp) {
        /* reference comparison: a new branch block starts where the engine restarts */
        if (pt->index == 0 && r->last_index > 0) r->block++;
        r->last_index = pt->index;
        if (sf_compare_add(r->cmp, eq, r->probes, pt->y, pt->p, r->block, r->err)) {
            r->failed = 1;
            return 1;
        }
    }
    if (!r->opt->quiet) {
        fprintf(stderr, "point %4ld  p %-11.6g s %-10.4g newton %2d  |g| %-9.2g", r->npoints,
                pt->p, sarc, pt->newton_iters, fmax(rr, rt));
        if (s->nprobes) fprintf(stderr, "  %s uz %-11.5g", s->probes[0].name, u0[2]);
        fprintf(stderr, "%s%s\n", pt->label[0] ? "  " : "", pt->label);
    }
    r->npoints++;
    return 0;
}

static int component_index(const char *c)
{
    return strcmp(c, "x") == 0 ? 0 : strcmp(c, "y") == 0 ? 1 : 2;
}

static int run_equilibrium(run_ctx *r)
{
    sf_scene *sc = r->sc;
    const sf_study *s = &sc->study;
    sf_error *err = r->err;
    const char *param, *group, *probe, *comp;
    double start, end, step, min_step, max_step, load;
    int max_steps;
    if (sf_study_string(s, "analysis.parameter", "load", &param, err) ||
        sf_study_string(s, "analysis.group", "", &group, err) ||
        sf_study_double(s, "analysis.start", 0.0, &start, err) ||
        sf_study_double(s, "analysis.end", (double)s->nstages, &end, err) ||
        sf_study_double(s, "analysis.step", 0.05, &step, err) ||
        sf_study_double(s, "analysis.min_step", 1e-6, &min_step, err) ||
        sf_study_double(s, "analysis.max_step", 0.2, &max_step, err) ||
        sf_study_int(s, "analysis.max_steps", 500, &max_steps, err) ||
        sf_study_double(s, "analysis.load", 0.0, &load, err) ||
        sf_study_string(s, "analysis.probe", "", &probe, err) ||
        sf_study_string(s, "analysis.component", "z", &comp, err))
        return err->code;
    int ptype = strcmp(param, "actuation") == 0 ? SF_PARAM_ACTUATION
              : strcmp(param, "displacement") == 0 ? SF_PARAM_DISPLACEMENT : SF_PARAM_LOAD;
    int gi = -1, pi = 0;
    if (group && group[0]) gi = sf_study_group_index(s, group);
    if (probe && probe[0]) pi = sf_study_probe_index(s, probe);
    if (ptype == SF_PARAM_DISPLACEMENT && (pi < 0 || s->nprobes == 0))
        return sf_fail(err, SF_EINPUT, "%s: the displacement parameter needs a probe", s->path);
    if (sf_equil_init(&r->eq, &sc->model, ptype, gi, pi, component_index(comp), load, err))
        return err->code;
    sf_equil *eq = &r->eq;
    if (s->constraints == SF_CONSTRAINTS_PENALTY)
        sf_equil_use_penalty(eq, s->penalty_rotation, s->penalty_translation);
    const char *linsol;
    if (sf_study_string(s, "solver.linear_solver", "dense", &linsol, err)) return err->code;
    sf_equil_use_sparse(eq, strcmp(linsol, "sparse") == 0);
    r->probes = calloc((size_t)s->nprobes + 1, sizeof(sf_mpoint));
    if (!r->probes) return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int i = 0; i < s->nprobes; i++)
        if (sf_model_locate(&sc->model, s->probes[i].at, &r->probes[i], err)) {
            sf_error_prefix(err, "%s:%d: probe %d", s->path, s->probes[i].line, i + 1);
            return err->code;
        }
    /* the continuation engine sees only this problem */
    if (sf_equil_create_solver(eq, &r->solver) != CONT_OK)
        return sf_fail(err, SF_ENOMEM, "continuation: %s",
                       r->solver ? cont_errmsg(r->solver) : "cannot create the solver");
    cont_solver *cs = r->solver;
    double lo = fmin(start, end), hi = fmax(start, end);
    cont_set_step(cs, step, min_step, max_step);
    cont_set_prange(cs, lo, hi);
    cont_set_max_steps(cs, max_steps);
    cont_set_newton(cs, s->tolerance > 0 ? s->tolerance : 1e-10, 12, 0);
    cont_set_callback(cs, on_point, r);
    cont_set_store(cs, 0);
    r->p_start = start;
    r->p_end = end;
    r->nshapes = s->shapes;
    r->shape_dp = s->shapes > 0 ? fabs(end - start) / s->shapes : 0.0;
    r->next_shape = start;
    double *y0 = calloc((size_t)eq->n + 1, sizeof(double));
    if (!y0) return sf_fail(err, SF_ENOMEM, "out of memory");
    int dir = end >= start ? +1 : -1, rc;
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
    if (F0norm > 1e-14) {
        sf_equil_set_param(eq, start);
        for (int i = 0; i < sc->model.nfolds; i++)
            if (eq->par.rest[i] != 0.0) {
                y0[sc->model.qoff[i]] = eq->par.rest[i];
                rested = 1;
            }
    }
    if (eq->nloop > 0 && F0norm <= 1e-14) {
        /* The flat state solves the exact problem at the start, but it is a
         * singular point of loop closure (multipliers of the second-order
         * rows are undetermined there).  Report it, then start the branch
         * one step further from the penalty homotopy. */
        cont_point p0;
        memset(&p0, 0, sizeof p0);
        p0.y = y0;
        p0.p = start;
        on_point(&p0, r);
        if (r->failed) { free(y0); return err->code; }
        double p1 = start + dir * fmin(step, 0.25 * fabs(end - start));
        rc = sf_equil_start_off_flat(eq, p1, s->tolerance > 0 ? s->tolerance : 1e-10, y0, err);
        if (rc) { free(y0); return rc; }
        double d2 = (p1 - start) * (p1 - start);
        for (int i = 0; i < eq->n; i++) d2 += y0[i] * y0[i];
        r->s_offset = sqrt(d2);
        rc = cont_start(cs, y0, p1, dir);
    } else {
        rc = cont_start(cs, y0, start, dir);
        if (rc != CONT_OK && rested && !r->failed) {
            /* the rest state did not lead Newton anywhere: try the flat sheet */
            memset(y0, 0, (size_t)eq->n * sizeof *y0);
            rc = cont_start(cs, y0, start, dir);
        }
    }
    free(y0);
    if (rc != CONT_OK) {
        if (r->failed) return err->code;
        return sf_fail(err, SF_ENUMERIC, "%s: no equilibrium at the start of the path: %s%s",
                       s->path, cont_errmsg(cs),
                       eq->nloop ? " (exact loop closure: the KKT matrix may be singular here; "
                                   "solver.constraints = \"penalty\" is the paper's method)" : "");
    }
    rc = cont_run(cs);
    if (r->failed) return err->code;
    if (rc == CONT_FAIL)
        return sf_fail(err, SF_ENUMERIC, "%s: path stopped after %ld points: %s", s->path,
                       r->npoints, cont_errmsg(cs));
    return SF_OK;
}

static int write_outputs(run_ctx *r)
{
    const sf_study *s = &r->sc->study;
    sf_error *err = r->err;
    char path[1200];
    sbuf out = {0};
#define WRITE(name, buf)                                                           \
    do {                                                                           \
        if ((buf).oom) return sf_fail(err, SF_ENOMEM, "out of memory");            \
        snprintf(path, sizeof path, "%s/%s", r->dir, name);                        \
        if (sf_write_atomic(path, fill_sbuf, &(buf), err)) return err->code;       \
    } while (0)
    /* branch.tsv: comments, column names, rows */
    sb_printf(&out, "%s", r->header.s ? r->header.s : "");
    sb_printf(&out, "# units: s, p, load: as the parameter (load factor, actuation factor, or m); "
                    "probe*: m; energy: J; residual_rot: 1; residual_tra: m; theta*: rad\n");
    sb_printf(&out, "point\ts\tp\tload");
    for (int i = 0; i < s->nprobes; i++)
        sb_printf(&out, "\tprobe%d_ux\tprobe%d_uy\tprobe%d_uz", i + 1, i + 1, i + 1);
    sb_printf(&out, "\tenergy\tresidual\tresidual_rot\tresidual_tra\tnewton\ttype");
    for (int i = 0; i < s->nfolds; i++) sb_printf(&out, "\ttheta%d", i + 1);
    sb_printf(&out, "\n");
    if (r->branch.n) sb_printf(&out, "%.*s", (int)r->branch.n, r->branch.s);
    WRITE("branch.tsv", out);
    out.n = 0;
    sb_printf(&out, "# smoothfold %s per-step solver statistics for %s\n", PACKAGE_VERSION, s->name);
    sb_printf(&out, "point,p,ds,newton,residual_evals,jacobian_evals,retries,locate_points,wall_s\n");
    if (r->stats.n) sb_printf(&out, "%.*s", (int)r->stats.n, r->stats.s);
    WRITE("stats.csv", out);
    out.n = 0;
    sb_printf(&out, "%s", r->header.s ? r->header.s : "");
    sb_printf(&out, "point\ttype\tp\ts");
    for (int i = 0; i < s->nprobes; i++)
        sb_printf(&out, "\tprobe%d_ux\tprobe%d_uy\tprobe%d_uz", i + 1, i + 1, i + 1);
    sb_printf(&out, "\n");
    if (r->special.n) sb_printf(&out, "%.*s", (int)r->special.n, r->special.s);
    WRITE("special.tsv", out);
    free(out.s);
#undef WRITE
    if (r->nshapes > 0 && sf_pvd_write(&r->pvd, err)) return err->code;
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
    run_ctx r;
    memset(&r, 0, sizeof r);
    r.sc = &sc;
    r.opt = o;
    r.err = err;
    snprintf(r.dir, sizeof r.dir, "%s", o->output);
    int rc = SF_OK;
    if (strcmp(sc.study.analysis_type, "equilibrium") != 0) {
        rc = sf_fail(err, SF_EINPUT, "%s: analysis.type \"%s\" is not available in this version "
                     "(only \"equilibrium\")", sc.study.path, sc.study.analysis_type);
    }
    char shapes[1100];
    snprintf(shapes, sizeof shapes, "%s/shapes", r.dir);
    if (!rc) rc = sf_compare_open(&r.cmp, &sc.study, err);   /* bad reference files: before any output */
    if (!rc) rc = make_dir(r.dir, err);
    if (!rc && sc.study.shapes > 0) rc = make_dir(shapes, err);
    if (!rc) {
        char pvd[1100];
        snprintf(pvd, sizeof pvd, "%s/shapes.pvd", r.dir);
        sf_pvd_init(&r.pvd, pvd);
        sb_printf(&r.header, "# smoothfold %s: %s, analysis %s\n", PACKAGE_VERSION,
                  sc.study.name, sc.study.analysis_type);
        rc = run_equilibrium(&r);
        if (rc == SF_ENUMERIC && r.npoints > 0) {
            /* keep the path up to where it stopped: complete files whose
             * header says why it stopped; the exit status stays non-zero */
            sb_printf(&r.header, "# STOPPED EARLY: %s\n", err->msg);
            sf_error keep = *err;
            sf_error_clear(err);
            if (write_outputs(&r) == SF_OK) *err = keep;
            rc = err->code;
        } else if (!rc) {
            cont_get_stats(r.solver, NULL, &r.tot);
            if (r.cmp) {
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
    sf_compare_free(r.cmp);
    if (r.solver) cont_free(r.solver);
    sf_equil_free(&r.eq);
    free(r.probes);
    free(r.branch.s);
    free(r.stats.s);
    free(r.special.s);
    free(r.header.s);
    sf_pvd_free(&r.pvd);
    sf_scene_close(&sc);
    return rc;
}
