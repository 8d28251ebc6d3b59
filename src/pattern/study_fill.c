/* study_fill.c - the semantic pass of the study reader (study_impl.h):
 * names resolved (vertices, materials, groups, probes), references and
 * geometry checked, the plain sf_study of pattern.h filled. */
#include "study_impl.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Numbers of a default text "[0.0, 1.0]" / "24" / "true". */
int st_parse_def(const char *def, double *out, int max)
{
    int n = 0;
    const char *p = def;
    while (*p && n < max) {
        while (*p && (*p == '[' || *p == ']' || *p == ',' || isspace((unsigned char)*p))) p++;
        if (!*p) break;
        if (strncmp(p, "true", 4) == 0) { out[n++] = 1; p += 4; continue; }
        if (strncmp(p, "false", 5) == 0) { out[n++] = 0; p += 5; continue; }
        char *e;
        double v = strtod(p, &e);
        if (e == p) break;
        out[n++] = v;
        p = e;
    }
    return n;
}

static double def_num(const char *pattern)
{
    const sf_study_key *k = st_schema_find(pattern);
    double v = 0;
    if (k && k->def) st_parse_def(k->def, &v, 1);
    return v;
}

/* Value of key in g, or of the same key in dflt (a group of defaults),
 * else the schema default of dpattern.  which (if non-NULL) receives the
 * setting used (NULL for a schema default). */
static double get_num(const config_setting_t *g, const config_setting_t *dflt,
                      const char *key, const char *dpattern,
                      const config_setting_t **which)
{
    const config_setting_t *m = st_mem(g, key);
    if (!m) m = st_mem(dflt, key);
    if (which) *which = m;
    if (m) return st_numval(m);
    return def_num(dpattern);
}

static void get_vec(const config_setting_t *g, const config_setting_t *dflt,
                    const char *key, const char *dpattern, double *out,
                    int n)
{
    const config_setting_t *m = st_mem(g, key);
    if (!m) m = st_mem(dflt, key);
    for (int i = 0; i < n; i++) out[i] = 0;
    if (m) {
        for (int i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(m, (unsigned)i);
            out[i] = e->type == CONFIG_TYPE_BOOL ? (double)e->value.ival : st_numval(e);
        }
    } else {
        const sf_study_key *k = st_schema_find(dpattern);
        if (k && k->def) st_parse_def(k->def, out, n);
    }
}

const char *st_get_str(const config_setting_t *g, const char *key,
                       const char *dpattern)
{
    const config_setting_t *m = st_mem(g, key);
    if (m) return m->value.sval;
    const sf_study_key *k = st_schema_find(dpattern);
    return k && k->def ? k->def : NULL;
}

static int get_bool(const config_setting_t *g, const char *key,
                    const char *dpattern)
{
    const config_setting_t *m = st_mem(g, key);
    if (m) return m->value.ival;
    return def_num(dpattern) != 0;
}

int st_find_name(const char *name, const void *base, size_t stride, int n)
{
    for (int i = 0; i < n; i++) {
        const char *nm = (const char *)base + (size_t)i * stride;
        if (strcmp(nm, name) == 0) return i;
    }
    return -1;
}

/* Suggestion among n names laid out with stride. */
static const char *suggest_in(const char *word, const void *base,
                              size_t stride, int n)
{
    const char **cand = malloc((size_t)(n > 0 ? n : 1) * sizeof *cand);
    if (!cand) return NULL;
    for (int i = 0; i < n; i++) cand[i] = (const char *)base + (size_t)i * stride;
    const char *r = sf_study_suggest(word, n, cand);
    free(cand);
    return r;
}

#define VIDX(nm) st_find_name((nm), s->vertices[0].name, sizeof(sf_vertex), s->nvertices)
#define VSUG(nm) suggest_in((nm), s->vertices[0].name, sizeof(sf_vertex), s->nvertices)
#define MIDX(nm) st_find_name((nm), s->materials[0].name, sizeof(sf_material), s->nmaterials)
#define MSUG(nm) suggest_in((nm), s->materials[0].name, sizeof(sf_material), s->nmaterials)

/* Vertices and the outline. */
static int fill_vertices(sf_study *s, const config_setting_t *root, sf_error *err)
{
    char h[200];
    /* vertices */
    const config_setting_t *vs = st_mem(root, "vertices");
    int nv = config_setting_length(vs);
    if (nv == 0) return st_bad(s, err, vs, "no vertices");
    s->vertices = calloc((size_t)nv, sizeof *s->vertices);
    if (!s->vertices) return sf_fail(err, SF_ENOMEM, "out of memory");
    s->nvertices = nv;
    for (int i = 0; i < nv; i++) {
        const config_setting_t *e = config_setting_get_elem(vs, (unsigned)i);
        st_copy_name(s->vertices[i].name, e->name);
        s->vertices[i].x[0] = st_numval(config_setting_get_elem(e, 0));
        s->vertices[i].x[1] = st_numval(config_setting_get_elem(e, 1));
        s->vertices[i].line = (int)e->line;
    }

    /* outline */
    const config_setting_t *ol = st_mem(st_mem(root, "sheet"), "outline");
    int no = config_setting_length(ol);
    if (no < 3) return st_bad(s, err, ol, "needs at least 3 vertices (got %d)", no);
    s->outline = calloc((size_t)no, sizeof *s->outline);
    if (!s->outline) return sf_fail(err, SF_ENOMEM, "out of memory");
    s->noutline = no;
    for (int i = 0; i < no; i++) {
        const config_setting_t *e = config_setting_get_elem(ol, (unsigned)i);
        int k = VIDX(e->value.sval);
        if (k < 0)
            return st_bad(s, err, e, "unknown vertex '%s'%s", e->value.sval, st_hint(h, sizeof h, VSUG(e->value.sval)));
        for (int j = 0; j < i; j++)
            if (s->outline[j] == k)
                return st_bad(s, err, e, "vertex '%s' appears twice in the outline", e->value.sval);
        s->outline[i] = k;
    }
    return SF_OK;
}

/* Materials and the faces' material. */
static int fill_materials(sf_study *s, const config_setting_t *root, sf_error *err)
{
    char h[200];
    /* materials */
    const config_setting_t *ms = st_mem(root, "materials");
    int nm = config_setting_length(ms);
    if (nm == 0) return st_bad(s, err, ms, "no materials");
    s->materials = calloc((size_t)nm, sizeof *s->materials);
    if (!s->materials) return sf_fail(err, SF_ENOMEM, "out of memory");
    s->nmaterials = nm;
    for (int i = 0; i < nm; i++) {
        const config_setting_t *e = config_setting_get_elem(ms, (unsigned)i);
        sf_material *m = &s->materials[i];
        st_copy_name(m->name, e->name);
        m->E = st_mem(e, "E") ? st_numval(st_mem(e, "E")) : 0.0;
        m->nu = st_mem(e, "nu") ? st_numval(st_mem(e, "nu")) : 0.0;
        m->thickness = st_numval(st_mem(e, "thickness"));
        m->density = st_mem(e, "density") ? st_numval(st_mem(e, "density")) : 0.0;
    }

    /* faces */
    s->face_material = -1;
    const config_setting_t *fm = st_mem(st_mem(root, "faces"), "material");
    if (fm) {
        s->face_material = MIDX(fm->value.sval);
        if (s->face_material < 0)
            return st_bad(s, err, fm, "unknown material '%s'%s", fm->value.sval, st_hint(h, sizeof h, MSUG(fm->value.sval)));
    }
    /* bending faces: the facet hinges' stiffness needs the plate's E, nu */
    const config_setting_t *fc = st_mem(root, "faces");
    s->bending = fc && get_bool(fc, "bending", "faces.bending");
    s->bending_coefficient = get_num(fc, NULL, "bending_coefficient", "faces.bending_coefficient", NULL);
    s->facet_width = get_num(fc, NULL, "facet_width", "faces.facet_width", NULL);
    if (s->bending) {
        const config_setting_t *mse = st_mem(ms, fm->value.sval);
        if (!st_mem(mse, "E"))
            return st_bad(s, err, mse, "missing E (required because faces.bending is on and the faces use this material)");
        if (!st_mem(mse, "nu"))
            return st_bad(s, err, mse, "missing nu (required because faces.bending is on and the faces use this material)");
    }
    return SF_OK;
}

/* Actuation groups. */
static int fill_groups(sf_study *s, const config_setting_t *root, sf_error *err)
{
    /* actuation groups */
    const config_setting_t *as = st_mem(root, "actuation");
    int ng = as ? config_setting_length(as) : 0;
    if (ng) {
        s->groups = calloc((size_t)ng, sizeof *s->groups);
        if (!s->groups) return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int i = 0; i < ng; i++) {
        const config_setting_t *e = config_setting_get_elem(as, (unsigned)i);
        const config_setting_t *n = st_mem(e, "name");
        if (st_find_name(n->value.sval, s->groups[0].name, sizeof(sf_group), i) >= 0)
            return st_bad(s, err, n, "group '%s' is defined twice", n->value.sval);
        st_copy_name(s->groups[i].name, n->value.sval);
        s->groups[i].rest_angle = st_numval(st_mem(e, "rest_angle"));
        s->groups[i].line = (int)e->line;
        s->ngroups = i + 1;
    }
    return SF_OK;
}

/* The vertex names sorted, for the folds' ends: a search of O(log n)
 * each instead of a linear one (thousands of folds on large sheets). */
typedef struct vname { const char *name; int index; } vname;

static int vname_cmp(const void *a, const void *b)
{
    const vname *x = a, *y = b;
    int c = strcmp(x->name, y->name);
    return c ? c : (x->index > y->index) - (x->index < y->index);
}

/* The first vertex named name (as st_find_name), -1 when none. */
static int vname_find(const vname *v, int n, const char *name)
{
    int lo = 0, hi = n;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (strcmp(v[mid].name, name) < 0) lo = mid + 1;
        else hi = mid;
    }
    return lo < n && strcmp(v[lo].name, name) == 0 ? v[lo].index : -1;
}

static int fill_fold_list(sf_study *s, const config_setting_t *root, const vname *vn,
                           sf_error *err);

/* Folds: ends, name, width and the other defaults, material, group. */
static int fill_folds(sf_study *s, const config_setting_t *root, sf_error *err)
{
    int nv = s->nvertices;
    vname *vn = malloc(sizeof(vname) * (size_t)(nv ? nv : 1));
    if (!vn) return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int v = 0; v < nv; v++) {
        vn[v].name = s->vertices[v].name;
        vn[v].index = v;
    }
    qsort(vn, (size_t)nv, sizeof(vname), vname_cmp);
    int rc = fill_fold_list(s, root, vn, err);
    free(vn);
    return rc;
}

static int fill_fold_list(sf_study *s, const config_setting_t *root, const vname *vn,
                           sf_error *err)
{
    char h[200];
    const config_setting_t *ms = st_mem(root, "materials");
    /* folds */
    const config_setting_t *dft = st_mem(root, "defaults");
    const config_setting_t *fs = st_mem(root, "folds");
    int nf = config_setting_length(fs);
    if (nf == 0) return st_bad(s, err, fs, "no folds");
    s->folds = calloc((size_t)nf, sizeof *s->folds);
    if (!s->folds) return sf_fail(err, SF_ENOMEM, "out of memory");
    s->nfolds = nf;
    for (int i = 0; i < nf; i++) {
        const config_setting_t *e = config_setting_get_elem(fs, (unsigned)i);
        sf_fold_def *f = &s->folds[i];
        f->line = (int)e->line;
        const config_setting_t *from = st_mem(e, "from"), *to = st_mem(e, "to");
        f->a = vname_find(vn, s->nvertices, from->value.sval);
        if (f->a < 0)
            return st_bad(s, err, from, "unknown vertex '%s'%s", from->value.sval, st_hint(h, sizeof h, VSUG(from->value.sval)));
        f->b = vname_find(vn, s->nvertices, to->value.sval);
        if (f->b < 0)
            return st_bad(s, err, to, "unknown vertex '%s'%s", to->value.sval, st_hint(h, sizeof h, VSUG(to->value.sval)));
        if (f->a == f->b)
            return st_bad2(s, err, to->hook ? to : from->hook ? from : e, e,
                        "from and to are the same vertex '%s'", from->value.sval);
        const config_setting_t *nmset = st_mem(e, "name");
        if (nmset) {
            if (st_find_name(nmset->value.sval, s->folds[0].name, sizeof(sf_fold_def), i) >= 0)
                return st_bad(s, err, nmset, "fold name '%s' is used twice", nmset->value.sval);
            st_copy_name(f->name, nmset->value.sval);
        }
        const config_setting_t *wset;
        f->width = get_num(e, dft, "width", "defaults.width", &wset);
        if (!wset)
            return st_bad(s, err, e, "no width (give width here or defaults.width)");
        get_vec(e, dft, "setback", "defaults.setback", f->setback, 2);
        f->continuity = (int)get_num(e, dft, "continuity", "defaults.continuity", NULL);
        f->modes = (int)get_num(e, dft, "modes", "defaults.modes", NULL);
        f->rest_angle = get_num(e, dft, "rest_angle", "defaults.rest_angle", NULL);
        /* material */
        const config_setting_t *mset = st_mem(e, "material");
        if (!mset) mset = st_mem(dft, "material");
        const char *mname = mset ? mset->value.sval : "fold";
        f->material = MIDX(mname);
        if (f->material < 0) {
            if (mset)
                return st_bad(s, err, mset, "unknown material '%s'%s", mname, st_hint(h, sizeof h, MSUG(mname)));
            return st_bad(s, err, e, "no material given and no material named 'fold' (set defaults.material or material here)");
        }
        const config_setting_t *mse = st_mem(ms, mname);
        if (!st_mem(mse, "E"))
            return st_bad(s, err, mse, "missing E (required because folds[%d] uses this material)", i);
        if (!st_mem(mse, "nu"))
            return st_bad(s, err, mse, "missing nu (required because folds[%d] uses this material)", i);
        /* group */
        f->group = -1;
        const config_setting_t *gset = st_mem(e, "group");
        if (gset) {
            f->group = st_find_name(gset->value.sval, s->groups ? s->groups[0].name : "", sizeof(sf_group), s->ngroups);
            if (f->group < 0) {
                const char *sg = s->ngroups ? suggest_in(gset->value.sval, s->groups[0].name, sizeof(sf_group), s->ngroups) : NULL;
                return st_bad(s, err, gset, "unknown group '%s'%s%s", gset->value.sval, st_hint(h, sizeof h, sg),
                           s->ngroups ? "" : " (no actuation groups are defined)");
            }
        }
    }
    return SF_OK;
}

/* Loads, gravity and load stages (1, 2, ... without gaps). */
static int fill_loads(sf_study *s, const config_setting_t *root, sf_error *err)
{
    /* loads and stages */
    const config_setting_t *ls = st_mem(root, "loads");
    int nl = ls ? config_setting_length(ls) : 0;
    if (nl) {
        s->loads = calloc((size_t)nl, sizeof *s->loads);
        if (!s->loads) return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    s->nloads = nl;
    int maxstage = 1;
    for (int i = 0; i < nl; i++) {
        const config_setting_t *e = config_setting_get_elem(ls, (unsigned)i);
        sf_point_load *L = &s->loads[i];
        get_vec(e, NULL, "at", "", L->at, 2);
        get_vec(e, NULL, "force", "", L->force, 3);
        L->stage = (int)get_num(e, NULL, "stage", "loads[].stage", NULL);
        L->line = (int)e->line;
        if (L->stage > maxstage) maxstage = L->stage;
    }
    const config_setting_t *gr = st_mem(root, "gravity");
    if (gr && get_bool(gr, "enabled", "gravity.enabled")) {
        s->gravity_on = 1;
        get_vec(gr, NULL, "g", "", s->gravity, 3);
        s->gravity_stage = (int)get_num(gr, NULL, "stage", "gravity.stage", NULL);
        if (s->gravity_stage > maxstage) maxstage = s->gravity_stage;
    } else {
        s->gravity_stage = 1;
    }
    s->nstages = maxstage;
    for (int k = 1; k < maxstage; k++) {
        int used = s->gravity_on && s->gravity_stage == k;
        for (int i = 0; i < nl; i++) used |= s->loads[i].stage == k;
        if (used) continue;
        /* blame the first thing in a later stage */
        const config_setting_t *blame = NULL;
        for (int i = 0; i < nl && !blame; i++)
            if (s->loads[i].stage > k)
                blame = st_mem(config_setting_get_elem(ls, (unsigned)i), "stage");
        if (!blame) blame = st_mem(gr, "stage");
        return st_bad(s, err, blame, "stage %d has no loads (stages must be 1, 2, ... without gaps)", k);
    }
    return SF_OK;
}

/* Supports. */
static int fill_supports(sf_study *s, const config_setting_t *root, sf_error *err)
{
    /* supports */
    const config_setting_t *sp = st_mem(root, "supports");
    int ns = sp ? config_setting_length(sp) : 0;
    if (ns) {
        s->supports = calloc((size_t)ns, sizeof *s->supports);
        if (!s->supports) return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    s->nsupports = ns;
    for (int i = 0; i < ns; i++) {
        const config_setting_t *e = config_setting_get_elem(sp, (unsigned)i);
        sf_support *S = &s->supports[i];
        double fix[3];
        get_vec(e, NULL, "at", "", S->at, 2);
        get_vec(e, NULL, "fix", "supports[].fix", fix, 3);
        get_vec(e, NULL, "value", "supports[].value", S->value, 3);
        for (int d = 0; d < 3; d++) S->dof[d] = fix[d] != 0;
        S->line = (int)e->line;
        if (!S->dof[0] && !S->dof[1] && !S->dof[2])
            return st_bad(s, err, st_mem(e, "fix"), "fixes nothing (at least one component must be true)");
    }
    return SF_OK;
}

/* Probes. */
static int fill_probes(sf_study *s, const config_setting_t *root, sf_error *err)
{
    /* probes */
    const config_setting_t *ps = st_mem(root, "probes");
    int np = ps ? config_setting_length(ps) : 0;
    if (np) {
        s->probes = calloc((size_t)np, sizeof *s->probes);
        if (!s->probes) return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int i = 0; i < np; i++) {
        const config_setting_t *e = config_setting_get_elem(ps, (unsigned)i);
        const config_setting_t *n = st_mem(e, "name");
        if (st_find_name(n->value.sval, s->probes[0].name, sizeof(sf_probe), i) >= 0)
            return st_bad(s, err, n, "probe name '%s' is used twice", n->value.sval);
        st_copy_name(s->probes[i].name, n->value.sval);
        get_vec(e, NULL, "at", "", s->probes[i].at, 2);
        s->probes[i].line = (int)e->line;
        s->nprobes = i + 1;
    }
    return SF_OK;
}

/* The fixed face, solver and output settings. */
static void fill_settings(sf_study *s, const config_setting_t *root)
{
    /* fixed face */
    const config_setting_t *ff = st_mem(root, "fixed_face");
    get_vec(root, NULL, "fixed_face", "", s->fixed_point, 2);
    s->fixed_line = (int)ff->line;

    /* solver, output */
    const config_setting_t *so = st_mem(root, "solver");
    const char *cons = st_get_str(so, "constraints", "solver.constraints");
    s->constraints = strcmp(cons, "penalty") == 0 ? SF_CONSTRAINTS_PENALTY : SF_CONSTRAINTS_EXACT;
    s->penalty_rotation = get_num(so, NULL, "penalty_rotation", "solver.penalty_rotation", NULL);
    s->penalty_translation = get_num(so, NULL, "penalty_translation", "solver.penalty_translation", NULL);
    s->quadrature = (int)get_num(so, NULL, "quadrature", "solver.quadrature", NULL);
    s->tolerance = get_num(so, NULL, "tolerance", "solver.tolerance", NULL);
    const config_setting_t *ou = st_mem(root, "output");
    s->samples = (int)get_num(ou, NULL, "samples", "output.samples", NULL);
    s->shapes = (int)get_num(ou, NULL, "shapes", "output.shapes", NULL);
}

/* The analysis plan, and densities where mass matters. */
static int fill_analysis(sf_study *s, const config_setting_t *root, sf_error *err)
{
    char h[200];
    const config_setting_t *ms = st_mem(root, "materials");
    const config_setting_t *gr = st_mem(root, "gravity");
    /* analysis */
    const config_setting_t *an = st_mem(root, "analysis");
    const char *type = st_get_str(an, "type", "analysis.type");
    st_copy_name(s->analysis_type, type);
    int dynamics = strcmp(type, "dynamics") == 0;
    const char *param = st_get_str(an, "parameter", "analysis.parameter");
    const config_setting_t *agr = st_mem(an, "group");
    if (agr && agr->value.sval[0]) {
        if (st_find_name(agr->value.sval, s->groups ? s->groups[0].name : "", sizeof(sf_group), s->ngroups) < 0) {
            const char *sg = s->ngroups ? suggest_in(agr->value.sval, s->groups[0].name, sizeof(sf_group), s->ngroups) : NULL;
            return st_bad(s, err, agr, "unknown group '%s'%s%s", agr->value.sval, st_hint(h, sizeof h, sg),
                       s->ngroups ? "" : " (no actuation groups are defined)");
        }
    }
    if (strcmp(param, "actuation") == 0 && s->ngroups == 0)
        return st_bad(s, err, st_mem(an, "parameter"), "\"actuation\" needs at least one actuation group");
    const config_setting_t *rep = st_mem(an, "report");
    if (rep && rep->value.sval[0]
        && st_find_name(rep->value.sval, s->probes ? s->probes[0].name : "", sizeof(sf_probe), s->nprobes) < 0) {
        const char *sg = s->nprobes ? suggest_in(rep->value.sval, s->probes[0].name, sizeof(sf_probe), s->nprobes) : NULL;
        return st_bad(s, err, rep, "unknown probe '%s'%s%s", rep->value.sval, st_hint(h, sizeof h, sg),
                   s->nprobes ? "" : " (no probes are defined)");
    }
    {
        const config_setting_t *w1, *w2, *w3;
        double st = get_num(an, NULL, "step", "analysis.step", &w1);
        double mn = get_num(an, NULL, "min_step", "analysis.min_step", &w2);
        double mx = get_num(an, NULL, "max_step", "analysis.max_step", &w3);
        if (mn > mx)
            return st_bad(s, err, w2 ? w2 : w3 ? w3 : an, "min_step %g is larger than max_step %g", mn, mx);
        if (st < mn || st > mx)
            return st_bad(s, err, w1 ? w1 : an, "step %g is outside [min_step, max_step] = [%g, %g]", st, mn, mx);
    }
    if (dynamics) {
        if (!st_mem(an, "duration"))
            return st_bad(s, err, an, "missing duration (required when type is \"dynamics\")");
        const config_setting_t *sc = st_mem(an, "schedule");
        int nsc = sc ? config_setting_length(sc) : 0;
        double tprev = -INFINITY;
        for (int i = 0; i < nsc; i++) {
            const config_setting_t *e = config_setting_get_elem(sc, (unsigned)i);
            double t = st_numval(st_mem(e, "t"));
            if (!(t > tprev))
                return st_bad(s, err, st_mem(e, "t"), "times must increase (got %g after %g)", t, tprev);
            tprev = t;
        }
        /* the other time histories of a trajectory: same rule */
        const config_setting_t *lists[64];
        int nl = 0;
        lists[nl++] = st_mem(an, "load_schedule");
        const config_setting_t *acts = st_mem(root, "actuation");
        for (int g = 0; acts && g < config_setting_length(acts) && nl < 64; g++)
            lists[nl++] = st_mem(config_setting_get_elem(acts, (unsigned)g), "schedule");
        for (int l = 0; l < nl; l++) {
            int nlen = lists[l] ? config_setting_length(lists[l]) : 0;
            tprev = -INFINITY;
            for (int i = 0; i < nlen; i++) {
                const config_setting_t *e = config_setting_get_elem(lists[l], (unsigned)i);
                double t = st_numval(st_mem(e, "t"));
                if (!(t > tprev))
                    return st_bad(s, err, st_mem(e, "t"), "times must increase (got %g after %g)", t, tprev);
                tprev = t;
            }
        }
    }


    /* densities where mass matters */
    int inertia = dynamics && get_bool(an, "inertia", "analysis.inertia");
    if (s->gravity_on && s->face_material < 0)
        return st_bad(s, err, gr, "needs faces.material (the weight of the faces comes from its thickness and density)");
    if (s->gravity_on || inertia) {
        for (int i = -1; i < s->nfolds; i++) {
            int mi = i < 0 ? s->face_material : s->folds[i].material;
            if (mi < 0) continue;
            const config_setting_t *mse = st_mem(ms, s->materials[mi].name);
            if (!st_mem(mse, "density"))
                return st_bad(s, err, mse, "missing density (required when %s is on)", s->gravity_on ? "gravity" : "inertia");
        }
    }
    return SF_OK;
}

int st_fill(sf_study *s, config_t *cfg, sf_error *err)
{
    const config_setting_t *root = config_root_setting(cfg);
    st_copy_name(s->name, st_mem(root, "name")->value.sval);
    int rc = fill_vertices(s, root, err);
    if (!rc) rc = fill_materials(s, root, err);
    if (!rc) rc = fill_groups(s, root, err);
    if (!rc) rc = fill_folds(s, root, err);
    if (!rc) rc = fill_loads(s, root, err);
    if (!rc) rc = fill_supports(s, root, err);
    if (!rc) rc = fill_probes(s, root, err);
    if (!rc) fill_settings(s, root);
    if (!rc) rc = fill_analysis(s, root, err);
    return rc;
}
#undef VIDX
#undef VSUG
#undef MIDX
#undef MSUG
