/* compare_impl.h - private to the comparison files of src/analysis/compare/
 * (compare.c, compare_read.c, compare_eval.c, compare_write.c): the
 * comparison's structures and the functions they share (prefix cm_).  The
 * public face is compare.h.
 *
 *   compare.c         quantities compared (p, load, energy, probes), life
 *                     cycle (sf_compare_open, _free, _add)
 *   compare_read.c    reference files found, provenance and rows read,
 *                     columns checked
 *   compare_eval.c    the computed path at the reference abscissae (solve
 *                     at fixed p or interpolate), errors (sf_compare_eval)
 *   compare_write.c   compare.tsv, the summary, the tolerance check
 */
#ifndef SF_COMPARE_IMPL_H
#define SF_COMPARE_IMPL_H

#include <stddef.h>

#include "compare.h"
#include "study.h"

enum { M_SCALED = 0, M_RELATIVE = 1, M_ABSOLUTE = 2 };
enum { N_MAX = 0, N_RMS = 1, N_END = 2 };
enum { Q_P = 0, Q_LOAD = 1, Q_ENERGY = 2, Q_FIRST_PROBE = 3 };

#define PROV_MAX 512

typedef struct cmp_col {
    char key[96];           /* "references[0].columns[1]" */
    char column[SF_NAME_MAX], quantity[SF_NAME_MAX];
    int ccol, q;
    double scale;
    int measure, norm;
    int has_tol;
    double tol;
    double refmax;          /* max |scale * value| over the file's rows */
    /* results */
    int npts;               /* rows compared (relative: rows with a nonzero reference) */
    double emax, erms, eend, xmax;
    double amax, arms, aend;
    int pass;               /* 1 ok, 0 exceeded, -1 no tolerance */
    double *comp;           /* per row: computed value (valid where row is placed) */
} cmp_col;

typedef struct cmp_ref {
    char key[64];           /* "references[0]" */
    char name[SF_NAME_MAX];
    char file[1024];        /* as written in the study */
    char path[2048];        /* where it was found */
    char source[PROV_MAX], kind[PROV_MAX], units[PROV_MAX];
    int ncol, nrow;
    char (*colname)[SF_NAME_MAX];
    double *v;              /* nrow x ncol */
    int *line;              /* file line of each row */
    int xcol, xq;
    double xscale;
    int solve;              /* solve at reference values of p (else interpolate) */
    int ncols;
    cmp_col *cols;
    /* results */
    char *method;           /* per row: 'p' computed point, 's' solved, 'i' interpolated, 'o' outside */
    double *x;              /* per row: abscissa in study units */
    int noutside, nsolved, ninterp, npoint;
} cmp_ref;

struct sf_compare {
    const sf_study *s;
    int nq;                 /* quantities */
    char (*qname)[SF_NAME_MAX];
    int nalias;
    char (*alias)[SF_NAME_MAX];
    int *alias_q;
    int nref;
    cmp_ref *refs;
    /* the recorded path */
    int ny, npts, cap;
    double *pv, *py;        /* npts x nq values, npts x ny states */
    int *pblock;
};

/* compare.c: quantities; life cycle */
void cm_quantities(const sf_compare *c, sf_equil *eq, const sf_mpoint *probes,
                   const double *y, double p, double *out);
const char *cm_suggest_quantity(const sf_compare *c, const char *name);

/* compare_read.c: reference files */
int cm_bad_column(const sf_study *s, const cmp_ref *r, sf_error *err, const char *key,
                  const char *name);
int cm_bad_quantity(const sf_compare *c, sf_error *err, const char *key, const char *name);
int cm_find_column(const cmp_ref *r, const char *name);
int cm_find_file(const char *study_path, const char *file, char *out, size_t n);
int cm_read_reference(cmp_ref *r, sf_error *err);

#endif
