/* commands.h - the program's commands, one function each.  They may print
 * (to stdout for results, progress to stderr); they never exit. */
#ifndef SF_COMMANDS_H
#define SF_COMMANDS_H

#include "sf_error.h"

typedef struct sf_options {
    const char *study_path;
    const char *output;
    const char **sets;
    int nset;
    const char *angles;
    int quiet;
} sf_options;

int sf_cmd_check(const sf_options *o, sf_error *err);
int sf_cmd_shape(const sf_options *o, sf_error *err);
int sf_cmd_run(const sf_options *o, sf_error *err);
/* `smoothfold sweep STUDY.cfg [OPTION]...` (argv[0] = "sweep"): parses
 * its own options, returns the exit status (sweep.c, docs/sweep.md). */
int sf_cmd_sweep(int argc, char **argv);
/* Run the gnuplot scripts of plots/ on a run directory. */
int sf_cmd_plot(const char *dir, sf_error *err);
/* plots/trajectory.gp on a dynamics run directory (prints nothing). */
int sf_plot_trajectory(const char *dir, sf_error *err);

#endif
