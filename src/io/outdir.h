/* outdir.h - the output directory of a run.
 *
 * A run writes into DIR a fixed set of files (docs/reference/output-files.md).  So
 * that old and new results never stand side by side, sf_outdir_prepare
 * removes smoothfold's own earlier outputs from DIR (branch.tsv, shapes/,
 * shapes_branch*.pvd, compare*.tsv, plots, left-over *.tmp, ...) and keeps
 * every other file.  A DIR that is not empty and was not written by
 * smoothfold (no DIR/.smoothfold marker and no table with smoothfold's
 * header) is refused unless force is set.  DIR is created when absent, and
 * the marker DIR/.smoothfold is written.
 */
#ifndef SF_OUTDIR_H
#define SF_OUTDIR_H

#include "sf_error.h"

/* *removed = number of earlier output files removed.  SF_EIO on refusal
 * (the message names DIR and one of its foreign files) or failure. */
int sf_outdir_prepare(const char *dir, int force, int *removed, sf_error *err);

#endif
