/* commands.c - check and shape commands; the scene (study + topology +
 * model) every command starts from. */
#include "commands.h"

#include <errno.h>
#include <sys/stat.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "compare.h"
#include "kinematics.h"
#include "mobility.h"
#include "outdir.h"
#include "progress.h"
#include "scene.h"
#include "study.h"
#include "topology.h"
#include "vtk.h"

static const char *vname(const sf_study *s, int v) { return s->vertices[v].name; }

static void print_dof(int dof, int first, double gap, double radius, int kind)
{
    if (dof > 0) printf("%d degree%s of freedom (%d at first order)", dof, dof == 1 ? "" : "s", first);
    else if (dof == 0) printf("locked (%d at first order, %s; loops do not close better than %.2g "
                              "at %g rad)", first, kind == SF_CERT_SECOND_ORDER ?
                              "no second-order motion" : "a prestress", gap, radius);
    else printf("undecided: no closed state found at %g rad (residual %.2g) and no proof "
                "of locking (%d at first order)", radius, gap, first);
}

/* The one line of the mobility verdict of the whole sheet, from the
 * mobility API (src/analysis/stability/mobility.h): foldable, locked, or undecided.
 * The only place `check` turns the analysis into a verdict, so that a new
 * verdict (its certificate) replaces this function alone. */
static void print_mobility_verdict(const sf_scene *sc, const sf_mobility *mb)
{
    printf("mobility (exact loop closure, about the flat sheet): ");
    if (!mb->probed)
        printf("undecided: %d degree%s of freedom at first order (sparse rank); the second-order "
               "probe of the whole sheet runs up to %d coordinates, this one has %d\n",
               mb->first_order, mb->first_order == 1 ? "" : "s", SF_MOBILITY_DENSE_MAX, mb->nq);
    else if (mb->dof > 0)
        printf("foldable, %d degree%s of freedom (%d at first order)\n", mb->dof, mb->dof == 1 ? "" : "s",
               mb->first_order);
    else if (mb->dof == 0 && mb->cert_kind == SF_CERT_SECOND_ORDER)
        printf("locked (%d at first order; no second-order motion: the stresses' forms sum in "
               "squares to at least %.3g |v|^4)\n", mb->first_order, mb->certificate);
    else if (mb->dof == 0)
        printf("locked (%d at first order; a stress certifies it to second order: %.3g > 0)\n",
               mb->first_order, mb->certificate);
    else
        printf("undecided: no closed state found at %g rad (residual %.2g) and no proof of locking "
               "(%d at first order)\n", mb->radius, mb->gap, mb->first_order);
    if (sf_mobility_locked(mb)) {
        char what[1500];
        sf_mobility_describe(&sc->model, mb, what, sizeof what);
        printf("warning: %s\n", what);
    }
    int rows, coords, coords2, k1;
    if ((!mb->probed || mb->dof < 0) &&
        sf_mobility_overcounted(&sc->model, &rows, &coords, &coords2, &k1))
        printf("note: the loops have %d rows for %d fold coordinates (%d folds with at most 1 shape "
               "mode), so a folded state closes only where rows are dependent; if `run` stops at the "
               "flat sheet, try --set defaults.modes=2 (%d coordinates)\n", rows, coords, k1, coords2);
}

/* Up to max names of the vertices whose own loops give verdict dof
 * (0 locked, -1 undecided), after the count. */
static void print_vertex_group(const sf_scene *sc, const sf_mobility *mb, int dof, const char *what,
                               int max)
{
    int n = 0;
    for (int v = 0; v < mb->nvertices; v++) n += dof < 0 ? mb->v[v].dof < 0 : mb->v[v].dof == dof;
    if (!n) return;
    printf("  %d %s", n, what);
    int k = 0;
    for (int v = 0; v < mb->nvertices && k < max; v++) {
        if (!(dof < 0 ? mb->v[v].dof < 0 : mb->v[v].dof == dof)) continue;
        printf("%s%s", k++ ? ", " : ": ", vname(&sc->study, sc->topo.ivertices[v].vertex));
    }
    printf("%s\n", n > max ? ", ..." : "");
}

/* Degrees of freedom left by exact loop closure (src/analysis/stability/mobility.h):
 * the verdict, the vertices that matter (locked, undecided), and with
 * verbose every vertex's own. */
static int print_mobility(const sf_scene *sc, int verbose, sf_progress *progress, sf_error *err)
{
    sf_mobility mb;
    sf_progress_phase(progress, 0, "check: mobility of the whole sheet (%d coordinates) and of its %d "
                      "interior vertices alone", sc->model.nq, sc->topo.nivertices);
    if (sf_mobility_analyse(&sc->model, NULL, &mb, err)) return err->code;
    sf_progress_phase(progress, 0, "check: writing the summary");
    const sf_study *s = &sc->study;
    const sf_topology *t = &sc->topo;
    print_mobility_verdict(sc, &mb);
    int mobile = 0, deg4 = 0, two = 0;
    for (int v = 0; v < mb.nvertices; v++) {
        mobile += mb.v[v].dof > 0;
        if (mb.v[v].dof > 0 && t->ivertices[v].degree == 4) {
            deg4++;
            two += mb.v[v].modes == 2;
        }
    }
    printf("vertices under their own loops: %d mobile, %d locked, %d undecided", mobile, mb.nlocked,
           mb.nvertices - mobile - mb.nlocked);
    /* a mobile degree-4 vertex has two folding modes (mobility.h) */
    if (deg4 > 0 && two == deg4)
        printf("; %s %d mobile of degree 4 with %s two folding modes", deg4 == 1 ? "the" : "all",
               deg4, deg4 == 1 ? "its" : "their");
    else if (deg4 > 0)
        printf("; %d of the %d mobile of degree 4 with two folding modes found", two, deg4);
    printf("%s\n", verbose ? "" : " (--verbose: each vertex)");
    if (!verbose) {
        print_vertex_group(sc, &mb, 0, "locked", 8);
        print_vertex_group(sc, &mb, -1, "undecided", 8);
    }
    for (int v = 0; verbose && v < mb.nvertices; v++) {
        const sf_mobility_vertex *mv = &mb.v[v];
        printf("  vertex %s (degree %d, %d coordinates) alone: ",
               vname(s, t->ivertices[v].vertex), t->ivertices[v].degree, mv->coords);
        print_dof(mv->dof, mv->first_order, mv->gap, mb.radius, mv->cert_kind);
        if (mv->modes > 0)
            printf(", %d folding mode%s%s", mv->modes, mv->modes == 1 ? "" : "s",
                   mv->modes == SF_MOBILITY_MODES_MAX ? " or more" : "");
        printf("\n");
    }
    sf_mobility_free(&mb);
    return SF_OK;
}

/* The interior vertices: counts by degree; with verbose each by name. */
static void print_vertices(const sf_study *s, const sf_topology *t, int verbose)
{
    printf("interior vertices: %d", t->nivertices);
    if (verbose) {
        for (int v = 0; v < t->nivertices; v++)
            printf("%s%s (degree %d)", v ? ", " : ": ", vname(s, t->ivertices[v].vertex),
                   t->ivertices[v].degree);
        printf("\n");
        return;
    }
    int maxdeg = 0;
    for (int v = 0; v < t->nivertices; v++)
        if (t->ivertices[v].degree > maxdeg) maxdeg = t->ivertices[v].degree;
    int k = 0;
    for (int d = 1; d <= maxdeg; d++) {
        int n = 0;
        for (int v = 0; v < t->nivertices; v++) n += t->ivertices[v].degree == d;
        if (n) printf("%s%d of degree %d", k++ ? ", " : " (", n, d);
    }
    printf("%s\n", k ? ")" : "");
}

int sf_cmd_check(const sf_options *o, sf_error *err)
{
    sf_scene sc;
    sf_progress_phase(o->progress, 0, "check: reading the study, building the sheet (faces, bands, model)");
    if (sf_scene_open(&sc, o->study_path, o->nset, o->sets, err)) {
        sf_scene_close(&sc);
        return err->code;
    }
    sf_cli_warn(&sc.study);
    const sf_study *s = &sc.study;
    const sf_topology *t = &sc.topo;
    const sf_model *m = &sc.model;
    printf("study: %s (%s)\n", s->name, s->path);
    printf("faces: %d\n", t->nfaces);
    int ng1 = 0, ng2 = 0, kmin = 1 << 30, kmax = 0;
    for (int i = 0; i < s->nfolds; i++) {
        if (s->folds[i].continuity == 1) ng1++; else ng2++;
        if (s->folds[i].modes < kmin) kmin = s->folds[i].modes;
        if (s->folds[i].modes > kmax) kmax = s->folds[i].modes;
    }
    if (s->nfolds == 0) kmin = 0;
    printf("folds: %d (G1 %d, G2 %d; shape modes K = %d", s->nfolds, ng1, ng2, kmin);
    if (kmax != kmin) printf("..%d", kmax);
    printf("; %d generalised coordinates)\n", m->nq);
    if (s->bending)
        printf("bending faces: %d facet hinges (folds %d..%d; docs/guides/bending-faces.md), %d setback%s of "
               "the study's folds raised to clear them\n", s->nfacets, s->nfolds - s->nfacets + 1,
               s->nfolds, s->nraised, s->nraised == 1 ? "" : "s");
    print_vertices(s, t, o->verbose);
    const sf_face *root = &t->faces[t->root];
    printf("fixed face: %d (contains (%g, %g); %d corners, area %.6g m^2)\n", t->root + 1,
           s->fixed_point[0], s->fixed_point[1], root->nverts, root->area);
    printf("constraints: %s, %d loop equations", s->constraints == SF_CONSTRAINTS_EXACT
           ? "exact (Lagrange multipliers)" : "penalty", m->ncon);
    if (s->constraints == SF_CONSTRAINTS_PENALTY)
        printf(" (lambda_R = %g J, lambda_d = %g J/m^2)", s->penalty_rotation,
               s->penalty_translation);
    printf("\n");
    printf("effects: bending");
    int nact = 0;
    for (int i = 0; i < s->nfolds; i++) nact += s->folds[i].group >= 0;
    if (s->nloads) printf(", %d point load%s", s->nloads, s->nloads > 1 ? "s" : "");
    if (s->gravity_on)
        printf(", gravity (%g, %g, %g) m/s^2 in stage %d", s->gravity[0], s->gravity[1],
               s->gravity[2], s->gravity_stage);
    if (s->ngroups) printf(", actuation of %d fold%s in %d group%s", nact, nact == 1 ? "" : "s",
                           s->ngroups, s->ngroups == 1 ? "" : "s");
    if (s->nsupports) printf(", %d support%s", s->nsupports, s->nsupports > 1 ? "s" : "");
    printf("; %d load stage%s\n", s->nstages, s->nstages > 1 ? "s" : "");
    for (int i = 0; i < s->nprobes; i++) {
        sf_mpoint p;
        if (sf_model_locate(m, s->probes[i].at, &p, err)) {
            sf_error_prefix(err, "%s:%d: probe %d", s->path, s->probes[i].line, i + 1);
            sf_scene_close(&sc);
            return err->code;
        }
        printf("probe %d: %s at (%g, %g), ", i + 1, s->probes[i].name, s->probes[i].at[0],
               s->probes[i].at[1]);
        if (p.fold >= 0) printf("on the band of fold %d\n", p.fold + 1);
        else printf("on face %d\n", p.face + 1);
    }
    if (t->nivertices > 0 && print_mobility(&sc, o->verbose, o->progress, err)) {
        sf_scene_close(&sc);
        return err->code;
    }
    printf("analysis: %s\n", s->analysis_type);
    sf_progress_phase(o->progress, 0, "check: reading the reference files");
    sf_compare *cmp = NULL;     /* reference files: read and checked here too */
    int rc = sf_compare_open(&cmp, s, err);
    if (!rc) sf_compare_print_files(cmp, stdout);
    sf_compare_free(cmp);
    sf_scene_close(&sc);
    return rc;
}

void sf_cli_warn(const sf_study *s)
{
    /* values far outside physical sense: one line each, the run goes on */
    for (int i = 0; i < s->nfolds; i++) {
        const sf_fold_def *f = &s->folds[i];
        if (fabs(f->rest_angle) > M_PI)
            fprintf(stderr, "smoothfold: warning: %s:%d: fold %d: rest_angle %g rad is beyond pi "
                    "(radians are meant; degrees?)\n", s->path, f->line, i + 1, f->rest_angle);
        if (f->width < 1e-6)
            fprintf(stderr, "smoothfold: warning: %s:%d: fold %d: width %g m is below a micrometre "
                    "(metres are meant)\n", s->path, f->line, i + 1, f->width);
    }
    for (int g = 0; g < s->ngroups; g++)
        if (fabs(s->groups[g].rest_angle) > M_PI)
            fprintf(stderr, "smoothfold: warning: %s:%d: actuation group %s: rest_angle %g rad is "
                    "beyond pi (radians are meant; degrees?)\n", s->path, s->groups[g].line,
                    s->groups[g].name, s->groups[g].rest_angle);
    for (int m = 0; m < s->nmaterials; m++) {
        const sf_material *mt = &s->materials[m];
        if (mt->E > 0 && (mt->E < 1e3 || mt->E > 1e13))
            fprintf(stderr, "smoothfold: warning: %s: material %s: E = %g Pa is outside 1 kPa .. "
                    "10 TPa (pascals are meant)\n", s->path, mt->name, mt->E);
    }
}

int sf_cli_outdir(const sf_options *o, const char *dir, sf_error *err)
{
    int removed = 0;
    if (sf_outdir_prepare(dir, o->force, &removed, err)) return err->code;
    if (removed && !o->quiet)
        fprintf(stderr, "smoothfold: note: removed %d file%s of an earlier run from %s "
                "(results, shapes, plots)\n", removed, removed == 1 ? "" : "s", dir);
    return SF_OK;
}

/* Parse --angles: one value for all folds, or one per fold. */
static int parse_angles(const char *txt, int nfolds, double *theta, sf_error *err)
{
    int n = 0;
    const char *p = txt;
    double vals[4096];
    while (*p) {
        char *end;
        errno = 0;
        double v = strtod(p, &end);
        if (end == p || errno || !isfinite(v))
            return sf_fail(err, SF_EINPUT, "--angles: cannot read a finite number at '%s'", p);
        if (n >= 4096) return sf_fail(err, SF_EINPUT, "--angles: too many values");
        vals[n++] = v;
        p = end;
        while (*p == ' ') p++;
        if (*p == ',') p++;
        else if (*p) return sf_fail(err, SF_EINPUT, "--angles: expected ',' at '%s'", p);
    }
    if (n == 1) {
        for (int i = 0; i < nfolds; i++) theta[i] = vals[0];
        return SF_OK;
    }
    if (n != nfolds)
        return sf_fail(err, SF_EINPUT, "--angles: got %d values for %d folds (give one value "
                       "or one per fold)", n, nfolds);
    for (int i = 0; i < nfolds; i++) theta[i] = vals[i];
    return SF_OK;
}

int sf_cmd_shape(const sf_options *o, sf_error *err)
{
    if (!o->output) return sf_fail(err, SF_EINPUT, "shape: give the output file with -o FILE");
    sf_scene sc;
    if (sf_scene_open(&sc, o->study_path, o->nset, o->sets, err)) {
        sf_scene_close(&sc);
        return err->code;
    }
    sf_cli_warn(&sc.study);
    const sf_model *m = &sc.model;
    double *q = calloc((size_t)m->nq + 1, sizeof(double));
    double *theta = calloc((size_t)m->nfolds + 1, sizeof(double));
    int rc = (!q || !theta) ? sf_fail(err, SF_ENOMEM, "out of memory") : SF_OK;
    if (!rc && o->angles) rc = parse_angles(o->angles, m->nfolds, theta, err);
    if (!rc) {
        for (int i = 0; i < m->nfolds; i++) q[m->qoff[i]] = theta[i];
        rc = sf_vtk_write_shape(m, q, sc.study.samples, o->output, err);
    }
    if (!rc && !o->quiet) {
        /* the shape is drawn along the face tree; say how far the vertex
         * loops are from closing for these angles */
        double *g = calloc((size_t)m->ncon + 1, sizeof(double));
        sf_kin k;
        if (g && !sf_kin_alloc(m, &k)) {
            sf_kin_eval(m, q, 0, &k);
            sf_constraints(m, &k, g, NULL, NULL, NULL, 0);
            double gr = 0, gt = 0;
            for (int c = 0; c < m->ncon; c++) {
                if (c % 6 < 3) gr = fmax(gr, fabs(g[c]));
                else gt = fmax(gt, fabs(g[c]));
            }
            printf("wrote %s (%d faces, %d folds); loop residual: rotation %.3g, "
                   "translation %.3g m\n", o->output, m->nfaces, m->nfolds, gr, gt);
            sf_kin_free(&k);
        }
        free(g);
    }
    free(q);
    free(theta);
    sf_scene_close(&sc);
    return rc;
}
