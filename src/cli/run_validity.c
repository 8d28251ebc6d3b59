/* run_validity.c - the physical validity of a run's rows, tallied
 * (run_validity.h). */
#include "run_validity.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "topology.h"

int run_validity_check(run_validity *v, const sf_model *m, const double *q, sf_validity_report *rep,
                       sf_error *err)
{
    if (!v->val && sf_validity_create(m, m->study->samples, &v->val, err)) return err->code;
    return sf_validity_check(v->val, q, 0, rep, err);
}

void run_validity_add(run_validity *v, const sf_validity_report *rep, long row, double at, char *field,
                      size_t size)
{
    field[0] = '\0';
    if (rep->nbeyond) {
        snprintf(field, size, "beyond180");
        if (!v->beyond_rows) v->first_beyond = row;
        if (!v->beyond_rows++ || fabs(rep->beyond_angle) > fabs(v->worst_beyond.beyond_angle)) {
            v->worst_beyond = *rep;
            v->worst_beyond_row = row;
            v->worst_beyond_at = at;
        }
    }
    if (rep->ncross) {
        size_t L = strlen(field);
        snprintf(field + L, size - L, "%scrossing", L ? "," : "");
        if (!v->cross_rows) v->first_cross = row;
        if (!v->cross_rows++ || rep->cross_sep > v->worst_cross.cross_sep) {
            v->worst_cross = *rep;
            v->worst_cross_row = row;
            v->worst_cross_at = at;
        }
    }
}

int run_validity_row(run_validity *v, const sf_model *m, const double *q, long row, double at,
                     char *field, size_t size, sf_error *err)
{
    field[0] = '\0';
    sf_validity_report rep;
    if (run_validity_check(v, m, q, &rep, err)) return err->code;
    run_validity_add(v, &rep, row, at, field, size);
    return SF_OK;
}

void run_validity_line(const run_validity *v, const sf_model *m, const char *at_name, const char *file,
                       char *buf, size_t size)
{
    buf[0] = '\0';
    if (!v->beyond_rows && !v->cross_rows) return;
    size_t L = 0;
    L += snprintf(buf + L, size - L, "physically invalid shapes:");
    if (v->beyond_rows) {
        const sf_validity_report *w = &v->worst_beyond;
        char f[200];
        sf_topology_fold_name(m->study, w->beyond_fold, f, sizeof f);
        L += snprintf(buf + L, L < size ? size - L : 0, " %ld row%s with folds beyond +-180 degrees "
                      "(from row %ld; farthest %s at %.1f degrees, row %ld, %s = %.6g)",
                      v->beyond_rows, v->beyond_rows == 1 ? "" : "s", v->first_beyond, f,
                      w->beyond_angle * 180 / M_PI, v->worst_beyond_row, at_name, v->worst_beyond_at);
    }
    if (v->cross_rows) {
        const sf_validity_report *w = &v->worst_cross;
        char a[300], b[300];
        sf_validity_part_name(v->val, w->cross_part[0], a, sizeof a);
        sf_validity_part_name(v->val, w->cross_part[1], b, sizeof b);
        L += snprintf(buf + L, L < size ? size - L : 0, "%s %ld row%s where the sheet passes through "
                      "itself (from row %ld; deepest at row %ld, %s = %.6g: %s through %s, material "
                      "%.3g m apart in the flat sheet meeting at (%.4g, %.4g, %.4g) m)",
                      v->beyond_rows ? ";" : "", v->cross_rows, v->cross_rows == 1 ? "" : "s",
                      v->first_cross, v->worst_cross_row, at_name, v->worst_cross_at,
                      a, b, w->cross_sep, w->cross_at[0], w->cross_at[1], w->cross_at[2]);
    }
    if (L < size)
        snprintf(buf + L, size - L, " (warning column of %s; docs/reference/output-files.md, "
                 "\"Physical validity\")", file);
}

void run_validity_free(run_validity *v)
{
    sf_validity_free(v->val);
    memset(v, 0, sizeof *v);
}
