/* study_write.c - a study written back as a .cfg file (sf_study_print,
 * sf_study_write; study.h): the merged tree after --set and defaults, in
 * libconfig syntax that reads back to the same study. */
#include "study_impl.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void w_double(FILE *f, double x)
{
    char g[40], fx[64];
    int p;
    for (p = 1; p <= 17; p++) {
        snprintf(g, sizeof g, "%.*g", p, x);
        if (strtod(g, NULL) == x) break;
    }
    fx[0] = '\0';
    double ax = fabs(x);
    if (ax == 0 || (ax >= 1e-4 && ax < 1e16)) {
        for (int d = 1; d <= 20; d++) {
            snprintf(fx, sizeof fx, "%.*f", d, x);
            if (strtod(fx, NULL) == x) break;
        }
        /* trim trailing zeros but keep one digit after the point */
        char *pt = strchr(fx, '.');
        if (pt) {
            size_t l = strlen(fx);
            while (l > (size_t)(pt - fx) + 2 && fx[l - 1] == '0') fx[--l] = '\0';
        }
    }
    char *ep = strchr(g, 'e');
    if (ep) {   /* 1.52e+07 -> 1.52e7, 1e-06 -> 1e-6 */
        char *q = ep + 1, *d = ep + 1;
        if (*q == '+') q++;
        else if (*q == '-') { q++; d++; }
        while (*q == '0' && q[1]) q++;
        memmove(d, q, strlen(q) + 1);
    }
    if (!strpbrk(g, ".e")) {
        size_t l = strlen(g);
        snprintf(g + l, sizeof g - l, ".0");
    }
    if (fx[0] && strlen(fx) <= strlen(g)) fputs(fx, f);
    else fputs(g, f);
}

static void w_string(FILE *f, const char *t)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)t; *p; p++) {
        switch (*p) {
        case '"': fputs("\\\"", f); break;
        case '\\': fputs("\\\\", f); break;
        case '\n': fputs("\\n", f); break;
        case '\r': fputs("\\r", f); break;
        case '\t': fputs("\\t", f); break;
        case '\f': fputs("\\f", f); break;
        default:
            if (*p < 0x20) fprintf(f, "\\x%02x", *p);
            else fputc(*p, f);
        }
    }
    fputc('"', f);
}

static void w_inline(FILE *f, const config_setting_t *st)
{
    int n;
    switch (st->type) {
    case CONFIG_TYPE_INT: fprintf(f, "%d", st->value.ival); break;
    case CONFIG_TYPE_INT64: fprintf(f, "%lldL", st->value.llval); break;
    case CONFIG_TYPE_FLOAT: w_double(f, st->value.fval); break;
    case CONFIG_TYPE_BOOL: fputs(st->value.ival ? "true" : "false", f); break;
    case CONFIG_TYPE_STRING: w_string(f, st->value.sval ? st->value.sval : ""); break;
    case CONFIG_TYPE_ARRAY:
    case CONFIG_TYPE_LIST:
        n = config_setting_length(st);
        fputs(st->type == CONFIG_TYPE_ARRAY ? "[" : "(", f);
        for (int i = 0; i < n; i++) {
            fputs(i ? ", " : (st->type == CONFIG_TYPE_LIST ? " " : ""), f);
            w_inline(f, config_setting_get_elem(st, (unsigned)i));
        }
        fputs(st->type == CONFIG_TYPE_ARRAY ? "]" : (n ? " )" : ")"), f);
        break;
    case CONFIG_TYPE_GROUP:
        n = config_setting_length(st);
        fputs("{", f);
        for (int i = 0; i < n; i++) {
            const config_setting_t *m = config_setting_get_elem(st, (unsigned)i);
            fprintf(f, " %s = ", m->name);
            w_inline(f, m);
            fputc(';', f);
        }
        fputs(n ? " }" : "}", f);
        break;
    default: break;
    }
}

/* The --set comments of a subtree: "  # --set a=1; --set b=2" */
static void w_hooks(FILE *f, const config_setting_t *st, int *first)
{
    if (st->hook) {
        fputs(*first ? "  # " : "; ", f);
        for (const char *p = st->hook; *p; p++) fputc(*p == '\n' ? ' ' : *p, f);
        *first = 0;
    }
    if (config_setting_is_aggregate(st)) {
        int n = config_setting_length(st);
        for (int i = 0; i < n; i++) w_hooks(f, config_setting_get_elem(st, (unsigned)i), first);
    }
}

static void w_top(FILE *f, const config_setting_t *st)
{
    int n = config_setting_length(st);
    int first = 1;
    fprintf(f, "%s = ", st->name);
    if (st->type == CONFIG_TYPE_GROUP && n > 0) {
        fputs("{", f);
        if (st->hook) { w_hooks(f, st, &first); }
        fputc('\n', f);
        for (int i = 0; i < n; i++) {
            const config_setting_t *m = config_setting_get_elem(st, (unsigned)i);
            fprintf(f, "  %s = ", m->name);
            w_inline(f, m);
            fputc(';', f);
            int fi = 1;
            w_hooks(f, m, &fi);
            fputc('\n', f);
        }
        fputs("};\n", f);
    } else if (st->type == CONFIG_TYPE_LIST && n > 0) {
        fputs("(", f);
        if (st->hook) { w_hooks(f, st, &first); }
        fputc('\n', f);
        for (int i = 0; i < n; i++) {
            const config_setting_t *m = config_setting_get_elem(st, (unsigned)i);
            fputs("  ", f);
            w_inline(f, m);
            if (i < n - 1) fputc(',', f);
            int fi = 1;
            w_hooks(f, m, &fi);
            fputc('\n', f);
        }
        fputs(");\n", f);
    } else {
        w_inline(f, st);
        fputc(';', f);
        w_hooks(f, st, &first);
        fputc('\n', f);
    }
}

static void w_body(FILE *f, const config_setting_t *root)
{
    int n = config_setting_length(root);
    for (int i = 0; i < n; i++) {
        const config_setting_t *m = config_setting_get_elem(root, (unsigned)i);
        if (i && (config_setting_is_aggregate(m) || config_setting_is_aggregate(config_setting_get_elem(root, (unsigned)i - 1))))
            fputc('\n', f);
        w_top(f, m);
    }
}

int sf_study_print(const sf_study *s, FILE *f, const char *prefix,
                   sf_error *err)
{
    if (!s || !s->cfg) return sf_fail(err, SF_EINTERNAL, "sf_study_print: no study");
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    if (!m) return sf_fail(err, SF_ENOMEM, "out of memory");
    w_body(m, config_root_setting((config_t *)s->cfg));
    if (fclose(m) != 0 || !buf) {
        free(buf);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    if (!prefix) prefix = "";
    for (const char *p = buf; *p;) {
        size_t l = strcspn(p, "\n");
        if (l == 0) {   /* no trailing blanks after the prefix */
            size_t lp = strlen(prefix);
            while (lp && prefix[lp - 1] == ' ') lp--;
            fprintf(f, "%.*s\n", (int)lp, prefix);
        } else {
            fprintf(f, "%s%.*s\n", prefix, (int)l, p);
        }
        p += l;
        if (*p == '\n') p++;
    }
    free(buf);
    if (ferror(f)) return sf_fail(err, SF_EIO, "cannot write the study: %s", strerror(errno));
    return SF_OK;
}

int sf_study_write(const sf_study *s, const char *path,
                   const char *header_comment, sf_error *err)
{
    if (!s || !s->cfg) return sf_fail(err, SF_EINTERNAL, "sf_study_write: no study");
    size_t lp = strlen(path);
    char *tmp = malloc(lp + 5);
    if (!tmp) return sf_fail(err, SF_ENOMEM, "out of memory");
    snprintf(tmp, lp + 5, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f) {
        int rc = sf_fail(err, SF_EIO, "%s: cannot write: %s", tmp, strerror(errno));
        free(tmp);
        return rc;
    }
    if (header_comment) {
        const char *p = header_comment;
        while (*p) {
            size_t l = strcspn(p, "\n");
            fprintf(f, "#%s%.*s\n", l ? " " : "", (int)l, p);
            p += l;
            if (*p == '\n') p++;
        }
    }
    w_body(f, config_root_setting((config_t *)s->cfg));
    int bad_write = ferror(f);
    if (fclose(f) != 0) bad_write = 1;
    if (bad_write) {
        int rc = sf_fail(err, SF_EIO, "%s: write failed: %s", tmp, strerror(errno));
        remove(tmp);
        free(tmp);
        return rc;
    }
    if (rename(tmp, path) != 0) {
        int rc = sf_fail(err, SF_EIO, "%s: cannot rename to %s: %s", tmp, path, strerror(errno));
        remove(tmp);
        free(tmp);
        return rc;
    }
    free(tmp);
    return SF_OK;
}
