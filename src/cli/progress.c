/* progress.c - the progress reporter thread (progress.h). */
#include "progress.h"

#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct sf_progress {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    pthread_t thread;
    int stop;
    double period;
    double last_line;     /* when the last progress line was printed */
    double phase_start;
    char phase[512];
    long total, done, evals;
};

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void *report(void *arg)
{
    sf_progress *p = arg;
    pthread_mutex_lock(&p->mu);
    while (!p->stop) {
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        /* look four times a second, or twice a period if that is shorter */
        until.tv_nsec += (long)(1e9 * fmin(0.25, 0.5 * p->period));
        if (until.tv_nsec >= 1000000000L) {
            until.tv_sec++;
            until.tv_nsec -= 1000000000L;
        }
        pthread_cond_timedwait(&p->cv, &p->mu, &until);
        double t = now();
        if (p->stop || !p->phase[0] || t - p->last_line < p->period) continue;
        char how[128] = "";
        if (p->total > 0)
            snprintf(how, sizeof how, ": %ld of %ld", p->done, p->total);
        else if (p->evals > 0)
            snprintf(how, sizeof how, ": %ld evaluation%s of the equations", p->evals, p->evals == 1 ? "" : "s");
        fprintf(stderr, "smoothfold: %s%s (%.0f s)\n", p->phase, how, t - p->phase_start);
        p->last_line = t;
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

sf_progress *sf_progress_start(int quiet, double period)
{
    if (quiet) return NULL;
    sf_progress *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->cv, NULL);
    p->period = period;
    p->last_line = p->phase_start = now();
    if (pthread_create(&p->thread, NULL, report, p) != 0) {
        pthread_mutex_destroy(&p->mu);
        pthread_cond_destroy(&p->cv);
        free(p);
        return NULL;
    }
    return p;
}

void sf_progress_stop(sf_progress *p)
{
    if (!p) return;
    pthread_mutex_lock(&p->mu);
    p->stop = 1;
    pthread_cond_signal(&p->cv);
    pthread_mutex_unlock(&p->mu);
    pthread_join(p->thread, NULL);
    pthread_mutex_destroy(&p->mu);
    pthread_cond_destroy(&p->cv);
    free(p);
}

void sf_progress_phase(sf_progress *p, long total, const char *fmt, ...)
{
    if (!p) return;
    pthread_mutex_lock(&p->mu);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(p->phase, sizeof p->phase, fmt, ap);
    va_end(ap);
    p->total = total;
    p->done = p->evals = 0;
    p->phase_start = now();
    pthread_mutex_unlock(&p->mu);
}

void sf_progress_done(sf_progress *p, long done)
{
    if (!p) return;
    pthread_mutex_lock(&p->mu);
    p->done = done;
    pthread_mutex_unlock(&p->mu);
}

void sf_progress_eval(sf_progress *p)
{
    if (!p) return;
    pthread_mutex_lock(&p->mu);
    p->evals++;
    pthread_mutex_unlock(&p->mu);
}

void sf_progress_printed(sf_progress *p)
{
    if (!p) return;
    pthread_mutex_lock(&p->mu);
    p->last_line = now();
    pthread_mutex_unlock(&p->mu);
}
