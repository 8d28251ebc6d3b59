/* run_boundary.c - `smoothfold run` with analysis.type = "boundary": a
 * stability boundary in two parameters (docs/guides/stability.md).
 *
 * 1. The study's path in p (analysis.parameter, start .. end) at the
 *    study's value q0 of the second parameter, until the first limit point
 *    or branch point the engine locates (analysis.from).
 * 2. That point continued in q (analysis.second, second_min .. second_max)
 *    with the extended system of boundary.h, in both directions.
 * 3. DIR/boundary.tsv (one block: the curve from its q-minimum end to its
 *    other end), DIR/study.cfg; `smoothfold plot DIR` draws
 *    plots/boundary.gp. */
#include "run_boundary.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "boundary.h"
#include "cont.h"
#include "outbuf.h"
#include "stability.h"
#include "study.h"
#include "run_validity.h"
#include "vtk.h"

#ifndef PACKAGE_VERSION
#define PACKAGE_VERSION "0.1.0"
#endif

typedef struct bnd_row {
    double q, p, mu, test;
    char label[4];
    int morse, neig;       /* morse -1: no stability */
    double *vals;          /* nev eigenvalues, then nfolds fold angles */
    sf_validity_report valid;  /* its physical validity */
} bnd_row;

typedef struct bnd_ctx {
    sf_scene *sc;
    const sf_options *opt;
    sf_error *err;
    sf_family fam;
    sf_bnd B;
    int want;              /* 0: the first LP or BP; else SF_BND_LP / SF_BND_BP */
    int found;             /* SF_BND_LP / SF_BND_BP once found */
    double *ystar, pstar;
    int start_morse;
    double plo, phi;       /* window of p on the curve */
    int do_stab, nev, nfolds;
    sf_stab stab;
    bnd_row *rows;
    int nrows, caprows, failed;
    long ncusp;
    run_validity vt;       /* the physical validity of the rows */
} bnd_ctx;

/* Stability at (y, p) of the problem at q: the Morse index without the
 * eigenvalue nearest zero (the critical one on the curve), and the
 * eigenvalues into vals. */
static int stab_at(bnd_ctx *r, double q, const double *y, double p, int critical, double *vals,
                   int *neig)
{
    sf_equil *eq;
    sf_error e;
    sf_error_clear(&e);
    *neig = 0;
    if (!r->do_stab || sf_family_get(&r->fam, q, &eq, &e) || sf_stab_eval(&r->stab, eq, y, p, &e))
        return -1;
    const sf_stab_result *R = &r->stab.res;
    if (R->morse_unknown) return -1; /* an ambiguous inertia: no index */
    int morse = R->morse;
    if (critical && R->neig > 0) {
        int k = 0;
        for (int i = 1; i < R->neig; i++)
            if (fabs(R->eig[i]) < fabs(R->eig[k])) k = i;
        if (R->eig[k] < 0) morse--;
    }
    for (int i = 0; i < R->neig && i < r->nev; i++) vals[i] = R->eig[i];
    *neig = R->neig < r->nev ? R->neig : r->nev;
    return morse;
}

static int on_primary(const cont_point *pt, void *data)
{
    bnd_ctx *r = data;
    int n = r->fam.n, ne;
    if (pt->index == 0 && !pt->type) {
        double *v = malloc(sizeof(double) * (size_t)(r->nev + 1));
        r->start_morse = v ? stab_at(r, r->fam.q0, pt->y, pt->p, 0, v, &ne) : -1;
        free(v);
    }
    int kind = pt->type == CONT_PT_LP ? SF_BND_LP : pt->type == CONT_PT_BP ? SF_BND_BP : 0;
    if (!kind || (r->want && kind != r->want) || pt->index == 0) return 0;
    memcpy(r->ystar, pt->y, sizeof(double) * (size_t)n);
    r->pstar = pt->p;
    r->found = kind;
    return 1;
}

static int on_curve(const cont_point *pt, void *data)
{
    bnd_ctx *r = data;
    sf_bnd *B = &r->B;
    int n = B->n;
    if (sf_bnd_update(B, pt->y, pt->p)) {
        r->failed = 1;
        sf_fail(r->err, SF_ENUMERIC, "boundary: no singular vectors at q = %g%s%s",
                sf_bnd_q(B, pt->p), B->err.code ? ": " : "", B->err.msg);
        return 1;
    }
    if (r->nrows == r->caprows) {
        int cap = r->caprows ? 2 * r->caprows : 64;
        bnd_row *nr = realloc(r->rows, sizeof *nr * (size_t)cap);
        if (!nr) { r->failed = 1; sf_fail(r->err, SF_ENOMEM, "out of memory"); return 1; }
        r->rows = nr;
        r->caprows = cap;
    }
    bnd_row *w = &r->rows[r->nrows];
    memset(w, 0, sizeof *w);
    w->vals = calloc((size_t)(r->nev + r->nfolds + 1), sizeof(double));
    if (!w->vals) { r->failed = 1; sf_fail(r->err, SF_ENOMEM, "out of memory"); return 1; }
    r->nrows++;
    w->q = sf_bnd_q(B, pt->p);
    w->p = pt->y[n];
    w->mu = B->kind == SF_BND_BP ? pt->y[n + 1] : NAN;
    w->test = pt->test ? pt->test[0] : NAN;
    snprintf(w->label, sizeof w->label, "%s", pt->type == CONT_PT_USER ? "CP" : pt->index == 0 ? "SP"
             : pt->type == CONT_PT_EP ? "EP" : "");
    if (pt->type == CONT_PT_USER) r->ncusp++;
    w->morse = stab_at(r, w->q, pt->y, w->p, 1, w->vals, &w->neig);
    sf_equil *eq;
    sf_error e;
    sf_error_clear(&e);
    if (sf_family_get(&r->fam, w->q, &eq, &e) != SF_OK) {
        r->failed = 1;
        sf_fail(r->err, e.code, "boundary: fold angles at row %d (q = %g): %s", r->nrows - 1, w->q, e.msg);
        return 1;
    }
    for (int i = 0; i < r->nfolds; i++) w->vals[r->nev + i] = pt->y[eq->m->qoff[i]];
    /* each row's own problem (the second parameter may move the sheet's
     * geometry): its checker made anew */
    run_validity_free(&r->vt);
    if (run_validity_check(&r->vt, eq->m, pt->y, &w->valid, r->err)) {
        r->failed = 1;
        sf_error_prefix(r->err, "boundary row %d (%s = %g)", r->nrows - 1, r->fam.shown, w->q);
        return 1;
    }
    /* the row's numbers finite (outbuf.h): else stop, nothing is written */
    int bad = sf_need_finite(r->err, w->q, "second parameter at boundary row %d", r->nrows - 1) ||
              sf_need_finite(r->err, w->p, "p at boundary row %d (q = %g)", r->nrows - 1, w->q);
    for (int i = 0; i < r->nfolds && !bad; i++)
        bad = sf_need_finite(r->err, w->vals[r->nev + i], "fold angle of fold %d at boundary row %d (q = %g)",
                             i + 1, r->nrows - 1, w->q);
    if (bad) {
        r->failed = 1;
        return 1;
    }
    /* the path parameter far outside the study's range: stop */
    return !(w->p >= r->plo && w->p <= r->phi);
}

/* The path at q0 up to its first LP/BP. */
static int primary(bnd_ctx *r, double start, double end, double step, double min_step,
                   double max_step, int max_steps, double tol)
{
    const sf_study *s = &r->sc->study;
    sf_equil *eq;
    if (sf_family_get(&r->fam, r->fam.q0, &eq, r->err)) return r->err->code;
    cont_solver *cs = NULL;
    if (sf_equil_create_solver(eq, &cs) != CONT_OK) {
        cont_free(cs);
        return sf_fail(r->err, SF_ENOMEM, "continuation: cannot create the solver");
    }
    cont_set_step(cs, step, min_step, max_step);
    cont_set_prange(cs, fmin(start, end), fmax(start, end));
    cont_set_max_steps(cs, max_steps);
    cont_set_newton(cs, tol, 12, 0);
    cont_set_callback(cs, on_primary, r);
    cont_set_store(cs, 0);
    int n = eq->n, dir = end >= start ? 1 : -1;
    double *y0 = calloc((size_t)n + 1, sizeof(double));
    if (!y0) { cont_free(cs); return sf_fail(r->err, SF_ENOMEM, "out of memory"); }
    /* the rest angles at the start, as in `run` (a compressed sheet folded
     * by actuation has the flat state as an unstable equilibrium nearby) */
    sf_equil_set_param(eq, start);
    for (int i = 0; i < eq->m->nfolds; i++) y0[eq->m->qoff[i]] = eq->par.rest[i];
    int rc = cont_start(cs, y0, start, dir);
    if (rc != CONT_OK) {
        memset(y0, 0, sizeof(double) * (size_t)n);
        rc = cont_start(cs, y0, start, dir);
    }
    if (rc == CONT_OK && !r->found) rc = cont_run(cs) == CONT_FAIL ? CONT_FAIL : CONT_OK;
    if (rc != CONT_OK && !r->found)
        sf_fail(r->err, SF_ENUMERIC, "%s: boundary: the path at %s = %g failed before its first %s: %s",
                s->path, r->fam.shown, r->fam.q0, r->want == SF_BND_LP ? "limit point"
                : r->want == SF_BND_BP ? "branch point" : "limit or branch point", cont_errmsg(cs));
    else if (!r->found)
        sf_fail(r->err, SF_ENUMERIC, "%s: boundary: no %s on the path from p = %g to %g at %s = %g "
                "(widen analysis.start .. analysis.end)", s->path,
                r->want == SF_BND_LP ? "limit point" : r->want == SF_BND_BP ? "branch point"
                : "limit or branch point", start, end, r->fam.shown, r->fam.q0);
    free(y0);
    cont_free(cs);
    return r->found ? SF_OK : r->err->code;
}

/* The curve through the special point, both directions. */
static int follow(bnd_ctx *r, double smin, double smax, double step, double min_step,
                  double max_step, int max_steps, double tol)
{
    sf_bnd *B = &r->B;
    int N = B->N, n = B->n;
    double *buf = calloc((size_t)(4 * N + B->m * B->k + n + 2), sizeof(double));
    if (!buf) return sf_fail(r->err, SF_ENOMEM, "out of memory");
    double *ys = buf, *fs = ys + N, *w = fs + N, *Y0 = w + N, *C0 = Y0 + N, *b0 = C0 + B->m * B->k;
    cont_problem prob;
    sf_bnd_problem(B, ys, fs, &prob);
    cont_solver *cs = NULL;
    int rc = cont_create(&prob, CONT_LINSOL_DENSE, &cs);
    for (int i = 0; i < N; i++) w[i] = i < r->fam.nq || i == n ? 1.0 : 0.0;
    if (rc == CONT_OK) rc = cont_set_weights(cs, w);
    if (rc != CONT_OK) {
        sf_fail(r->err, SF_ENOMEM, "boundary: %s", cs ? cont_errmsg(cs) : "cannot create the solver");
        cont_free(cs);
        free(buf);
        return r->err->code;
    }
    cont_set_step(cs, step, min_step, max_step);
    cont_set_prange(cs, smin, smax);
    cont_set_max_steps(cs, max_steps);
    cont_set_newton(cs, tol, 12, 0);
    cont_set_detect(cs, CONT_DETECT_USER, 1e-10);
    cont_set_callback(cs, on_curve, r);
    cont_set_store(cs, 0);
    memcpy(Y0, r->ystar, sizeof(double) * (size_t)n);
    Y0[n] = r->pstar;
    memcpy(C0, B->C, sizeof(double) * (size_t)(B->m * B->k));
    memcpy(b0, B->b, sizeof(double) * (size_t)n);
    int first = 0;
    for (int d = 0; d < 2 && !r->failed; d++) {
        memcpy(B->C, C0, sizeof(double) * (size_t)(B->m * B->k));
        memcpy(B->b, b0, sizeof(double) * (size_t)n);
        int nbefore = r->nrows;
        rc = cont_start(cs, Y0, 0.0, d ? +1 : -1);
        if (rc == CONT_OK) rc = cont_run(cs) == CONT_FAIL ? CONT_FAIL : CONT_OK;
        if (r->failed) break;
        if (rc != CONT_OK) {
            sf_fail(r->err, SF_ENUMERIC, "%s: boundary: the curve stopped at %s = %g after %d points: %s",
                    r->sc->study.path, r->fam.shown, r->nrows > nbefore ? r->rows[r->nrows - 1].q
                    : r->fam.q0, r->nrows - nbefore, cont_errmsg(cs));
            break;
        }
        if (d == 0) {
            /* the first run backwards, then the second without its start */
            for (int i = 0, j = r->nrows - 1; i < j; i++, j--) {
                bnd_row t = r->rows[i];
                r->rows[i] = r->rows[j];
                r->rows[j] = t;
            }
            first = r->nrows;
        } else if (r->nrows > first) {
            free(r->rows[first].vals);
            memmove(&r->rows[first], &r->rows[first + 1], sizeof(bnd_row) * (size_t)(r->nrows - first - 1));
            r->nrows--;
        }
    }
    cont_free(cs);
    free(buf);
    return r->failed || rc != CONT_OK ? r->err->code : SF_OK;
}

static int write_boundary(bnd_ctx *r, const char *dir, double pstart)
{
    const sf_study *s = &r->sc->study;
    sf_outbuf o = {0};
    const char *kind = r->found == SF_BND_LP ? "LP" : "BP";
    sf_outbuf_printf(&o, "# smoothfold %s: %s, analysis boundary\n", PACKAGE_VERSION, s->name);
    sf_outbuf_printf(&o, "# the %s located on the path at p = %.12g (%s = %.12g), continued in %s\n",
                     kind, r->pstar, r->fam.shown, r->fam.q0, r->fam.shown);
    const char *pname = r->fam.param == SF_PARAM_LOAD ? "load factor"
                      : r->fam.param == SF_PARAM_ACTUATION ? "actuation factor" : "displacement, m";
    sf_outbuf_printf(&o, "# kind: %s\n# second: %s\n# parameter: %s\n# path_start: %.12g\n"
                     "# start_side: %s\n# start_morse: %d\n# cusps: %ld\n", kind, r->fam.shown, pname, pstart,
                     pstart < r->pstar ? "below" : "above", r->start_morse, r->ncusp);
    sf_outbuf_printf(&o, "# columns: second = %s; p = the path parameter (%s); mu = unfolding "
                     "parameter of the BP system (0 at a symmetric branch point; empty for LP); "
                     "cusp_test = quadratic coefficient of the fold (LP; zero at a cusp CP); "
                     "morse = negative eigenvalues besides the critical one; eig*: J per unit of "
                     "the coordinates; theta*: rad; type: SP start (the point of the path), "
                     "CP cusp, EP end\n", r->fam.shown, pname);
    /* the rows' validity, counted in their final order */
    run_validity tally = {0};
    char (*warn)[40] = calloc((size_t)r->nrows + 1, sizeof *warn);
    if (!warn) { sf_outbuf_free(&o); return sf_fail(r->err, SF_ENOMEM, "out of memory"); }
    for (int k = 0; k < r->nrows; k++) run_validity_add(&tally, &r->rows[k].valid, k, r->rows[k].q, warn[k], sizeof warn[k]);
    tally.val = r->vt.val;   /* the part names */
    char vline[1500];
    run_validity_line(&tally, &r->sc->model, r->fam.shown, "boundary.tsv", vline, sizeof vline);
    if (vline[0]) {
        sf_outbuf_printf(&o, "# warning: %s\n", vline);
        fprintf(stderr, "smoothfold: warning: %s\n", vline);   /* also with --quiet */
    }
    sf_outbuf_printf(&o, "point\tsecond\tp\tmu\tcusp_test\tmorse");
    sf_outbuf_numbered_columns(&o, "eig", r->nev);
    sf_outbuf_printf(&o, "\ttype");
    sf_outbuf_numbered_columns(&o, "theta", r->nfolds);
    sf_outbuf_printf(&o, "\twarning\n");
    for (int k = 0; k < r->nrows; k++) {
        const bnd_row *w = &r->rows[k];
        sf_outbuf_printf(&o, "%d\t%.15g\t%.15g\t", k, w->q, w->p);
        if (isfinite(w->mu)) sf_outbuf_printf(&o, "%.6e", w->mu);
        sf_outbuf_printf(&o, "\t");
        if (isfinite(w->test)) sf_outbuf_printf(&o, "%.6e", w->test);
        sf_outbuf_printf(&o, "\t");
        if (w->morse >= 0) sf_outbuf_printf(&o, "%d", w->morse);
        for (int i = 0; i < r->nev; i++) {
            sf_outbuf_printf(&o, "\t");
            if (i < w->neig && isfinite(w->vals[i])) sf_outbuf_printf(&o, "%.10g", w->vals[i]);
        }
        sf_outbuf_printf(&o, "\t%s", w->label);
        for (int i = 0; i < r->nfolds; i++) sf_outbuf_printf(&o, "\t%.15g", w->vals[r->nev + i]);
        sf_outbuf_printf(&o, "\t%s\n", warn[k]);
    }
    free(warn);
    char path[1200];
    int rc = SF_OK;
    if (o.oom) rc = sf_fail(r->err, SF_ENOMEM, "out of memory");
    snprintf(path, sizeof path, "%s/boundary.tsv", dir);
    if (!rc) rc = sf_write_atomic(path, sf_outbuf_fill, &o, r->err);
    sf_outbuf_free(&o);
    snprintf(path, sizeof path, "%s/study.cfg", dir);
    if (!rc) rc = sf_study_write(s, path, "merged study run by smoothfold (after --set overrides)", r->err);
    return rc;
}

int sf_run_boundary(sf_scene *sc, const sf_options *o, sf_error *err)
{
    const sf_study *s = &sc->study;
    bnd_ctx r;
    memset(&r, 0, sizeof r);
    r.sc = sc;
    r.opt = o;
    r.err = err;
    r.start_morse = -1;
    double start, end, step, min_step, max_step, qmin, qmax, qstep, qmax_step;
    int max_steps, nev, stab_on;
    const char *second, *from;
    if (!sf_study_has(s, "analysis.second") || !sf_study_has(s, "analysis.second_min") ||
        !sf_study_has(s, "analysis.second_max"))
        return sf_study_fail(s, err, SF_EINPUT, "analysis", "type \"boundary\" needs second, "
                             "second_min and second_max (the second parameter and its range)");
    if (sf_study_double(s, "analysis.start", 0.0, &start, err) ||
        sf_study_double(s, "analysis.end", 1.0, &end, err) ||
        sf_study_double(s, "analysis.step", 0.05, &step, err) ||
        sf_study_double(s, "analysis.min_step", 1e-6, &min_step, err) ||
        sf_study_double(s, "analysis.max_step", 0.2, &max_step, err) ||
        sf_study_int(s, "analysis.max_steps", 500, &max_steps, err) ||
        sf_study_int(s, "analysis.eigenvalues", 4, &nev, err) ||
        sf_study_bool(s, "analysis.stability", 1, &stab_on, err) ||
        sf_study_string(s, "analysis.second", "", &second, err) ||
        sf_study_string(s, "analysis.from", "any", &from, err) ||
        sf_study_double(s, "analysis.second_min", 0.0, &qmin, err) ||
        sf_study_double(s, "analysis.second_max", 0.0, &qmax, err) ||
        sf_study_double(s, "analysis.second_step", 0.02, &qstep, err) ||
        sf_study_double(s, "analysis.second_max_step", 0.1, &qmax_step, err))
        return err->code;
    if (!(qmin < qmax))
        return sf_study_fail(s, err, SF_EINPUT, "analysis.second_max", "must be greater than "
                             "analysis.second_min (got %g and %g)", qmax, qmin);
    r.want = strcmp(from, "LP") == 0 ? SF_BND_LP : strcmp(from, "BP") == 0 ? SF_BND_BP : 0;
    r.do_stab = stab_on;
    r.nev = stab_on ? (nev > 0 ? nev : 1) : 0;
    r.nfolds = sc->model.nfolds;
    double span = fabs(end - start);
    r.plo = fmin(start, end) - span;
    r.phi = fmax(start, end) + span;
    double tol = s->tolerance > 0 ? s->tolerance : 1e-10;
    int rc = sf_family_init(&r.fam, s->path, o->nset, o->sets, second, err);
    if (!rc && !(r.fam.q0 >= qmin && r.fam.q0 <= qmax))
        rc = sf_study_fail(s, err, SF_EINPUT, "analysis.second_min", "the study's %s = %g is "
                           "outside second_min .. second_max (%g .. %g)", r.fam.shown, r.fam.q0, qmin, qmax);
    sf_equil *eq0;
    if (!rc && r.do_stab && !(rc = sf_family_get(&r.fam, r.fam.q0, &eq0, err)))
        rc = sf_stab_init(&r.stab, eq0, SF_EIG_AUTO, r.nev, err);
    if (!rc && !(r.ystar = calloc((size_t)r.fam.n + 1, sizeof(double))))
        rc = sf_fail(err, SF_ENOMEM, "out of memory");
    if (!rc) rc = primary(&r, start, end, step, min_step, max_step, max_steps, tol);
    if (!rc && !o->quiet)
        fprintf(stderr, "%s: %s at p = %.10g (%s = %g); following it in %s from %g to %g\n", s->name,
                r.found == SF_BND_LP ? "limit point" : "branch point", r.pstar, r.fam.shown,
                r.fam.q0, r.fam.shown, qmin, qmax);
    if (!rc) rc = sf_bnd_init(&r.B, &r.fam, r.found, r.ystar, r.pstar, r.fam.q0, err);
    if (!rc)
        rc = follow(&r, (qmin - r.fam.q0) / r.fam.qs, (qmax - r.fam.q0) / r.fam.qs, qstep, min_step,
                    qmax_step, max_steps, tol);
    if (!rc) rc = sf_cli_outdir(o, o->output, err);   /* earlier results removed */
    if (!rc) rc = write_boundary(&r, o->output, start);
    if (!rc && !o->quiet)
        printf("%s: boundary of %d points, %ld cusps, %ld problems built, %ld Jacobians for "
               "differences; results in %s\n", s->name, r.nrows, r.ncusp, r.fam.builds,
               r.B.njac_diff, o->output);
    for (int i = 0; i < r.nrows; i++) free(r.rows[i].vals);
    free(r.rows);
    free(r.ystar);
    sf_bnd_free(&r.B);
    if (r.do_stab && r.stab.nq) sf_stab_free(&r.stab);
    run_validity_free(&r.vt);
    sf_family_free(&r.fam);
    return rc;
}
