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
    int verbose;      /* check: every vertex, not only those that matter */
    int force;        /* run: write into a directory holding other files */
    int plot;         /* run: 1 draw plots, 0 do not, -1 as output.plots says */
    double tol;       /* compare: --tol (when have_tol) */
    int have_tol;
    const char *folds; /* plot: --folds selection */
    struct sf_progress *progress;  /* run, check: the progress reporter
                                      (progress.h), NULL when quiet */
} sf_options;

int sf_cmd_check(const sf_options *o, sf_error *err);
int sf_cmd_shape(const sf_options *o, sf_error *err);
int sf_cmd_run(const sf_options *o, sf_error *err);
/* `smoothfold sweep STUDY.cfg [OPTION]...` (argv[0] = "sweep"): parses
 * its own options, returns the exit status (sweep.c, docs/guides/sweeps.md). */
int sf_cmd_sweep(int argc, char **argv);
/* `smoothfold keys [--verbose]` (argv[0] = "keys"): the study keys of the
 * schema, one per line (cmd_keys.c); returns the exit status. */
int sf_cmd_keys(int argc, char **argv);
/* One warning line on stderr per value far outside physical sense
 * (rest angles beyond pi, widths below a micrometre, E outside 1 kPa ..
 * 10 TPa); the study stays valid. */
struct sf_study;
void sf_cli_warn(const struct sf_study *s);
/* Prepare the output directory of a run (outdir.h: own earlier outputs
 * removed, a foreign non-empty directory refused without --force); says
 * on stderr what it removed unless quiet. */
int sf_cli_outdir(const sf_options *o, const char *dir, sf_error *err);
/* After `run`: when the study asks (analysis.convergence), run it again
 * with K+1 shape modes in every fold into DIR/kplus1, write
 * DIR/convergence.tsv and print the largest differences (cmp_runs.c). */
int sf_cli_convergence(const sf_options *o, sf_error *err);
/* Differences between two equilibrium runs (cmp_runs.c). */
int sf_cmd_compare(const char *dir_a, const char *dir_b, const sf_options *o, sf_error *err);
/* Run the gnuplot scripts of plots/ on a run directory (plot.c); folds:
 * which folds angles.png draws (names, groups, numbers, "all"), or NULL. */
int sf_cmd_plot(const char *dir, const char *folds, sf_error *err);
/* After `run` of an equilibrium path: the plots when --plot, or when the
 * study's output.plots is true and --no-plot was not given. */
int sf_cli_run_plots(const sf_options *o, sf_error *err);
/* plots/trajectory.gp on a dynamics run directory (prints nothing). */
int sf_plot_trajectory(const char *dir, sf_error *err);

/* cmd_pattern.c: the crease-pattern commands pattern, import and export,
 * with their own options (argv[0] is the command). */
#define SF_CMD_USAGE (-2)   /* returned for a usage error (message in err): exit 2 */
int sf_cmd_is_pattern(const char *cmd);
int sf_cmd_pattern(int argc, char **argv, sf_error *err);
/* cmd_fold.c: import a FOLD or SVG crease pattern as a study (or as
 * FOLD); export a study as FOLD. */
struct sf_cp_study_opts;
struct sf_import_opts;
int sf_cmd_import(int argc, char **argv, const char *cmdline, const char *output,
                  const struct sf_import_opts *io, struct sf_cp_study_opts *so, int nset,
                  const char **sets, sf_error *err);
int sf_cmd_export(int argc, char **argv, const char *output, int nset,
                  const char **sets, sf_error *err);

#endif
