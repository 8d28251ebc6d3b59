/* progress.h - what a long command is doing, on stderr, at least every few
 * seconds: a reporter thread prints the current phase ("following the
 * path: step to point 12 from p = 0.35"), how far it is (done of total,
 * or the evaluations of the equations so far) and its time, whenever no
 * other progress line was printed for a period.  The program's thread
 * only records (under a mutex), at the places it passes anyway.  Never
 * in a result file; nothing at all with --quiet. */
#ifndef SF_PROGRESS_H
#define SF_PROGRESS_H

typedef struct sf_progress sf_progress;

/* Start reporting every period seconds; NULL when quiet (every other call
 * accepts NULL and does nothing) or when no thread can be started. */
sf_progress *sf_progress_start(int quiet, double period);
/* Stop the thread and free. */
void sf_progress_stop(sf_progress *p);

/* A new phase: what is being done (printf format), with total steps
 * (0: not counted); its clock and counts start at zero. */
void sf_progress_phase(sf_progress *p, long total, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Steps of the phase done so far. */
void sf_progress_done(sf_progress *p, long done);
/* One more evaluation of the equations (residual, Jacobian) in the phase. */
void sf_progress_eval(sf_progress *p);
/* The program printed a progress line of its own: the period starts again. */
void sf_progress_printed(sf_progress *p);

#endif
