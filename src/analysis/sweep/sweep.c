/* sweep.c - the plan of a parameter sweep: varied keys, their values, the
 * variants (sweep.h).  Running and collecting: sweep_run.c. */
#include "sweep.h"

#include <ctype.h>
#include <errno.h>
#include <libconfig.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "study.h"

static char *dup_str(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

/* Does path ("folds[f1].width", "materials.fold.E") match the schema
 * pattern ("folds[].width", "materials.*.E")? */
static int key_matches(const char *pat, const char *path)
{
    while (*pat && *path) {
        if (*pat == '*') {
            pat++;
            if (*path == '.' || *path == '[') return 0;
            while (*path && *path != '.' && *path != '[') path++;
        } else if (pat[0] == '[' && pat[1] == ']') {
            if (*path != '[') return 0;
            const char *e = strchr(path, ']');
            if (!e || e == path + 1) return 0;
            pat += 2;
            path = e + 1;
        } else if (*pat++ != *path++) {
            return 0;
        }
    }
    return *pat == '\0' && *path == '\0';
}

static int check_key(const char *key, const char *spec, sf_error *err)
{
    int n;
    const sf_study_key *sch = sf_study_schema(&n);
    for (int i = 0; i < n; i++)
        if (key_matches(sch[i].path, key)) return SF_OK;
    const char **cand = malloc((size_t)n * sizeof *cand);
    const char *sugg = NULL;
    if (cand) {
        for (int i = 0; i < n; i++) cand[i] = sch[i].path;
        sugg = sf_study_suggest(key, n, cand);
    }
    char hint[200] = "";
    if (sugg) snprintf(hint, sizeof hint, " (did you mean '%s'?)", sugg);
    free(cand);
    return sf_fail(err, SF_EINPUT, "--vary %s: unknown study key '%s'%s", spec, key, hint);
}

static int add_value(sf_sweep_key *k, const char *set, const char *label)
{
    char **s = realloc(k->set, (size_t)(k->nvalues + 1) * sizeof *s);
    if (!s) return SF_ENOMEM;
    k->set = s;
    char **l = realloc(k->label, (size_t)(k->nvalues + 1) * sizeof *l);
    if (!l) return SF_ENOMEM;
    k->label = l;
    k->set[k->nvalues] = dup_str(set);
    k->label[k->nvalues] = dup_str(label);
    if (!k->set[k->nvalues] || !k->label[k->nvalues]) {
        free(k->set[k->nvalues]);
        free(k->label[k->nvalues]);
        return SF_ENOMEM;
    }
    k->nvalues++;
    return SF_OK;
}

static int is_number(const char *s, double *x)
{
    char *end;
    errno = 0;
    *x = strtod(s, &end);
    return end != s && *end == '\0' && errno == 0 && isfinite(*x);
}

/* START:STOP:N, evenly spaced, the ends exact. */
static int add_range(sf_sweep_key *k, char *item, const char *spec, sf_error *err)
{
    char *c1 = strchr(item, ':'), *c2 = c1 ? strchr(c1 + 1, ':') : NULL;
    if (!c2 || strchr(c2 + 1, ':'))
        return sf_fail(err, SF_EINPUT, "--vary %s: expected KEY=START:STOP:N", spec);
    *c1 = *c2 = '\0';
    double a, b, nn;
    if (!is_number(item, &a) || !is_number(c1 + 1, &b))
        return sf_fail(err, SF_EINPUT, "--vary %s: START and STOP must be numbers", spec);
    if (!is_number(c2 + 1, &nn) || nn != floor(nn) || nn < 1 || nn > SF_SWEEP_MAX_VARIANTS)
        return sf_fail(err, SF_EINPUT, "--vary %s: N must be an integer from 1 to %d", spec,
                       SF_SWEEP_MAX_VARIANTS);
    int n = (int)nn;
    if (n == 1 && a != b)
        return sf_fail(err, SF_EINPUT, "--vary %s: N = 1 needs START = STOP", spec);
    for (int i = 0; i < n; i++) {
        double x = n == 1 ? a : (a * (n - 1 - i) + b * i) / (n - 1);
        char buf[64];   /* 15 digits: 0.0048, not 0.0048000000000000004 */
        snprintf(buf, sizeof buf, "%.15g", x);
        if (add_value(k, buf, buf)) return sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    }
    return SF_OK;
}

/* One explicit value: numbers, true/false, "strings", [arrays] and
 * {groups} as given; a bare word becomes a string. */
static int add_item(sf_sweep_key *k, const char *item, const char *spec, sf_error *err)
{
    double x;
    char set[1100], label[1100];
    size_t len = strlen(item);
    if (len == 0 || len > 1000)
        return sf_fail(err, SF_EINPUT, "--vary %s: empty or overlong value", spec);
    if (strchr(item, '\t') || strchr(item, '\n'))
        return sf_fail(err, SF_EINPUT, "--vary %s: a value holds a tab or newline", spec);
    if (is_number(item, &x) || strcmp(item, "true") == 0 || strcmp(item, "false") == 0
        || item[0] == '[' || item[0] == '{' || item[0] == '(') {
        snprintf(set, sizeof set, "%s", item);
        snprintf(label, sizeof label, "%s", item);
    } else if (item[0] == '"') {
        if (len < 2 || item[len - 1] != '"')
            return sf_fail(err, SF_EINPUT, "--vary %s: unterminated string %s", spec, item);
        snprintf(set, sizeof set, "%s", item);
        snprintf(label, sizeof label, "%.*s", (int)(len - 2), item + 1);
    } else {
        if (strchr(item, '"') || strchr(item, '\\'))
            return sf_fail(err, SF_EINPUT, "--vary %s: quote the string value %s", spec, item);
        snprintf(set, sizeof set, "\"%s\"", item);
        snprintf(label, sizeof label, "%s", item);
    }
    if (add_value(k, set, label)) return sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    return SF_OK;
}

/* KEY=V1,V2,... (commas inside [], {}, () and quotes do not split) or
 * KEY=START:STOP:N. */
static int parse_vary(const char *spec, sf_sweep_key *k, sf_error *err)
{
    const char *eq = strchr(spec, '=');
    if (!eq || eq == spec)
        return sf_fail(err, SF_EINPUT, "--vary %s: expected KEY=V1,V2,... or KEY=START:STOP:N", spec);
    k->key = malloc((size_t)(eq - spec) + 1);
    if (!k->key) return sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    memcpy(k->key, spec, (size_t)(eq - spec));
    k->key[eq - spec] = '\0';
    for (const char *c = k->key; *c; c++)
        if (isspace((unsigned char)*c) || *c == '\t')
            return sf_fail(err, SF_EINPUT, "--vary %s: blank in the key", spec);
    if (check_key(k->key, spec, err)) return err->code;
    char *rest = dup_str(eq + 1);
    if (!rest) return sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    int depth = 0, quoted = 0, colon = 0, nitems = 0, rc = SF_OK;
    char *item = rest;
    for (char *c = rest;; c++) {
        if (*c == '"') quoted = !quoted;
        else if (!quoted && (*c == '[' || *c == '{' || *c == '(')) depth++;
        else if (!quoted && (*c == ']' || *c == '}' || *c == ')')) depth--;
        else if (!quoted && depth == 0 && *c == ':') colon = 1;
        if (*c == '\0' || (*c == ',' && !quoted && depth == 0)) {
            int end = *c == '\0';
            *c = '\0';
            nitems++;
            if (colon && (nitems > 1 || !end)) {
                rc = sf_fail(err, SF_EINPUT, "--vary %s: a START:STOP:N range stands alone", spec);
                break;
            }
            rc = colon ? add_range(k, item, spec, err) : add_item(k, item, spec, err);
            if (rc || end) break;
            item = c + 1;
        }
    }
    free(rest);
    if (!rc && k->nvalues == 0) rc = sf_fail(err, SF_EINPUT, "--vary %s: no values", spec);
    return rc;
}

void sf_sweep_plan_free(sf_sweep_plan *pl)
{
    for (int k = 0; k < pl->nkeys; k++) {
        for (int i = 0; i < pl->keys[k].nvalues; i++) {
            free(pl->keys[k].set[i]);
            free(pl->keys[k].label[i]);
        }
        free(pl->keys[k].set);
        free(pl->keys[k].label);
        free(pl->keys[k].key);
    }
    free(pl->keys);
    for (int i = 0; i < pl->nbase; i++) free(pl->base[i]);
    free(pl->base);
    free(pl->study_echo);
    memset(pl, 0, sizeof *pl);
}

static int hash_file(const char *path, unsigned long long *h, sf_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) return sf_fail(err, SF_EIO, "%s: cannot read: %s", path, strerror(errno));
    unsigned long long x = 1469598103934665603ULL;
    int c;
    while ((c = getc(f)) != EOF) x = (x ^ (unsigned char)c) * 1099511628211ULL;
    fclose(f);
    *h = x;
    return SF_OK;
}

/* The varied keys of the study's sweep group (sweep.vary, an array of
 * "KEY=..." strings as for --vary). */
static int study_vary(const sf_study *s, const char ***vary, int *nvary, sf_error *err)
{
    const config_setting_t *v = config_lookup((const config_t *)s->cfg, "sweep.vary");
    *nvary = v ? config_setting_length(v) : 0;
    *vary = calloc((size_t)*nvary + 1, sizeof **vary);
    if (!*vary) return sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    for (int i = 0; i < *nvary; i++)
        (*vary)[i] = config_setting_get_string_elem(v, i);
    return SF_OK;
}

static int plan_keys(sf_sweep_plan *pl, int nvary, const char *const *vary, const sf_study *s,
                     sf_error *err)
{
    pl->keys = calloc((size_t)nvary, sizeof *pl->keys);
    if (!pl->keys) return sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    for (int k = 0; k < nvary; k++) {
        pl->nkeys++;
        if (parse_vary(vary[k], &pl->keys[k], err)) {
            char where[1100];
            if (s) {
                sf_study_where(s, "sweep.vary", where, sizeof where);
                sf_error_prefix(err, "%s: sweep.vary", where);
            }
            return err->code;
        }
        for (int j = 0; j < k; j++)
            if (strcmp(pl->keys[j].key, pl->keys[k].key) == 0)
                return sf_fail(err, SF_EINPUT, "--vary %s: key varied twice", vary[k]);
    }
    double n = pl->list ? pl->keys[0].nvalues : 1;
    for (int k = 0; k < pl->nkeys; k++) {
        if (pl->list && pl->keys[k].nvalues != pl->keys[0].nvalues)
            return sf_fail(err, SF_EINPUT, "sweep list: %s has %d values, %s %d (a list needs "
                           "equal lengths)", pl->keys[k].key, pl->keys[k].nvalues,
                           pl->keys[0].key, pl->keys[0].nvalues);
        if (!pl->list) n *= pl->keys[k].nvalues;
    }
    if (n > SF_SWEEP_MAX_VARIANTS)
        return sf_fail(err, SF_EINPUT, "sweep: %.0f variants, more than %d", n, SF_SWEEP_MAX_VARIANTS);
    pl->nvariants = (int)n;
    pl->width = 1;
    for (int m = pl->nvariants - 1; m >= 10; m /= 10) pl->width++;
    return SF_OK;
}

static int plan_study(sf_sweep_plan *pl, const sf_study *s, int nvary, const char *const *vary,
                      int list, const char *map, sf_error *err)
{
    snprintf(pl->study_name, sizeof pl->study_name, "%s", s->name);
    pl->nprobes = s->nprobes;
    const char *mode = NULL, *smap = NULL;
    if (sf_study_string(s, "sweep.mode", "product", &mode, err)) return err->code;
    if (sf_study_string(s, "sweep.map", "", &smap, err)) return err->code;
    pl->list = list >= 0 ? list : strcmp(mode, "list") == 0;
    snprintf(pl->map, sizeof pl->map, "%s", map ? map : smap);
    char *echo = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&echo, &len);
    if (!f) return sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    int rc = sf_study_print(s, f, "# ", err);
    fclose(f);
    pl->study_echo = echo;
    if (rc) return rc;
    const char **svary = NULL;
    int nsvary = 0;
    if (nvary == 0) {
        if (study_vary(s, &svary, &nsvary, err)) return err->code;
        vary = svary;
        nvary = nsvary;
    }
    if (nvary == 0)
        rc = sf_fail(err, SF_EINPUT, "%s: nothing to vary (give --vary KEY=V1,V2,... or a "
                     "sweep group with vary = [\"KEY=...\"])", pl->study_path);
    else
        rc = plan_keys(pl, nvary, vary, nsvary ? s : NULL, err);
    free(svary);
    return rc;
}

int sf_sweep_plan_make(sf_sweep_plan *pl, const char *study_path, int nset,
                       const char *const *sets, int nvary,
                       const char *const *vary, int list, const char *map,
                       sf_error *err)
{
    memset(pl, 0, sizeof *pl);
    snprintf(pl->study_path, sizeof pl->study_path, "%s", study_path);
    pl->base = calloc((size_t)nset + 1, sizeof *pl->base);
    if (!pl->base) return sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    for (int i = 0; i < nset; i++) {
        pl->base[i] = dup_str(sets[i]);
        if (!pl->base[i]) return sf_fail(err, SF_ENOMEM, "sweep: out of memory");
        pl->nbase++;
    }
    if (hash_file(study_path, &pl->study_hash, err)) return err->code;
    sf_study s;
    if (sf_study_load(study_path, nset, sets, &s, err)) return err->code;
    int rc = plan_study(pl, &s, nvary, vary, list, map, err);
    sf_study_free(&s);
    return rc;
}

int sf_sweep_value(const sf_sweep_plan *pl, int v, int k)
{
    if (pl->list) return v;
    for (int j = pl->nkeys - 1; j > k; j--) v /= pl->keys[j].nvalues;
    return v % pl->keys[k].nvalues;
}

const char *sf_sweep_describe(const sf_sweep_plan *pl, int v, char *buf, size_t n)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int k = 0; k < pl->nkeys && used < n; k++) {
        int r = snprintf(buf + used, n - used, "%s%s=%s", k ? " " : "", pl->keys[k].key,
                         pl->keys[k].label[sf_sweep_value(pl, v, k)]);
        if (r < 0) break;
        used += (size_t)r;
    }
    return buf;
}

const char *sf_sweep_vdir(const sf_sweep_plan *pl, const char *dir, int v, char *buf, size_t n)
{
    snprintf(buf, n, "%s/%0*d", dir, pl->width, v);
    return buf;
}
