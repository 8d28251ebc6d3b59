/* outbuf.c - output helpers (outbuf.h). */
#include "outbuf.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int sf_need_finite(sf_error *err, double v, const char *fmt, ...)
{
    if (isfinite(v)) return 0;
    char what[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return sf_fail(err, SF_ENUMERIC, "non-finite %s (%g): not written", what, v);
}

void sf_outbuf_printf(sf_outbuf *b, const char *fmt, ...)
{
    if (b->oom) return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        size_t room = b->cap - b->n;
        int k = vsnprintf(b->s ? b->s + b->n : NULL, b->s ? room : 0, fmt, ap);
        va_end(ap);
        if (k < 0) { b->oom = 1; return; }
        if (b->s && (size_t)k < room) { b->n += (size_t)k; return; }
        size_t cap = b->cap ? 2 * b->cap : 4096;
        while (cap < b->n + (size_t)k + 1) cap *= 2;
        char *ns = realloc(b->s, cap);
        if (!ns) { b->oom = 1; return; }
        b->s = ns;
        b->cap = cap;
    }
}

void sf_outbuf_numbered_columns(sf_outbuf *b, const char *name, int n)
{
    for (int i = 0; i < n; i++) sf_outbuf_printf(b, "\t%s%d", name, i + 1);
}

void sf_outbuf_probe_columns(sf_outbuf *b, int nprobes)
{
    for (int i = 0; i < nprobes; i++)
        sf_outbuf_printf(b, "\tprobe%d_ux\tprobe%d_uy\tprobe%d_uz", i + 1, i + 1, i + 1);
}

int sf_outbuf_fill(void *ctx, void *f)
{
    const sf_outbuf *b = ctx;
    if (b->n && fwrite(b->s, 1, b->n, (FILE *)f) != b->n) return SF_EIO;
    return SF_OK;
}

void sf_outbuf_free(sf_outbuf *b)
{
    free(b->s);
    memset(b, 0, sizeof *b);
}

int sf_mkdir_p(const char *d, sf_error *err)
{
    char tmp[1024];
    snprintf(tmp, sizeof tmp, "%s", d);
    for (char *p = tmp + 1; *p; p++)
        if (*p == '/') {
            *p = '\0';
            if (mkdir(tmp, 0777) != 0 && errno != EEXIST)
                return sf_fail(err, SF_EIO, "%s: cannot create directory: %s", tmp, strerror(errno));
            *p = '/';
        }
    if (mkdir(tmp, 0777) != 0 && errno != EEXIST)
        return sf_fail(err, SF_EIO, "%s: cannot create directory: %s", tmp, strerror(errno));
    return SF_OK;
}
