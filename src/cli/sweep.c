/* sweep.c - `smoothfold sweep`: the variants of a study one after another,
 * each in a child process (src/analysis/sweep/sweep.h).  Started by an MPI
 * launcher, it replaces itself by smoothfold-sweep-mpi (sweep_mpi.c): the
 * smoothfold program itself does not link MPI (MUMPS's sequential build
 * brings its own MPI stubs).  docs/guides/sweeps.md. */
#include "commands.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "sweep_cli.h"

/* The one piece of process-wide state: which signal asked the sweep to
 * stop.  A signal handler can only reach a static object. */
static volatile sig_atomic_t stop_signal;

static void on_signal(int sig) { stop_signal = sig; }

static void catch_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;   /* no SA_RESTART: waitpid returns EINTR */
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
}

/* Started by mpirun, srun or another launcher? */
static const char *mpi_launched(void)
{
    const char *vars[] = {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"};
    for (size_t i = 0; i < sizeof vars / sizeof *vars; i++)
        if (getenv(vars[i])) return vars[i];
    return NULL;
}

/* Replace this process by smoothfold-sweep-mpi with the same arguments.
 * Returns only when that is impossible (an exit status, or -1: run
 * serially, there is one process). */
static int exec_mpi(int argc, char **argv, const char *var)
{
    char mpi[4096];
    if (sf_sweep_sibling("smoothfold-sweep-mpi", mpi, sizeof mpi) == 0 && access(mpi, X_OK) == 0) {
        char **args = calloc((size_t)argc + 1, sizeof *args);
        if (!args) return 3;
        args[0] = mpi;
        for (int i = 1; i < argc; i++) args[i] = argv[i];
        execv(mpi, args);
        fprintf(stderr, "smoothfold: sweep: cannot start %s: %s\n", mpi, strerror(errno));
        free(args);
        return 4;
    }
    const char *size = getenv("OMPI_COMM_WORLD_SIZE");
    if (!size) size = getenv("PMI_SIZE");
    if (size && atoi(size) == 1) return -1;
    fprintf(stderr, "smoothfold: sweep: started by an MPI launcher (%s is set) but this smoothfold "
            "was built without MPI (smoothfold-sweep-mpi is missing): install libopenmpi-dev and "
            "configure --with-mpi, or run `smoothfold sweep` without mpirun\n", var);
    return 2;
}

/* Run variant v to its end; returns its row, or NULL when a signal
 * stopped it (the child was killed and is not recorded). */
static char *run_one(const sf_sweep *sw, int v, const char *exe, sf_error *err)
{
    pid_t pid;
    double t0 = sf_sweep_now();
    if (sf_sweep_spawn(sw->plan, sw->dir, v, exe, &pid, err)) return NULL;
    int st = 0, killed = 0;
    while (waitpid(pid, &st, 0) < 0) {
        if (errno != EINTR) {
            sf_fail(err, SF_EIO, "sweep: waitpid: %s", strerror(errno));
            return NULL;
        }
        if (stop_signal && !killed) {
            kill(pid, SIGTERM);
            killed = 1;
        }
    }
    if (stop_signal && WIFSIGNALED(st)) return NULL;
    char *row = sf_sweep_collect(sw->plan, sw->dir, v, st, sf_sweep_now() - t0);
    if (!row) sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    return row;
}

int sf_cmd_sweep(int argc, char **argv)
{
    sf_sweep_opts o;
    int rc = sf_sweep_opts_parse(argc, argv, &o);
    if (rc >= 0) {
        sf_sweep_opts_free(&o);
        return rc;
    }
    const char *var = mpi_launched();
    if (var && (rc = exec_mpi(argc, argv, var)) >= 0) {
        sf_sweep_opts_free(&o);
        return rc;
    }
    char exe[4096];
    if (sf_sweep_sibling("smoothfold", exe, sizeof exe) != 0) {
        fprintf(stderr, "smoothfold: sweep: cannot find the smoothfold program (/proc/self/exe)\n");
        sf_sweep_opts_free(&o);
        return 4;
    }
    sf_sweep_plan pl;
    sf_sweep sw;
    memset(&sw, 0, sizeof sw);
    sw.lock_fd = -1;
    catch_signals();
    rc = sf_sweep_setup(&o, &pl, &sw, 1);
    int ran = 0;
    sf_error err;
    sf_error_clear(&err);
    for (int v = 0; rc < 0 && v < pl.nvariants && !stop_signal; v++) {
        if (sw.rows[v]) continue;
        char *row = run_one(&sw, v, exe, &err);
        if (row && sf_sweep_record(&sw, row, &err) == SF_OK) {
            ran++;
            if (!o.quiet) sf_sweep_progress(&sw, row, NULL);
        }
        free(row);
        if (err.code) {
            fprintf(stderr, "smoothfold: %s\n", err.msg);
            rc = sf_sweep_exit_code(err.code);
        }
    }
    if (rc < 0) rc = sf_sweep_finish(&sw, stop_signal, ran);
    sf_sweep_close(&sw);
    sf_sweep_plan_free(&pl);
    sf_sweep_opts_free(&o);
    return rc;
}
