/* sf_error.h - error context shared by every smoothfold module.
 *
 * Library functions never print and never exit: they return a status and
 * record the first error (with its origin) in an sf_error.  Later failures
 * up the call chain may add context in front of the message with
 * sf_error_prefix(), PETSc style, so the program prints one line such as
 *   studies/x.cfg:12: fold 3 (v1->v2): width must be positive (got -0.01)
 */
#ifndef SF_ERROR_H
#define SF_ERROR_H

#include <stddef.h>

enum {
    SF_OK = 0,
    SF_EINPUT = 1,    /* bad input: syntax, value, geometry */
    SF_ENOMEM = 2,
    SF_ENUMERIC = 3,  /* non-finite value, singular matrix, no convergence */
    SF_EIO = 4,       /* file could not be read or written */
    SF_ELOCKED = 5,   /* constraints leave no motion */
    SF_EINTERNAL = 6,
    SF_ETOLERANCE = 7, /* a reference comparison exceeded its declared tolerance */
    SF_ESHORT = 8,    /* a run stopped before the end of its range (max_steps) */
    SF_EDIFFER = 9    /* compare: two runs differ by more than the tolerance */
};

/* the longest message kept, terminator included */
#define SF_MSG_SIZE 2048

typedef struct sf_error {
    int code;         /* SF_OK when no error was recorded */
    char msg[SF_MSG_SIZE];   /* first error, one line, no trailing newline (a stop with
                              * its diagnosis and the keys to try runs to about 1000
                              * characters) */
} sf_error;

void sf_error_clear(sf_error *e);
/* Record an error unless one is already recorded; returns code.  e may be
 * NULL.  The message is kept on one line: control characters (a newline
 * in a value) are written as escapes (\n, \t, \xNN). */
int sf_fail(sf_error *e, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Put "context: " in front of the recorded message (no-op without error). */
void sf_error_prefix(sf_error *e, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

#endif
