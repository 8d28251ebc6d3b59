/* study_access.c - typed accessors of a study's settings (sf_study_double,
 * sf_study_int, ... in study.h): the key path resolved, type and
 * finiteness checked again, errors naming the file and line or the --set
 * option. */
#include "study_impl.h"

#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* Resolve for reading: SF_OK with *node (NULL when absent) and *k. */
static int lookup(const sf_study *s, const char *path, const char *fn,
                  config_setting_t **node, const sf_study_key **k,
                  sf_error *err)
{
    char msg[1024];
    resolved r;
    *node = NULL;
    *k = NULL;
    if (!s || !s->cfg) return sf_fail(err, SF_EINTERNAL, "%s(%s): no study loaded", fn, path);
    if (st_resolve((config_t *)s->cfg, path, 0, NULL, &r, msg, sizeof msg)) {
        if (strstr(msg, "unknown key") || strstr(msg, "not in the schema"))
            return sf_fail(err, SF_EINTERNAL, "%s(%s): %s; add the key to the schema table in study.c", fn, path, msg);
        return sf_fail(err, SF_EINTERNAL, "%s(%s): %s", fn, path, msg);
    }
    *node = r.node;
    *k = r.key;
    return SF_OK;
}

static int wrong_kind(sf_error *err, const char *fn, const char *path,
                      const sf_study_key *k)
{
    return sf_fail(err, SF_EINTERNAL, "%s(%s): the schema types this key as %s",
                   fn, path, st_key_type_name(k->type));
}

int sf_study_double(const sf_study *s, const char *path, double def,
                    double *out, sf_error *err)
{
    config_setting_t *st;
    const sf_study_key *k;
    int rc = lookup(s, path, "sf_study_double", &st, &k, err);
    if (rc) return rc;
    if (k->type != SF_KEY_NUMBER) return wrong_kind(err, "sf_study_double", path, k);
    if (!st) {
        if (k->def) st_parse_def(k->def, &def, 1);
        *out = def;
        return SF_OK;
    }
    char got[128];
    if (!st_is_num(st)) return st_bad(s, err, st, "expected a number, got %s", st_show(st, got, sizeof got));
    double x = st_numval(st);
    if (!isfinite(x)) return st_bad(s, err, st, "must be a finite number (got %g)", x);
    *out = x;
    return SF_OK;
}

int sf_study_int(const sf_study *s, const char *path, int def, int *out,
                 sf_error *err)
{
    config_setting_t *st;
    const sf_study_key *k;
    int rc = lookup(s, path, "sf_study_int", &st, &k, err);
    if (rc) return rc;
    if (k->type != SF_KEY_INT) return wrong_kind(err, "sf_study_int", path, k);
    if (!st) {
        if (k->def) { double v; st_parse_def(k->def, &v, 1); def = (int)v; }
        *out = def;
        return SF_OK;
    }
    char got[128];
    if (st->type == CONFIG_TYPE_INT) { *out = st->value.ival; return SF_OK; }
    if (st->type == CONFIG_TYPE_INT64 && st->value.llval <= INT_MAX && st->value.llval >= INT_MIN) {
        *out = (int)st->value.llval;
        return SF_OK;
    }
    return st_bad(s, err, st, "expected an integer, got %s", st_show(st, got, sizeof got));
}

int sf_study_string(const sf_study *s, const char *path, const char *def,
                    const char **out, sf_error *err)
{
    config_setting_t *st;
    const sf_study_key *k;
    int rc = lookup(s, path, "sf_study_string", &st, &k, err);
    if (rc) return rc;
    if (k->type != SF_KEY_STRING) return wrong_kind(err, "sf_study_string", path, k);
    if (!st) { *out = k->def ? k->def : def; return SF_OK; }
    char got[128];
    if (st->type != CONFIG_TYPE_STRING)
        return st_bad(s, err, st, "expected a string, got %s", st_show(st, got, sizeof got));
    *out = st->value.sval;
    return SF_OK;
}

int sf_study_set_string(sf_study *s, const char *path, const char *value, sf_error *err)
{
    config_setting_t *st;
    const sf_study_key *k;
    int rc = lookup(s, path, "sf_study_set_string", &st, &k, err);
    if (rc) return rc;
    if (k->type != SF_KEY_STRING) return wrong_kind(err, "sf_study_set_string", path, k);
    if (!st || st->type != CONFIG_TYPE_STRING) return SF_OK;
    if (!config_setting_set_string(st, value)) return sf_fail(err, SF_ENOMEM, "out of memory");
    return SF_OK;
}

int sf_study_bool(const sf_study *s, const char *path, int def, int *out,
                  sf_error *err)
{
    config_setting_t *st;
    const sf_study_key *k;
    int rc = lookup(s, path, "sf_study_bool", &st, &k, err);
    if (rc) return rc;
    if (k->type != SF_KEY_BOOL) return wrong_kind(err, "sf_study_bool", path, k);
    if (!st) {
        if (k->def) { double v; st_parse_def(k->def, &v, 1); def = v != 0; }
        *out = def;
        return SF_OK;
    }
    char got[128];
    if (st->type != CONFIG_TYPE_BOOL)
        return st_bad(s, err, st, "expected true or false, got %s", st_show(st, got, sizeof got));
    *out = st->value.ival != 0;
    return SF_OK;
}

int sf_study_doubles(const sf_study *s, const char *path, int nmin, int nmax,
                     double *out, int *n, sf_error *err)
{
    config_setting_t *st;
    const sf_study_key *k;
    *n = 0;
    int rc = lookup(s, path, "sf_study_doubles", &st, &k, err);
    if (rc) return rc;
    if (k->type != SF_KEY_VEC2 && k->type != SF_KEY_VEC3)
        return wrong_kind(err, "sf_study_doubles", path, k);
    if (!st) {
        if (k->def) *n = st_parse_def(k->def, out, nmax);
        return SF_OK;
    }
    char got[128];
    if (st->type != CONFIG_TYPE_ARRAY && st->type != CONFIG_TYPE_LIST)
        return st_bad(s, err, st, "expected an array of numbers, got %s", st_show(st, got, sizeof got));
    int len = config_setting_length(st);
    if (len < nmin || len > nmax) {
        if (nmin == nmax) return st_bad(s, err, st, "expected %d numbers, got %d", nmin, len);
        return st_bad(s, err, st, "expected %d to %d numbers, got %d", nmin, nmax, len);
    }
    for (int i = 0; i < len; i++) {
        const config_setting_t *e = config_setting_get_elem(st, (unsigned)i);
        if (!st_is_num(e)) return st_bad(s, err, e, "expected a number, got %s", st_show(e, got, sizeof got));
        double x = st_numval(e);
        if (!isfinite(x)) return st_bad(s, err, e, "must be a finite number (got %g)", x);
        out[i] = x;
    }
    *n = len;
    return SF_OK;
}

int sf_study_has(const sf_study *s, const char *path)
{
    char msg[512];
    resolved r;
    if (!s || !s->cfg) return 0;
    if (st_resolve((config_t *)s->cfg, path, 0, NULL, &r, msg, sizeof msg)) return 0;
    return r.node != NULL;
}

int sf_study_count(const sf_study *s, const char *path)
{
    char msg[512];
    resolved r;
    if (!s || !s->cfg) return 0;
    if (st_resolve((config_t *)s->cfg, path, 0, NULL, &r, msg, sizeof msg)) return 0;
    if (!r.node || !config_setting_is_aggregate(r.node)) return 0;
    return config_setting_length(r.node);
}

const char *sf_study_where(const sf_study *s, const char *path, char *buf,
                           size_t n)
{
    char msg[512];
    resolved r;
    if (!s || !s->cfg || !path || st_resolve((config_t *)s->cfg, path, 0, NULL, &r, msg, sizeof msg)) {
        snprintf(buf, n, "%s", s ? s->path : "");
        return buf;
    }
    const config_setting_t *st = r.node ? r.node : r.parent;
    if (st) st_where(s, st, buf, n);
    else snprintf(buf, n, "%s", s->path);
    return buf;
}

int sf_study_fail(const sf_study *s, sf_error *err, int code,
                  const char *path, const char *fmt, ...)
{
    char loc[1200], msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    sf_study_where(s, path, loc, sizeof loc);
    if (path && path[0]) return sf_fail(err, code, "%s: %s: %s", loc, path, msg);
    return sf_fail(err, code, "%s: %s", loc, msg);
}
