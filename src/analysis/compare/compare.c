/* compare.c - reference data against the computed path (compare.h): the
 * quantities compared and the life cycle.  The other files are listed in
 * compare_impl.h.
 */
#include "compare_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int build_quantities(sf_compare *c, const sf_study *s)
{
    c->nq = Q_FIRST_PROBE + 3 * s->nprobes + s->nfolds;
    c->qname = calloc((size_t)c->nq, sizeof *c->qname);
    c->alias = calloc((size_t)3 * s->nprobes + 1, sizeof *c->alias);
    c->alias_q = calloc((size_t)3 * s->nprobes + 1, sizeof *c->alias_q);
    if (!c->qname || !c->alias || !c->alias_q) return SF_ENOMEM;
    snprintf(c->qname[Q_P], SF_NAME_MAX, "p");
    snprintf(c->qname[Q_LOAD], SF_NAME_MAX, "load");
    snprintf(c->qname[Q_ENERGY], SF_NAME_MAX, "energy");
    static const char comp[3] = {'x', 'y', 'z'};
    for (int i = 0; i < s->nprobes; i++)
        for (int k = 0; k < 3; k++) {
            int q = Q_FIRST_PROBE + 3 * i + k;
            snprintf(c->qname[q], SF_NAME_MAX, "probe%d_u%c", i + 1, comp[k]);
            snprintf(c->alias[c->nalias], SF_NAME_MAX, "%.58s_u%c", s->probes[i].name, comp[k]);
            c->alias_q[c->nalias++] = q;
        }
    for (int j = 0; j < s->nfolds; j++)
        snprintf(c->qname[Q_FIRST_PROBE + 3 * s->nprobes + j], SF_NAME_MAX, "theta%d", j + 1);
    return SF_OK;
}

static int find_quantity(const sf_compare *c, const char *name)
{
    for (int q = 0; q < c->nq; q++)
        if (strcmp(c->qname[q], name) == 0) return q;
    for (int a = 0; a < c->nalias; a++)
        if (strcmp(c->alias[a], name) == 0) return c->alias_q[a];
    return -1;
}

const char *cm_suggest_quantity(const sf_compare *c, const char *name)
{
    int n = c->nq + c->nalias;
    const char **cand = malloc(sizeof(char *) * (size_t)(n + 1));
    if (!cand) return NULL;
    for (int q = 0; q < c->nq; q++) cand[q] = c->qname[q];
    for (int a = 0; a < c->nalias; a++) cand[c->nq + a] = c->alias[a];
    const char *sg = sf_study_suggest(name, n, cand);
    free(cand);
    return sg;
}

/* Values of every quantity at state y, parameter p (as branch.tsv has them). */
void cm_quantities(const sf_compare *c, sf_equil *eq, const sf_mpoint *probes,
                   const double *y, double p, double *out)
{
    const sf_study *s = c->s;
    const sf_model *m = eq->m;
    double Pi, rr, rt;
    sf_equil_report(eq, y, p, &Pi, &rr, &rt);   /* evaluates the maps at y */
    out[Q_P] = p;
    out[Q_LOAD] = eq->param == SF_PARAM_LOAD ? p : eq->load;
    out[Q_ENERGY] = Pi;
    for (int i = 0; i < s->nprobes; i++) {
        double x[3];
        sf_point_eval(m, &eq->k, &probes[i], x, NULL);
        out[Q_FIRST_PROBE + 3 * i + 0] = x[0] - probes[i].X[0];
        out[Q_FIRST_PROBE + 3 * i + 1] = x[1] - probes[i].X[1];
        out[Q_FIRST_PROBE + 3 * i + 2] = x[2];
    }
    for (int j = 0; j < s->nfolds; j++) out[Q_FIRST_PROBE + 3 * s->nprobes + j] = y[m->qoff[j]];
}

int sf_compare_count(const sf_compare *c) { return c ? c->nref : 0; }

void sf_compare_free(sf_compare *c)
{
    if (!c) return;
    for (int i = 0; i < c->nref; i++) {
        cmp_ref *r = &c->refs[i];
        for (int k = 0; k < r->ncols; k++) free(r->cols[k].comp);
        free(r->cols);
        free(r->colname);
        free(r->v);
        free(r->line);
        free(r->method);
        free(r->x);
    }
    free(c->refs);
    free(c->qname);
    free(c->alias);
    free(c->alias_q);
    free(c->pv);
    free(c->py);
    free(c->pblock);
    free(c);
}

int sf_compare_open(sf_compare **out, const sf_study *s, sf_error *err)
{
    *out = NULL;
    int nref = sf_study_count(s, "references");
    if (nref <= 0) return SF_OK;
    sf_compare *c = calloc(1, sizeof *c);
    if (!c) return sf_fail(err, SF_ENOMEM, "out of memory");
    c->s = s;
    int rc = build_quantities(c, s);
    if (!rc) {
        c->refs = calloc((size_t)nref, sizeof *c->refs);
        if (!c->refs) rc = SF_ENOMEM;
    }
    if (rc) {
        sf_compare_free(c);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int i = 0; i < nref && !rc; i++) {
        cmp_ref *r = &c->refs[c->nref++];
        char key[160];
        const char *t;
        snprintf(r->key, sizeof r->key, "references[%d]", i);
        snprintf(key, sizeof key, "%s.file", r->key);
        if ((rc = sf_study_string(s, key, "", &t, err))) break;
        snprintf(r->file, sizeof r->file, "%s", t);
        if (!cm_find_file(s->path, r->file, r->path, sizeof r->path)) {
            rc = sf_study_fail(s, err, SF_EIO, key, "cannot find '%s' (looked beside the study, in "
                               "$SMOOTHFOLD_DATA and in shared/data above the study's directory)", r->file);
            break;
        }
        snprintf(key, sizeof key, "%s.name", r->key);
        if ((rc = sf_study_string(s, key, "", &t, err))) break;
        if (t[0]) {
            snprintf(r->name, sizeof r->name, "%s", t);
        } else {
            const char *b = strrchr(r->file, '/');
            snprintf(r->name, sizeof r->name, "%.*s", SF_NAME_MAX - 1, b ? b + 1 : r->file);
        }
        for (int j = 0; j < i && !rc; j++)
            if (strcmp(c->refs[j].name, r->name) == 0)
                rc = sf_study_fail(s, err, SF_EINPUT, r->key,
                                   "reference name '%s' is used twice (give each a distinct name)", r->name);
        if (rc) break;
        if ((rc = cm_read_reference(r, err))) break;   /* the message names the file and line */
        /* abscissa */
        snprintf(key, sizeof key, "%s.abscissa.column", r->key);
        if ((rc = sf_study_string(s, key, "", &t, err))) break;
        if ((r->xcol = cm_find_column(r, t)) < 0) { rc = cm_bad_column(s, r, err, key, t); break; }
        snprintf(key, sizeof key, "%s.abscissa.quantity", r->key);
        if ((rc = sf_study_string(s, key, "p", &t, err))) break;
        if ((r->xq = find_quantity(c, t)) < 0) { rc = cm_bad_quantity(c, err, key, t); break; }
        snprintf(key, sizeof key, "%s.abscissa.scale", r->key);
        if ((rc = sf_study_double(s, key, 1.0, &r->xscale, err))) break;
        if (r->xscale == 0.0) { rc = sf_study_fail(s, err, SF_EINPUT, key, "must not be 0"); break; }
        snprintf(key, sizeof key, "%s.solve", r->key);
        if ((rc = sf_study_bool(s, key, 1, &r->solve, err))) break;
        /* compared columns */
        snprintf(key, sizeof key, "%s.columns", r->key);
        r->ncols = sf_study_count(s, key);
        if (r->ncols <= 0) { rc = sf_study_fail(s, err, SF_EINPUT, key, "name at least one column to compare"); break; }
        r->cols = calloc((size_t)r->ncols, sizeof *r->cols);
        r->method = calloc((size_t)r->nrow, 1);
        r->x = calloc((size_t)r->nrow, sizeof *r->x);
        if (!r->cols || !r->method || !r->x) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); break; }
        for (int k = 0; k < r->ncols && !rc; k++) {
            cmp_col *cc = &r->cols[k];
            snprintf(cc->key, sizeof cc->key, "%s.columns[%d]", r->key, k);
            snprintf(key, sizeof key, "%s.column", cc->key);
            if ((rc = sf_study_string(s, key, "", &t, err))) break;
            snprintf(cc->column, sizeof cc->column, "%s", t);
            if ((cc->ccol = cm_find_column(r, t)) < 0) { rc = cm_bad_column(s, r, err, key, t); break; }
            snprintf(key, sizeof key, "%s.quantity", cc->key);
            if ((rc = sf_study_string(s, key, cc->column, &t, err))) break;
            snprintf(cc->quantity, sizeof cc->quantity, "%s", t);
            if ((cc->q = find_quantity(c, t)) < 0) { rc = cm_bad_quantity(c, err, key, t); break; }
            snprintf(key, sizeof key, "%s.scale", cc->key);
            if ((rc = sf_study_double(s, key, 1.0, &cc->scale, err))) break;
            if (cc->scale == 0.0) { rc = sf_study_fail(s, err, SF_EINPUT, key, "must not be 0"); break; }
            snprintf(key, sizeof key, "%s.measure", cc->key);
            if ((rc = sf_study_string(s, key, "scaled", &t, err))) break;
            cc->measure = strcmp(t, "scaled") == 0 ? M_SCALED : strcmp(t, "relative") == 0 ? M_RELATIVE : M_ABSOLUTE;
            snprintf(key, sizeof key, "%s.norm", cc->key);
            if ((rc = sf_study_string(s, key, "max", &t, err))) break;
            cc->norm = strcmp(t, "max") == 0 ? N_MAX : strcmp(t, "rms") == 0 ? N_RMS : N_END;
            snprintf(key, sizeof key, "%s.tolerance", cc->key);
            cc->has_tol = sf_study_has(s, key);
            if (cc->has_tol && (rc = sf_study_double(s, key, 0.0, &cc->tol, err))) break;
            cc->comp = calloc((size_t)r->nrow, sizeof *cc->comp);
            if (!cc->comp) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); break; }
            for (int row = 0; row < r->nrow; row++)
                cc->refmax = fmax(cc->refmax, fabs(cc->scale * r->v[(size_t)row * r->ncol + cc->ccol]));
            if (cc->measure == M_SCALED && cc->refmax == 0.0) {
                rc = sf_study_fail(s, err, SF_EINPUT, cc->key, "column '%s' of %s is zero throughout: "
                                   "use measure = \"absolute\"", cc->column, r->path);
                break;
            }
        }
    }
    if (rc) {
        sf_compare_free(c);
        return rc;
    }
    *out = c;
    return SF_OK;
}

int sf_compare_add(sf_compare *c, sf_equil *eq, const sf_mpoint *probes,
                   const double *y, double p, int block, sf_error *err)
{
    if (!c) return SF_OK;
    if (c->npts == 0) c->ny = eq->n;
    if (eq->n != c->ny) return sf_fail(err, SF_EINTERNAL, "compare: the state size changed along the path");
    if (c->npts == c->cap) {
        int cap = c->cap ? 2 * c->cap : 64;
        double *pv = realloc(c->pv, sizeof(double) * (size_t)cap * c->nq);
        if (pv) c->pv = pv;
        double *py = realloc(c->py, sizeof(double) * (size_t)cap * (c->ny + 1));
        if (py) c->py = py;
        int *pb = realloc(c->pblock, sizeof(int) * (size_t)cap);
        if (pb) c->pblock = pb;
        if (!pv || !py || !pb) return sf_fail(err, SF_ENOMEM, "out of memory");
        c->cap = cap;
    }
    int i = c->npts++;
    memcpy(c->py + (size_t)i * c->ny, y, sizeof(double) * c->ny);
    c->pblock[i] = block;
    cm_quantities(c, eq, probes, y, p, c->pv + (size_t)i * c->nq);
    return SF_OK;
}
