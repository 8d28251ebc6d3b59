/* compare_read.c - the reference files of a study (compare_impl.h): found
 * next to the study or in a data directory (SMOOTHFOLD_DATA, shared/data),
 * provenance ("# key: value") and rows read, columns and quantities
 * checked against the study.
 *
 * Reading: a reference file is a CSV file whose first lines are '#'
 * comments carrying its provenance as "# key: value" lines (a key is one
 * word right after "# "; lines "#  ..." indented by two or more spaces
 * continue the previous value).  Required keys: source, kind (its value
 * starts with "measured" or "simulated"), units.  An optional "columns"
 * key must list the header row's names (text in parentheses ignored).
 * Then one row of comma-separated column names and rows of finite numbers.
 */
#include "compare_impl.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static int readable(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* The search rule of docs/reference/study-keys.md: an absolute path as is; a
 * relative one beside the study, then in each directory of
 * $SMOOTHFOLD_DATA (':'-separated), then in shared/data of the study's
 * directory and of each directory above it. */
int cm_find_file(const char *study_path, const char *file, char *out, size_t n)
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

/* A data row t (file line ln) of a reference file: its values appended to
 * r->v (*rcap rows allocated). */
static int read_row(cmp_ref *r, char *t, int ln, int *rcap, sf_error *err)
{
    if (r->nrow == *rcap) {
        *rcap = *rcap ? 2 * *rcap : 32;
        double *v = realloc(r->v, sizeof(double) * (size_t)*rcap * r->ncol);
        int *l = realloc(r->line, sizeof(int) * (size_t)*rcap);
        if (v) r->v = v;
        if (l) r->line = l;
        if (!v || !l) return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    int rc = SF_OK;
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
    if (rc) return rc;
    r->line[r->nrow++] = ln;
    return SF_OK;
}

int cm_read_reference(cmp_ref *r, sf_error *err)
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
                             "(docs/reference/study-keys.md, reference files)", r->path, ln, missing);
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
        rc = read_row(r, t, ln, &rcap, err);
        if (rc) break;
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

int cm_find_column(const cmp_ref *r, const char *name)
{
    for (int j = 0; j < r->ncol; j++)
        if (strcmp(r->colname[j], name) == 0) return j;
    return -1;
}

int cm_bad_column(const sf_study *s, const cmp_ref *r, sf_error *err, const char *key,
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

int cm_bad_quantity(const sf_compare *c, sf_error *err, const char *key, const char *name)
{
    const char *sg = cm_suggest_quantity(c, name);
    char h[128] = "";
    if (sg) snprintf(h, sizeof h, " (did you mean '%s'?)", sg);
    return sf_study_fail(c->s, err, SF_EINPUT, key,
                         "unknown quantity '%s'%s: use p, load, energy, probe<i>_ux|uy|uz, "
                         "<probe name>_ux|uy|uz or theta<j>", name, h);
}
