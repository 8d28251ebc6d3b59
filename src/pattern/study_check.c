/* study_check.c - checks of a study before it is filled in (study_impl.h):
 * integer literals libconfig 1.5 would silently wrap, the generic check of
 * the tree against the schema (unknown keys, types, finiteness, bounds,
 * required keys, choices), and the schema defaults written into the tree
 * so that the written study and the accessors see them. */
#include "study_impl.h"

#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* Finds the first decimal integer literal (no '.', exponent or L suffix)
 * beyond the range of int.  Returns its line (>= 1) or 0. */
int st_find_int_overflow(const char *p, char *tok, size_t ntok)
{
    int line = 1;
    while (*p) {
        unsigned char c = (unsigned char)*p;
        if (c == '\n') { line++; p++; }
        else if (c == '#' || (c == '/' && p[1] == '/')) {
            while (*p && *p != '\n') p++;
        } else if (c == '/' && p[1] == '*') {
            p += 2;
            while (*p && !(p[0] == '*' && p[1] == '/')) { if (*p == '\n') line++; p++; }
            if (*p) p += 2;
        } else if (c == '"') {
            p++;
            while (*p && *p != '"') {
                if (*p == '\\' && p[1]) p++;
                if (*p == '\n') line++;
                p++;
            }
            if (*p) p++;
        } else if (isalpha(c) || c == '_' || c == '*' || c == '@') {
            p++;   /* '@' (of @include) is no identifier character: step over it */
            while (isalnum((unsigned char)*p) || *p == '_' || *p == '-' || *p == '*') p++;
        } else if (isdigit(c) || (c == '.' && isdigit((unsigned char)p[1]))) {
            const char *start = p;
            int hex = (p[0] == '0' && (p[1] == 'x' || p[1] == 'X'));
            int flt = 0;
            while (*p) {
                if (isalnum((unsigned char)*p) || *p == '.') {
                    if (!hex && (*p == '.' || *p == 'e' || *p == 'E')) flt = 1;
                    p++;
                } else if ((*p == '+' || *p == '-') && !hex && (p[-1] == 'e' || p[-1] == 'E')) {
                    p++;
                } else {
                    break;
                }
            }
            size_t len = (size_t)(p - start);
            if (hex || flt || start[len - 1] == 'L') continue;
            const char *d = start;
            while (*d == '0' && d < p - 1) d++;
            size_t nd = (size_t)(p - d);
            if (nd > 10 || (nd == 10 && strncmp(d, "2147483647", 10) > 0)) {
                snprintf(tok, ntok, "%.*s", (int)(len < 40 ? len : 40), start);
                return line;
            }
        } else {
            p++;
        }
    }
    return 0;
}

static int check_bounds(const sf_study *s, sf_error *err,
                        const config_setting_t *st, const sf_study_key *k,
                        double x)
{
    char got[64];
    unsigned f = k->flags;
    st_show(st, got, sizeof got);
    int isint = k->type == SF_KEY_INT;
    if (!isfinite(x))
        return st_bad(s, err, st, "must be a finite number (got %s)", got);
    int ok = 1;
    if ((f & SF_KEY_GT) && !(x > k->lo)) ok = 0;
    if ((f & SF_KEY_GE) && !(x >= k->lo)) ok = 0;
    if ((f & SF_KEY_LT) && !(x < k->hi)) ok = 0;
    if ((f & SF_KEY_LE) && !(x <= k->hi)) ok = 0;
    if (ok) return SF_OK;
    unsigned lower = f & (SF_KEY_GT | SF_KEY_GE), upper = f & (SF_KEY_LT | SF_KEY_LE);
    if (!upper && lower == SF_KEY_GT && k->lo == 0)
        return st_bad(s, err, st, "must be positive (got %s)", got);
    if (!upper && lower == SF_KEY_GE && k->lo == 0)
        return st_bad(s, err, st, "must not be negative (got %s)", got);
    if (!upper && lower == SF_KEY_GE)
        return st_bad(s, err, st, "must be at least %g (got %s)", k->lo, got);
    if (!upper && lower == SF_KEY_GT)
        return st_bad(s, err, st, "must be greater than %g (got %s)", k->lo, got);
    if (isint && lower == SF_KEY_GE && upper == SF_KEY_LE && k->hi - k->lo == 1)
        return st_bad(s, err, st, "must be %g or %g (got %s)", k->lo, k->hi, got);
    if (lower == SF_KEY_GE && upper == SF_KEY_LE)
        return st_bad(s, err, st, "must be between %g and %g (got %s)", k->lo, k->hi, got);
    return st_bad(s, err, st, "must be in %s%g, %g%s (got %s)",
               lower == SF_KEY_GT ? "(" : "[", k->lo, k->hi,
               upper == SF_KEY_LT ? ")" : "]", got);
}

static int check_node(const sf_study *s, sf_error *err,
                      const config_setting_t *st, const sf_study_key *k,
                      const char *pat);

int st_check_group(const sf_study *s, sf_error *err,
                   const config_setting_t *st, const char *pat)
{
    int n = config_setting_length(st);
    for (int i = 0; i < n; i++) {
        const config_setting_t *m = config_setting_get_elem(st, (unsigned)i);
        char cp[512];
        st_join3(cp, sizeof cp, pat, pat[0] ? "." : "", m->name);
        const sf_study_key *ck = st_schema_find(cp);
        if (!ck) {
            /* the key path only for the message: it costs the position of
             * the group in its list (libconfig), for every fold */
            char kp[512], sb[512], h[600];
            st_keypath(st, kp, sizeof kp);
            const char *sg = st_suggest_key(pat, m->name, sb, sizeof sb);
            if (kp[0])
                return st_bad_raw(s, err, m, "unknown key '%s' in %s%s", m->name, kp, st_hint(h, sizeof h, sg));
            return st_bad_raw(s, err, m, "unknown key '%s' at top level%s", m->name, st_hint(h, sizeof h, sg));
        }
        int rc = check_node(s, err, m, ck, cp);
        if (rc) return rc;
    }
    /* a group switched off (enabled = false, e.g. gravity) needs nothing else */
    const config_setting_t *en = config_setting_get_member(st, "enabled");
    if (en && en->type == CONFIG_TYPE_BOOL && !config_setting_get_bool(en)) return SF_OK;
    int nschema;
    const sf_study_key *schema = sf_study_schema(&nschema);
    for (int i = 0; i < nschema; i++) {
        const char *name;
        if (!(schema[i].flags & SF_KEY_REQUIRED)) continue;
        if (!st_schema_is_child(&schema[i], pat, &name)) continue;
        if (strcmp(name, "*") == 0 || strcmp(name, "[]") == 0) continue;
        if (!config_setting_get_member(st, name)) {
            char kp[512];
            st_keypath(st, kp, sizeof kp);
            if (kp[0]) return st_bad(s, err, st, "missing required key '%s'", name);
            return st_bad_raw(s, err, st, "missing required key '%s'", name);
        }
    }
    return SF_OK;
}

static int check_node(const sf_study *s, sf_error *err,
                      const config_setting_t *st, const sf_study_key *k,
                      const char *pat)
{
    char got[128], cp[512];
    int t = st->type;
    switch (k->type) {
    case SF_KEY_GROUP:
        if (t != CONFIG_TYPE_GROUP)
            return st_bad(s, err, st, "expected a group { ... }, got %s", st_show(st, got, sizeof got));
        return st_check_group(s, err, st, pat);
    case SF_KEY_NAMED: {
        if (t != CONFIG_TYPE_GROUP)
            return st_bad(s, err, st, "expected a group { name = ...; ... }, got %s", st_show(st, got, sizeof got));
        st_join3(cp, sizeof cp, pat, ".*", "");
        const sf_study_key *ck = st_schema_find(cp);
        int n = config_setting_length(st);
        for (int i = 0; i < n && ck; i++) {
            const config_setting_t *m = config_setting_get_elem(st, (unsigned)i);
            if (strlen(m->name) >= SF_NAME_MAX)
                return st_bad_raw(s, err, m, "name '%.20s...' is too long (at most %d characters)", m->name, SF_NAME_MAX - 1);
            int rc = check_node(s, err, m, ck, cp);
            if (rc) return rc;
        }
        return SF_OK;
    }
    case SF_KEY_LIST: {
        int n = config_setting_length(st);
        if (t == CONFIG_TYPE_ARRAY && n == 0) return SF_OK;  /* [] is an empty list too */
        if (t != CONFIG_TYPE_LIST)
            return st_bad(s, err, st, "expected a list ( {...}, {...} ), got %s", st_show(st, got, sizeof got));
        st_join3(cp, sizeof cp, pat, "[]", "");
        const sf_study_key *ck = st_schema_find(cp);
        for (int i = 0; i < n && ck; i++) {
            int rc = check_node(s, err, config_setting_get_elem(st, (unsigned)i), ck, cp);
            if (rc) return rc;
        }
        return SF_OK;
    }
    case SF_KEY_NUMBER:
        if (!st_is_num(st))
            return st_bad(s, err, st, "expected a number, got %s", st_show(st, got, sizeof got));
        return check_bounds(s, err, st, k, st_numval(st));
    case SF_KEY_INT:
        if (t == CONFIG_TYPE_FLOAT)
            return st_bad(s, err, st, "expected an integer, got %s", st_show(st, got, sizeof got));
        if (t != CONFIG_TYPE_INT && t != CONFIG_TYPE_INT64)
            return st_bad(s, err, st, "expected an integer, got %s", st_show(st, got, sizeof got));
        if (t == CONFIG_TYPE_INT64 && (st->value.llval > INT_MAX || st->value.llval < INT_MIN))
            return st_bad(s, err, st, "integer out of range (got %lld)", st->value.llval);
        return check_bounds(s, err, st, k, st_numval(st));
    case SF_KEY_STRING: {
        if (t != CONFIG_TYPE_STRING)
            return st_bad(s, err, st, "expected a string \"...\", got %s", st_show(st, got, sizeof got));
        const char *v = st->value.sval ? st->value.sval : "";
        if (k->choices) {
            char buf[256];
            snprintf(buf, sizeof buf, "%s", k->choices);
            const char *cand[16];
            int nc = 0, found = 0;
            char *save = NULL;
            for (char *tk = strtok_r(buf, "|", &save); tk && nc < 16; tk = strtok_r(NULL, "|", &save)) {
                cand[nc++] = tk;
                if (strcmp(tk, v) == 0) found = 1;
            }
            if (!found) {
                char list[300] = "";
                for (int i = 0; i < nc; i++) {
                    size_t l = strlen(list);
                    snprintf(list + l, sizeof list - l, "%s\"%s\"", i ? (i == nc - 1 ? " or " : ", ") : "", cand[i]);
                }
                char h[300];
                return st_bad(s, err, st, "must be %s (got \"%s\")%s", list, v,
                           st_hint(h, sizeof h, sf_study_suggest(v, nc, cand)));
            }
        }
        if ((k->flags & (SF_KEY_IDENT | SF_KEY_FILESAFE)) && strlen(v) >= SF_NAME_MAX)
            return st_bad(s, err, st, "too long (at most %d characters)", SF_NAME_MAX - 1);
        if ((k->flags & SF_KEY_IDENT) && !st_is_ident(v))
            return st_bad(s, err, st, "'%s' is not a valid name (letters, digits, '_' and '-', starting with a letter or '_')", v);
        if ((k->flags & SF_KEY_FILESAFE) && !st_is_filesafe(v))
            return st_bad(s, err, st, "'%s' is not a valid name (use letters, digits, '_', '-' and '.')", v);
        return SF_OK;
    }
    case SF_KEY_BOOL:
        if (t != CONFIG_TYPE_BOOL)
            return st_bad(s, err, st, "expected true or false, got %s", st_show(st, got, sizeof got));
        return SF_OK;
    case SF_KEY_VEC2:
    case SF_KEY_VEC3:
    case SF_KEY_BOOL3: {
        int want = k->type == SF_KEY_VEC2 ? 2 : 3;
        int isb = k->type == SF_KEY_BOOL3;
        if (t != CONFIG_TYPE_ARRAY && t != CONFIG_TYPE_LIST)
            return st_bad(s, err, st, "expected %s, got %s", st_key_type_name(k->type), st_show(st, got, sizeof got));
        int n = config_setting_length(st);
        if (n != want)
            return st_bad(s, err, st, "expected %s (%d %s), got %d element%s", st_key_type_name(k->type),
                       want, isb ? "booleans" : "numbers", n, n == 1 ? "" : "s");
        for (int i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(st, (unsigned)i);
            if (isb) {
                if (e->type != CONFIG_TYPE_BOOL)
                    return st_bad(s, err, e, "expected true or false, got %s", st_show(e, got, sizeof got));
            } else {
                if (!st_is_num(e))
                    return st_bad(s, err, e, "expected a number, got %s", st_show(e, got, sizeof got));
                int rc = check_bounds(s, err, e, k, st_numval(e));
                if (rc) return rc;
            }
        }
        return SF_OK;
    }
    case SF_KEY_NAMES: {
        if (t != CONFIG_TYPE_ARRAY && t != CONFIG_TYPE_LIST)
            return st_bad(s, err, st, "expected %s, got %s", st_key_type_name(k->type), st_show(st, got, sizeof got));
        int n = config_setting_length(st);
        for (int i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(st, (unsigned)i);
            if (e->type != CONFIG_TYPE_STRING)
                return st_bad(s, err, e, "expected a name \"...\", got %s", st_show(e, got, sizeof got));
        }
        return SF_OK;
    }
    default:
        return sf_fail(err, SF_EINTERNAL, "study schema: bad type for %s", k->path);
    }
}

static int put_default(config_setting_t *g, const char *name,
                       const sf_study_key *k)
{
    double v[3];
    config_setting_t *m;
    switch (k->type) {
    case SF_KEY_NUMBER:
        st_parse_def(k->def, v, 1);
        m = config_setting_add(g, name, CONFIG_TYPE_FLOAT);
        return m && config_setting_set_float(m, v[0]) ? 0 : -1;
    case SF_KEY_INT:
        st_parse_def(k->def, v, 1);
        m = config_setting_add(g, name, CONFIG_TYPE_INT);
        return m && config_setting_set_int(m, (int)v[0]) ? 0 : -1;
    case SF_KEY_BOOL:
        st_parse_def(k->def, v, 1);
        m = config_setting_add(g, name, CONFIG_TYPE_BOOL);
        return m && config_setting_set_bool(m, v[0] != 0) ? 0 : -1;
    case SF_KEY_STRING:
        m = config_setting_add(g, name, CONFIG_TYPE_STRING);
        return m && config_setting_set_string(m, k->def) ? 0 : -1;
    case SF_KEY_VEC2:
    case SF_KEY_VEC3:
    case SF_KEY_BOOL3: {
        int n = k->type == SF_KEY_VEC2 ? 2 : 3;
        st_parse_def(k->def, v, n);
        m = config_setting_add(g, name, CONFIG_TYPE_ARRAY);
        if (!m) return -1;
        for (int i = 0; i < n; i++) {
            if (k->type == SF_KEY_BOOL3) {
                if (!config_setting_set_bool_elem(m, -1, v[i] != 0)) return -1;
            } else if (!config_setting_set_float_elem(m, -1, v[i])) {
                return -1;
            }
        }
        return 0;
    }
    default:
        return -1;
    }
}

int st_materialize(sf_study *s, config_t *cfg, sf_error *err)
{
    config_setting_t *root = config_root_setting(cfg);
    config_setting_t *an = st_mem(root, "analysis");
    const char *type = st_get_str(an, "type", "analysis.type");
    int dynamics = strcmp(type, "dynamics") == 0;
    int nschema;
    const sf_study_key *schema = sf_study_schema(&nschema);
    for (int i = 0; i < nschema; i++) {
        const sf_study_key *k = &schema[i];
        if (strchr(k->path, '[') || strchr(k->path, '*')) continue;
        const char *dot = strchr(k->path, '.');
        if (!dot) continue;                         /* top-level keys */
        if (strchr(dot + 1, '.')) continue;         /* deeper: none with defaults */
        char gname[SF_NAME_MAX];
        snprintf(gname, sizeof gname, "%.*s", (int)(dot - k->path), k->path);
        const char *name = dot + 1;
        const sf_study_key *gk = st_schema_find(gname);
        config_setting_t *g = config_setting_get_member(root, gname);
        if (!g) {
            if (!gk || !(gk->flags & SF_KEY_AUTO)) continue;
            g = config_setting_add(root, gname, CONFIG_TYPE_GROUP);
            if (!g) return sf_fail(err, SF_EINTERNAL, "cannot add %s", gname);
        }
        if (config_setting_get_member(g, name)) continue;
        if ((k->flags & SF_KEY_DYNAMICS) && !dynamics) continue;
        const char *def = k->def;
        char buf[64];
        if (strcmp(k->path, "analysis.end") == 0) {
            const char *param = st_get_str(an, "parameter", "analysis.parameter");
            snprintf(buf, sizeof buf, "%d.0", strcmp(param, "load") == 0 ? s->nstages : 1);
            def = buf;
        } else if (strcmp(k->path, "analysis.report") == 0) {
            def = s->nprobes ? s->probes[0].name : "";
        }
        if (!def) continue;
        sf_study_key tmp = *k;
        tmp.def = def;
        if (put_default(g, name, &tmp))
            return sf_fail(err, SF_EINTERNAL, "cannot add the default of %s", k->path);
    }
    return SF_OK;
}
