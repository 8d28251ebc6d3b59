/* sf_error.c - first-error-wins error context. */
#include "sf_error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

void sf_error_clear(sf_error *e)
{
    if (!e) return;
    e->code = SF_OK;
    e->msg[0] = '\0';
}

int sf_fail(sf_error *e, int code, const char *fmt, ...)
{
    if (!e || e->code != SF_OK) return code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->msg, sizeof e->msg, fmt, ap);
    va_end(ap);
    e->code = code;
    return code;
}

void sf_error_prefix(sf_error *e, const char *fmt, ...)
{
    if (!e || e->code == SF_OK) return;
    char head[512], old[sizeof e->msg];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(head, sizeof head, fmt, ap);
    va_end(ap);
    memcpy(old, e->msg, sizeof old);
    /* head, ": ", then as much of the old message as fits */
    size_t nh = strlen(head), cap = sizeof e->msg - 1;
    if (nh > cap) nh = cap;
    memcpy(e->msg, head, nh);
    size_t n = nh;
    for (const char *p = ": "; *p && n < cap; p++) e->msg[n++] = *p;
    size_t no = strlen(old);
    if (no > cap - n) no = cap - n;
    memcpy(e->msg + n, old, no);
    e->msg[n + no] = '\0';
}
