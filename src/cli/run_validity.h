/* run_validity.h - the physical validity (validity.h) of every row a run
 * writes, tallied for the line at its end: equilibrium paths (branch.tsv)
 * trajectories (trajectory.tsv) and stability boundaries (boundary.tsv)
 * share it.  docs/reference/output-files.md,
 * "Physical validity". */
#ifndef SF_RUN_VALIDITY_H
#define SF_RUN_VALIDITY_H

#include <stddef.h>

#include "validity.h"

typedef struct run_validity {
    sf_validity *val;                      /* made at the first row */
    long beyond_rows, cross_rows;          /* rows with folds beyond 180 deg, crossings */
    long first_beyond, first_cross;        /* their first rows */
    sf_validity_report worst_beyond;       /* the row with the fold farthest beyond */
    sf_validity_report worst_cross;        /* the row with the deepest crossing */
    long worst_beyond_row, worst_cross_row;
    double worst_beyond_at, worst_cross_at; /* p or t there */
} run_validity;

/* Check state q of model m (the checker made at the first call; SF_OK or
 * its error, whose message then needs the caller's prefix naming the row). */
int run_validity_check(run_validity *v, const sf_model *m, const double *q, sf_validity_report *rep,
                       sf_error *err);
/* Count the report of row `row` (at = its p, t or second parameter) and
 * write the row's warning field: "" or a comma-separated list of
 * "beyond180" and "crossing". */
void run_validity_add(run_validity *v, const sf_validity_report *rep, long row, double at, char *field,
                      size_t size);
/* Both, for a row checked as it is written. */
int run_validity_row(run_validity *v, const sf_model *m, const double *q, long row, double at,
                     char *field, size_t size, sf_error *err);

/* The line for the end of the run ("" when no row was flagged); at_name
 * is what `at` was ("p", "t", the second parameter's name), file the table
 * with the warning column. */
void run_validity_line(const run_validity *v, const sf_model *m, const char *at_name, const char *file,
                       char *buf, size_t size);

void run_validity_free(run_validity *v);

#endif
