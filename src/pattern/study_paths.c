/* study_paths.c - key paths of a study ("analysis.step", "folds[2].width",
 * "folds[f1].width"): parsed into components and resolved in the libconfig
 * tree against the schema, for --set (study_set.c) and the accessors
 * (study_access.c). */
#include "study_impl.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { COMP_NAME, COMP_INDEX, COMP_SELECT };
typedef struct comp { int kind; char text[SF_NAME_MAX]; long index; } comp;

/* "a.b[2].c[name]" -> components.  Returns count or -1. */
static int parse_path(const char *path, comp *c, int maxc, char *msg, size_t n)
{
    int nc = 0;
    const char *p = path;
    if (!*p) { snprintf(msg, n, "empty key"); return -1; }
    while (*p) {
        if (nc == maxc) { snprintf(msg, n, "key path too deep"); return -1; }
        if (*p == '[') {
            const char *e = strchr(p, ']');
            if (!e || e == p + 1) { snprintf(msg, n, "bad selector in '%s' (use [index] or [name])", path); return -1; }
            size_t len = (size_t)(e - p - 1);
            if (len >= SF_NAME_MAX) { snprintf(msg, n, "selector too long in '%s'", path); return -1; }
            memcpy(c[nc].text, p + 1, len);
            c[nc].text[len] = '\0';
            char *end;
            errno = 0;
            long v = strtol(c[nc].text, &end, 10);
            if (isdigit((unsigned char)c[nc].text[0]) && *end == '\0' && errno == 0) {
                c[nc].kind = COMP_INDEX;
                c[nc].index = v;
            } else {
                c[nc].kind = COMP_SELECT;
            }
            nc++;
            p = e + 1;
            if (*p == '.') { p++; if (!*p || *p == '.') { snprintf(msg, n, "bad key '%s'", path); return -1; } }
            else if (*p && *p != '[') { snprintf(msg, n, "bad key '%s' (expected '.' or '[' after ']')", path); return -1; }
        } else {
            size_t len = strcspn(p, ".[");
            if (len == 0 || len >= SF_NAME_MAX) { snprintf(msg, n, "bad key '%s'", path); return -1; }
            memcpy(c[nc].text, p, len);
            c[nc].text[len] = '\0';
            c[nc].kind = COMP_NAME;
            nc++;
            p += len;
            if (*p == '.') { p++; if (!*p || *p == '.') { snprintf(msg, n, "bad key '%s'", path); return -1; } }
        }
    }
    return nc;
}

/* Resolve a key path in cfg.  create: make missing groups on the way
 * (their top-most one gets the hook text).  Returns 0, or -1 with msg. */
int st_resolve(config_t *cfg, const char *path, int create,
               const char *hooktext, resolved *r, char *msg, size_t n)
{
    comp c[16];
    int nc = parse_path(path, c, 16, msg, n);
    if (nc < 0) return -1;
    config_setting_t *cur = config_root_setting(cfg);
    const sf_study_key *ck = NULL;   /* entry of cur, NULL = root group */
    char pat[512] = "", shown[512] = "";
    int hooked = 0;
    memset(r, 0, sizeof *r);
    for (int i = 0; i < nc; i++) {
        int last = i == nc - 1;
        int ctype = ck ? ck->type : SF_KEY_GROUP;
        char npat[512];
        if (c[i].kind == COMP_NAME) {
            if (ctype == SF_KEY_GROUP) {
                st_join3(npat, sizeof npat, pat, pat[0] ? "." : "", c[i].text);
                const sf_study_key *k = st_schema_find(npat);
                if (!k) {
                    char sb[512], h[600];
                    const char *sg = st_suggest_key(pat, c[i].text, sb, sizeof sb);
                    if (shown[0])
                        snprintf(msg, n, "unknown key '%s' in %s%s", c[i].text, shown, st_hint(h, sizeof h, sg));
                    else
                        snprintf(msg, n, "unknown key '%s' at top level%s", c[i].text, st_hint(h, sizeof h, sg));
                    return -1;
                }
                ck = k;
            } else if (ctype == SF_KEY_NAMED) {
                st_join3(npat, sizeof npat, pat, ".*", "");
                ck = st_schema_find(npat);
            } else if (ctype == SF_KEY_LIST) {
                snprintf(msg, n, "%s is a list: select an element with [index] or [name]", shown);
                return -1;
            } else {
                snprintf(msg, n, "%s is %s and has no keys (set it whole)", shown, st_key_type_name(ctype));
                return -1;
            }
            if (!ck) { snprintf(msg, n, "'%s' is not in the schema", npat); return -1; }
            config_setting_t *child = cur ? config_setting_get_member(cur, c[i].text) : NULL;
            st_join3(pat, sizeof pat, npat, "", "");
            size_t ls = strlen(shown);
            snprintf(shown + ls, sizeof shown - ls, "%s%s", ls ? "." : "", c[i].text);
            if (last) {
                r->parent = cur;
                r->node = child;
                snprintf(r->name, sizeof r->name, "%s", c[i].text);
                break;
            }
            if (!child && create && cur) {
                if (ck->type != SF_KEY_GROUP && ck->type != SF_KEY_NAMED) {
                    snprintf(msg, n, "%s is absent: set it whole first", shown);
                    return -1;
                }
                if (cur->type != CONFIG_TYPE_GROUP) {
                    snprintf(msg, n, "%s is not a group", shown);
                    return -1;
                }
                child = config_setting_add(cur, c[i].text, CONFIG_TYPE_GROUP);
                if (!child) { snprintf(msg, n, "invalid name '%s'", c[i].text); return -1; }
                if (!hooked && hooktext) { st_set_hook(child, hooktext); hooked = 1; }
            }
            cur = child;
        } else {
            if (ctype != SF_KEY_LIST) {
                if (ctype == SF_KEY_VEC2 || ctype == SF_KEY_VEC3 || ctype == SF_KEY_BOOL3 || ctype == SF_KEY_NAMES)
                    snprintf(msg, n, "%s is an array: set it whole (e.g. %s=%s)", shown, shown, st_key_type_name(ctype));
                else
                    snprintf(msg, n, "%s is not a list", shown[0] ? shown : "the study");
                return -1;
            }
            st_join3(npat, sizeof npat, pat, "[]", "");
            ck = st_schema_find(npat);
            if (!ck) { snprintf(msg, n, "'%s' is not in the schema", npat); return -1; }
            config_setting_t *child = NULL;
            if (cur && cur->type != CONFIG_TYPE_LIST && cur->type != CONFIG_TYPE_ARRAY) {
                snprintf(msg, n, "%s is not a list", shown);
                return -1;
            }
            int len = cur ? config_setting_length(cur) : 0;
            if (c[i].kind == COMP_INDEX) {
                if (c[i].index >= len) {
                    if (len == 0) snprintf(msg, n, "%s has no elements", shown);
                    else snprintf(msg, n, "%s has %d element%s (index 0 to %d)", shown, len, len == 1 ? "" : "s", len - 1);
                    return -1;
                }
                child = config_setting_get_elem(cur, (unsigned)c[i].index);
            } else {
                const char *names[256];
                int nn = 0;
                for (int j = 0; j < len; j++) {
                    config_setting_t *e = config_setting_get_elem(cur, (unsigned)j);
                    config_setting_t *nm = st_mem(e, "name");
                    const char *t = nm && nm->type == CONFIG_TYPE_STRING ? nm->value.sval : NULL;
                    if (t && strcmp(t, c[i].text) == 0) { child = e; break; }
                    if (t && nn < 256) names[nn++] = t;
                }
                if (!child) {
                    char h[600];
                    snprintf(msg, n, "no element named '%s' in %s%s", c[i].text, shown,
                             st_hint(h, sizeof h, sf_study_suggest(c[i].text, nn, names)));
                    return -1;
                }
            }
            st_join3(pat, sizeof pat, npat, "", "");
            size_t ls = strlen(shown);
            snprintf(shown + ls, sizeof shown - ls, "[%s]", c[i].text);
            if (last) {
                r->parent = cur;
                r->node = child;
                r->name[0] = '\0';
                break;
            }
            cur = child;
        }
    }
    r->key = ck;
    st_join3(r->pattern, sizeof r->pattern, pat, "", "");
    return 0;
}
