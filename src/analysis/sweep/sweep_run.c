/* sweep_run.c - running the variants of a sweep as child processes,
 * collecting their results into rows of DIR/sweep.tsv, resume (sweep.h). */
#include "sweep.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "outbuf.h"

#ifndef PACKAGE_VERSION
#define PACKAGE_VERSION "0.1.0"
#endif

extern char **environ;

double sf_sweep_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* ---- files -------------------------------------------------------------- */

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f) return NULL;
    sf_outbuf b = {0};
    char chunk[4096];
    size_t n;
    while ((n = fread(chunk, 1, sizeof chunk, f)) > 0) sf_outbuf_printf(&b, "%.*s", (int)n, chunk);
    fclose(f);
    if (b.oom || !b.s) {
        sf_outbuf_free(&b);
        b.s = calloc(1, 1);
    }
    return b.s;
}

static int write_text(const char *path, const char *text, sf_error *err)
{
    char tmp[1200];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f) return sf_fail(err, SF_EIO, "%s: cannot write: %s", tmp, strerror(errno));
    int bad = fputs(text, f) == EOF;
    if (fclose(f) != 0 || bad) {
        remove(tmp);
        return sf_fail(err, SF_EIO, "%s: write failed", path);
    }
    if (rename(tmp, path) != 0) {
        remove(tmp);
        return sf_fail(err, SF_EIO, "%s: cannot rename from %s: %s", path, tmp, strerror(errno));
    }
    return SF_OK;
}

/* Split a line at tabs in place (empty fields kept); returns the count. */
static int split_tabs(char *line, char **f, int max)
{
    int n = 0;
    f[n++] = line;
    for (char *c = line; *c && n < max; c++)
        if (*c == '\t') {
            *c = '\0';
            f[n++] = c + 1;
        }
    return n;
}

/* ---- the plan on disk: DIR/variants.tsv ---------------------------------- */

static char *plan_text(const sf_sweep_plan *pl)
{
    sf_outbuf b = {0};
    sf_outbuf_printf(&b, "# smoothfold sweep plan: study %s (file contents FNV-1a %016llx), %s of "
                     "%d variants\n# --set of every variant:", pl->study_name, pl->study_hash,
                     pl->list ? "list" : "product", pl->nvariants);
    for (int i = 0; i < pl->nbase; i++) sf_outbuf_printf(&b, " %s", pl->base[i]);
    sf_outbuf_printf(&b, "\nindex");
    for (int k = 0; k < pl->nkeys; k++) sf_outbuf_printf(&b, "\t%s", pl->keys[k].key);
    sf_outbuf_printf(&b, "\n");
    for (int v = 0; v < pl->nvariants; v++) {
        sf_outbuf_printf(&b, "%0*d", pl->width, v);
        for (int k = 0; k < pl->nkeys; k++)
            sf_outbuf_printf(&b, "\t%s", pl->keys[k].set[sf_sweep_value(pl, v, k)]);
        sf_outbuf_printf(&b, "\n");
    }
    if (b.oom) {
        sf_outbuf_free(&b);
        return NULL;
    }
    return b.s;
}

/* The first fields of variant v's row: "<index>\t<label>...\t". */
static void row_prefix(const sf_sweep_plan *pl, int v, sf_outbuf *b)
{
    sf_outbuf_printf(b, "%0*d", pl->width, v);
    for (int k = 0; k < pl->nkeys; k++)
        sf_outbuf_printf(b, "\t%s", pl->keys[k].label[sf_sweep_value(pl, v, k)]);
    sf_outbuf_printf(b, "\t");
}

/* Take over DIR/<index>/row.tsv of variant v when it is that variant's. */
static void resume_row(sf_sweep *sw, int v)
{
    char vd[1100], path[1200];
    sf_sweep_vdir(sw->plan, sw->dir, v, vd, sizeof vd);
    snprintf(path, sizeof path, "%s/row.tsv", vd);
    char *row = read_text(path);
    if (!row) return;
    sf_outbuf pre = {0};
    row_prefix(sw->plan, v, &pre);
    char *nl = strchr(row, '\n');
    if (nl) *nl = '\0';
    if (!pre.oom && strncmp(row, pre.s, pre.n) == 0) {
        sw->rows[v] = row;
        sw->nfinished++;
        sw->nresumed++;
    } else {
        free(row);
    }
    sf_outbuf_free(&pre);
}

/* One sweep at a time in a directory: two would run the same variants
 * and overwrite each other's table. */
static int lock_dir(sf_sweep *sw, sf_error *err)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/sweep.lock", sw->dir);
    sw->lock_fd = open(path, O_RDWR | O_CREAT, 0644);
    if (sw->lock_fd < 0) return sf_fail(err, SF_EIO, "%s: cannot open: %s", path, strerror(errno));
    if (flock(sw->lock_fd, LOCK_EX | LOCK_NB) != 0) {
        int e = errno;
        close(sw->lock_fd);
        sw->lock_fd = -1;
        if (e == EWOULDBLOCK)
            return sf_fail(err, SF_EINPUT, "%s: another sweep is running in %s (started twice, or "
                           "under a launcher whose MPI smoothfold-sweep-mpi does not speak?)",
                           path, sw->dir);
        return sf_fail(err, SF_EIO, "%s: cannot lock: %s", path, strerror(e));
    }
    return SF_OK;
}

int sf_sweep_open(sf_sweep *sw, const sf_sweep_plan *pl, const char *dir, sf_error *err)
{
    memset(sw, 0, sizeof *sw);
    sw->lock_fd = -1;
    sw->plan = pl;
    snprintf(sw->dir, sizeof sw->dir, "%s", dir);
    sw->rows = calloc((size_t)pl->nvariants, sizeof *sw->rows);
    char *text = plan_text(pl);
    if (!sw->rows || !text) {
        free(text);
        return sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    }
    char path[1200];
    int rc = sf_mkdir_p(dir, err);
    if (!rc) rc = lock_dir(sw, err);
    snprintf(path, sizeof path, "%s/variants.tsv", dir);
    char *old = rc ? NULL : read_text(path);
    if (!rc && old && strcmp(old, text) != 0)
        rc = sf_fail(err, SF_EINPUT, "%s: %s holds another sweep (other study file, --vary, "
                     "--set or mode); give another -o DIR or remove it", path, dir);
    else if (!rc && !old)
        rc = write_text(path, text, err);
    free(old);
    free(text);
    if (rc) return rc;
    for (int v = 0; v < pl->nvariants; v++) resume_row(sw, v);
    return sf_sweep_write_table(sw, err);
}

void sf_sweep_close(sf_sweep *sw)
{
    if (sw->lock_fd >= 0) close(sw->lock_fd);   /* releases the lock */
    sw->lock_fd = -1;
    if (sw->rows && sw->plan)
        for (int v = 0; v < sw->plan->nvariants; v++) free(sw->rows[v]);
    free(sw->rows);
    sw->rows = NULL;
}

int sf_sweep_record(sf_sweep *sw, const char *row, sf_error *err)
{
    char *end;
    long v = strtol(row, &end, 10);
    if (end == row || *end != '\t' || v < 0 || v >= sw->plan->nvariants)
        return sf_fail(err, SF_EINTERNAL, "sweep: bad row '%.40s'", row);
    size_t n = strlen(row);
    char *copy = malloc(n + 2);
    if (!copy) return sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    memcpy(copy, row, n + 1);
    char vd[1100], path[1200];
    sf_sweep_vdir(sw->plan, sw->dir, (int)v, vd, sizeof vd);
    snprintf(path, sizeof path, "%s/row.tsv", vd);
    copy[n] = '\n';
    copy[n + 1] = '\0';
    int rc = write_text(path, copy, err);
    copy[n] = '\0';
    if (rc) {
        free(copy);
        return rc;
    }
    if (!sw->rows[v]) sw->nfinished++;
    free(sw->rows[v]);
    sw->rows[v] = copy;
    return sf_sweep_write_table(sw, err);
}

/* ---- the table ------------------------------------------------------------ */

static const char *const comps[] = {"ux", "uy", "uz"};

static void probe_names(const sf_sweep_plan *pl, sf_outbuf *b, const char *prefix)
{
    for (int i = 1; i <= pl->nprobes; i++)
        for (int c = 0; c < 3; c++) sf_outbuf_printf(b, "\t%sprobe%d_%s", prefix, i, comps[c]);
}

/* Status field of a row (the one after the varied values). */
static int row_status(const sf_sweep_plan *pl, const char *row)
{
    const char *c = row;
    for (int k = 0; k <= pl->nkeys && c; k++) {
        c = strchr(c, '\t');
        if (c) c++;
    }
    return c ? atoi(c) : -1;
}

int sf_sweep_failed(const sf_sweep *sw)
{
    int n = 0;
    for (int v = 0; v < sw->plan->nvariants; v++)
        if (sw->rows[v] && row_status(sw->plan, sw->rows[v]) != 0) n++;
    return n;
}

/* Column mapped by plots/sweep.gp: sweep.map, else the first of lp_p,
 * bp_p with a value, else the end displacement uz of probe 1, else end_p. */
static void map_column(const sf_sweep *sw, char *buf, size_t n)
{
    const sf_sweep_plan *pl = sw->plan;
    if (pl->map[0]) {
        snprintf(buf, n, "%s", pl->map);
        return;
    }
    int nf = pl->nkeys + 10 + 3 * 3 * pl->nprobes;
    int lp = pl->nkeys + 6 + 3 * pl->nprobes, bp = lp + 3 * pl->nprobes + 2;
    int have_lp = 0, have_bp = 0;
    char **f = malloc((size_t)nf * sizeof *f);
    for (int v = 0; f && v < pl->nvariants; v++) {
        if (!sw->rows[v]) continue;
        char *row = strdup(sw->rows[v]);
        if (!row) break;
        if (split_tabs(row, f, nf) == nf) {
            have_lp |= f[lp][0] != '\0';
            have_bp |= f[bp][0] != '\0';
        }
        free(row);
    }
    free(f);
    snprintf(buf, n, "%s", have_lp ? "lp_p" : have_bp ? "bp_p" : pl->nprobes ? "end_probe1_uz" : "end_p");
}

int sf_sweep_write_table(const sf_sweep *sw, sf_error *err)
{
    const sf_sweep_plan *pl = sw->plan;
    sf_outbuf b = {0};
    sf_outbuf_printf(&b, "# smoothfold %s: sweep of %s (study %s)\n", PACKAGE_VERSION,
                     pl->study_path, pl->study_name);
    sf_outbuf_printf(&b, "# plan: %s of %d variants:", pl->list ? "list" : "product", pl->nvariants);
    for (int k = 0; k < pl->nkeys; k++)
        sf_outbuf_printf(&b, "%s %s (%d values)", k ? (pl->list ? "," : " x") : "",
                         pl->keys[k].key, pl->keys[k].nvalues);
    sf_outbuf_printf(&b, "\n# finished: %d of %d variants, %d with a non-zero status%s\n",
                     sw->nfinished, pl->nvariants, sf_sweep_failed(sw),
                     sw->nfinished < pl->nvariants ? " (INCOMPLETE: run the same command again "
                     "to run the others)" : "");
    char map[128];
    map_column(sw, map, sizeof map);
    sf_outbuf_printf(&b, "# map: %s %s %s\n", pl->keys[0].key,
                     pl->nkeys > 1 ? pl->keys[1].key : "-", map);
    sf_outbuf_printf(&b, "# units: varied keys as in the study; *_p as the parameter; *probe*: m; "
                     "wall_s: s (the only column that differs between runs)\n");
    sf_outbuf_printf(&b, "# base study of every variant (before its own --set):\n%s",
                     pl->study_echo ? pl->study_echo : "");
    sf_outbuf_printf(&b, "index");
    for (int k = 0; k < pl->nkeys; k++) sf_outbuf_printf(&b, "\t%s", pl->keys[k].key);
    sf_outbuf_printf(&b, "\tstatus\treason\tpoints\tbranches\tend_p");
    probe_names(pl, &b, "end_");
    sf_outbuf_printf(&b, "\tlp_p");
    probe_names(pl, &b, "lp_");
    sf_outbuf_printf(&b, "\tbp_type\tbp_p");
    probe_names(pl, &b, "bp_");
    sf_outbuf_printf(&b, "\twall_s\n");
    for (int v = 0; v < pl->nvariants; v++)
        if (sw->rows[v]) sf_outbuf_printf(&b, "%s\n", sw->rows[v]);
    if (b.oom) {
        sf_outbuf_free(&b);
        return sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    }
    char path[1200];
    snprintf(path, sizeof path, "%s/sweep.tsv", sw->dir);
    int rc = write_text(path, b.s, err);
    sf_outbuf_free(&b);
    return rc;
}

/* ---- one variant ---------------------------------------------------------- */

static int launcher_var(const char *e)
{
    return strncmp(e, "OMPI_", 5) == 0 || strncmp(e, "PMIX_", 5) == 0 || strncmp(e, "PMI_", 4) == 0;
}

int sf_sweep_spawn(const sf_sweep_plan *pl, const char *dir, int v, const char *exe, pid_t *pid,
                   sf_error *err)
{
    char vd[1100], log[1200];
    sf_sweep_vdir(pl, dir, v, vd, sizeof vd);
    if (sf_mkdir_p(vd, err)) return err->code;
    snprintf(log, sizeof log, "%s/row.tsv", vd);
    remove(log);
    snprintf(log, sizeof log, "%s/run.log", vd);
    int nargs = 8 + 2 * (pl->nbase + pl->nkeys);
    char **argv = calloc((size_t)nargs + 1, sizeof *argv);
    char **sets = calloc((size_t)pl->nkeys + 1, sizeof *sets);
    size_t nenv = 0;
    while (environ[nenv]) nenv++;
    char **env = calloc(nenv + 1, sizeof *env);
    int rc = SF_OK;
    if (!argv || !sets || !env) rc = sf_fail(err, SF_ENOMEM, "sweep: out of memory");
    for (int k = 0; !rc && k < pl->nkeys; k++) {
        const sf_sweep_key *key = &pl->keys[k];
        const char *val = key->set[sf_sweep_value(pl, v, k)];
        sets[k] = malloc(strlen(key->key) + strlen(val) + 2);
        if (!sets[k]) rc = sf_fail(err, SF_ENOMEM, "sweep: out of memory");
        else sprintf(sets[k], "%s=%s", key->key, val);
    }
    if (!rc) {
        int a = 0;
        argv[a++] = (char *)exe;
        argv[a++] = "run";
        argv[a++] = (char *)pl->study_path;
        for (int i = 0; i < pl->nbase; i++) {
            argv[a++] = "--set";
            argv[a++] = pl->base[i];
        }
        for (int k = 0; k < pl->nkeys; k++) {
            argv[a++] = "--set";
            argv[a++] = sets[k];
        }
        argv[a++] = "-o";
        argv[a++] = vd;
        argv[a++] = "-q";
        argv[a++] = "--force";   /* run.log is ours: run keeps it */
        size_t e = 0;
        for (size_t i = 0; i < nenv; i++)
            if (!launcher_var(environ[i])) env[e++] = environ[i];
        posix_spawn_file_actions_t fa;
        posix_spawn_file_actions_init(&fa);
        posix_spawn_file_actions_addopen(&fa, 1, log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_adddup2(&fa, 1, 2);
        posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
        int e2 = posix_spawn(pid, exe, &fa, NULL, argv, env);
        posix_spawn_file_actions_destroy(&fa);
        if (e2 != 0) rc = sf_fail(err, SF_EIO, "sweep: cannot start %s: %s", exe, strerror(e2));
    }
    for (int k = 0; sets && k < pl->nkeys; k++) free(sets[k]);
    free(sets);
    free(argv);
    free(env);
    return rc;
}

/* Fields of the first non-comment line (the header) and of the rows. */
typedef struct table {
    char *text;
    char *hdr[512];
    int nhdr;
} table;

static int col(const table *t, const char *name)
{
    for (int i = 0; i < t->nhdr; i++)
        if (strcmp(t->hdr[i], name) == 0) return i;
    return -1;
}

/* Next data line (skipping comments and blank lines) split into f. */
static int next_row(char **cursor, char **f, int max)
{
    while (*cursor && **cursor) {
        char *line = *cursor;
        char *nl = strchr(line, '\n');
        if (nl) {
            *nl = '\0';
            *cursor = nl + 1;
        } else {
            *cursor = line + strlen(line);
        }
        if (line[0] == '#' || line[0] == '\0') continue;
        return split_tabs(line, f, max);
    }
    return 0;
}

static int open_table(table *t, const char *path, char **cursor)
{
    t->text = read_text(path);
    t->nhdr = 0;
    *cursor = t->text;
    if (!t->text) return 0;
    t->nhdr = next_row(cursor, t->hdr, 512);
    return t->nhdr > 0;
}

static const char *field(char **f, int n, int i) { return i >= 0 && i < n ? f[i] : ""; }

/* p and the probe displacements of a row of t (empty fields when absent). */
static void point_fields(sf_outbuf *b, const sf_sweep_plan *pl, const table *t, char **f, int n)
{
    char name[64];
    sf_outbuf_printf(b, "\t%s", f ? field(f, n, col(t, "p")) : "");
    for (int i = 1; i <= pl->nprobes; i++)
        for (int c = 0; c < 3; c++) {
            snprintf(name, sizeof name, "probe%d_%s", i, comps[c]);
            sf_outbuf_printf(b, "\t%s", f ? field(f, n, col(t, name)) : "");
        }
}

/* points, branches, end state of branch 1 from branch.tsv or trajectory.tsv. */
static void path_fields(sf_outbuf *b, const sf_sweep_plan *pl, const char *vd)
{
    char path[1200], *cur, *f[512], *end[512];
    table t;
    snprintf(path, sizeof path, "%s/branch.tsv", vd);
    if (!open_table(&t, path, &cur)) {
        free(t.text);
        snprintf(path, sizeof path, "%s/trajectory.tsv", vd);
        open_table(&t, path, &cur);
    }
    int points = 0, branches = 0, nend = 0, n, cb = col(&t, "branch");
    while (t.nhdr && (n = next_row(&cur, f, 512)) > 0) {
        points++;
        int br = cb >= 0 ? atoi(field(f, n, cb)) : 1;
        if (br > branches) branches = br;
        if (br == 1) {
            memcpy(end, f, (size_t)n * sizeof *f);
            nend = n;
        }
    }
    sf_outbuf_printf(b, "\t%d\t%d", points, branches);
    point_fields(b, pl, &t, nend ? end : NULL, nend);
    free(t.text);
}

/* First LP and first BP (BP, BPk) of branch 1 in special.tsv. */
static void special_fields(sf_outbuf *b, const sf_sweep_plan *pl, const char *vd)
{
    char path[1200], *cur, *f[512], *lp[512], *bp[512];
    table t;
    snprintf(path, sizeof path, "%s/special.tsv", vd);
    open_table(&t, path, &cur);
    int n, nlp = 0, nbp = 0, cb = col(&t, "branch"), ct = col(&t, "type");
    while (t.nhdr && (n = next_row(&cur, f, 512)) > 0) {
        if (cb >= 0 && atoi(field(f, n, cb)) != 1) continue;
        const char *type = field(f, n, ct);
        if (!nlp && strcmp(type, "LP") == 0) {
            memcpy(lp, f, (size_t)n * sizeof *f);
            nlp = n;
        }
        if (!nbp && strncmp(type, "BP", 2) == 0) {
            memcpy(bp, f, (size_t)n * sizeof *f);
            nbp = n;
        }
    }
    point_fields(b, pl, &t, nlp ? lp : NULL, nlp);
    sf_outbuf_printf(b, "\t%s", nbp ? field(bp, nbp, ct) : "");
    point_fields(b, pl, &t, nbp ? bp : NULL, nbp);
    free(t.text);
}

/* The child's last "smoothfold: " line in run.log, tabs made blanks. */
static void reason_of(const char *vd, char *buf, size_t n)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/run.log", vd);
    char *log = read_text(path);
    buf[0] = '\0';
    const char *last = NULL, *pre = "smoothfold: ";
    for (char *c = log; c && *c;) {
        if (strncmp(c, pre, strlen(pre)) == 0) last = c + strlen(pre);
        char *nl = strchr(c, '\n');
        c = nl ? nl + 1 : c + strlen(c);
    }
    if (last) {
        size_t i = 0;
        for (; last[i] && last[i] != '\n' && i + 1 < n; i++) buf[i] = last[i] == '\t' ? ' ' : last[i];
        buf[i] = '\0';
    }
    free(log);
}

char *sf_sweep_collect(const sf_sweep_plan *pl, const char *dir, int v, int wstatus, double wall_s)
{
    char vd[1100], reason[600];
    sf_sweep_vdir(pl, dir, v, vd, sizeof vd);
    int status;
    reason_of(vd, reason, sizeof reason);
    if (WIFSIGNALED(wstatus)) {
        status = 128 + WTERMSIG(wstatus);
        snprintf(reason, sizeof reason, "killed by signal %d (%s)", WTERMSIG(wstatus),
                 strsignal(WTERMSIG(wstatus)));
    } else {
        status = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : 127;
        if (!reason[0]) snprintf(reason, sizeof reason, "%s", status ? "failed without a message" : "-");
    }
    sf_outbuf b = {0};
    row_prefix(pl, v, &b);
    sf_outbuf_printf(&b, "%d\t%s", status, reason);
    path_fields(&b, pl, vd);
    special_fields(&b, pl, vd);
    sf_outbuf_printf(&b, "\t%.3f", wall_s);
    if (b.oom) {
        sf_outbuf_free(&b);
        return NULL;
    }
    return b.s;
}
