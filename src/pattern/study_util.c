/* study_util.c - small helpers of the study reader (study_impl.h): names,
 * suggestions, where a setting is (file:line or --set), its key path, the
 * one-line error messages, type names, values shown in messages. */
#include "study_impl.h"

#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int osa_distance(const char *a, const char *b)
{
    enum { M = 64 };
    int la = (int)strlen(a), lb = (int)strlen(b);
    if (la > M - 1) la = M - 1;
    if (lb > M - 1) lb = M - 1;
    int d[M][M];
    for (int i = 0; i <= la; i++) d[i][0] = i;
    for (int j = 0; j <= lb; j++) d[0][j] = j;
    for (int i = 1; i <= la; i++)
        for (int j = 1; j <= lb; j++) {
            int ca = tolower((unsigned char)a[i - 1]);
            int cb = tolower((unsigned char)b[j - 1]);
            int cost = ca != cb;
            int v = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < v) v = d[i][j - 1] + 1;
            if (d[i - 1][j - 1] + cost < v) v = d[i - 1][j - 1] + cost;
            if (i > 1 && j > 1 && ca == tolower((unsigned char)b[j - 2])
                && tolower((unsigned char)a[i - 2]) == cb
                && d[i - 2][j - 2] + 1 < v)
                v = d[i - 2][j - 2] + 1;
            d[i][j] = v;
        }
    return d[la][lb];
}

const char *sf_study_suggest(const char *word, int ncand,
                             const char *const *cand)
{
    if (!word || !word[0]) return NULL;
    int len = (int)strlen(word);
    int maxd = len <= 3 ? 1 : len <= 6 ? 2 : 3;
    const char *best = NULL;
    int bestd = INT_MAX;
    for (int i = 0; i < ncand; i++) {
        if (!cand[i] || !cand[i][0]) continue;
        int d = osa_distance(word, cand[i]);
        if (d < bestd) { bestd = d; best = cand[i]; }
    }
    if (!best || bestd > maxd || bestd >= len) return NULL;
    if (strcmp(best, word) == 0) return NULL;
    return best;
}

/* " (did you mean 'x'?)" or "" */
const char *st_hint(char *buf, size_t n, const char *sugg)
{
    if (sugg) snprintf(buf, n, " (did you mean '%s'?)", sugg);
    else buf[0] = '\0';
    return buf;
}

int st_is_ident(const char *t)
{
    if (!(isalpha((unsigned char)t[0]) || t[0] == '_')) return 0;
    for (const char *p = t + 1; *p; p++)
        if (!(isalnum((unsigned char)*p) || *p == '_' || *p == '-')) return 0;
    return 1;
}

int st_is_filesafe(const char *t)
{
    if (!t[0]) return 0;
    for (const char *p = t; *p; p++)
        if (!(isalnum((unsigned char)*p) || *p == '_' || *p == '-' || *p == '.'))
            return 0;
    return strcmp(t, ".") != 0 && strcmp(t, "..") != 0;
}

void st_copy_name(char *dst, const char *src)
{
    snprintf(dst, SF_NAME_MAX, "%s", src);
}

/* dst = a sep b, truncated to n (no format-truncation warnings) */
void st_join3(char *dst, size_t n, const char *a, const char *sep,
              const char *b)
{
    size_t la = strlen(a), ls = strlen(sep), lb = strlen(b), o = 0;
    if (n == 0) return;
    if (la > n - 1) la = n - 1;
    memmove(dst, a, la);
    o = la;
    if (ls > n - 1 - o) ls = n - 1 - o;
    memcpy(dst + o, sep, ls);
    o += ls;
    if (lb > n - 1 - o) lb = n - 1 - o;
    memcpy(dst + o, b, lb);
    dst[o + lb] = '\0';
}

char *st_xstrdup(const char *t)
{
    size_t n = strlen(t) + 1;
    char *p = malloc(n);
    if (p) memcpy(p, t, n);
    return p;
}

void st_where(const sf_study *s, const config_setting_t *st, char *buf,
              size_t n)
{
    for (const config_setting_t *p = st; p; p = p->parent)
        if (p->hook) { snprintf(buf, n, "%s", (const char *)p->hook); return; }
    const config_setting_t *p = st;
    while (p && p->parent && p->line == 0) p = p->parent;
    if (p && p->parent && p->line > 0) {
        const char *f = config_setting_source_file(p);
        snprintf(buf, n, "%s:%u", f ? f : s->path, p->line);
    } else {
        snprintf(buf, n, "%s", s->path);
    }
}

void st_keypath(const config_setting_t *st, char *buf, size_t n)
{
    if (!st || !st->parent) { buf[0] = '\0'; return; }
    st_keypath(st->parent, buf, n);
    size_t l = strlen(buf);
    if (l >= n) return;
    if (st->parent->type == CONFIG_TYPE_GROUP)
        snprintf(buf + l, n - l, "%s%s", l ? "." : "", st->name);
    else
        snprintf(buf + l, n - l, "[%d]", config_setting_index(st));
}

/* Record "<where>: <keypath>: <message>" (keypath omitted when withpath is
 * 0 or the setting is the root). */
static int vfailat2(const sf_study *s, sf_error *err, int code,
                    const config_setting_t *locst, const config_setting_t *st,
                    int withpath, const char *fmt, va_list ap)
{
    char loc[1200], kp[512], msg[1024];
    st_where(s, locst, loc, sizeof loc);
    st_keypath(st, kp, sizeof kp);
    vsnprintf(msg, sizeof msg, fmt, ap);
    if (withpath && kp[0])
        return sf_fail(err, code, "%s: %s: %s", loc, kp, msg);
    return sf_fail(err, code, "%s: %s", loc, msg);
}

static int vfailat(const sf_study *s, sf_error *err, int code,
                   const config_setting_t *st, int withpath, const char *fmt,
                   va_list ap)
{
    return vfailat2(s, err, code, st, st, withpath, fmt, ap);
}

/* "<where of locst>: <keypath of st>: <message>" */
__attribute__((format(printf, 5, 6)))
int st_bad2(const sf_study *s, sf_error *err, const config_setting_t *locst,
            const config_setting_t *st, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int r = vfailat2(s, err, SF_EINPUT, locst, st, 1, fmt, ap);
    va_end(ap);
    return r;
}

__attribute__((format(printf, 4, 5)))
int st_bad(const sf_study *s, sf_error *err, const config_setting_t *st,
           const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int r = vfailat(s, err, SF_EINPUT, st, 1, fmt, ap);
    va_end(ap);
    return r;
}

__attribute__((format(printf, 4, 5)))
int st_bad_raw(const sf_study *s, sf_error *err,
               const config_setting_t *st, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int r = vfailat(s, err, SF_EINPUT, st, 0, fmt, ap);
    va_end(ap);
    return r;
}

const char *st_type_name(int t)
{
    switch (t) {
    case CONFIG_TYPE_GROUP: return "a group";
    case CONFIG_TYPE_INT:
    case CONFIG_TYPE_INT64: return "an integer";
    case CONFIG_TYPE_FLOAT: return "a number";
    case CONFIG_TYPE_STRING: return "a string";
    case CONFIG_TYPE_BOOL: return "a boolean";
    case CONFIG_TYPE_ARRAY: return "an array";
    case CONFIG_TYPE_LIST: return "a list";
    default: return "nothing";
    }
}

const char *st_key_type_name(int t)
{
    switch (t) {
    case SF_KEY_GROUP:
    case SF_KEY_NAMED: return "a group { ... }";
    case SF_KEY_LIST: return "a list ( ... )";
    case SF_KEY_NUMBER: return "a number";
    case SF_KEY_INT: return "an integer";
    case SF_KEY_STRING: return "a string";
    case SF_KEY_BOOL: return "true or false";
    case SF_KEY_VEC2: return "[x, y]";
    case SF_KEY_VEC3: return "[x, y, z]";
    case SF_KEY_BOOL3: return "[bool, bool, bool]";
    case SF_KEY_NAMES: return "an array of names [\"a\", \"b\", ...]";
    default: return "?";
    }
}

/* A short rendering of a value for "got ..." */
const char *st_show(const config_setting_t *st, char *buf, size_t n)
{
    switch (st->type) {
    case CONFIG_TYPE_INT: snprintf(buf, n, "%d", st->value.ival); break;
    case CONFIG_TYPE_INT64: snprintf(buf, n, "%lld", st->value.llval); break;
    case CONFIG_TYPE_FLOAT:
        snprintf(buf, n, "%g", st->value.fval);
        if (!strpbrk(buf, ".eni") && strlen(buf) + 3 <= n) strcat(buf, ".0");
        break;
    case CONFIG_TYPE_BOOL: snprintf(buf, n, "%s", st->value.ival ? "true" : "false"); break;
    case CONFIG_TYPE_STRING: snprintf(buf, n, "\"%.40s%s\"", st->value.sval ? st->value.sval : "",
                                      st->value.sval && strlen(st->value.sval) > 40 ? "..." : "");
        break;
    default: snprintf(buf, n, "%s", st_type_name(st->type)); break;
    }
    return buf;
}

int st_is_num(const config_setting_t *st)
{
    return st->type == CONFIG_TYPE_INT || st->type == CONFIG_TYPE_INT64
        || st->type == CONFIG_TYPE_FLOAT;
}

double st_numval(const config_setting_t *st)
{
    switch (st->type) {
    case CONFIG_TYPE_INT: return st->value.ival;
    case CONFIG_TYPE_INT64: return (double)st->value.llval;
    case CONFIG_TYPE_FLOAT: return st->value.fval;
    default: return NAN;
    }
}

config_setting_t *st_mem(const config_setting_t *g, const char *name)
{
    if (!g || g->type != CONFIG_TYPE_GROUP) return NULL;
    return config_setting_get_member(g, name);
}
