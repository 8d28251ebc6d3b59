/* cp_study.c - a crease pattern (cpattern.h) written as a commented,
 * ready-to-run study: outline from the boundary edges, folds from the M, V
 * and U edges with their assignment, automatic setbacks, actuation groups
 * "mountain" and "valley", the fixed face nearest the centroid and a probe
 * on the face farthest from it.  The written file is read back and its
 * topology built before it is put in place. */
#include "cpattern.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "outbuf.h"
#include "study.h"
#include "topology.h"
#include "vtk.h"

void sf_cp_study_opts_default(sf_cp_study_opts *o)
{
    memset(o, 0, sizeof *o);
    o->fold_angle = 1.0;
    o->modes = 1;
}

typedef struct plan {
    const sf_cpattern *cp;
    const sf_cp_study_opts *o;
    int *outline, noutline;     /* cp vertex indices, ccw, collinear fold ends dropped */
    int nfold;
    int *fold_edge;             /* fold k -> its first cp edge (assignment, angle, name) */
    int (*fold_end)[2];         /* fold k -> cp vertices [from, to] */
    double (*fold_sb)[2];       /* fold k -> setbacks [at from, at to] [m] */
    int nmerged;                /* cp edges that joined a longer fold */
    int nfacet;
    int *facet_edge;            /* facet k -> cp edge */
    double *width;              /* per cp edge: the band width (folds), 0 (outline), -1 (other) [m] */
    double (*sb)[2];            /* per cp edge [m] */
    double *rest;               /* per fold: rest angle [rad], NAN for none */
    int ngroup;
    double grest[64];           /* group rest angles [rad] */
    char gname[64][SF_NAME_MAX];
    int *group;                 /* per fold: group index or -1 */
    char (*vname)[SF_NAME_MAX]; /* per cp vertex */
    char *vused;
    double w, w_auto;           /* the band width [m]; the automatic one before fitting */
    int w_fitted;               /* 1: narrowed so that every band keeps a quarter of its fold */
    int halved;                 /* k: the automatic width halved k times to fit the faces */
    double fixed[2], probe[2];
    int modes;                  /* defaults.modes written */
    int ninterior;              /* interior vertices (fold ends off the outline) */
} plan;

static void plan_free(plan *p)
{
    free(p->outline); free(p->fold_edge); free(p->fold_end); free(p->fold_sb); free(p->facet_edge);
    free(p->width); free(p->sb); free(p->rest); free(p->group); free(p->vname); free(p->vused);
}

static int is_ident(const char *s)
{
    if (!*s || !(((*s | 32) >= 'a' && (*s | 32) <= 'z') || *s == '_')) return 0;
    for (; *s; s++)
        if (!(((*s | 32) >= 'a' && (*s | 32) <= 'z') || (*s >= '0' && *s <= '9') || *s == '_' || *s == '-'))
            return 0;
    return 1;
}

static int is_fold(const sf_cpattern *cp, const sf_cp_study_opts *o, int e)
{
    char a = cp->e[e].assign;
    return a == 'M' || a == 'V' || a == 'U' || (a == 'F' && o->include_flat);
}

static int add_group(plan *p, const char *base, double rest)
{
    for (int g = 0; g < p->ngroup; g++)
        if (fabs(p->grest[g] - rest) <= 1e-12 * fabs(rest)) return g;
    if (p->ngroup == 64) return -1;
    int same = 0;
    for (int g = 0; g < p->ngroup; g++)
        if (strncmp(p->gname[g], base, strlen(base)) == 0) same++;
    if (same) snprintf(p->gname[p->ngroup], SF_NAME_MAX, "%s%d", base, same + 1);
    else snprintf(p->gname[p->ngroup], SF_NAME_MAX, "%s", base);
    p->grest[p->ngroup] = rest;
    return p->ngroup++;
}

/* ---- folds: collinear edges through degree-2 vertices joined ------------ */

typedef struct vinc { int nfold, nbound, e[2]; } vinc;

/* can a fold pass straight through v (two collinear fold edges of one
 * assignment and angle, nothing else but facet edges)? */
static int pass_through(const sf_cpattern *cp, const vinc *vi, int v)
{
    if (vi[v].nfold != 2 || vi[v].nbound) return 0;
    const sf_cp_edge *e1 = &cp->e[vi[v].e[0]], *e2 = &cp->e[vi[v].e[1]];
    if (e1->assign != e2->assign) return 0;
    if (!(isnan(e1->angle) && isnan(e2->angle)) && !(e1->angle == e2->angle)) return 0;
    int u = e1->a == v ? e1->b : e1->a, w = e2->a == v ? e2->b : e2->a;
    const double *a = cp->v[u].x, *b = cp->v[v].x, *c = cp->v[w].x;
    double d1[2] = {b[0] - a[0], b[1] - a[1]}, d2[2] = {c[0] - b[0], c[1] - b[1]};
    double cr = d1[0] * d2[1] - d1[1] * d2[0], dt = d1[0] * d2[0] + d1[1] * d2[1];
    return dt > 0 && fabs(cr) <= 1e-9 * hypot(d1[0], d1[1]) * hypot(d2[0], d2[1]);
}

/* fold chains in the order of their first edges; a chain runs the way its
 * first edge does */
static int plan_folds(plan *p, int (*lastedge)[2], sf_error *err)
{
    const sf_cpattern *cp = p->cp;
    vinc *vi = calloc((size_t)cp->nv + 1, sizeof *vi);
    char *done = calloc((size_t)cp->ne + 1, 1);
    if (!vi || !done) { free(vi); free(done); return sf_fail(err, SF_ENOMEM, "out of memory"); }
    for (int e = 0; e < cp->ne; e++) {
        int ends[2] = {cp->e[e].a, cp->e[e].b};
        for (int k = 0; k < 2; k++) {
            vinc *x = &vi[ends[k]];
            if (cp->e[e].assign == 'B') x->nbound++;
            else if (is_fold(cp, p->o, e)) { if (x->nfold < 2) x->e[x->nfold] = e; x->nfold++; }
        }
    }
    for (int e0 = 0; e0 < cp->ne; e0++) {
        if (done[e0] || !is_fold(cp, p->o, e0)) continue;
        done[e0] = 1;
        int end[2] = {cp->e[e0].a, cp->e[e0].b}, last[2] = {e0, e0};
        for (int side = 0; side < 2; side++)   /* 0: back from a, 1: on from b */
            while (pass_through(cp, vi, end[side])) {
                int v = end[side], nx = vi[v].e[0] == last[side] ? vi[v].e[1] : vi[v].e[0];
                if (done[nx]) break;
                done[nx] = 1;
                p->nmerged++;
                last[side] = nx;
                end[side] = cp->e[nx].a == v ? cp->e[nx].b : cp->e[nx].a;
            }
        int k = p->nfold++;
        p->fold_edge[k] = e0;
        p->fold_end[k][0] = end[0];
        p->fold_end[k][1] = end[1];
        lastedge[k][0] = last[0];   /* whose setbacks the fold's ends take */
        lastedge[k][1] = last[1];
    }
    free(vi);
    free(done);
    return SF_OK;
}

/* setbacks at width w: per cp edge, then at each fold's ends */
static void plan_setbacks(plan *p, const int *loop, int nl, const int (*lastedge)[2])
{
    const sf_cpattern *cp = p->cp;
    double *wu = malloc((size_t)(cp->ne + 1) * sizeof *wu);
    if (!wu) return;
    for (int e = 0; e < cp->ne; e++)
        wu[e] = cp->e[e].assign == 'B' ? 0 : is_fold(cp, p->o, e) ? p->w / cp->unit : -1;
    sf_cp_setbacks(cp, wu, loop, nl, 1.25, 0.1, p->sb);
    free(wu);
    for (int k = 0; k < p->nfold; k++)
        for (int s = 0; s < 2; s++) {
            int e = lastedge[k][s], v = p->fold_end[k][s];
            p->fold_sb[k][s] = cp->unit * p->sb[e][cp->e[e].a == v ? 0 : 1];
        }
}

static double fold_len(const plan *p, int k)
{
    const double *a = p->cp->v[p->fold_end[k][0]].x, *b = p->cp->v[p->fold_end[k][1]].x;
    return p->cp->unit * hypot(b[0] - a[0], b[1] - a[1]);
}

/* defaults.modes: the option's K, or (o->modes < 0, import's default) the
 * smallest K >= 1, at most 3, whose fold coordinates, K + 1 a fold,
 * outnumber the loop rows, 6 at each interior vertex (MODEL.md 4), so that
 * the count leaves the sheet a motion: a sheet of degree-4 vertices, about
 * two folds a vertex, has 4 coordinates a vertex for 6 rows with K = 1 and
 * closes only where rows happen to be dependent, while a sheet of
 * degree-6 vertices keeps K = 1. */
static int plan_modes(plan *p, const int *loop, int nl, sf_error *err)
{
    const sf_cpattern *cp = p->cp;
    char *mark = calloc((size_t)cp->nv + 1, 1);   /* 1 outline, 2 counted */
    if (!mark) return sf_fail(err, SF_ENOMEM, "out of memory");
    p->ninterior = 0;
    for (int i = 0; i < nl; i++) mark[loop[i]] = 1;
    for (int k = 0; k < p->nfold; k++)
        for (int j = 0; j < 2; j++) {
            int v = p->fold_end[k][j];
            if (!mark[v]) mark[v] = 2, p->ninterior++;
        }
    free(mark);
    p->modes = p->o->modes;
    if (p->modes >= 0) return SF_OK;
    p->modes = 1;
    while (p->modes < 3 && (p->modes + 1) * p->nfold <= 6 * p->ninterior) p->modes++;
    return SF_OK;
}

static int plan_make(plan *p, const sf_cpattern *cp, const sf_cp_study_opts *o, sf_error *err)
{
    memset(p, 0, sizeof *p);
    p->cp = cp;
    p->o = o;
    int *loop, nl;
    if (sf_cp_outline(cp, &loop, &nl, NULL, err)) return err->code;
    size_t ne = (size_t)cp->ne + 1;
    p->fold_edge = malloc(ne * sizeof *p->fold_edge);
    p->fold_end = malloc(ne * sizeof *p->fold_end);
    p->fold_sb = malloc(ne * sizeof *p->fold_sb);
    p->facet_edge = malloc(ne * sizeof *p->facet_edge);
    p->width = calloc(ne, sizeof *p->width);
    p->sb = calloc(ne, sizeof *p->sb);
    p->rest = malloc(ne * sizeof *p->rest);
    p->group = malloc(ne * sizeof *p->group);
    p->vname = calloc((size_t)cp->nv + 1, sizeof *p->vname);
    p->vused = calloc((size_t)cp->nv + 1, 1);
    p->outline = malloc((size_t)nl * sizeof *p->outline);
    int (*lastedge)[2] = malloc(ne * sizeof *lastedge);
    if (!p->fold_edge || !p->fold_end || !p->fold_sb || !p->facet_edge || !p->width || !p->sb || !p->rest ||
        !p->group || !p->vname || !p->vused || !p->outline || !lastedge) {
        free(loop); free(lastedge);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    if (plan_folds(p, lastedge, err) || plan_modes(p, loop, nl, err)) {
        free(loop); free(lastedge);
        return err->code;
    }
    double lmin = INFINITY;
    for (int k = 0; k < p->nfold; k++) {
        lmin = fmin(lmin, fold_len(p, k));
        p->vused[p->fold_end[k][0]] = p->vused[p->fold_end[k][1]] = 1;
    }
    for (int e = 0; e < cp->ne; e++)
        if (cp->e[e].assign == 'F' && !o->include_flat) {
            p->facet_edge[p->nfacet++] = e;
            p->vused[cp->e[e].a] = p->vused[cp->e[e].b] = 2;   /* 2: listed, not a fold end */
        }
    if (p->nfold == 0) {
        free(loop); free(lastedge);
        return sf_fail(err, SF_EINPUT, "the crease pattern has no folds (no M, V or U edges%s)%s",
                       o->include_flat ? ", nor F" : "",
                       p->nfacet && !o->include_flat ? ": its F (flat, facet) edges become folds with --include-flat" : "");
    }
    if (o->width > 0) p->w = o->width;
    else {   /* 0.1 x the shortest fold, to 3 digits */
        char wb[40];
        snprintf(wb, sizeof wb, "%.3g", 0.1 * lmin);
        p->w = p->w_auto = strtod(wb, NULL);
    }
    plan_setbacks(p, loop, nl, (const int (*)[2])lastedge);
    if (!(o->width > 0)) {
        /* setbacks grow with the width: narrow it where a band would keep
         * less than a quarter of its fold (narrow sectors, as in a fan) */
        double fit = INFINITY;
        for (int k = 0; k < p->nfold; k++) {
            double s = p->fold_sb[k][0] + p->fold_sb[k][1];
            if (s > 0) fit = fmin(fit, p->w * 0.75 * fold_len(p, k) / s);
        }
        if (fit < p->w) {
            char wb[40];
            snprintf(wb, sizeof wb, "%.2g", fit * (1 - 1e-9));
            double w2 = strtod(wb, NULL);
            if (w2 > fit) w2 = fit;
            p->w = w2;
            p->w_fitted = 1;
            plan_setbacks(p, loop, nl, (const int (*)[2])lastedge);
        }
    }
    free(lastedge);
    for (int e = 0; e < cp->ne; e++) p->width[e] = 0;
    for (int k = 0; k < p->nfold; k++) p->width[p->fold_edge[k]] = p->w;
    /* outline: drop vertices on a straight stretch that only end folds
     * (the topology inserts them again) */
    for (int k = 0; k < nl; k++) {
        int v = loop[k], u = loop[(k + nl - 1) % nl], x = loop[(k + 1) % nl];
        const double *a = cp->v[u].x, *b = cp->v[v].x, *c = cp->v[x].x;
        double cr = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        double l = hypot(c[0] - a[0], c[1] - a[1]);
        if (fabs(cr) <= 1e-12 * l * l && p->vused[v]) continue;
        p->outline[p->noutline++] = v;
        p->vused[v] = 1;
    }
    free(loop);
    /* vertex names: the pattern's where usable and unique, else v<index+1> */
    for (int v = 0; v < cp->nv; v++) {
        const char *nm = cp->v[v].name;
        int ok = is_ident(nm) && strlen(nm) < SF_NAME_MAX;
        for (int u = 0; ok && u < v; u++)
            if (strcmp(p->vname[u], nm) == 0) ok = 0;
        if (ok) snprintf(p->vname[v], SF_NAME_MAX, "%s", nm);
        else snprintf(p->vname[v], SF_NAME_MAX, "v%d", v + 1);
    }
    /* rest angles and actuation groups */
    for (int k = 0; k < p->nfold; k++) {
        const sf_cp_edge *e = &cp->e[p->fold_edge[k]];
        p->group[k] = -1;
        p->rest[k] = NAN;
        if (e->assign != 'M' && e->assign != 'V') continue;
        double sg = e->assign == 'V' ? 1.0 : -1.0;
        double r = isfinite(e->angle) && e->angle != 0 ? e->angle * M_PI / 180 : sg * o->fold_angle;
        p->rest[k] = r;
        p->group[k] = add_group(p, e->assign == 'V' ? "valley" : "mountain", r);
        if (p->group[k] < 0)
            return sf_fail(err, SF_EINPUT, "more than 64 different fold angles: too many actuation groups");
    }
    return SF_OK;
}

static const char *real(char *b, double x) { sf_cp_real(b, 40, x); return b; }

static void emit(const plan *p, sf_outbuf *b, const char *name)
{
    const sf_cpattern *cp = p->cp;
    const sf_cp_study_opts *o = p->o;
    char r1[40], r2[40], r3[40];
    if (o->header) {
        const char *s = o->header;
        while (*s) {
            const char *nl = strchr(s, '\n');
            int len = nl ? (int)(nl - s) : (int)strlen(s);
            sf_outbuf_printf(b, "# %.*s\n", len, s);
            s += len + (nl ? 1 : 0);
        }
    }
    sf_outbuf_printf(b, "#\n# Folds: mountain (assignment \"M\") and valley (\"V\") by FOLD's sign\n"
                     "# convention, valley positive (docs/reference/study-keys.md).  Setbacks were sized\n"
                     "# so that no two bands overlap (1.25 x the distance at which their edges\n"
                     "# meet, at least 0.1 x the width); change width and setbacks together.\n"
                     "# SI units: m, N, Pa, kg/m^3, rad.\n\n");
    sf_outbuf_printf(b, "name = \"%s\";\n", name);
    if (cp->description[0]) sf_outbuf_printf(b, "description = \"%s\";\n", cp->description);
    sf_outbuf_printf(b, "\nvertices = {\n");
    for (int v = 0; v < cp->nv; v++)
        if (p->vused[v])
            sf_outbuf_printf(b, "  %s = [%s, %s];\n", p->vname[v], real(r1, cp->unit * cp->v[v].x[0]),
                             real(r2, cp->unit * cp->v[v].x[1]));
    sf_outbuf_printf(b, "};\n\nsheet = { outline = [");
    for (int k = 0; k < p->noutline; k++)
        sf_outbuf_printf(b, "%s\"%s\"", k ? ", " : "", p->vname[p->outline[k]]);
    sf_outbuf_printf(b, "]; };\n\n");
    int nflat = p->nfacet;   /* F edges not made folds: facet edges of bending faces */
    int plate = o->bending || nflat;
    sf_outbuf_printf(b, "materials = {\n"
                     "  fold = { E = 15.2e6; nu = 0.45; thickness = 1.8e-3; density = 1200.0; };\n"
                     "  face = { %sthickness = 2.0e-3; density = 1040.0; };\n"
                     "};\n", plate ? "E = 2.0e9; nu = 0.3; " : "");
    if (!plate) {
        sf_outbuf_printf(b, "faces = { material = \"face\"; };\n\n");
    } else {
        if (nflat)
            sf_outbuf_printf(b, "# The pattern's flat (F) edges are the facet edges of its faces: with\n"
                             "# bending = true the faces bend along them (docs/guides/bending-faces.md).\n");
        else
            sf_outbuf_printf(b, "# This pattern folds only if its faces bend (docs/guides/bending-faces.md).\n");
        sf_outbuf_printf(b, "faces = {\n  material = \"face\";\n  bending = %s;\n", o->bending ? "true" : "false");
        if (nflat) {
            sf_outbuf_printf(b, "  facets = [");
            for (int k = 0; k < p->nfacet; k++) {
                const sf_cp_edge *ed = &cp->e[p->facet_edge[k]];
                sf_outbuf_printf(b, "%s\"%s %s\"", k ? ", " : "", p->vname[ed->a], p->vname[ed->b]);
            }
            sf_outbuf_printf(b, "];\n");
        }
        sf_outbuf_printf(b, "};\n\n");
    }
    if (p->halved)
        sf_outbuf_printf(b, "# The band width is the automatic one halved %d time%s: wider bands did not fit\n"
                         "# the faces (their bodies between the bands would be empty, or bands overlap).\n",
                         p->halved, p->halved == 1 ? "" : "s");
    else if (p->w_fitted)
        sf_outbuf_printf(b, "# The band width is narrower than 0.1 x the shortest fold (%s m) so that\n"
                         "# every band keeps at least a quarter of its fold between its setbacks.\n",
                         real(r1, p->w_auto));
    if (o->modes < 0 && p->modes > 1)
        sf_outbuf_printf(b, "# K = %d shape modes: with K = %d the %d folds' %d coordinates would not exceed\n"
                         "# the 6 loop rows of each of the %d interior vertices (%d rows).\n", p->modes,
                         p->modes - 1, p->nfold, p->modes * p->nfold, p->ninterior, 6 * p->ninterior);
    sf_outbuf_printf(b, "defaults = {\n  width = %s;   # band width of every fold\n"
                     "  continuity = 1;\n  modes = %d;\n  material = \"fold\";\n};\n\n",
                     real(r1, p->w), p->modes);
    if (p->ngroup) {
        sf_outbuf_printf(b, "# Actuation: the rest angle of each group's folds at actuation parameter 1.\n"
                         "actuation = (\n");
        for (int g = 0; g < p->ngroup; g++)
            sf_outbuf_printf(b, "  { name = \"%s\"; rest_angle = %s; }%s   # %.6g degrees\n", p->gname[g],
                             real(r1, p->grest[g]), g + 1 < p->ngroup ? "," : "",
                             p->grest[g] * 180 / M_PI);
        sf_outbuf_printf(b, ");\n\n");
    }
    sf_outbuf_printf(b, "folds = (\n");
    for (int k = 0; k < p->nfold; k++) {
        const sf_cp_edge *ed = &cp->e[p->fold_edge[k]];
        sf_outbuf_printf(b, "  { ");
        if (ed->name[0] && is_ident(ed->name)) sf_outbuf_printf(b, "name = \"%s\"; ", ed->name);
        sf_outbuf_printf(b, "from = \"%s\"; to = \"%s\";", p->vname[p->fold_end[k][0]],
                         p->vname[p->fold_end[k][1]]);
        if (ed->assign == 'M' || ed->assign == 'V')
            sf_outbuf_printf(b, " assignment = \"%c\"; group = \"%s\";", ed->assign, p->gname[p->group[k]]);
        if (!o->setback_given)
            sf_outbuf_printf(b, " setback = [%.4g, %.4g];", p->fold_sb[k][0], p->fold_sb[k][1]);
        sf_outbuf_printf(b, " }%s%s\n", k + 1 < p->nfold ? "," : "",
                         ed->assign == 'U' ? "   # unassigned" : ed->assign == 'F' ? "   # flat" : "");
    }
    sf_outbuf_printf(b, ");\n\n");
    sf_outbuf_printf(b, "fixed_face = [%s, %s];   # the face nearest the centroid\n\n",
                     real(r1, p->fixed[0]), real(r2, p->fixed[1]));
    sf_outbuf_printf(b, "probes = ( { name = \"tip\"; at = [%s, %s]; } );   # the face farthest from the fixed one\n\n",
                     real(r1, p->probe[0]), real(r2, p->probe[1]));
    int nstage = 0;
    if (o->gravity) {
        nstage++;
        sf_outbuf_printf(b, "gravity = { g = [0.0, 0.0, -9.81]; stage = 1; };\n\n");
    }
    if (o->load != 0) {
        nstage++;
        sf_outbuf_printf(b, "loads = ( { at = [%s, %s]; force = [0.0, 0.0, %s]; stage = %d; } );\n\n",
                         real(r1, p->probe[0]), real(r2, p->probe[1]), real(r3, -o->load), nstage);
    }
    sf_outbuf_printf(b, "solver = { constraints = \"exact\"; tolerance = 1e-10; };\n"
                     "output = { samples = 8; shapes = 10; };\n\n");
    if (nstage)
        sf_outbuf_printf(b, "analysis = {\n  type = \"equilibrium\";\n  parameter = \"load\";   # %s\n"
                         "  end = %d.0;\n  step = 0.05;\n  max_step = 0.1;\n  report = \"tip\";\n};\n",
                         nstage == 2 ? "stage 1 gravity, stage 2 the point load" : o->gravity ? "gravity" : "the point load",
                         nstage);
    else if (p->ngroup) {
        if (o->drive)
            sf_outbuf_printf(b, "analysis = {\n  type = \"equilibrium\";\n"
                             "  parameter = \"actuation\";   # the rest angle of group '%s' from 0 to its rest_angle\n"
                             "  group = \"%s\";\n", o->drive, o->drive);
        else
            sf_outbuf_printf(b, "analysis = {\n  type = \"equilibrium\";\n"
                             "  parameter = \"actuation\";   # every group's rest angle from 0 to its rest_angle\n");
        if (o->fold_percent > 0)
            sf_outbuf_printf(b, "  end = %s;   # --fold-percent %g (Origami Simulator's): p = 1 is the full target angle\n",
                             real(r1, o->fold_percent / 100), o->fold_percent);
        else
            sf_outbuf_printf(b, "  end = 1.0;\n");
        sf_outbuf_printf(b, "  step = 0.05;\n  max_step = 0.1;\n  report = \"tip\";\n};\n");
    }
    else
        sf_outbuf_printf(b, "analysis = { type = \"none\"; };   # no assigned folds to actuate: add loads\n");
}

static int write_text(const char *path, sf_outbuf *b, sf_error *err)
{
    FILE *f = fopen(path, "w");
    if (!f) return sf_fail(err, SF_EIO, "%s: cannot write: %s", path, strerror(errno));
    size_t n = fwrite(b->s, 1, b->n, f);
    int bad = n != b->n;
    if (fclose(f) != 0) bad = 1;
    if (bad) { remove(path); return sf_fail(err, SF_EIO, "%s: cannot write: %s", path, strerror(errno)); }
    return SF_OK;
}

/* first pass: the fixed face (nearest the centroid) and the probe (on the
 * face farthest from it), from the topology of the written study */
static int choose_faces(plan *p, const char *tmp, sf_error *err)
{
    sf_study s;
    sf_topology t;
    memset(&t, 0, sizeof t);
    int rc = sf_study_load(tmp, 0, NULL, &s, err);
    if (!rc) rc = sf_topology_build(&s, &t, err);
    if (rc) { sf_study_free(&s); sf_topology_free(&t); return rc; }
    double c[2] = {0, 0}, A = 0;
    for (int f = 0; f < t.nfaces; f++) {
        A += t.faces[f].area;
        c[0] += t.faces[f].area * t.faces[f].centroid[0];
        c[1] += t.faces[f].area * t.faces[f].centroid[1];
    }
    c[0] /= A; c[1] /= A;
    int best = -1;
    double dbest = INFINITY;
    for (int f = 0; f < t.nfaces; f++) {
        const sf_face *fc = &t.faces[f];
        if (!sf_polygon_contains(&fc->body, fc->centroid, 0)) continue;
        double d = hypot(fc->centroid[0] - c[0], fc->centroid[1] - c[1]);
        if (d < dbest - 1e-12 * t.size) { dbest = d; best = f; }
    }
    if (best < 0) best = 0;
    if (!p->o->fixed_given) { p->fixed[0] = t.faces[best].centroid[0]; p->fixed[1] = t.faces[best].centroid[1]; }
    int far = best;
    double dfar = -1;
    for (int f = 0; f < t.nfaces; f++) {
        const sf_face *fc = &t.faces[f];
        if (!sf_polygon_contains(&fc->body, fc->centroid, 0)) continue;
        double d = hypot(fc->centroid[0] - p->fixed[0], fc->centroid[1] - p->fixed[1]);
        if (d > dfar + 1e-12 * t.size) { dfar = d; far = f; }
    }
    p->probe[0] = t.faces[far].centroid[0];
    p->probe[1] = t.faces[far].centroid[1];
    sf_topology_free(&t);
    sf_study_free(&s);
    return SF_OK;
}

static int sizing_failed(const char *msg)
{
    return strstr(msg, "leave no band") || strstr(msg, "overlap") || strstr(msg, "too wide");
}

static int write_once(const sf_cpattern *cp, const sf_cp_study_opts *o, int halved, double *w_out,
                      const char *path, int nset, const char *const *sets, sf_error *err);

int sf_cp_write_study(const sf_cpattern *cp, const sf_cp_study_opts *o,
                      const char *path, int nset, const char *const *sets,
                      sf_error *err)
{
    double w = 0;
    int rc = write_once(cp, o, 0, &w, path, nset, sets, err);
    if (!rc || o->width > 0 || !sizing_failed(err->msg)) return rc;
    /* the automatic width does not fit the faces (the setbacks only see the
     * vertices): the largest of w/2, w/4, ... w/16 whose bands fit */
    sf_error first = *err;
    sf_cp_study_opts o2 = *o;
    double w2;
    for (int k = 1; k <= 4 && rc && sizing_failed(err->msg); k++) {
        char wb[40];
        snprintf(wb, sizeof wb, "%.2g", w / (1 << k));
        o2.width = strtod(wb, NULL);
        sf_error_clear(err);
        rc = write_once(cp, &o2, k, &w2, path, nset, sets, err);
    }
    if (rc) {
        char wb[40];
        snprintf(wb, sizeof wb, "%.2g", w / 16);
        *err = first;
        size_t l = strlen(err->msg);
        snprintf(err->msg + l, sizeof err->msg - l, " (halving it down to %s m did not fit either)", wb);
    }
    return rc;
}

static int write_once(const sf_cpattern *cp, const sf_cp_study_opts *o, int halved, double *w_out,
                      const char *path, int nset, const char *const *sets, sf_error *err)
{
    plan p;
    int rc = plan_make(&p, cp, o, err);
    if (rc) { plan_free(&p); return rc; }
    p.halved = halved;
    *w_out = p.w;
    const char *name = o->name ? o->name : cp->title[0] ? cp->title : "pattern";
    char tmp[1100];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    /* a point just inside the first outline edge for the first pass */
    {
        const double *a = cp->v[p.outline[0]].x, *bb = cp->v[p.outline[1]].x;
        double d[2] = {bb[0] - a[0], bb[1] - a[1]}, l = hypot(d[0], d[1]);
        p.fixed[0] = cp->unit * (0.5 * (a[0] + bb[0]) - 1e-3 * d[1] / l * l);
        p.fixed[1] = cp->unit * (0.5 * (a[1] + bb[1]) + 1e-3 * d[0] / l * l);
        if (o->fixed_given) { p.fixed[0] = o->fixed[0]; p.fixed[1] = o->fixed[1]; }
        p.probe[0] = p.fixed[0]; p.probe[1] = p.fixed[1];
    }
    sf_outbuf b = {0};
    for (int pass = 0; pass < 2 && !rc; pass++) {
        b.n = 0;
        emit(&p, &b, name);
        if (b.oom) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); break; }
        rc = write_text(tmp, &b, err);
        if (!rc && pass == 0) rc = choose_faces(&p, tmp, err);
    }
    sf_outbuf_free(&b);
    if (!rc) {   /* the final check, with the overrides */
        sf_study s;
        sf_topology t;
        memset(&t, 0, sizeof t);
        rc = sf_study_load(tmp, nset, (const char **)sets, &s, err);
        if (!rc) rc = sf_topology_build(&s, &t, err);
        if (!rc && nset > 0) {
            char hdr[600];
            snprintf(hdr, sizeof hdr, "%s\n(written with --set overrides: the merged study)",
                     o->header ? o->header : name);
            rc = sf_study_write(&s, path, hdr, err);
        } else if (!rc && rename(tmp, path) != 0) {
            rc = sf_fail(err, SF_EIO, "%s: cannot write: %s", path, strerror(errno));
        }
        sf_topology_free(&t);
        sf_study_free(&s);
    }
    if (rc) {
        /* a message about the temporary file names no file: it is removed */
        char *at = strstr(err->msg, tmp);
        if (at) {
            char rest[SF_MSG_SIZE];
            const char *r = at + strlen(tmp);
            int line = 0, used = 0;
            if (sscanf(r, ":%d%n", &line, &used) == 1) r += used;
            snprintf(rest, sizeof rest, "%s", r);
            if (line)
                snprintf(at, sizeof err->msg - (size_t)(at - err->msg), "the generated study (line %d; %s not written)%s",
                         line, path, rest);
            else
                snprintf(at, sizeof err->msg - (size_t)(at - err->msg), "the generated study (%s not written)%s", path, rest);
        }
        /* the bands do not fit: a narrower width is what to try */
        if (strstr(err->msg, "leave no band") || strstr(err->msg, "overlap") || strstr(err->msg, "setback")) {
            char w1[40], w2[40];
            sf_cp_real(w1, sizeof w1, p.w);
            snprintf(w2, sizeof w2, "%.2g", 0.5 * p.w);
            size_t l = strlen(err->msg);
            snprintf(err->msg + l, sizeof err->msg - l, "; the band width was %s m: try a narrower one, "
                     "--set defaults.width=%s", w1, w2);
        }
    }
    remove(tmp);
    plan_free(&p);
    return rc;
}
