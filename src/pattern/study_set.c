/* study_set.c - --set key.path=value overrides (study.h): the value
 * parsed in libconfig syntax, copied into the tree at the resolved path,
 * the option remembered as the setting's origin for messages. */
#include "study_impl.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int copy_value(config_setting_t *dst, const config_setting_t *src)
{
    switch (src->type) {
    case CONFIG_TYPE_INT: return config_setting_set_int(dst, src->value.ival) ? 0 : -1;
    case CONFIG_TYPE_INT64: return config_setting_set_int64(dst, src->value.llval) ? 0 : -1;
    case CONFIG_TYPE_FLOAT: return config_setting_set_float(dst, src->value.fval) ? 0 : -1;
    case CONFIG_TYPE_BOOL: return config_setting_set_bool(dst, src->value.ival) ? 0 : -1;
    case CONFIG_TYPE_STRING: return config_setting_set_string(dst, src->value.sval) ? 0 : -1;
    case CONFIG_TYPE_GROUP:
    case CONFIG_TYPE_ARRAY:
    case CONFIG_TYPE_LIST: {
        int n = config_setting_length(src);
        for (int i = 0; i < n; i++) {
            const config_setting_t *c = config_setting_get_elem(src, (unsigned)i);
            config_setting_t *d = config_setting_add(
                dst, src->type == CONFIG_TYPE_GROUP ? c->name : NULL, c->type);
            if (!d || copy_value(d, c)) return -1;
        }
        return 0;
    }
    default: return -1;
    }
}

void st_set_hook(config_setting_t *st, const char *text)
{
    free(st->hook);   /* an earlier --set of the same key */
    st->hook = st_xstrdup(text);
}

void st_trim(char *t)
{
    size_t n = strlen(t);
    while (n && isspace((unsigned char)t[n - 1])) t[--n] = '\0';
    size_t i = 0;
    while (isspace((unsigned char)t[i])) i++;
    if (i) memmove(t, t + i, n - i + 1);
}

/* The value text as the schema types the key: a bare word for a string
 * key is that string (the shell ate the quotes of "penalty"); integers
 * where the key holds real numbers (a number, [x, y], [x, y, z]) are
 * those numbers ([0, 0.01] would be a mixed array to libconfig).  Other
 * values are left as they are.  Returns 0, or -1 when out is too small. */
static int typed_value(const sf_study_key *k, const char *val, char *out, size_t n)
{
    size_t o = 0;
#define PUT(ch) do { if (o + 1 >= n) return -1; out[o++] = (ch); } while (0)
    if (k && k->type == SF_KEY_STRING && val[0] != '"') {
        PUT('"');
        for (const char *p = val; *p; p++) {
            if (*p == '"' || *p == '\\') PUT('\\');
            PUT(*p);
        }
        PUT('"');
    } else if (k && (k->type == SF_KEY_NUMBER || k->type == SF_KEY_VEC2 || k->type == SF_KEY_VEC3)) {
        int instr = 0;
        for (const char *p = val; *p; p++) {
            if (*p == '"') instr = !instr;
            int start = !instr && isdigit((unsigned char)*p) &&
                        (p == val || !(isalnum((unsigned char)p[-1]) || p[-1] == '.' || p[-1] == '_'));
            if (!start || (p[0] == '0' && (p[1] == 'x' || p[1] == 'X'))) { PUT(*p); continue; }
            /* the whole literal: digits [. digits] [e [+-] digits] */
            const char *q = p;
            int is_int = 1;
            while (isdigit((unsigned char)*q)) q++;
            if (*q == '.') { is_int = 0; q++; while (isdigit((unsigned char)*q)) q++; }
            if ((*q == 'e' || *q == 'E') &&
                (isdigit((unsigned char)q[1]) || ((q[1] == '-' || q[1] == '+') && isdigit((unsigned char)q[2])))) {
                is_int = 0;
                q += 2;
                while (isdigit((unsigned char)*q)) q++;
            }
            if (isalpha((unsigned char)*q) || *q == '_') is_int = 0;   /* 5L, or a word */
            for (; p < q; p++) PUT(*p);
            if (is_int) { PUT('.'); PUT('0'); }
            p--;
        }
    } else {
        for (const char *p = val; *p; p++) PUT(*p);
    }
    out[o] = '\0';
    return 0;
#undef PUT
}

int st_apply_set(config_t *cfg, const char *text, sf_error *err)
{
    char key[512], val[4096], shown[4700], msg[1024];
    const char *eq = strchr(text, '=');
    if (!eq)
        return sf_fail(err, SF_EINPUT, "--set %s: expected key=value", text);
    size_t lk = (size_t)(eq - text);
    if (lk >= sizeof key || strlen(eq + 1) >= sizeof val)
        return sf_fail(err, SF_EINPUT, "--set %.60s...: too long", text);
    memcpy(key, text, lk);
    key[lk] = '\0';
    snprintf(val, sizeof val, "%s", eq + 1);
    st_trim(key);
    st_trim(val);
    size_t lv = strlen(val);
    if (lv && val[lv - 1] == ';') { val[--lv] = '\0'; st_trim(val); }
    snprintf(shown, sizeof shown, "--set %s=%s", key, val);
    for (char *p = shown; *p; p++) if (*p == '\n' || *p == '\r') *p = ' ';
    if (!key[0]) return sf_fail(err, SF_EINPUT, "%s: empty key", shown);
    if (!val[0]) return sf_fail(err, SF_EINPUT, "%s: empty value", shown);

    /* the key first: its schema type decides how the value reads */
    resolved r;
    if (st_resolve(cfg, key, 1, shown, &r, msg, sizeof msg))
        return sf_fail(err, SF_EINPUT, "%s: %s", shown, msg);
    char typed[sizeof val + 64];
    if (typed_value(r.key, val, typed, sizeof typed))
        return sf_fail(err, SF_EINPUT, "%.60s...: too long", shown);
    snprintf(val, sizeof val, "%s", typed);
    lv = strlen(val);

    char tok[64];
    if (st_find_int_overflow(val, tok, sizeof tok))
        return sf_fail(err, SF_EINPUT,
                       "%s: integer %s is out of range (libconfig would wrap it): write it with a decimal point",
                       shown, tok);

    /* parse the value */
    size_t lb = lv + 16;
    char *buf = malloc(lb);
    if (!buf) return sf_fail(err, SF_ENOMEM, "out of memory");
    snprintf(buf, lb, "v = %s;\n", val);
    config_t tmp;
    config_init(&tmp);
    int ok = config_read_string(&tmp, buf);
    free(buf);
    if (!ok) {
        int code = sf_fail(err, SF_EINPUT, "%s: %s (the value must be in libconfig syntax, e.g. 0.02, \"text\", [0.0, 1.0], true)",
                           shown, config_error_text(&tmp));
        config_destroy(&tmp);
        return code;
    }
    config_setting_t *root = config_root_setting(&tmp);
    config_setting_t *v = config_setting_get_member(root, "v");
    if (config_setting_length(root) != 1 || !v) {
        config_destroy(&tmp);
        return sf_fail(err, SF_EINPUT, "%s: the value must be a single value", shown);
    }

    config_setting_t *t = r.node;
    int rc = SF_OK;
    if (t && t->type == CONFIG_TYPE_FLOAT && (v->type == CONFIG_TYPE_INT || v->type == CONFIG_TYPE_INT64)) {
        /* an integer for a real number: keep the setting (and its place) */
        if (!config_setting_set_float(t, st_numval(v)))
            rc = sf_fail(err, SF_EINTERNAL, "%s: cannot copy the value", shown);
    } else if (t && t->type == v->type) {
        if (config_setting_is_aggregate(t))
            while (config_setting_length(t) > 0) config_setting_remove_elem(t, 0);
        if (copy_value(t, v)) rc = sf_fail(err, SF_EINTERNAL, "%s: cannot copy the value", shown);
    } else if (t && (!r.name[0] || !r.parent || r.parent->type != CONFIG_TYPE_GROUP)) {
        rc = sf_fail(err, SF_EINPUT, "%s: expected %s, got %s", shown,
                     r.key ? st_key_type_name(r.key->type) : st_type_name(t->type), st_type_name(v->type));
    } else {
        if (!r.parent || r.parent->type != CONFIG_TYPE_GROUP) {
            config_destroy(&tmp);
            return sf_fail(err, SF_EINPUT, "%s: cannot set a key inside something that is not a group", shown);
        }
        if (t) config_setting_remove(r.parent, r.name);
        t = config_setting_add(r.parent, r.name, v->type);
        if (!t) rc = sf_fail(err, SF_EINPUT, "%s: invalid name '%s'", shown, r.name);
        else if (copy_value(t, v)) rc = sf_fail(err, SF_EINTERNAL, "%s: cannot copy the value", shown);
    }
    if (rc == SF_OK) st_set_hook(t, shown);
    config_destroy(&tmp);
    return rc;
}
