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

/* Messages are one line: control characters that came with a value (a
 * newline inside a string of the study) are shown as escapes, so "a\nb"
 * stays on one line; the escaped text is cut at the buffer's end. */
static void one_line(char *msg, size_t cap)
{
    char out[sizeof ((sf_error *)0)->msg];
    size_t n = 0;
    for (const char *p = msg; *p && n + 1 < sizeof out; p++) {
        unsigned char c = (unsigned char)*p;
        if (c >= 0x20 && c != 0x7f) { out[n++] = (char)c; continue; }
        char esc[8];
        if (c == '\n') snprintf(esc, sizeof esc, "\\n");
        else if (c == '\r') snprintf(esc, sizeof esc, "\\r");
        else if (c == '\t') snprintf(esc, sizeof esc, "\\t");
        else snprintf(esc, sizeof esc, "\\x%02x", c);
        size_t l = strlen(esc);
        if (n + l + 1 > sizeof out) break;
        memcpy(out + n, esc, l);
        n += l;
    }
    out[n] = '\0';
    snprintf(msg, cap, "%s", out);
}

int sf_fail(sf_error *e, int code, const char *fmt, ...)
{
    if (!e || e->code != SF_OK) return code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->msg, sizeof e->msg, fmt, ap);
    va_end(ap);
    one_line(e->msg, sizeof e->msg);
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
    one_line(e->msg, sizeof e->msg);
}
