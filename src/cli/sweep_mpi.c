/* sweep_mpi.c - smoothfold-sweep-mpi: the variants of a sweep handed out
 * by MPI rank 0, one at a time, to whichever rank is free (run times
 * differ by orders of magnitude, so no static split).  Rank 0 runs
 * variants too, between handing them out: its own variant is a child
 * process it polls, so it answers the others within a millisecond.
 *
 * Every rank runs a variant the way the serial sweep does (`smoothfold
 * run` in a child process, src/analysis/sweep/sweep.h) and sends its sweep.tsv
 * row to rank 0, the only writer of DIR/sweep.tsv and the row files; the
 * table is therefore the serial one, row for row, apart from wall_s.
 *
 * Started as `mpirun -n N smoothfold-sweep-mpi STUDY.cfg ...` or, the
 * same thing, `mpirun -n N smoothfold sweep STUDY.cfg ...` (smoothfold
 * execs this program when it finds an MPI launcher's variables).  Waiting
 * is done by polling with short sleeps, not in blocking MPI calls, which
 * spin and would take a core from the variants.  docs/guides/sweeps.md. */
#include <mpi.h>

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "sweep_cli.h"

enum { TAG_READY = 1, TAG_RESULT, TAG_TASK, TAG_STOP };

/* Which signal asked the sweep to stop (a handler reaches only statics). */
static volatile sig_atomic_t stop_signal;
/* The launcher that started this rank (mpirun, orted, srun), and whether
 * it has gone: a rank must not outlive its job.  Set once in main. */
static pid_t launcher;
static int orphaned;

static void on_signal(int sig) { stop_signal = sig; }

static void on_child(int sig) { (void)sig; }

static void catch_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    /* SIGCHLD cuts rank 0's nap short when its own variant ends (nanosleep
     * returns at any handled signal); SA_RESTART keeps it from
     * interrupting anything else, MPI's own calls included. */
    sa.sa_handler = on_child;
    sa.sa_flags = SA_RESTART;
    sigaction(SIGCHLD, &sa, NULL);
}

static void nap(void)
{
    struct timespec t = {0, 1000000};
    nanosleep(&t, NULL);
}

/* Stop? On SIGTERM or SIGINT, or when the launcher has gone without
 * passing the signal on (mpirun killed while starting the job was seen to
 * leave its ranks running): then as if SIGTERM had come. */
static int stopping(void)
{
    if (!stop_signal && getppid() != launcher) {
        orphaned = 1;
        stop_signal = SIGTERM;
    }
    return stop_signal;
}

/* Leave at once after a stop: without a launcher MPI_Abort may hang. */
static void leave(int rc)
{
    fflush(NULL);
    if (orphaned) _exit(rc);
    MPI_Abort(MPI_COMM_WORLD, rc);
}

/* Wait for a request without spinning; 0 when done, -1 on a stop. */
static int wait_request(MPI_Request *r, MPI_Status *st)
{
    int done = 0;
    for (;;) {
        MPI_Test(r, &done, st);
        if (done) return 0;
        if (stopping()) return -1;
        nap();
    }
}

static void die(const sf_error *err)
{
    fprintf(stderr, "smoothfold: %s\n", err->msg);
    MPI_Abort(MPI_COMM_WORLD, sf_sweep_exit_code(err->code));
}

/* ---- rank 0 -------------------------------------------------------------- */

typedef struct dispatcher {
    sf_sweep *sw;
    const char *exe;
    int quiet;
    int next;           /* next variant to look at */
    pid_t own;          /* rank 0's own variant, 0 when none */
    int own_v;
    double own_t0;
    int ran;
} dispatcher;

static int next_variant(dispatcher *d)
{
    while (d->next < d->sw->plan->nvariants && d->sw->rows[d->next]) d->next++;
    return d->next < d->sw->plan->nvariants ? d->next++ : -1;
}

static void record(dispatcher *d, const char *row, int rank)
{
    sf_error err;
    sf_error_clear(&err);
    if (sf_sweep_record(d->sw, row, &err)) die(&err);
    d->ran++;
    if (!d->quiet) {
        char who[32];
        snprintf(who, sizeof who, "rank %d", rank);
        sf_sweep_progress(d->sw, row, who);
    }
}

/* Start or reap rank 0's own variant; 1 when something happened. */
static int own_work(dispatcher *d)
{
    sf_error err;
    sf_error_clear(&err);
    if (!d->own) {
        int v = next_variant(d);
        if (v < 0) return 0;
        d->own_v = v;
        d->own_t0 = sf_sweep_now();
        if (sf_sweep_spawn(d->sw->plan, d->sw->dir, v, d->exe, &d->own, &err)) die(&err);
        return 1;
    }
    int st;
    pid_t r = waitpid(d->own, &st, WNOHANG);
    if (r == 0 || (r < 0 && errno == EINTR)) return 0;
    if (r < 0) {
        sf_fail(&err, SF_EIO, "sweep: waitpid: %s", strerror(errno));
        die(&err);
    }
    d->own = 0;
    /* killed by the signal that stops the sweep: not finished (as in
     * sweep.c); the resume runs it again */
    if (stop_signal && WIFSIGNALED(st)) return 0;
    char *row = sf_sweep_collect(d->sw->plan, d->sw->dir, d->own_v, st, sf_sweep_now() - d->own_t0);
    if (!row) {
        sf_fail(&err, SF_ENOMEM, "sweep: out of memory");
        die(&err);
    }
    record(d, row, 0);
    free(row);
    return 1;
}

/* Answer one waiting message; 1 when there was one.  A rank that asks
 * when nothing is left waits (polling, idle) for the STOP sent once the
 * last variant anywhere has finished: a rank in MPI_Finalize would spin
 * on a core the last variants need. */
static int serve(dispatcher *d, int *idle, int *nidle)
{
    int flag;
    MPI_Status st;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
    if (!flag) return 0;
    int n;
    MPI_Get_count(&st, MPI_CHAR, &n);
    char *row = malloc((size_t)n + 1);
    if (!row) MPI_Abort(MPI_COMM_WORLD, 3);
    MPI_Recv(row, n, MPI_CHAR, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    row[n] = '\0';
    if (st.MPI_TAG == TAG_RESULT) record(d, row, st.MPI_SOURCE);
    free(row);
    int v = next_variant(d);
    if (v >= 0) MPI_Send(&v, 1, MPI_INT, st.MPI_SOURCE, TAG_TASK, MPI_COMM_WORLD);
    else idle[(*nidle)++] = st.MPI_SOURCE;
    return 1;
}

static int rank0(sf_sweep *sw, const char *exe, int size, int quiet)
{
    dispatcher d = {sw, exe, quiet, 0, 0, 0, 0.0, 0};
    int *idle = calloc((size_t)size, sizeof *idle), nidle = 0;
    if (!idle) MPI_Abort(MPI_COMM_WORLD, 3);
    while (!stopping()) {
        int busy = serve(&d, idle, &nidle);
        busy |= own_work(&d);
        if (!d.own && nidle == size - 1 && d.next >= sw->plan->nvariants) break;
        if (!busy) nap();
    }
    if (!stop_signal) {
        int none = -1;
        for (int i = 0; i < nidle; i++) MPI_Send(&none, 1, MPI_INT, idle[i], TAG_STOP, MPI_COMM_WORLD);
    }
    free(idle);
    if (stop_signal) {
        if (d.own) {
            kill(d.own, SIGTERM);
            waitpid(d.own, NULL, 0);
        }
        leave(sf_sweep_finish(sw, stop_signal, d.ran));
    }
    return sf_sweep_finish(sw, 0, d.ran);
}

/* ---- ranks 1.. ------------------------------------------------------------- */

static void worker(const sf_sweep_plan *pl, const char *dir, const char *exe)
{
    MPI_Send("", 0, MPI_CHAR, 0, TAG_READY, MPI_COMM_WORLD);
    for (;;) {
        int v;
        MPI_Request req;
        MPI_Status st;
        MPI_Irecv(&v, 1, MPI_INT, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &req);
        if (wait_request(&req, &st)) _exit(128 + stop_signal);
        if (st.MPI_TAG == TAG_STOP) return;
        sf_error err;
        sf_error_clear(&err);
        pid_t pid;
        double t0 = sf_sweep_now();
        if (sf_sweep_spawn(pl, dir, v, exe, &pid, &err)) die(&err);
        int ws = 0, killed = 0;
        for (;;) {   /* polled, to see a vanished launcher; SIGCHLD ends the nap */
            pid_t r = waitpid(pid, &ws, WNOHANG);
            if (r == pid) break;
            if (r < 0 && errno != EINTR) {
                sf_fail(&err, SF_EIO, "sweep: waitpid: %s", strerror(errno));
                die(&err);
            }
            if (stopping() && !killed) {
                kill(pid, SIGTERM);
                killed = 1;
            }
            if (r == 0) nap();
        }
        if (stop_signal) _exit(128 + stop_signal);
        char *row = sf_sweep_collect(pl, dir, v, ws, sf_sweep_now() - t0);
        if (!row) MPI_Abort(MPI_COMM_WORLD, 3);
        MPI_Send(row, (int)strlen(row), MPI_CHAR, 0, TAG_RESULT, MPI_COMM_WORLD);
        free(row);
    }
}

int main(int argc, char **argv)
{
    launcher = getppid();
    MPI_Init(&argc, &argv);
    catch_signals();
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const char *launched = getenv("PMI_SIZE");   /* e.g. MPICH's launcher */
    if (size == 1 && launched && atoi(launched) > 1) {
        fprintf(stderr, "smoothfold: sweep: the launcher started %s processes but MPI sees one: "
                "smoothfold-sweep-mpi was built with OpenMPI, use OpenMPI's mpirun (or srun "
                "--mpi=pmix)\n", launched);
        MPI_Finalize();
        return 2;
    }
    sf_sweep_opts o;
    sf_sweep_plan pl;
    sf_sweep sw;
    memset(&pl, 0, sizeof pl);
    memset(&sw, 0, sizeof sw);
    sw.lock_fd = -1;
    char exe[4096];
    int rc = -1;
    if (rank == 0) {
        rc = sf_sweep_opts_parse(argc, argv, &o);
        if (rc < 0 && sf_sweep_sibling("smoothfold", exe, sizeof exe) != 0) {
            fprintf(stderr, "smoothfold: sweep: cannot find the smoothfold program\n");
            rc = 4;
        }
        if (rc < 0) rc = sf_sweep_setup(&o, &pl, &sw, 1);
    }
    /* Workers plan only once rank 0 has checked the input and made DIR
     * (waiting without spinning: rank 0 may take a while to resume). */
    MPI_Request req;
    MPI_Ibcast(&rc, 1, MPI_INT, 0, MPI_COMM_WORLD, &req);
    if (wait_request(&req, MPI_STATUS_IGNORE)) _exit(128 + stop_signal);
    if (rc >= 0) {
        if (rank == 0) {
            sf_sweep_close(&sw);
            sf_sweep_plan_free(&pl);
            sf_sweep_opts_free(&o);
        }
        MPI_Finalize();
        return rc;
    }
    if (rank == 0) {
        rc = rank0(&sw, exe, size, o.quiet);
        sf_sweep_close(&sw);
    } else {
        if (sf_sweep_opts_parse(argc, argv, &o) >= 0 || sf_sweep_sibling("smoothfold", exe, sizeof exe)
            || sf_sweep_setup(&o, &pl, &sw, 0) >= 0)
            MPI_Abort(MPI_COMM_WORLD, 1);
        worker(&pl, o.dir, exe);
        rc = 0;
    }
    sf_sweep_plan_free(&pl);
    sf_sweep_opts_free(&o);
    MPI_Finalize();
    return rc;
}
