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

#include "commands.h"
#include "kinematics.h"
#include "study.h"
#include "topology.h"
#include "vtk.h"

#ifndef PACKAGE_VERSION
#define PACKAGE_VERSION "0.1.0"
#endif

static const char *usage_text =
    "Usage: smoothfold COMMAND STUDY.cfg [OPTION]...\n"
    "Structural analysis of origami sheets with smooth (finite-width) folds.\n"
    "\n"
    "Commands:\n"
    "  check STUDY.cfg         validate a study and print a summary of its sheet\n"
    "  shape STUDY.cfg -o F    write the 3-D shape for given fold angles as VTK\n"
    "                          (.vtp, XML PolyData; default: the flat sheet)\n"
    "  run STUDY.cfg -o DIR    run the study's analysis, write results to DIR\n"
    "  plot DIR                draw the diagrams of a run's results (gnuplot;\n"
    "                          PNG and PDF in DIR)\n"
    "  sweep STUDY.cfg --vary KEY=V1,V2,... -o DIR\n"
    "                          run variants of a study (serially, or under\n"
    "                          mpirun); `smoothfold sweep --help`\n"
    "\n"
    "Options:\n"
    "  -o, --output=PATH       output file (shape) or directory (run)\n"
    "      --set KEY=VALUE     override a study setting by its path, e.g.\n"
    "                          --set materials.fold.E=30.4e6 (repeatable;\n"
    "                          VALUE in libconfig syntax)\n"
    "      --angles=LIST       fold angles in radians, comma-separated in study\n"
    "                          order, or one value for every fold (shape)\n"
    "  -q, --quiet             no progress lines\n"
    "  -h, --help              show this help and exit\n"
    "  -V, --version           show the version and exit\n"
    "\n"
    "Exit status: 0 success, 1 bad input, 2 usage error, 3 numerical failure,\n"
    "4 file error, 5 constraints leave no motion, 6 a reference comparison\n"
    "exceeded its tolerance (run: see DIR/compare.tsv).\n"
    "Documentation: docs/study-format.md, docs/output-format.md.\n";

static int exit_code(int code)
{
    switch (code) {
    case SF_OK: return 0;
    case SF_EINPUT: return 1;
    case SF_ENUMERIC: return 3;
    case SF_EIO: return 4;
    case SF_ELOCKED: return 5;
    case SF_ETOLERANCE: return 6;
    default: return 3;
    }
}

static int fail_usage(const char *msg)
{
    fprintf(stderr, "smoothfold: %s\nTry 'smoothfold --help'.\n", msg);
    return 2;
}

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

int main(int argc, char **argv)
{
    single_threaded_blas();
    if (argc >= 2 && strcmp(argv[1], "sweep") == 0) return sf_cmd_sweep(argc - 1, argv + 1);
    static const struct option longopts[] = {
        {"output", required_argument, NULL, 'o'},
        {"set", required_argument, NULL, 's'},
        {"angles", required_argument, NULL, 'a'},
        {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},
        {"version", no_argument, NULL, 'V'},
        {NULL, 0, NULL, 0},
    };
    sf_options opt;
    memset(&opt, 0, sizeof opt);
    const char **sets = calloc((size_t)argc + 1, sizeof(char *));
    if (!sets) return 3;
    int c;
    while ((c = getopt_long(argc, argv, "o:qhV", longopts, NULL)) != -1) {
        switch (c) {
        case 'o': opt.output = optarg; break;
        case 's':
            if (!strchr(optarg, '=')) {
                free(sets);
                return fail_usage("--set needs KEY=VALUE");
            }
            sets[opt.nset++] = optarg;
            break;
        case 'a': opt.angles = optarg; break;
        case 'q': opt.quiet = 1; break;
        case 'h':
            fputs(usage_text, stdout);
            free(sets);
            return 0;
        case 'V':
            printf("smoothfold %s\n", PACKAGE_VERSION);
            free(sets);
            return 0;
        default:
            free(sets);
            return 2;
        }
    }
    opt.sets = sets;
    if (optind + 2 == argc && strcmp(argv[optind], "plot") == 0) {
        free(sets);
        sf_error err;
        sf_error_clear(&err);
        if (sf_cmd_plot(argv[optind + 1], &err) != SF_OK) {
            fprintf(stderr, "smoothfold: %s\n", err.msg);
            return exit_code(err.code);
        }
        return 0;
    }
    if (optind + 2 != argc) {
        free(sets);
        return fail_usage(optind >= argc ? "missing command" : "expected COMMAND STUDY.cfg");
    }
    const char *cmd = argv[optind];
    opt.study_path = argv[optind + 1];
    sf_error err;
    sf_error_clear(&err);
    int rc;
    if (strcmp(cmd, "check") == 0)
        rc = sf_cmd_check(&opt, &err);
    else if (strcmp(cmd, "shape") == 0)
        rc = sf_cmd_shape(&opt, &err);
    else if (strcmp(cmd, "run") == 0)
        rc = sf_cmd_run(&opt, &err);
    else {
        free(sets);
        char msg[256];
        snprintf(msg, sizeof msg, "unknown command '%s' (commands: check, shape, run, plot, sweep)", cmd);
        return fail_usage(msg);
    }
    free(sets);
    if (rc != SF_OK) {
        if (rc == 2 && err.code == SF_OK) return 2;
        fprintf(stderr, "smoothfold: %s\n", err.code ? err.msg : "failed");
        return exit_code(err.code ? err.code : rc);
    }
    return 0;
}
