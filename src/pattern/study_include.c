/* study_include.c - a study's @include directives confined to the study's
 * folder (study_impl.h).
 *
 * libconfig 1.5 reads `@include "NAME"` (at the start of a line) as the
 * file include_dir/NAME, whatever NAME holds ("../../etc/passwd" too), and
 * has no hook to refuse one.  So the text is scanned first, the way its
 * scanner reads it, and each included file (and the files it includes, to
 * libconfig's depth of 10) must resolve, symbolic links followed, inside
 * the study's folder or a folder the user allowed: smoothfold
 * --allow-include=DIR, which sets SMOOTHFOLD_ALLOW_INCLUDE (folders
 * separated by ':'; sweeps pass it on to their runs). */
#include "study_impl.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* is p (a resolved path) dir itself or inside it? */
static int inside(const char *p, const char *dir)
{
    size_t n = strlen(dir);
    if (n == 1 && dir[0] == '/') return 1;
    return strncmp(p, dir, n) == 0 && (p[n] == '/' || p[n] == '\0');
}

static int allowed(const char *real, const char *home)
{
    if (inside(real, home)) return 1;
    const char *env = getenv("SMOOTHFOLD_ALLOW_INCLUDE");
    while (env && *env) {
        const char *c = strchr(env, ':');
        size_t n = c ? (size_t)(c - env) : strlen(env);
        char d[PATH_MAX], r[PATH_MAX];
        if (n > 0 && n < sizeof d) {
            memcpy(d, env, n);
            d[n] = '\0';
            if (realpath(d, r) && inside(real, r)) return 1;
        }
        env = c ? c + 1 : NULL;
    }
    return 0;
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 4096, n = 0;
    char *b = malloc(cap);
    while (b) {
        size_t k = fread(b + n, 1, cap - n - 1, f);
        n += k;
        if (k == 0) break;
        if (n + 1 == cap) {
            char *nb = realloc(b, cap *= 2);
            if (!nb) { free(b); b = NULL; break; }
            b = nb;
        }
    }
    fclose(f);
    if (b) b[n] = '\0';
    return b;
}

static int scan(const char *file, const char *text, const char *incdir, const char *home, int depth,
                sf_error *err)
{
    int line = 1;
    for (const char *s = text; *s; line++) {
        const char *e = strchr(s, '\n');
        const char *p = s;
        while (*p == ' ' || *p == '\t') p++;
        if (strncmp(p, "@include", 8) == 0 && (p[8] == ' ' || p[8] == '\t')) {
            p += 8;
            while (*p == ' ' || *p == '\t') p++;
            const char *q = *p == '"' ? strchr(p + 1, '"') : NULL;
            if (q && (!e || q < e)) {
                char name[PATH_MAX], full[2 * PATH_MAX + 2], real[PATH_MAX];
                size_t n = (size_t)(q - p - 1);
                if (n >= sizeof name) return sf_fail(err, SF_EINPUT, "%s:%d: @include: file name too long", file, line);
                memcpy(name, p + 1, n);
                name[n] = '\0';
                snprintf(full, sizeof full, "%s/%s", incdir, name);
                if (realpath(full, real)) {   /* a missing file: libconfig says so */
                    if (!allowed(real, home))
                        return sf_fail(err, SF_EINPUT, "%s:%d: @include \"%s\": %s is outside the study's folder %s "
                                       "(smoothfold --allow-include=DIR reads includes from DIR too)",
                                       file, line, name, real, home);
                    if (depth >= 10)
                        return sf_fail(err, SF_EINPUT, "%s:%d: @include \"%s\": includes nested deeper than 10",
                                       file, line, name);
                    char *t = slurp(real);
                    if (t) {
                        int rc = scan(name, t, incdir, home, depth + 1, err);
                        free(t);
                        if (rc) return rc;
                    }
                }
            }
        }
        if (!e) break;
        s = e + 1;
    }
    return SF_OK;
}

int st_check_includes(const char *path, const char *text, const char *incdir, sf_error *err)
{
    if (!strstr(text, "@include")) return SF_OK;
    char home[PATH_MAX];
    if (!realpath(incdir, home))
        return sf_fail(err, SF_EIO, "%s: its folder %s: %s", path, incdir, strerror(errno));
    return scan(path, text, incdir, home, 0, err);
}
