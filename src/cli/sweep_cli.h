/* sweep_cli.h - what `smoothfold sweep` (sweep.c, serial) and
 * `smoothfold-sweep-mpi` (sweep_mpi.c) share: options, exit statuses,
 * where the programs are.  docs/guides/sweeps.md. */
#ifndef SF_SWEEP_CLI_H
#define SF_SWEEP_CLI_H

#include <stddef.h>

#include "sweep.h"

typedef struct sf_sweep_opts {
    const char *study;
    const char *dir;
    const char **sets;
    int nset;
    const char **vary;
    int nvary;
    int list;           /* -1: the study's sweep.mode */
    const char *map;
    int quiet;
} sf_sweep_opts;

/* Parse `STUDY.cfg [OPTION]...` (argv[0] is the program or command name).
 * Returns -1 when the sweep should run, else the exit status (0 after
 * --help, 2 after a usage error, printed). */
int sf_sweep_opts_parse(int argc, char **argv, sf_sweep_opts *o);
void sf_sweep_opts_free(sf_sweep_opts *o);

/* Exit status of an sf_error code (as smoothfold's). */
int sf_sweep_exit_code(int code);

/* Directory of the running program (from /proc/self/exe) + "/" + name. */
int sf_sweep_sibling(const char *name, char *buf, size_t n);

/* Plan and open DIR from the options; prints the error and returns the
 * exit status on failure, -1 on success. */
int sf_sweep_setup(const sf_sweep_opts *o, sf_sweep_plan *pl, sf_sweep *sw, int open_dir);

/* One progress line on stderr for a finished variant. */
void sf_sweep_progress(const sf_sweep *sw, const char *row, const char *who);

/* The closing line on stdout (complete) or stderr (stopped by signal sig). */
int sf_sweep_finish(const sf_sweep *sw, int sig, int ran);

#endif
