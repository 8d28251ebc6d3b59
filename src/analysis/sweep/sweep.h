/* sweep.h - parameter sweeps: many variants of one study, each a full
 * `smoothfold run` in a child process, summarised in one table.
 *
 * A plan (sweep.c) expands the varied keys, given on the command line
 * (--vary KEY=V1,V2,... or KEY=START:STOP:N) or in the study's `sweep`
 * group, into variants: the cartesian product of the value lists, or an
 * explicit list (variant i takes the i-th value of every key).  Each
 * variant is the study with the base --set overrides and its own.
 *
 * Running (sweep_run.c): sf_sweep_spawn() starts `EXE run STUDY --set ...
 * -o DIR/<index> -q` as a child process, its stdout and stderr going to
 * DIR/<index>/run.log; sf_sweep_collect() turns the child's exit status and
 * result files (branch.tsv or trajectory.tsv, special.tsv) into one row of
 * DIR/sweep.tsv; sf_sweep_record() stores the row (DIR/<index>/row.tsv, the
 * mark of a finished variant) and rewrites DIR/sweep.tsv atomically, so the
 * table is complete for the finished variants whenever the sweep is
 * stopped.  sf_sweep_open() on a directory that holds the same plan
 * (DIR/variants.tsv) takes the finished variants over: resume.
 *
 * No MPI here: the serial command (src/cli/sweep.c) and the MPI dispatcher
 * (src/cli/sweep_mpi.c) drive these functions.  docs/guides/sweeps.md.
 */
#ifndef SF_SWEEP_H
#define SF_SWEEP_H

#include <stddef.h>
#include <sys/types.h>

#include "sf_error.h"

#define SF_SWEEP_MAX_VARIANTS 1000000

typedef struct sf_sweep_key {
    char *key;          /* study key path, as for --set ("defaults.width") */
    int nvalues;
    char **set;         /* value in libconfig syntax, for --set */
    char **label;       /* value as written in sweep.tsv (strings unquoted) */
} sf_sweep_key;

typedef struct sf_sweep_plan {
    char study_path[1024];
    char study_name[128];
    unsigned long long study_hash;  /* FNV-1a of the study file's bytes */
    char *study_echo;   /* the merged base study, every line "# " */
    int nbase;          /* --set overrides of every variant */
    char **base;
    int list;           /* 1: explicit list, 0: cartesian product */
    int nkeys;
    sf_sweep_key *keys;
    int nvariants;
    int nprobes;        /* probes of the study: probe<i>_u{x,y,z} columns */
    char map[128];      /* column drawn by plots/sweep.gp ("" = chosen) */
    int width;          /* digits of the variant index (directory names) */
} sf_sweep_plan;

/* Build the plan.  The study is loaded with the nset base overrides (a bad
 * study or override is SF_EINPUT); nvary > 0 --vary specs replace the
 * study's sweep.vary; list < 0 takes sweep.mode from the study, else
 * 1 (list) or 0 (product); map NULL takes sweep.map.  Unknown keys, bad
 * specs, unequal list lengths: SF_EINPUT naming the spec. */
int sf_sweep_plan_make(sf_sweep_plan *pl, const char *study_path, int nset,
                       const char *const *sets, int nvary,
                       const char *const *vary, int list, const char *map,
                       sf_error *err);
void sf_sweep_plan_free(sf_sweep_plan *pl);
/* Index into keys[k].set / .label of the value variant v takes. */
int sf_sweep_value(const sf_sweep_plan *pl, int v, int k);
/* "KEY=LABEL KEY=LABEL" of variant v into buf (for progress lines). */
const char *sf_sweep_describe(const sf_sweep_plan *pl, int v, char *buf,
                              size_t n);
/* "DIR/<index>" of variant v into buf. */
const char *sf_sweep_vdir(const sf_sweep_plan *pl, const char *dir, int v,
                          char *buf, size_t n);

/* Results so far of a sweep into one directory. */
typedef struct sf_sweep {
    const sf_sweep_plan *plan;
    char dir[1024];
    char **rows;        /* nvariants rows of sweep.tsv, NULL: not finished */
    int nfinished;
    int nresumed;       /* finished before this run (resume) */
    int lock_fd;        /* DIR/sweep.lock, locked while the sweep runs */
} sf_sweep;

/* Create dir, lock it (DIR/sweep.lock, flock: a second sweep into the
 * same directory at the same time is SF_EINPUT), write DIR/variants.tsv,
 * or check that an existing one holds the same plan (else SF_EINPUT:
 * another sweep is there), take over the rows of finished variants, write
 * DIR/sweep.tsv. */
int sf_sweep_open(sf_sweep *sw, const sf_sweep_plan *pl, const char *dir,
                  sf_error *err);
void sf_sweep_close(sf_sweep *sw);
/* Store the row of a finished variant (its index is the row's first field)
 * in DIR/<index>/row.tsv and rewrite DIR/sweep.tsv. */
int sf_sweep_record(sf_sweep *sw, const char *row, sf_error *err);
int sf_sweep_write_table(const sf_sweep *sw, sf_error *err);
/* Number of finished variants whose status is not 0. */
int sf_sweep_failed(const sf_sweep *sw);

/* Start variant v: `exe run STUDY --set ... -o DIR/<index> -q` with stdout
 * and stderr in DIR/<index>/run.log and the MPI launcher's variables
 * (OMPI_*, PMIX_*, PMI_*) left out of its environment. */
int sf_sweep_spawn(const sf_sweep_plan *pl, const char *dir, int v,
                   const char *exe, pid_t *pid, sf_error *err);
/* The sweep.tsv row (malloc'd, no newline) of variant v from its exit
 * status (as from waitpid; spawn_failed: the child never started), its
 * wall time and its files.  NULL only when out of memory. */
char *sf_sweep_collect(const sf_sweep_plan *pl, const char *dir, int v,
                       int wstatus, double wall_s);
/* Monotonic clock [s]. */
double sf_sweep_now(void);

#endif
