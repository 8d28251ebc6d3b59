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
    snprintf(e->msg, sizeof e->msg, "%s: %s", head, old);
}
