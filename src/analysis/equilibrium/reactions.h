/* reactions.h - forces of the supports and of a prescribed displacement
 * (MODEL.md 5: their multipliers are the reactions), collected along a
 * path and written as DIR/reactions.tsv (docs/reference/output-files.md).
 *
 * Sign convention: a reaction is the force [N] that the support exerts on
 * the sheet, along the global axis of the prescribed component, i.e.
 * minus the multiplier of its row (F = grad Pi + J^T lambda; a force f on
 * the sheet adds -f . dx/dq to grad Pi).  For the displacement parameter
 * it is the force that holds the probe at the prescribed displacement: the
 * dead load that would give the same equilibrium under load control. */
#ifndef SF_REACTIONS_H
#define SF_REACTIONS_H

#include <stddef.h>

#include "equilibrium.h"
#include "outbuf.h"

/* Reaction of each support/displacement row (q->nsup values) at a solved
 * state y of the problem q. */
void sf_equil_reactions(const sf_equil *q, const double *y, double *out);

/* Column name of row r: "support<i>_<x|y|z>" (support i of the study,
 * from 1) or, for the displacement row, "probe<k>_f<x|y|z>" (probe k, from
 * 1, whose displacement probe<k>_u<c> is prescribed). */
void sf_reaction_name(const sf_equil *q, int probe, int r, char *buf, size_t size);

/* The table along a path. */
typedef struct sf_reactions {
    sf_outbuf rows;
    int probe;      /* probe of the displacement parameter (0-based), or -1 */
} sf_reactions;

void sf_reactions_init(sf_reactions *t, int probe);
/* Append the row of a solved point.  A non-finite value appends nothing
 * and returns SF_ENUMERIC naming the reaction and the point (err). */
int sf_reactions_add(sf_reactions *t, const sf_equil *q, long point, const double *y,
                     double p, double load, sf_error *err);
/* Write path (atomically): the comment lines in header (may be NULL), a
 * units line, the column names, the rows. */
int sf_reactions_write(const sf_reactions *t, const sf_equil *q, const char *path,
                       const char *header, sf_error *err);
void sf_reactions_free(sf_reactions *t);

#endif
