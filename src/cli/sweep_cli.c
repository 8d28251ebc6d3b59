/* sweep_cli.c - options and messages shared by `smoothfold sweep` and
 * `smoothfold-sweep-mpi` (sweep_cli.h). */
#include "sweep_cli.h"

#include <getopt.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *usage_text =
    "Usage: smoothfold sweep STUDY.cfg [--vary KEY=V1,V2,...|KEY=START:STOP:N]... -o DIR\n"
    "       mpirun -n N smoothfold sweep STUDY.cfg ... -o DIR\n"
    "Run variants of a study, each a full `smoothfold run` into DIR/<index>/, and\n"
    "summarise them in DIR/sweep.tsv (one row per variant).  Running the same\n"
    "command again skips the finished variants (resume).\n"
    "\n"
    "Options:\n"
    "      --vary SPEC         a varied study key: KEY=V1,V2,... (values in libconfig\n"
    "                          syntax; bare words are strings) or KEY=START:STOP:N\n"
    "                          (N evenly spaced values); repeatable; replaces the\n"
    "                          study's sweep.vary\n"
    "      --list              variant i takes the i-th value of every key (default:\n"
    "                          every combination, the cartesian product)\n"
    "      --product           every combination (overrides sweep.mode = \"list\")\n"
    "      --map COLUMN        column of sweep.tsv drawn by `smoothfold plot DIR`\n"
    "      --set KEY=VALUE     override a study setting in every variant\n"
    "  -o, --output=DIR        results directory (required)\n"
    "  -q, --quiet             no progress lines\n"
    "  -h, --help              show this help and exit\n"
    "\n"
    "Under mpirun (or another MPI launcher) rank 0 hands the variants out to\n"
    "all ranks, itself included.  Exit status: 0 every variant ran (failed\n"
    "variants are rows with their status), 1 bad input, 2 usage error, 4 file\n"
    "error, 128+signal when stopped by SIGTERM or SIGINT.  docs/guides/sweeps.md.\n";

static int usage_error(const char *msg)
{
    fprintf(stderr, "smoothfold sweep: %s\nTry 'smoothfold sweep --help'.\n", msg);
    return 2;
}

int sf_sweep_opts_parse(int argc, char **argv, sf_sweep_opts *o)
{
    static const struct option longopts[] = {
        {"vary", required_argument, NULL, 'v'},
        {"list", no_argument, NULL, 'l'},
        {"product", no_argument, NULL, 'P'},
        {"map", required_argument, NULL, 'm'},
        {"set", required_argument, NULL, 's'},
        {"output", required_argument, NULL, 'o'},
        {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    memset(o, 0, sizeof *o);
    o->list = -1;
    o->sets = calloc((size_t)argc + 1, sizeof *o->sets);
    o->vary = calloc((size_t)argc + 1, sizeof *o->vary);
    if (!o->sets || !o->vary) return 3;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, "o:qh", longopts, NULL)) != -1) {
        switch (c) {
        case 'v': o->vary[o->nvary++] = optarg; break;
        case 'l': o->list = 1; break;
        case 'P': o->list = 0; break;
        case 'm': o->map = optarg; break;
        case 's':
            if (!strchr(optarg, '=')) return usage_error("--set needs KEY=VALUE");
            o->sets[o->nset++] = optarg;
            break;
        case 'o': o->dir = optarg; break;
        case 'q': o->quiet = 1; break;
        case 'h': fputs(usage_text, stdout); return 0;
        default: return 2;
        }
    }
    if (optind + 1 != argc) return usage_error(optind >= argc ? "missing STUDY.cfg" : "expected one STUDY.cfg");
    o->study = argv[optind];
    if (!o->dir) return usage_error("missing -o DIR");
    return -1;
}

void sf_sweep_opts_free(sf_sweep_opts *o)
{
    free(o->sets);
    free(o->vary);
    o->sets = o->vary = NULL;
}

int sf_sweep_exit_code(int code)
{
    switch (code) {
    case SF_OK: return 0;
    case SF_EINPUT: return 1;
    case SF_EIO: return 4;
    default: return 3;
    }
}

int sf_sweep_sibling(const char *name, char *buf, size_t n)
{
    char self[PATH_MAX];
    ssize_t len = readlink("/proc/self/exe", self, sizeof self - 1);
    if (len <= 0) return -1;
    self[len] = '\0';
    char *slash = strrchr(self, '/');
    if (!slash) return -1;
    *slash = '\0';
    if ((size_t)snprintf(buf, n, "%s/%s", self, name) >= n) return -1;
    return 0;
}

int sf_sweep_setup(const sf_sweep_opts *o, sf_sweep_plan *pl, sf_sweep *sw, int open_dir)
{
    sf_error err;
    sf_error_clear(&err);
    int rc = sf_sweep_plan_make(pl, o->study, o->nset, o->sets, o->nvary, o->vary, o->list, o->map, &err);
    if (!rc && open_dir) rc = sf_sweep_open(sw, pl, o->dir, &err);
    if (rc) {
        fprintf(stderr, "smoothfold: %s\n", err.msg);
        return sf_sweep_exit_code(err.code);
    }
    return -1;
}

void sf_sweep_progress(const sf_sweep *sw, const char *row, const char *who)
{
    const sf_sweep_plan *pl = sw->plan;
    int v = atoi(row);
    char desc[600];
    sf_sweep_describe(pl, v, desc, sizeof desc);
    const char *c = row;
    for (int k = 0; k <= pl->nkeys && c; k++) {
        c = strchr(c, '\t');
        if (c) c++;
    }
    int status = c ? atoi(c) : -1;
    const char *reason = c ? strchr(c, '\t') : NULL;
    const char *wall = strrchr(row, '\t');
    int rlen = reason ? (int)strcspn(reason + 1, "\t") : 0;
    fprintf(stderr, "variant %0*d (%d of %d%s%s) %s: ", pl->width, v, sw->nfinished, pl->nvariants,
            who ? ", " : "", who ? who : "", desc);
    if (status == 0) fprintf(stderr, "ok, %s s\n", wall ? wall + 1 : "?");
    else fprintf(stderr, "status %d, %.*s\n", status, rlen, reason ? reason + 1 : "");
}

int sf_sweep_finish(const sf_sweep *sw, int sig, int ran)
{
    const sf_sweep_plan *pl = sw->plan;
    if (sig) {
        fprintf(stderr, "smoothfold: sweep stopped by signal %d: %d of %d variants finished, "
                "in %s/sweep.tsv; run the same command again to run the others\n",
                sig, sw->nfinished, pl->nvariants, sw->dir);
        return 128 + sig;
    }
    printf("sweep %s: %d variant%s (%d run now, %d finished before), %d with a non-zero status; "
           "results in %s/sweep.tsv\n", pl->study_name, pl->nvariants, pl->nvariants == 1 ? "" : "s",
           ran, sw->nresumed, sf_sweep_failed(sw), sw->dir);
    return 0;
}
