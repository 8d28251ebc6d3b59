/* main.c - the smoothfold command-line program.
 *
 * The only place that prints or exits.  Every command loads the study
 * (applying --set overrides), builds its topology and model, and reports
 * the first error of any module as one line on stderr.
 */
#define _GNU_SOURCE   /* RTLD_DEFAULT */
#include <dlfcn.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "commands.h"
#include "progress.h"
#include "kinematics.h"
#include "study.h"
#include "topology.h"
#include "vtk.h"

#ifndef PACKAGE_VERSION
#define PACKAGE_VERSION "0.1.0"
#endif

static const char *usage_text =
    "Usage: smoothfold COMMAND ARGUMENT... [OPTION]...\n"
    "Structural analysis of origami sheets with smooth (finite-width) folds.\n"
    "\n"
    "Commands ('smoothfold COMMAND --help' for one command):\n"
    "  check STUDY.cfg         validate a study and print a summary of its sheet\n"
    "  shape STUDY.cfg -o F    write the 3-D shape for given fold angles as VTK\n"
    "                          XML PolyData (F must end in .vtp; default angles:\n"
    "                          the flat sheet)\n"
    "  run STUDY.cfg -o DIR    run the study's analysis, write results to DIR\n"
    "  plot DIR                draw the diagrams of a run's results (gnuplot;\n"
    "                          PNG and PDF in DIR)\n"
    "  compare DIR_A DIR_B     largest differences between two runs of one sheet\n"
    "                          (probes and fold angles at matched p)\n"
    "  pattern NAME -o F       generate a tessellation (miura, yoshimura,\n"
    "                          waterbomb) as a study (.cfg) or FOLD (.fold)\n"
    "  import P.fold -o S.cfg  a FOLD or SVG crease pattern as a ready-to-run\n"
    "                          study (P.svg: Origami Simulator's colours)\n"
    "  export S.cfg -o P.fold  a study's crease pattern as FOLD\n"
    "                          (smoothfold pattern --help for their options)\n"
    "  sweep STUDY.cfg --vary KEY=V1,V2,... -o DIR\n"
    "                          run variants of a study (serially, or under\n"
    "                          mpirun); smoothfold sweep --help\n"
    "  keys [--verbose]        list the study keys (with -v: type, default, unit,\n"
    "                          meaning)\n"
    "\n"
    "Options:\n"
    "  -o, --output=PATH       output file (shape) or directory (run)\n"
    "      --set KEY=VALUE     override a study setting by its path, e.g.\n"
    "                          --set materials.fold.E=30.4e6 (repeatable;\n"
    "                          VALUE in libconfig syntax)\n"
    "      --angles=LIST       fold angles in radians, comma-separated in study\n"
    "                          order, or one value for every fold (shape)\n"
    "      --force             run: write into a directory that holds other\n"
    "                          files than smoothfold's (they are kept)\n"
    "      --plot, --no-plot   run: draw the plots afterwards, or not (default:\n"
    "                          output.plots: true for dynamics, false else)\n"
    "      --folds=LIST        plot, run --plot: folds drawn in angles.png (names,\n"
    "                          groups, numbers, or all)\n"
    "      --allow-include=DIR a study's @include may read files in DIR too\n"
    "                          (default: only the study's folder)\n"
    "  -q, --quiet             no progress lines\n"
    "  -v, --verbose           check: every interior vertex (default: a summary)\n"
    "  -h, --help              show this help and exit\n"
    "  -V, --version           show the version and exit\n"
    "\n"
    "Exit status: 0 success, 1 bad input, 2 usage error, 3 numerical failure,\n"
    "4 file error, 5 constraints leave no motion, 6 a reference comparison\n"
    "exceeded its tolerance (run: see DIR/compare.tsv), 7 the run stopped\n"
    "at analysis.max_steps inside its range (results written, with a line\n"
    "# STOPPED EARLY), 8 compare: the runs differ by more than --tol.\n"
    "Documentation: docs/reference/study-keys.md, docs/reference/output-files.md.\n";

/* One command: its name, its positional arguments and its own help. */
typedef struct command {
    const char *name;
    int nargs;
    const char *args;
    const char *help;
} command;

static const command commands[] = {
    {"check", 1, "STUDY.cfg",
     "Usage: smoothfold check STUDY.cfg [--set KEY=VALUE]... [--verbose] [-q]\n"
     "Validate a study and print a summary of its sheet: faces, folds, vertices\n"
     "by degree, the fixed face, constraints, loads, probes, the mobility verdict\n"
     "(the degrees of freedom the loop constraints leave), the vertices that\n"
     "matter (locked or undecided under their own loops), and the reference files.\n"
     "--verbose: every interior vertex by name, and each one's own mobility.\n"
     "Long analyses say on stderr every 5 s what they are doing (not with -q).\n"
     "Exit status: 0 valid, 1 bad input (one line naming file, line, problem).\n"},
    {"shape", 1, "STUDY.cfg",
     "Usage: smoothfold shape STUDY.cfg -o FILE.vtp [--angles=LIST] [--set KEY=VALUE]...\n"
     "Write the 3-D shape of the sheet for given fold angles (radians; one value\n"
     "for every fold or one per fold in study order; default: flat) as VTK XML\n"
     "PolyData.  FILE must end in .vtp (the only format written; ParaView picks\n"
     "its reader by the extension).\n"
     "Exit status: 0 written, 1 bad input, 2 usage error, 4 file error.\n"},
    {"run", 1, "STUDY.cfg",
     "Usage: smoothfold run STUDY.cfg -o DIR [--set KEY=VALUE]... [--force] [--plot|--no-plot] [-q]\n"
     "Run the study's analysis (equilibrium path or dynamics) and write the results\n"
     "in DIR (docs/reference/output-files.md).  DIR is created if needed.  Earlier results\n"
     "of smoothfold in DIR are removed first (the message says which); a DIR that\n"
     "holds other files is refused unless --force is given (they are kept).\n"
     "--plot / --no-plot: draw the plots afterwards (as `smoothfold plot DIR`), or\n"
    "not (default: the study's output.plots, true for dynamics, false else).\n"
     "Exit status: 0 the end of the range was reached, 1 bad input, 2 usage error,\n"
     "3 numerical failure, 4 file error, 5 no motion, 6 reference tolerance\n"
     "exceeded, 7 stopped at analysis.max_steps inside the range.\n"},
    {"plot", 1, "DIR",
     "Usage: smoothfold plot DIR [--folds=LIST]\n"
     "Draw the diagrams of the results of `smoothfold run` in DIR with gnuplot\n"
     "(plots/*.gp): stability.png|pdf, eigenvalues.png|pdf, angles.png|pdf for an\n"
     "equilibrium run, trajectory.png|pdf for a dynamics run.  Names and units\n"
     "come from DIR/study.cfg.  --folds=LIST: the folds angles.png draws, by fold\n"
     "name, actuation group name or number from 1, comma-separated, or 'all'\n"
     "(default: all up to 8 folds, one colour each; more folds are coloured by\n"
     "group, or mountain/valley when the study has no actuation groups).\n"
     "Exit status: 0 drawn, 4 no results in DIR or gnuplot failed.\n"},
    {"compare", 2, "DIR_A DIR_B",
     "Usage: smoothfold compare DIR_A DIR_B [--tol=T]\n"
     "Compare two equilibrium runs of the same sheet (e.g. K and K+1 shape modes,\n"
     "two step sizes): for every probe displacement and fold angle, the largest\n"
     "difference along branch 1, with B interpolated linearly at the p of A's\n"
     "points (only where both runs have reached p, and only along stretches where\n"
     "p is monotone in B).  Prints a table; with --tol=T the exit status is 8 when\n"
     "a difference exceeds T (in the column's unit: m or rad).\n"
     "Exit status: 0 compared, 4 missing or unreadable branch.tsv, 1 the runs\n"
     "do not match (other columns), 8 a difference above --tol.\n"},
};

static int exit_code(int code)
{
    switch (code) {
    case SF_OK: return 0;
    case SF_EINPUT: return 1;
    case SF_ENUMERIC: return 3;
    case SF_EIO: return 4;
    case SF_ELOCKED: return 5;
    case SF_ETOLERANCE: return 6;
    case SF_ESHORT: return 7;
    case SF_EDIFFER: return 8;
    default: return 3;
    }
}

/* A usage error: one line, then where to find help (status 2). */
static int fail_usage_cmd(const char *msg, const char *cmd)
{
    fprintf(stderr, "smoothfold: %s (try 'smoothfold %s%s--help')\n", msg, cmd ? cmd : "",
            cmd ? " " : "");
    return 2;
}

static int fail_usage(const char *msg) { return fail_usage_cmd(msg, NULL); }

/* OpenBLAS, when it is the LAPACK loaded: its worker threads are of no use
 * on the small matrices here (at most a few hundred rows), and they spin
 * for a while after they start, doubling the CPU time of a run and taking
 * the other core of a shared machine.  One thread, and the idle workers
 * stopped (as OpenBLAS itself does before a fork).  Looked up at run time,
 * so that any LAPACK links. */
static void single_threaded_blas(void)
{
    void (*set)(int) = (void (*)(int))dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
    int (*stop)(void) = (int (*)(void))dlsym(RTLD_DEFAULT, "blas_thread_shutdown_");
    if (set) set(1);
    if (set && stop) stop();
}

/* OpenBLAS chooses its kernels when it loads, from the CPU's model number.
 * Debian 12's OpenBLAS (0.3.21) does not know the newer Intel models (e.g.
 * Sapphire Rapids) and falls back to its Prescott (SSE3) kernels, on
 * which the dense fronts of the large sheets' MUMPS factorisations are
 * slower (16x16 Miura: 1.2 to 1.6 times the CPU time; OpenBLAS issue 4267,
 * fixed in 0.3.25).  The choice can
 * only be changed before the library loads, through OPENBLAS_CORETYPE; so
 * when it fell back to Prescott on a CPU that has AVX2 (which no Prescott
 * has), the program starts itself again with the kernels the CPU supports
 * named.  A user's own OPENBLAS_CORETYPE is left alone; if the exec fails,
 * the run carries on with the slow kernels. */
static void blas_kernels_for_this_cpu(char **argv)
{
    if (getenv("OPENBLAS_CORETYPE")) return;
    char *(*corename)(void) = (char *(*)(void))dlsym(RTLD_DEFAULT, "openblas_get_corename");
    const char *core = corename ? corename() : NULL;
    if (!core || strcasecmp(core, "prescott") != 0) return;
    __builtin_cpu_init();
    const char *kernels = NULL;
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512vl"))
        kernels = "SkylakeX";
    else if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
        kernels = "Haswell";
    if (!kernels || setenv("OPENBLAS_CORETYPE", kernels, 1) != 0) return;
    execv("/proc/self/exe", argv);
    unsetenv("OPENBLAS_CORETYPE");   /* not passed on to plot or sweep children */
}

static const command *find_command(const char *name)
{
    for (size_t i = 0; i < sizeof commands / sizeof *commands; i++)
        if (strcmp(commands[i].name, name) == 0) return &commands[i];
    return NULL;
}

/* Dispatch a command whose arguments are counted; returns the exit status. */
static int dispatch(const command *cmd, char **args, sf_options *opt)
{
    sf_error err;
    sf_error_clear(&err);
    int rc;
    if (strcmp(cmd->name, "plot") == 0) {
        rc = sf_cmd_plot(args[0], opt->folds, &err);
    } else if (strcmp(cmd->name, "compare") == 0) {
        rc = sf_cmd_compare(args[0], args[1], opt, &err);
    } else {
        opt->study_path = args[0];
        /* a line on stderr at least every 5 s of run or check */
        if (strcmp(cmd->name, "shape") != 0) {
            /* SMOOTHFOLD_PROGRESS_PERIOD: another period in seconds, for tests */
            const char *pe = getenv("SMOOTHFOLD_PROGRESS_PERIOD");
            double period = pe && atof(pe) > 0 ? atof(pe) : 5.0;
            opt->progress = sf_progress_start(opt->quiet, period);
        }
        if (strcmp(cmd->name, "check") == 0) rc = sf_cmd_check(opt, &err);
        else if (strcmp(cmd->name, "shape") == 0) rc = sf_cmd_shape(opt, &err);
        else rc = sf_cmd_run(opt, &err);
        if (rc == SF_OK && strcmp(cmd->name, "run") == 0)
            rc = sf_cli_convergence(opt, &err);  /* analysis.convergence: K+1 */
        sf_progress_stop(opt->progress);
        opt->progress = NULL;
        if (rc == SF_OK && strcmp(cmd->name, "run") == 0)
            rc = sf_cli_run_plots(opt, &err);   /* --plot, output.plots */
    }
    if (rc != SF_OK) {
        fprintf(stderr, "smoothfold: %s\n", err.code ? err.msg : "failed");
        return exit_code(err.code ? err.code : rc);
    }
    return 0;
}

enum { OPT_SET = 256, OPT_ANGLES, OPT_FORCE, OPT_PLOT, OPT_NOPLOT, OPT_TOL, OPT_FOLDS };

/* --allow-include=DIR (any command, repeatable): a study's @include may
 * read from DIR too (src/pattern/study_include.c).  Taken out of argv
 * here and passed on as SMOOTHFOLD_ALLOW_INCLUDE, which sweeps hand to
 * their runs.  Returns 0, or 2 after a usage message. */
static int take_allow_include(int *argc, char **argv)
{
    int k = 1;
    for (int i = 1; i < *argc; i++) {
        const char *dir = NULL;
        if (strncmp(argv[i], "--allow-include=", 16) == 0) dir = argv[i] + 16;
        else if (strcmp(argv[i], "--allow-include") == 0 && i + 1 < *argc) dir = argv[++i];
        if (!dir) { argv[k++] = argv[i]; continue; }
        char real[4096];
        if (!*dir || !realpath(dir, real))
            return fail_usage("--allow-include needs an existing folder");
        const char *old = getenv("SMOOTHFOLD_ALLOW_INCLUDE");
        size_t n = (old ? strlen(old) + 1 : 0) + strlen(real) + 1;
        char *v = malloc(n);
        if (!v) return 3;
        snprintf(v, n, "%s%s%s", old ? old : "", old ? ":" : "", real);
        setenv("SMOOTHFOLD_ALLOW_INCLUDE", v, 1);
        free(v);
    }
    argv[k] = NULL;
    *argc = k;
    return 0;
}

int main(int argc, char **argv)
{
    blas_kernels_for_this_cpu(argv);
    single_threaded_blas();
    static const struct option longopts[] = {
        {"output", required_argument, NULL, 'o'},
        {"set", required_argument, NULL, OPT_SET},
        {"angles", required_argument, NULL, OPT_ANGLES},
        {"force", no_argument, NULL, OPT_FORCE},
        {"plot", no_argument, NULL, OPT_PLOT},
        {"no-plot", no_argument, NULL, OPT_NOPLOT},
        {"tol", required_argument, NULL, OPT_TOL},
        {"folds", required_argument, NULL, OPT_FOLDS},
        {"quiet", no_argument, NULL, 'q'},
        {"verbose", no_argument, NULL, 'v'},
        {"help", no_argument, NULL, 'h'},
        {"version", no_argument, NULL, 'V'},
        {NULL, 0, NULL, 0},
    };
    int arc = take_allow_include(&argc, argv);
    if (arc) return arc;
    if (argc >= 2 && strcmp(argv[1], "sweep") == 0) return sf_cmd_sweep(argc - 1, argv + 1);
    if (argc >= 2 && strcmp(argv[1], "keys") == 0) return sf_cmd_keys(argc - 1, argv + 1);
    if (argc >= 2 && sf_cmd_is_pattern(argv[1])) {   /* pattern, import, export */
        sf_error perr;
        sf_error_clear(&perr);
        int prc = sf_cmd_pattern(argc - 1, argv + 1, &perr);
        if (prc == SF_CMD_USAGE) return fail_usage_cmd(perr.msg, argv[1]);
        if (prc != SF_OK) {
            fprintf(stderr, "smoothfold: %s\n", perr.msg);
            return exit_code(perr.code);
        }
        return 0;
    }
    sf_options opt;
    memset(&opt, 0, sizeof opt);
    opt.plot = -1;
    const char **sets = calloc((size_t)argc + 1, sizeof(char *));
    if (!sets) return 3;
    opt.sets = sets;
    int c, help = 0, status = -1;
    char msg[512];
    opterr = 0;   /* messages here, under the program's name */
    while (status < 0 && (c = getopt_long(argc, argv, ":o:qvhV", longopts, NULL)) != -1) {
        switch (c) {
        case 'o': opt.output = optarg; break;
        case OPT_SET:
            if (!strchr(optarg, '=')) status = fail_usage("--set needs KEY=VALUE");
            else sets[opt.nset++] = optarg;
            break;
        case OPT_ANGLES: opt.angles = optarg; break;
        case OPT_FORCE: opt.force = 1; break;
        case OPT_FOLDS: opt.folds = optarg; break;
        case OPT_PLOT: opt.plot = 1; break;
        case OPT_NOPLOT: opt.plot = 0; break;
        case OPT_TOL: {
            char *end;
            opt.tol = strtod(optarg, &end);
            if (end == optarg || *end || !isfinite(opt.tol) || opt.tol < 0)
                status = fail_usage("--tol needs a finite number >= 0");
            else opt.have_tol = 1;
            break;
        }
        case 'q': opt.quiet = 1; break;
        case 'v': opt.verbose = 1; break;
        case 'h': help = 1; break;
        case 'V':
            printf("smoothfold %s\n", PACKAGE_VERSION);
            status = 0;
            break;
        case ':':
            snprintf(msg, sizeof msg, "option '%s' needs a value", argv[optind - 1]);
            status = fail_usage(msg);
            break;
        default:
            if (optopt) snprintf(msg, sizeof msg, "unknown option '-%c'", optopt);
            else snprintf(msg, sizeof msg, "unknown option '%s'", argv[optind - 1]);
            status = fail_usage(msg);
            break;
        }
    }
    if (status >= 0) {
        free(sets);
        return status;
    }
    const command *cmd = optind < argc ? find_command(argv[optind]) : NULL;
    if (help) {
        fputs(cmd ? cmd->help : usage_text, stdout);
        free(sets);
        return 0;
    }
    if (optind >= argc) {
        status = fail_usage("missing command (check, shape, run, plot, compare)");
    } else if (!cmd) {
        snprintf(msg, sizeof msg, "unknown command '%s' (commands: check, shape, run, plot, compare, pattern, import, export, sweep, keys)",
                 argv[optind]);
        status = fail_usage(msg);
    } else if (argc - optind - 1 != cmd->nargs) {
        snprintf(msg, sizeof msg, "%s: expected %s, got %d argument%s (smoothfold %s %s)",
                 cmd->name, cmd->args, argc - optind - 1, argc - optind - 1 == 1 ? "" : "s",
                 cmd->name, cmd->args);
        status = fail_usage_cmd(msg, cmd->name);
    } else if (!opt.output && (strcmp(cmd->name, "run") == 0 || strcmp(cmd->name, "shape") == 0)) {
        snprintf(msg, sizeof msg, "%s: give the output %s with -o", cmd->name,
                 cmd->name[0] == 'r' ? "directory" : "file");
        status = fail_usage_cmd(msg, cmd->name);
    } else {
        status = dispatch(cmd, argv + optind + 1, &opt);
    }
    free(sets);
    return status;
}
