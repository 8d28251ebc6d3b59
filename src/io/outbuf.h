/* outbuf.h - helpers for writing output files: a growing text buffer whose
 * contents sf_write_atomic writes in one go, and mkdir -p.  Used by the
 * run, dynamics and reactions writers. */
#ifndef SF_OUTBUF_H
#define SF_OUTBUF_H

#include <stddef.h>

#include "sf_error.h"

typedef struct sf_outbuf {
    char *s;
    size_t n, cap;
    int oom;        /* an allocation failed: later printfs do nothing */
} sf_outbuf;

/* Append formatted text (grows the buffer; sets oom on failure). */
void sf_outbuf_printf(sf_outbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Column headers of the TSV writers: "\tNAME1\tNAME2 .. \tNAMEn", and
 * "\tprobeK_ux\tprobeK_uy\tprobeK_uz" for K = 1..nprobes. */
void sf_outbuf_numbered_columns(sf_outbuf *b, const char *name, int n);
void sf_outbuf_probe_columns(sf_outbuf *b, int nprobes);
/* Fill callback for sf_write_atomic: ctx is an sf_outbuf, f a FILE *. */
int sf_outbuf_fill(void *ctx, void *f);
void sf_outbuf_free(sf_outbuf *b);

/* Finite values only reach an output file (never a NaN, never a NaN
 * replaced by 0).  Returns 0 when v is finite; else records SF_ENUMERIC
 * with the one line "non-finite WHAT (nan): not written", WHAT being fmt
 * formatted (the quantity and where: point, p, index), and returns it. */
int sf_need_finite(sf_error *err, double v, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Create directory d and its parents (existing ones are fine). */
int sf_mkdir_p(const char *d, sf_error *err);

#endif
