/* compare.h - reference data compared with a computed path (prefix
 * sf_compare_).
 *
 * A study names reference files in `references` (docs/reference/study-keys.md):
 * CSV files with a provenance header (`# source:`, `# kind:` measured or
 * simulated, `# units:`, optionally `# columns:`), one row of column
 * names, then rows of numbers.  One column, the abscissa, places each
 * reference row on the path (e.g. load_factor -> p); the other named
 * columns are compared with study quantities (e.g. probe1_uz -> probe1_uz).
 *
 * Life cycle, as `smoothfold run` uses it:
 *   sf_compare_open    read and check every reference file before anything
 *                      is computed (bad files: one line "file:line: ...");
 *   sf_compare_add     every computed point of the path (state y, p);
 *   sf_compare_eval    place the reference rows on the path and measure
 *                      the errors (see below);
 *   sf_compare_write   DIR/compare.tsv (one row per compared column: max,
 *                      RMS and end errors, tolerance, status) and
 *                      DIR/compare-points.tsv (one row per reference row);
 *   sf_compare_check   SF_ETOLERANCE when a declared tolerance is exceeded.
 *
 * Placing a reference row on the path.  The path is cut into pieces that
 * are strictly monotone in the abscissa quantity (a new piece starts where
 * the abscissa turns back, e.g. at a limit point when the abscissa is the
 * load, and at every new branch block); consecutive pieces share their
 * turning point.  A reference row is compared on the piece, among those
 * that contain its abscissa, whose values are closest to the row's (sum
 * over compared columns of |difference| / max |reference column|); on a
 * tie (pieces that meet at a turning point, a path that passes the same
 * state twice) the first piece at or after the previous row's wins, rows
 * being taken in file order, so a reference that follows the path is
 * matched in order.  Rows whose
 * abscissa lies on no piece are counted as `outside` and not compared.
 * When the abscissa is the continuation parameter p (or `load` while p is
 * the load factor) and references[].solve is true, the equilibrium is
 * solved at exactly that p (Newton at fixed p from the piece's
 * interpolated state, cont_solve_fixed), so the
 * comparison carries no interpolation error; the solve is accepted only if
 * it stays next to that piece (else the interpolated values are used).
 * Otherwise (references[].solve = false, another abscissa, or as that
 * fallback) values are interpolated along the path in its chord length t
 * (the distance between consecutive points in (scaled state, p), a
 * discrete arclength in which every quantity is smooth, also through a
 * limit point): cubic Lagrange through the two bracketing points and their
 * neighbours on the same branch, at the t where the interpolated abscissa
 * equals the row's (found by bisection).  A row whose abscissa equals a
 * computed point takes that point's values.
 */
#ifndef SF_COMPARE_H
#define SF_COMPARE_H

#include <stdio.h>

#include "equilibrium.h"
#include "kinematics.h"
#include "pattern.h"
#include "sf_error.h"

struct cont_solver;
typedef struct sf_compare sf_compare;

/* Read the study's `references`.  *out is NULL when the study has none.
 * Errors (SF_EINPUT, SF_EIO, SF_ENOMEM) name the study key or the file and
 * line. */
int sf_compare_open(sf_compare **out, const sf_study *s, sf_error *err);
void sf_compare_free(sf_compare *c);

/* Number of reference files. */
int sf_compare_count(const sf_compare *c);

/* Record a computed point (state y of eq, parameter p).  block numbers the
 * branch the point belongs to (points of different blocks are never
 * interpolated together).  probes: the study's probes, located. */
int sf_compare_add(sf_compare *c, sf_equil *eq, const sf_mpoint *probes,
                   const double *y, double p, int block, sf_error *err);

/* Place the reference rows on the recorded path and measure the errors.
 * cs: the solver that computed the path (for exact solves at reference
 * values of p), or NULL to interpolate only. */
int sf_compare_eval(sf_compare *c, sf_equil *eq, const sf_mpoint *probes,
                    struct cont_solver *cs, sf_error *err);

/* Write DIR/compare.tsv and DIR/compare-points.tsv (atomically); header:
 * comment lines put first in both. */
int sf_compare_write(const sf_compare *c, const char *dir, const char *header,
                     sf_error *err);

/* One line per reference file: name, where it was found, rows, kind. */
void sf_compare_print_files(const sf_compare *c, FILE *f);

/* One line per compared column (for the program's summary). */
void sf_compare_print(const sf_compare *c, FILE *f);

/* SF_ETOLERANCE with "<study>:<line>: references[..].columns[..]: ..." if a
 * declared tolerance is exceeded (or nothing could be compared), else SF_OK. */
int sf_compare_check(const sf_compare *c, sf_error *err);

/* The study quantity names a reference column may match, for messages and
 * documentation: "p", "load", "energy", "probe<i>_u{x,y,z}",
 * "<probe name>_u{x,y,z}", "theta<j>". */

#endif
