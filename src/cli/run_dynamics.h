/* run_dynamics.h - `smoothfold run` for analysis.type = "dynamics". */
#ifndef SF_RUN_DYNAMICS_H
#define SF_RUN_DYNAMICS_H

#include "commands.h"
#include "scene.h"
#include "sf_error.h"

/* Integrate the study's trajectory and write DIR/trajectory.tsv,
 * DIR/stats.csv, DIR/shapes.pvd (+ DIR/shapes/), DIR/study.cfg, then the
 * plots (docs/reference/output-files.md).  sc is open; the caller closes it. */
int sf_run_dynamics(sf_scene *sc, const sf_options *o, sf_error *err);

#endif
