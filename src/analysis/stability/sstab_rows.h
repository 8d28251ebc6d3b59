/* sstab_rows.h - a maximal set of independent constraint rows for sstab.c,
 * decided by SuiteSparseQR and reused from point to point while a check
 * shows that it still spans the rows (docs/guides/stability.md, "Rank of C").
 *
 * The rank-revealing QR of C^T (Heath's method) cost far more than the
 * LDL^T of the KKT matrix on large sheets (95 % of an evaluation on a
 * 16 x 16 Miura) while it factorised [C^T, I]; of C^T alone (2026-11-27)
 * it costs less than the check below on the 12 x 12 Miura path, where no
 * check passes (docs/guides/stability.md, "The QR of C^T alone").  The
 * independent rows change only at special states, so the set S of the
 * last QR is kept and checked at the next point:
 *  1. every row of S is nonzero and P = [I, Cs^T; Cs, 0] (Cs: the scaled
 *     rows of S) has no null pivot (MUMPS LDL^T, CNTL(3) = 1e-12): Cs has
 *     full row rank, rank C >= |S|;
 *  2. no other row of C leaves span(Cs): with u = projection of a random
 *     Gaussian vector g onto null(Cs) (one solve with P), d . u is
 *     Gaussian with standard deviation |Pi d|, Pi d the part of the unit
 *     row d outside span(Cs), which the QR compares with its tolerance
 *     1e-9.  Six such vectors; the rows of S give the round-off level of
 *     u (Cs u = 0 exactly).  Accepted when every |d . u| <= 1e-11 and the
 *     round-off is below 1e-12: a row with |Pi d| >= 1e-9 passes all six
 *     draws with probability below (8e-3)^6 ~ 3e-13.  (Round-off puts
 *     |d . u| near 1e-13 on a 16 x 16 Miura, and rows 1e-11 to 1e-9
 *     outside the span, as just off the flat state, get a new QR.)
 * Otherwise (and at the first point) the QR decides anew. */
#ifndef SF_SSTAB_ROWS_H
#define SF_SSTAB_ROWS_H

#include "sf_error.h"
#include "sstab.h"

typedef struct sf_rowbasis sf_rowbasis;

/* For m constraint rows of n coordinates. */
int sf_rowbasis_create(sf_rowbasis **out, int n, int m, sf_error *err);
void sf_rowbasis_free(sf_rowbasis *b);

/* On entry rs[i] = 1 / |row i| and rnew[i] = the index of row i among
 * the mnz nonzero rows (rs[i] = 0, rnew[i] = -1 for a row dropped as
 * zero).  On return rnew[i] is the index of row i among the independent
 * rows or -1 (then rs[i] = 0), *mk their number; *failed = 1 when the QR
 * could not decide the rank.  Errors: lack of memory. */
int sf_rowbasis_select(sf_rowbasis *b, const sf_csc *C, double *rs, int *rnew, int mnz, int *mk,
                       int *failed, sf_error *err);

/* The set of `from` (another object over the same rows, e.g. the one of
 * the evaluation at a point h away) taken as this one's without a QR or a
 * check, with its Heath residuals: 1 done (rs, rnew and *mk as after
 * sf_rowbasis_select), 0 when `from` has no set or a row of it is zero
 * here (rnew[i] < 0), and then nothing changed. */
int sf_rowbasis_adopt(sf_rowbasis *b, const sf_rowbasis *from, double *rs, int *rnew, int *mk);

/* [m]: for a row of the set, its Heath residual |R(k,k)| at the QR that
 * chose it (its distance from the span of the rows chosen before it, on
 * the unit rows); 0 for other rows. */
const double *sf_rowbasis_resid(const sf_rowbasis *b);

/* Counts since creation: rank-revealing QRs, points whose set was reused,
 * checks made.  Checks likely to fail are left out and the QR decides, as
 * after a failure: a set of n rows (Cs square, whose round-off fails the
 * check on nearly dependent rows) is not checked for the next 7 points
 * after a failed check (15, 31 after 2, 3 or more failures in a row); any
 * other set, after f >= 2 failures in a row, for the next 2^(f-1) - 1
 * points, at most 7 (docs/guides/stability.md, "Checks left out"). */
void sf_rowbasis_counts(const sf_rowbasis *b, int *qr, int *reused, int *checks);

/* SuiteSparseQR's count of floating-point operations, summed over the
 * QRs since creation. */
double sf_rowbasis_qr_flops(const sf_rowbasis *b);

#endif
