/* compare.c - reference data against the computed path (compare.h).
 *
 * Reading: a reference file is a CSV file whose first lines are '#'
 * comments carrying its provenance as "# key: value" lines (a key is one
 * word right after "# "; lines "#  ..." indented by two or more spaces
 * continue the previous value).  Required keys: source, kind (its value
 * starts with "measured" or "simulated"), units.  An optional "columns"
 * key must list the header row's names (text in parentheses ignored).
 * Then one row of comma-separated column names and rows of finite numbers.
 */
#include "compare.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cont.h"
#include "study.h"
#include "vtk.h"

enum { M_SCALED = 0, M_RELATIVE = 1, M_ABSOLUTE = 2 };
enum { N_MAX = 0, N_RMS = 1, N_END = 2 };
enum { Q_P = 0, Q_LOAD = 1, Q_ENERGY = 2, Q_FIRST_PROBE = 3 };

#define PROV_MAX 512

typedef struct cmp_col {
    char key[96];           /* "references[0].columns[1]" */
    char column[SF_NAME_MAX], quantity[SF_NAME_MAX];
    int ccol, q;
    double scale;
    int measure, norm;
    int has_tol;
    double tol;
    double refmax;          /* max |scale * value| over the file's rows */
    /* results */
    int npts;               /* rows compared (relative: rows with a nonzero reference) */
    double emax, erms, eend, xmax;
    double amax, arms, aend;
    int pass;               /* 1 ok, 0 exceeded, -1 no tolerance */
    double *comp;           /* per row: computed value (valid where row is placed) */
} cmp_col;

typedef struct cmp_ref {
    char key[64];           /* "references[0]" */
    char name[SF_NAME_MAX];
    char file[1024];        /* as written in the study */
    char path[2048];        /* where it was found */
    char source[PROV_MAX], kind[PROV_MAX], units[PROV_MAX];
    int ncol, nrow;
    char (*colname)[SF_NAME_MAX];
    double *v;              /* nrow x ncol */
    int *line;              /* file line of each row */
    int xcol, xq;
    double xscale;
    int solve;              /* solve at reference values of p (else interpolate) */
    int ncols;
    cmp_col *cols;
    /* results */
    char *method;           /* per row: 'p' computed point, 's' solved, 'i' interpolated, 'o' outside */
    double *x;              /* per row: abscissa in study units */
    int noutside, nsolved, ninterp, npoint;
} cmp_ref;

struct sf_compare {
    const sf_study *s;
    int nq;                 /* quantities */
    char (*qname)[SF_NAME_MAX];
    int nalias;
    char (*alias)[SF_NAME_MAX];
    int *alias_q;
    int nref;
    cmp_ref *refs;
    /* the recorded path */
    int ny, npts, cap;
    double *pv, *py;        /* npts x nq values, npts x ny states */
    int *pblock;
};

/* ---------------------------------------------------------------------- */
/* Quantities                                                               */
/* ---------------------------------------------------------------------- */

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

static const char *suggest_quantity(const sf_compare *c, const char *name)
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
static void quantities(const sf_compare *c, sf_equil *eq, const sf_mpoint *probes,
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

/* ---------------------------------------------------------------------- */
/* Finding and reading a reference file                                     */
/* ---------------------------------------------------------------------- */

static int readable(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* The search rule of docs/study-format.md: an absolute path as is; a
 * relative one beside the study, then in each directory of
 * $SMOOTHFOLD_DATA (':'-separated), then in shared/data of the study's
 * directory and of each directory above it. */
static int find_file(const char *study_path, const char *file, char *out, size_t n)
{
    if (file[0] == '/') {
        snprintf(out, n, "%s", file);
        return readable(out);
    }
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", study_path);
    char *sl = strrchr(dir, '/');
    if (sl) *sl = '\0';
    else snprintf(dir, sizeof dir, ".");
    snprintf(out, n, "%s/%s", dir, file);
    if (readable(out)) return 1;
    const char *env = getenv("SMOOTHFOLD_DATA");
    if (env && env[0]) {
        char list[4096];
        snprintf(list, sizeof list, "%s", env);
        char *save = NULL;
        for (char *d = strtok_r(list, ":", &save); d; d = strtok_r(NULL, ":", &save)) {
            if (!d[0]) continue;
            snprintf(out, n, "%s/%s", d, file);
            if (readable(out)) return 1;
        }
    }
    /* climb from the study's directory (made absolute) to the root */
    char *abs = realpath(dir, NULL);
    if (!abs) return 0;
    for (int up = 0; up < 64; up++) {
        snprintf(out, n, "%s/shared/data/%s", strcmp(abs, "/") == 0 ? "" : abs, file);
        if (readable(out)) { free(abs); return 1; }
        char *p = strrchr(abs, '/');
        if (!p || strcmp(abs, "/") == 0) break;
        if (p == abs) p[1] = '\0';
        else *p = '\0';
    }
    free(abs);
    return 0;
}

static void trim(char *t)
{
    size_t n = strlen(t);
    while (n && isspace((unsigned char)t[n - 1])) t[--n] = '\0';
    size_t i = 0;
    while (t[i] && isspace((unsigned char)t[i])) i++;
    if (i) memmove(t, t + i, strlen(t + i) + 1);
}

/* A provenance line "# key: value": returns the key length (value at
 * *val), or 0 for other comment lines. */
static int prov_key(const char *line, const char **val)
{
    if (line[0] != '#' || line[1] != ' ') return 0;
    const char *k = line + 2;
    int n = 0;
    while (isalpha((unsigned char)k[n]) || k[n] == '_') n++;
    if (n == 0 || k[n] != ':') return 0;
    *val = k + n + 1;
    while (**val == ' ') (*val)++;
    return n;
}

static void append(char *dst, size_t n, const char *text)
{
    size_t l = strlen(dst);
    if (l && l + 1 < n) dst[l++] = ' ', dst[l] = '\0';
    snprintf(dst + l, n - l, "%s", text);
}

/* The names of a "# columns:" value, text in parentheses dropped. */
static int split_columns_line(const char *val, char names[][SF_NAME_MAX], int max)
{
    char buf[PROV_MAX];
    int depth = 0, o = 0;
    for (const char *p = val; *p && o + 1 < (int)sizeof buf; p++) {
        if (*p == '(') depth++;
        else if (*p == ')') depth = depth > 0 ? depth - 1 : 0;
        else if (!depth) buf[o++] = *p;
    }
    buf[o] = '\0';
    int k = 0;
    char *save = NULL;
    for (char *t = strtok_r(buf, ",", &save); t && k < max; t = strtok_r(NULL, ",", &save)) {
        trim(t);
        snprintf(names[k++], SF_NAME_MAX, "%s", t);
    }
    return k;
}

static int read_reference(cmp_ref *r, sf_error *err)
{
    FILE *f = fopen(r->path, "r");
    if (!f) return sf_fail(err, SF_EIO, "%s: cannot read: %s", r->path, strerror(errno));
    char *line = NULL;
    size_t cap = 0;
    ssize_t len;
    int ln = 0, rc = SF_OK, header_line = 0, columns_line = 0, rcap = 0;
    char columns[PROV_MAX] = "";
    char *last = NULL;          /* value being continued */
    size_t lastn = 0;
    while ((len = getline(&line, &cap, f)) >= 0) {
        ln++;
        line[strcspn(line, "\r\n")] = '\0';
        if (line[0] == '#') {
            if (r->ncol) continue;          /* comments after the header row */
            const char *val;
            int kl = prov_key(line, &val);
            if (kl) {
                last = NULL;
                if (kl == 6 && strncmp(line + 2, "source", 6) == 0) last = r->source, lastn = sizeof r->source;
                else if (kl == 4 && strncmp(line + 2, "kind", 4) == 0) last = r->kind, lastn = sizeof r->kind;
                else if (kl == 5 && strncmp(line + 2, "units", 5) == 0) last = r->units, lastn = sizeof r->units;
                else if (kl == 7 && strncmp(line + 2, "columns", 7) == 0) last = columns, lastn = sizeof columns, columns_line = ln;
                if (last) {
                    if (last[0]) { rc = sf_fail(err, SF_EINPUT, "%s:%d: '# %.*s:' given twice", r->path, ln, kl, line + 2); break; }
                    snprintf(last, lastn, "%s", val);
                }
            } else if (last && strncmp(line, "#  ", 3) == 0) {
                char t[PROV_MAX];
                snprintf(t, sizeof t, "%s", line + 1);
                trim(t);
                append(last, lastn, t);
            } else {
                last = NULL;
            }
            continue;
        }
        char *t = line;
        while (isspace((unsigned char)*t)) t++;
        if (!*t) continue;                  /* blank line */
        if (r->ncol == 0) {
            /* the header row: provenance first */
            header_line = ln;
            const char *missing = !r->source[0] ? "'# source:' (where the data come from)"
                                : !r->kind[0] ? "'# kind:' (measured or simulated)"
                                : !r->units[0] ? "'# units:'" : NULL;
            if (missing) {
                rc = sf_fail(err, SF_EINPUT, "%s:%d: no provenance header: %s must come before the column names "
                             "(docs/study-format.md, reference files)", r->path, ln, missing);
                break;
            }
            char k0[16];
            memcpy(k0, r->kind, sizeof k0 - 1);     /* kind holds PROV_MAX > 16 bytes */
            k0[sizeof k0 - 1] = '\0';
            for (char *p = k0; *p; p++) *p = (char)tolower((unsigned char)*p);
            if (strncmp(k0, "measured", 8) != 0 && strncmp(k0, "simulated", 9) != 0) {
                rc = sf_fail(err, SF_EINPUT, "%s:%d: '# kind:' must start with \"measured\" or \"simulated\" (got \"%.40s\")",
                             r->path, ln, r->kind);
                break;
            }
            int n = 1;
            for (char *p = t; *p; p++) n += *p == ',';
            r->colname = calloc((size_t)n, sizeof *r->colname);
            if (!r->colname) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); break; }
            char *save = NULL, *tok = strtok_r(t, ",", &save);
            int k = 0;
            for (int i = 0; i < n; i++) {
                char nm[256] = "";
                if (tok) { snprintf(nm, sizeof nm, "%s", tok); tok = strtok_r(NULL, ",", &save); }
                trim(nm);
                if (!nm[0] || strlen(nm) >= SF_NAME_MAX) {
                    rc = sf_fail(err, SF_EINPUT, "%s:%d: column %d of the header row has %s name", r->path, ln,
                                 i + 1, nm[0] ? "a too long" : "an empty");
                    break;
                }
                for (int j = 0; j < k; j++)
                    if (strcmp(r->colname[j], nm) == 0) {
                        rc = sf_fail(err, SF_EINPUT, "%s:%d: column name '%s' appears twice", r->path, ln, nm);
                        break;
                    }
                if (rc) break;
                snprintf(r->colname[k++], SF_NAME_MAX, "%s", nm);
            }
            if (rc) break;
            r->ncol = k;
            if (columns[0]) {
                char (*cn)[SF_NAME_MAX] = calloc((size_t)k + 2, sizeof *cn);
                if (!cn) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); break; }
                int nc = split_columns_line(columns, cn, k + 1);
                for (int j = 0; j < k && j < nc && !rc; j++)
                    if (strcmp(cn[j], r->colname[j]) != 0)
                        rc = sf_fail(err, SF_EINPUT, "%s:%d: '# columns:' names column %d '%s' but the header row "
                                     "(line %d) has '%s'", r->path, columns_line, j + 1, cn[j], ln, r->colname[j]);
                if (!rc && nc != k)
                    rc = sf_fail(err, SF_EINPUT, "%s:%d: '# columns:' lists %d columns but the header row (line %d) has %d",
                                 r->path, columns_line, nc, ln, k);
                free(cn);
                if (rc) break;
            }
            continue;
        }
        /* a data row */
        if (r->nrow == rcap) {
            rcap = rcap ? 2 * rcap : 32;
            double *v = realloc(r->v, sizeof(double) * (size_t)rcap * r->ncol);
            int *l = realloc(r->line, sizeof(int) * (size_t)rcap);
            if (v) r->v = v;
            if (l) r->line = l;
            if (!v || !l) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); break; }
        }
        char *p = t;
        for (int j = 0; j < r->ncol && !rc; j++) {
            char *end = strchr(p, ',');
            if (!end && j < r->ncol - 1) {
                rc = sf_fail(err, SF_EINPUT, "%s:%d: expected %d values, got %d", r->path, ln, r->ncol, j + 1);
                break;
            }
            char fld[128];
            size_t fl = end ? (size_t)(end - p) : strlen(p);
            snprintf(fld, sizeof fld, "%.*s", (int)(fl < sizeof fld ? fl : sizeof fld - 1), p);
            trim(fld);
            char *e;
            errno = 0;
            double x = fld[0] ? strtod(fld, &e) : 0.0;
            if (!fld[0] || *e) {
                rc = sf_fail(err, SF_EINPUT, "%s:%d: column %d (%s): '%s' is not a number", r->path, ln, j + 1,
                             r->colname[j], fld);
                break;
            }
            if (!isfinite(x)) {
                rc = sf_fail(err, SF_EINPUT, "%s:%d: column %d (%s): not a finite number (%s)", r->path, ln, j + 1,
                             r->colname[j], fld);
                break;
            }
            r->v[(size_t)r->nrow * r->ncol + j] = x;
            p = end ? end + 1 : p + fl;
            if (j == r->ncol - 1 && end) {
                int extra = 1;
                for (char *q = end + 1; *q; q++) extra += *q == ',';
                rc = sf_fail(err, SF_EINPUT, "%s:%d: expected %d values, got %d", r->path, ln, r->ncol,
                             r->ncol + extra);
            }
        }
        if (rc) break;
        r->line[r->nrow++] = ln;
    }
    free(line);
    if (!rc && ferror(f)) rc = sf_fail(err, SF_EIO, "%s: read error", r->path);
    fclose(f);
    if (rc) return rc;
    if (r->ncol == 0)
        return sf_fail(err, SF_EINPUT, "%s:%d: no header row of column names", r->path, ln > 0 ? ln : 1);
    if (r->nrow == 0)
        return sf_fail(err, SF_EINPUT, "%s:%d: no data rows after the header row", r->path, header_line);
    return SF_OK;
}

static int find_column(const cmp_ref *r, const char *name)
{
    for (int j = 0; j < r->ncol; j++)
        if (strcmp(r->colname[j], name) == 0) return j;
    return -1;
}

static int bad_column(const sf_study *s, const cmp_ref *r, sf_error *err, const char *key,
                      const char *name)
{
    const char **cand = malloc(sizeof(char *) * (size_t)(r->ncol + 1));
    const char *sg = NULL;
    if (cand) {
        for (int j = 0; j < r->ncol; j++) cand[j] = r->colname[j];
        sg = sf_study_suggest(name, r->ncol, cand);
    }
    char h[128] = "";
    if (sg) snprintf(h, sizeof h, " (did you mean '%s'?)", sg);
    int rc = sf_study_fail(s, err, SF_EINPUT, key, "no column '%s' in %s%s", name, r->path, h);
    free(cand);
    return rc;
}

static int bad_quantity(const sf_compare *c, sf_error *err, const char *key, const char *name)
{
    const char *sg = suggest_quantity(c, name);
    char h[128] = "";
    if (sg) snprintf(h, sizeof h, " (did you mean '%s'?)", sg);
    return sf_study_fail(c->s, err, SF_EINPUT, key,
                         "unknown quantity '%s'%s: use p, load, energy, probe<i>_ux|uy|uz, "
                         "<probe name>_ux|uy|uz or theta<j>", name, h);
}

/* ---------------------------------------------------------------------- */
/* Open                                                                     */
/* ---------------------------------------------------------------------- */

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
        if (!find_file(s->path, r->file, r->path, sizeof r->path)) {
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
        if ((rc = read_reference(r, err))) break;   /* the message names the file and line */
        /* abscissa */
        snprintf(key, sizeof key, "%s.abscissa.column", r->key);
        if ((rc = sf_study_string(s, key, "", &t, err))) break;
        if ((r->xcol = find_column(r, t)) < 0) { rc = bad_column(s, r, err, key, t); break; }
        snprintf(key, sizeof key, "%s.abscissa.quantity", r->key);
        if ((rc = sf_study_string(s, key, "p", &t, err))) break;
        if ((r->xq = find_quantity(c, t)) < 0) { rc = bad_quantity(c, err, key, t); break; }
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
            if ((cc->ccol = find_column(r, t)) < 0) { rc = bad_column(s, r, err, key, t); break; }
            snprintf(key, sizeof key, "%s.quantity", cc->key);
            if ((rc = sf_study_string(s, key, cc->column, &t, err))) break;
            snprintf(cc->quantity, sizeof cc->quantity, "%s", t);
            if ((cc->q = find_quantity(c, t)) < 0) { rc = bad_quantity(c, err, key, t); break; }
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

/* ---------------------------------------------------------------------- */
/* Recording the path                                                       */
/* ---------------------------------------------------------------------- */

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
    quantities(c, eq, probes, y, p, c->pv + (size_t)i * c->nq);
    return SF_OK;
}

/* ---------------------------------------------------------------------- */
/* Placing rows on the path                                                 */
/* ---------------------------------------------------------------------- */

/* The recorded points as a curve: consecutive exact duplicates dropped,
 * each point with its cumulative chord length t in (yscale * y, p) within
 * its block (a discrete arclength: every quantity is a smooth function of
 * t, also through limit points, where it is not a function of p). */
typedef struct curve {
    int n;
    int *pt;            /* point index of each curve node */
    double *t;          /* chord length from the block's first node */
} curve;

static int make_curve(const sf_compare *c, const sf_equil *eq, curve *cv)
{
    cv->n = 0;
    cv->pt = malloc(sizeof(int) * (size_t)(c->npts + 1));
    cv->t = malloc(sizeof(double) * (size_t)(c->npts + 1));
    if (!cv->pt || !cv->t) return SF_ENOMEM;
    for (int i = 0; i < c->npts; i++) {
        double t = 0.0;
        if (cv->n > 0 && c->pblock[cv->pt[cv->n - 1]] == c->pblock[i]) {
            int j = cv->pt[cv->n - 1];
            double d2 = 0.0;
            for (int k = 0; k < c->ny; k++) {
                double d = (c->py[(size_t)i * c->ny + k] - c->py[(size_t)j * c->ny + k]) * eq->yscale[k];
                d2 += d * d;
            }
            double dp = c->pv[(size_t)i * c->nq + Q_P] - c->pv[(size_t)j * c->nq + Q_P];
            d2 += dp * dp;
            if (d2 == 0.0) continue;            /* the same point again */
            t = cv->t[cv->n - 1] + sqrt(d2);
        }
        cv->pt[cv->n] = i;
        cv->t[cv->n] = t;
        cv->n++;
    }
    return SF_OK;
}

static double xval(const sf_compare *c, int i, int xq) { return c->pv[(size_t)i * c->nq + xq]; }

static int same_block(const sf_compare *c, const curve *cv, int a, int b)
{
    return a >= 0 && b >= 0 && a < cv->n && b < cv->n && c->pblock[cv->pt[a]] == c->pblock[cv->pt[b]];
}

typedef struct piece {
    int start, n;       /* into the node index array */
} piece;

/* Cut the curve into pieces strictly monotone in quantity xq: a new piece
 * starts at each new block and at each turning point of x (shared by the
 * two pieces).  Nodes where x does not move are left out of the pieces
 * (they stay on the curve for interpolation). */
static int make_pieces(const sf_compare *c, const curve *cv, int xq, int **idx_out, piece **pc_out,
                       int *npc)
{
    int *idx = malloc(sizeof(int) * (size_t)(2 * cv->n + 1));
    piece *pc = malloc(sizeof(piece) * (size_t)(cv->n + 1));
    if (!idx || !pc) { free(idx); free(pc); return SF_ENOMEM; }
    int ni = 0, np = 0, dir = 0;
    for (int a = 0; a < cv->n; a++) {
        double x = xval(c, cv->pt[a], xq);
        if (np == 0 || !same_block(c, cv, a, idx[ni - 1])) {
            pc[np].start = ni;
            pc[np].n = 0;
            np++;
            dir = 0;
        } else {
            double dx = x - xval(c, cv->pt[idx[ni - 1]], xq);
            if (dx == 0.0) continue;
            int d = dx > 0 ? 1 : -1;
            if (dir != 0 && d != dir) {
                int turn = idx[ni - 1];
                pc[np].start = ni;
                pc[np].n = 1;
                idx[ni++] = turn;
                np++;
            }
            dir = d;
        }
        idx[ni++] = a;
        pc[np - 1].n++;
    }
    *idx_out = idx;
    *pc_out = pc;
    *npc = np;
    return SF_OK;
}

/* Where x lies on a piece: the bracketing nodes (*a, *b) with x between
 * their abscissae (returns 1), or an exact node (*a = *b), or 0 when x is
 * outside the piece. */
static int locate(const sf_compare *c, const curve *cv, const int *idx, const piece *pc, int xq,
                  double x, double eps, int *a, int *b)
{
    const int *id = idx + pc->start;
    for (int k = 0; k < pc->n; k++)
        if (fabs(xval(c, cv->pt[id[k]], xq) - x) <= eps) { *a = *b = id[k]; return 1; }
    for (int k = 0; k + 1 < pc->n; k++) {
        double xa = xval(c, cv->pt[id[k]], xq), xb = xval(c, cv->pt[id[k + 1]], xq);
        if ((x - xa) * (x - xb) < 0.0) { *a = id[k]; *b = id[k + 1]; return 1; }
    }
    return 0;
}

/* Lagrange weights at t of the nodes nd[0..nn-1]. */
static void lagrange(const curve *cv, const int *nd, int nn, double t, double *w)
{
    for (int i = 0; i < nn; i++) {
        w[i] = 1.0;
        for (int j = 0; j < nn; j++)
            if (j != i) w[i] *= (t - cv->t[nd[j]]) / (cv->t[nd[i]] - cv->t[nd[j]]);
    }
}

/* Values of every quantity (vals) and the state (ys, may be NULL) at x
 * between curve nodes a < b: each is interpolated in the chord length t,
 * cubically through a-1, a, b, b+1 where those exist in the block (also
 * across a turning point: the curve is smooth in t there), and t is where
 * the interpolated abscissa equals x (bisection; the data bracket it). */
static void interp_at(const sf_compare *c, const curve *cv, int a, int b, int xq, double x,
                      double *vals, double *ys)
{
    if (a == b) {
        memcpy(vals, c->pv + (size_t)cv->pt[a] * c->nq, sizeof(double) * c->nq);
        if (ys) memcpy(ys, c->py + (size_t)cv->pt[a] * c->ny, sizeof(double) * c->ny);
        return;
    }
    if (a > b) { int t = a; a = b; b = t; }
    int nd[4], nn = 0;
    if (same_block(c, cv, a - 1, a)) nd[nn++] = a - 1;
    nd[nn++] = a;
    nd[nn++] = b;
    if (same_block(c, cv, b + 1, b)) nd[nn++] = b + 1;
    double w[4];
    double lo = cv->t[a], hi = cv->t[b];
    double flo = xval(c, cv->pt[a], xq) - x;
    for (int it = 0; it < 200 && hi - lo > 1e-15 * (fabs(hi) + 1e-300); it++) {
        double mid = 0.5 * (lo + hi), xm = 0.0;
        lagrange(cv, nd, nn, mid, w);
        for (int i = 0; i < nn; i++) xm += w[i] * xval(c, cv->pt[nd[i]], xq);
        if ((xm - x) * flo > 0.0) { lo = mid; flo = xm - x; }
        else hi = mid;
    }
    lagrange(cv, nd, nn, 0.5 * (lo + hi), w);
    for (int q = 0; q < c->nq; q++) {
        double v = 0.0;
        for (int i = 0; i < nn; i++) v += w[i] * c->pv[(size_t)cv->pt[nd[i]] * c->nq + q];
        vals[q] = v;
    }
    vals[xq] = x;
    if (ys)
        for (int k = 0; k < c->ny; k++) {
            double v = 0.0;
            for (int i = 0; i < nn; i++) v += w[i] * c->py[(size_t)cv->pt[nd[i]] * c->ny + k];
            ys[k] = v;
        }
}

int sf_compare_eval(sf_compare *c, sf_equil *eq, const sf_mpoint *probes,
                    struct cont_solver *cs, sf_error *err)
{
    if (!c) return SF_OK;
    double *vals = malloc(sizeof(double) * (size_t)c->nq * 2 + 1);
    double *best = vals ? vals + c->nq : NULL;
    double *y = malloc(sizeof(double) * (size_t)(c->ny + 1));
    double *guess = malloc(sizeof(double) * (size_t)(c->ny + 1));
    curve cv = {0, NULL, NULL};
    if (!vals || !y || !guess || make_curve(c, eq, &cv)) {
        free(vals); free(y); free(guess); free(cv.pt); free(cv.t);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    int rc = SF_OK;
    for (int ri = 0; ri < c->nref && !rc; ri++) {
        cmp_ref *r = &c->refs[ri];
        int *idx = NULL, npc = 0;
        piece *pc = NULL;
        if (make_pieces(c, &cv, r->xq, &idx, &pc, &npc)) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); break; }
        double xlo = INFINITY, xhi = -INFINITY;
        for (int i = 0; i < c->npts; i++) {
            xlo = fmin(xlo, xval(c, i, r->xq));
            xhi = fmax(xhi, xval(c, i, r->xq));
        }
        double eps = c->npts ? 1e-10 * fmax(xhi - xlo, fmax(fabs(xlo), fabs(xhi))) : 0.0;
        int solvable = cs && r->solve && (r->xq == Q_P || (r->xq == Q_LOAD && eq->param == SF_PARAM_LOAD));
        int lastpc = 0;
        r->noutside = r->nsolved = r->ninterp = r->npoint = 0;
        for (int row = 0; row < r->nrow; row++) {
            const double *rv = r->v + (size_t)row * r->ncol;
            double x = r->xscale * rv[r->xcol];
            r->x[row] = x;
            /* the piece closest in value; on a tie (the path passes the
             * same state twice, or pieces meet at a turning point) the
             * first one at or after the previous row's piece */
            int bp = -1, ba = -1, bb = -1;
            double bscore = INFINITY;
            for (int jj = 0; jj < npc; jj++) {
                int j = (lastpc + jj) % npc;
                int na, nb;
                if (!locate(c, &cv, idx, &pc[j], r->xq, x, eps, &na, &nb)) continue;
                interp_at(c, &cv, na, nb, r->xq, x, vals, NULL);
                double score = 0.0;
                for (int cc = 0; cc < r->ncols; cc++) {
                    const cmp_col *col = &r->cols[cc];
                    double ref = col->scale * rv[col->ccol];
                    score += fabs(vals[col->q] - ref) / (col->refmax > 0 ? col->refmax : 1.0);
                }
                if (bp < 0 || score < bscore - 1e-12 * (1.0 + bscore)) {
                    bscore = score;
                    bp = j; ba = na; bb = nb;
                    memcpy(best, vals, sizeof(double) * c->nq);
                }
            }
            if (bp < 0) {
                r->method[row] = 'o';
                r->noutside++;
                continue;
            }
            lastpc = bp;
            char method = ba == bb ? 'p' : 'i';
            if (method == 'i' && solvable) {
                /* solve at exactly p = x from the interpolated state; accept
                 * it only if it stays next to that stretch of the path */
                interp_at(c, &cv, ba, bb, r->xq, x, vals, guess);
                double dab = 0.0;
                for (int i = 0; i < c->ny; i++)
                    dab = fmax(dab, fabs(c->py[(size_t)cv.pt[bb] * c->ny + i] -
                                         c->py[(size_t)cv.pt[ba] * c->ny + i]) * eq->yscale[i]);
                memcpy(y, guess, sizeof(double) * c->ny);
                if (cont_solve_fixed(cs, y, x) == CONT_OK) {
                    double dist = 0.0;
                    int finite = 1;
                    for (int i = 0; i < c->ny; i++) {
                        if (!isfinite(y[i])) finite = 0;
                        dist = fmax(dist, fabs(y[i] - guess[i]) * eq->yscale[i]);
                    }
                    if (finite && dist <= dab + 1e-8) {
                        quantities(c, eq, probes, y, x, best);
                        method = 's';
                    }
                }
            }
            r->method[row] = method;
            if (method == 'p') r->npoint++;
            else if (method == 's') r->nsolved++;
            else r->ninterp++;
            for (int cc = 0; cc < r->ncols; cc++) r->cols[cc].comp[row] = best[r->cols[cc].q];
        }
        free(idx);
        free(pc);
        /* errors */
        for (int cc = 0; cc < r->ncols; cc++) {
            cmp_col *col = &r->cols[cc];
            double se = 0, sa = 0;
            int na = 0;
            col->npts = 0;
            col->emax = col->erms = col->eend = col->amax = col->arms = col->aend = 0;
            col->xmax = 0;
            for (int row = 0; row < r->nrow; row++) {
                if (r->method[row] == 'o') continue;
                double ref = col->scale * r->v[(size_t)row * r->ncol + col->ccol];
                double d = fabs(col->comp[row] - ref);
                na++;
                sa += d * d;
                col->amax = fmax(col->amax, d);
                col->aend = d;
                double e;
                if (col->measure == M_ABSOLUTE) e = d;
                else if (col->measure == M_SCALED) e = d / col->refmax;
                else if (fabs(ref) > 1e-9 * col->refmax && ref != 0.0) e = d / fabs(ref);
                else continue;      /* relative error undefined at a zero reference */
                col->npts++;
                se += e * e;
                if (col->npts == 1 || e > col->emax) { col->emax = e; col->xmax = r->x[row]; }
                col->eend = e;
            }
            col->arms = na ? sqrt(sa / na) : 0.0;
            col->erms = col->npts ? sqrt(se / col->npts) : 0.0;
            double v = col->norm == N_MAX ? col->emax : col->norm == N_RMS ? col->erms : col->eend;
            col->pass = !col->has_tol ? -1 : (col->npts > 0 && v <= col->tol) ? 1 : 0;
        }
    }
    free(vals);
    free(y);
    free(guess);
    free(cv.pt);
    free(cv.t);
    return rc;
}

/* ---------------------------------------------------------------------- */
/* Output                                                                   */
/* ---------------------------------------------------------------------- */

static const char *measure_name(int m)
{
    return m == M_SCALED ? "scaled" : m == M_RELATIVE ? "relative" : "absolute";
}

static const char *norm_name(int n) { return n == N_MAX ? "max" : n == N_RMS ? "rms" : "end"; }

static double fin(double v) { return isfinite(v) ? v : 0.0; }

static void write_header(const sf_compare *c, FILE *f, const char *header)
{
    if (header) fputs(header, f);
    for (int i = 0; i < c->nref; i++) {
        const cmp_ref *r = &c->refs[i];
        fprintf(f, "# reference %s: %s (%d rows)\n", r->name, r->path, r->nrow);
        fprintf(f, "#   kind: %s\n#   source: %s\n#   units: %s\n", r->kind, r->source, r->units);
        fprintf(f, "#   abscissa: column %s x %.12g = %s; %d rows solved at that value, %d at computed "
                "points, %d interpolated, %d outside the path\n",
                r->colname[r->xcol], r->xscale, c->qname[r->xq], r->nsolved, r->npoint, r->ninterp,
                r->noutside);
    }
}

static int fill_summary(void *ctx, void *vf)
{
    const sf_compare *c = ((const void **)ctx)[0];
    const char *header = ((const void **)ctx)[1];
    FILE *f = vf;
    write_header(c, f, header);
    fprintf(f, "# error d = computed - scale x reference; measure scaled: |d| / max |reference column|, "
               "relative: |d| / |reference| (rows with a zero reference skipped), absolute: |d|; "
               "max, rms, end (last compared row) in that measure; *_abs: |d| in the quantity's unit\n");
    fprintf(f, "reference\tcolumn\tquantity\tmeasure\tpoints\toutside\tmax\trms\tend\tx_at_max\t"
               "max_abs\trms_abs\tend_abs\tnorm\ttolerance\tstatus\n");
    for (int i = 0; i < c->nref; i++) {
        const cmp_ref *r = &c->refs[i];
        for (int k = 0; k < r->ncols; k++) {
            const cmp_col *col = &r->cols[k];
            fprintf(f, "%s\t%s\t%s\t%s\t%d\t%d\t%.6e\t%.6e\t%.6e\t%.10g\t%.6e\t%.6e\t%.6e\t%s\t",
                    r->name, col->column, c->qname[col->q], measure_name(col->measure), col->npts,
                    r->noutside, fin(col->emax), fin(col->erms), fin(col->eend), fin(col->xmax),
                    fin(col->amax), fin(col->arms), fin(col->aend), norm_name(col->norm));
            if (col->has_tol) fprintf(f, "%.6g\t%s\n", col->tol, col->pass > 0 ? "ok" : "FAIL");
            else fprintf(f, "-\t-\n");
        }
    }
    return ferror(f) ? SF_EIO : SF_OK;
}

static int fill_points(void *ctx, void *vf)
{
    const sf_compare *c = ((const void **)ctx)[0];
    const char *header = ((const void **)ctx)[1];
    FILE *f = vf;
    write_header(c, f, header);
    fprintf(f, "# one row per reference row placed on the path; blocks (blank-line separated) per "
               "compared column; method: point (a computed point), solved (equilibrium solved at x), "
               "interpolated\n");
    fprintf(f, "reference\tcolumn\tquantity\tline\tx\treference_value\tcomputed\tdifference\terror\tmethod\n");
    int first = 1;
    for (int i = 0; i < c->nref; i++) {
        const cmp_ref *r = &c->refs[i];
        for (int k = 0; k < r->ncols; k++) {
            const cmp_col *col = &r->cols[k];
            if (!first) fputc('\n', f);
            first = 0;
            for (int row = 0; row < r->nrow; row++) {
                char m = r->method[row];
                if (m == 'o') continue;
                double ref = col->scale * r->v[(size_t)row * r->ncol + col->ccol];
                double d = col->comp[row] - ref;
                double e = col->measure == M_ABSOLUTE ? fabs(d)
                         : col->measure == M_SCALED ? fabs(d) / col->refmax
                         : (ref != 0.0 && fabs(ref) > 1e-9 * col->refmax) ? fabs(d) / fabs(ref) : 0.0;
                fprintf(f, "%s\t%s\t%s\t%d\t%.15g\t%.15g\t%.15g\t%.6e\t%.6e\t%s\n", r->name, col->column,
                        c->qname[col->q], r->line[row], fin(r->x[row]), fin(ref), fin(col->comp[row]),
                        fin(d), fin(e), m == 'p' ? "point" : m == 's' ? "solved" : "interpolated");
            }
        }
    }
    return ferror(f) ? SF_EIO : SF_OK;
}

int sf_compare_write(const sf_compare *c, const char *dir, const char *header, sf_error *err)
{
    if (!c) return SF_OK;
    const void *ctx[2] = {c, header};
    char path[1200];
    snprintf(path, sizeof path, "%s/compare.tsv", dir);
    if (sf_write_atomic(path, fill_summary, (void *)ctx, err)) return err->code;
    snprintf(path, sizeof path, "%s/compare-points.tsv", dir);
    if (sf_write_atomic(path, fill_points, (void *)ctx, err)) return err->code;
    return SF_OK;
}

void sf_compare_print_files(const sf_compare *c, FILE *f)
{
    if (!c) return;
    for (int i = 0; i < c->nref; i++) {
        const cmp_ref *r = &c->refs[i];
        fprintf(f, "reference %s: %s (%d rows, %d columns compared; %.60s)\n", r->name, r->path,
                r->nrow, r->ncols, r->kind);
    }
}

void sf_compare_print(const sf_compare *c, FILE *f)
{
    if (!c) return;
    for (int i = 0; i < c->nref; i++) {
        const cmp_ref *r = &c->refs[i];
        for (int k = 0; k < r->ncols; k++) {
            const cmp_col *col = &r->cols[k];
            double v = col->norm == N_MAX ? col->emax : col->norm == N_RMS ? col->erms : col->eend;
            fprintf(f, "compare %s %s: %s %s error %.3g over %d rows", r->name, col->column,
                    norm_name(col->norm), measure_name(col->measure), v, col->npts);
            if (r->noutside) fprintf(f, " (%d outside the path)", r->noutside);
            if (col->has_tol) fprintf(f, ", tolerance %.3g: %s", col->tol, col->pass > 0 ? "ok" : "EXCEEDED");
            fputc('\n', f);
        }
    }
}

int sf_compare_check(const sf_compare *c, sf_error *err)
{
    if (!c) return SF_OK;
    int nfail = 0;
    const cmp_ref *fr = NULL;
    const cmp_col *fc = NULL;
    for (int i = 0; i < c->nref; i++)
        for (int k = 0; k < c->refs[i].ncols; k++)
            if (c->refs[i].cols[k].pass == 0) {
                if (!nfail) { fr = &c->refs[i]; fc = &c->refs[i].cols[k]; }
                nfail++;
            }
    if (!nfail) return SF_OK;
    char more[64] = "";
    if (nfail > 1) snprintf(more, sizeof more, " (and %d more)", nfail - 1);
    if (fc->npts == 0)
        return sf_study_fail(c->s, err, SF_ETOLERANCE, fc->key, "%s against %s: no reference row lies on "
                             "the computed path, so the tolerance cannot be checked%s", c->qname[fc->q],
                             fr->name, more);
    double v = fc->norm == N_MAX ? fc->emax : fc->norm == N_RMS ? fc->erms : fc->eend;
    return sf_study_fail(c->s, err, SF_ETOLERANCE, fc->key, "%s against %s column %s: %s %s error %.4g "
                         "exceeds the tolerance %.4g%s", c->qname[fc->q], fr->name, fc->column,
                         norm_name(fc->norm), measure_name(fc->measure), v, fc->tol, more);
}
