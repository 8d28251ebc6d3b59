/* run_boundary.h - `smoothfold run` for analysis.type = "boundary". */
#ifndef SF_RUN_BOUNDARY_H
#define SF_RUN_BOUNDARY_H

#include "commands.h"
#include "scene.h"
#include "sf_error.h"

/* Follow the study's path until the first limit or branch point
 * (analysis.from), then continue that point in the second parameter
 * (analysis.second) in both directions, and write DIR/boundary.tsv and
 * DIR/study.cfg (docs/guides/stability.md, docs/reference/output-files.md).  sc is
 * open; the caller closes it. */
int sf_run_boundary(sf_scene *sc, const sf_options *o, sf_error *err);

#endif
