/* run_stability.c - `smoothfold run`: the stability analysis of the
 * equilibrium path (analysis.stability and its keys) and the hooks through
 * which the branch bookkeeping (bifurcation.h) writes notes and points and
 * starts switched branches. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "run_impl.h"
#include "study.h"

/* Hooks of the bifurcation bookkeeping (bifurcation.h). */
static void on_note(void *ctx, const char *line) { run_branch_note(ctx, "%s", line); }

static int on_located(void *ctx, const cont_point *q)
{
    run_ctx *r = ctx;
    r->neig_method[r->stab.res.method]++;
    return run_write_point(r, q);
}

static int on_failed(void *ctx) { return ((run_ctx *)ctx)->failed; }

/* A switched branch starts: its own series of shapes, the whole range of
 * p (it may run either way, all load stages together), a new block of
 * branch.tsv. */
static int on_branch(void *ctx, const sf_bif_bp *bp, int branch)
{
    run_ctx *r = ctx;
    (void)bp;
    if (run_flush_held(r)) return r->err->code ? r->err->code : SF_EINTERNAL;   /* the last branch's */
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
/* analysis.stability and its keys: the eigensolver of each point, the
 * branch bookkeeping (bifurcation.h) and, through *depth, how deep
 * branches are switched.  After the equilibrium problem is set up. */
int run_setup_stability(run_ctx *r, int *depth)
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
