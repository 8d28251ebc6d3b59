/* cmp_runs.c - `smoothfold compare DIR_A DIR_B`: how far apart two
 * equilibrium runs of the same sheet are (K against K+1 shape modes, two
 * step sizes, two solvers).
 *
 * Reads branch 1 of DIR_A/branch.tsv and DIR_B/branch.tsv, keeps the first
 * stretch of each along which p is monotone (a limit point ends it: past
 * it, p no longer names one state), and for every point of A inside B's
 * p range interpolates B linearly in p.  For every probe displacement and
 * fold angle column (`probe*`, `theta*`) it prints the largest difference
 * and where it occurs.  No NaN reaches the table: a non-numeric field is
 * an error naming file and line.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "commands.h"
#include "study.h"
#include "vtk.h"

typedef struct run_table {
    char path[1100];
    int ncol;
    char **name;       /* column names */
    int cp;            /* index of p */
    int n, cap;        /* rows kept */
    double *v;         /* n x ncol */
} run_table;

static void table_free(run_table *t)
{
    for (int i = 0; i < t->ncol; i++) free(t->name[i]);
    free(t->name);
    free(t->v);
    memset(t, 0, sizeof *t);
}

static int col_index(const run_table *t, const char *name)
{
    for (int i = 0; i < t->ncol; i++)
        if (strcmp(t->name[i], name) == 0) return i;
    return -1;
}

static int parse_header(run_table *t, char *line, sf_error *err)
{
    for (char *tok = strtok(line, "\t\n"); tok; tok = strtok(NULL, "\t\n")) {
        char **nn = realloc(t->name, sizeof(char *) * (size_t)(t->ncol + 1));
        if (!nn) return sf_fail(err, SF_ENOMEM, "out of memory");
        t->name = nn;
        if (!(t->name[t->ncol] = strdup(tok))) return sf_fail(err, SF_ENOMEM, "out of memory");
        t->ncol++;
    }
    t->cp = col_index(t, "p");
    if (t->cp < 0 || col_index(t, "branch") < 0)
        return sf_fail(err, SF_EINPUT, "%s: header row has no 'p' or 'branch' column "
                       "(not a branch table of `smoothfold run`)", t->path);
    return SF_OK;
}

/* One data row into t->v (only columns that are probes, thetas, p and
 * branch need to be numbers; others are read as NaN and never used). */
static int parse_row(run_table *t, char *line, int lineno, int *branch, double *row,
                     sf_error *err)
{
    int cb = col_index(t, "branch");
    char *p = line;
    *branch = 0;
    for (int c = 0; c < t->ncol; c++) {
        char *tab = strchr(p, '\t');
        if (tab) *tab = '\0';
        char *nl = strchr(p, '\n');
        if (nl) *nl = '\0';
        const char *nm = t->name[c];
        int need = c == t->cp || c == cb || strncmp(nm, "probe", 5) == 0 ||
                   strncmp(nm, "theta", 5) == 0;
        row[c] = NAN;
        if (need) {
            char *end;
            errno = 0;
            double x = strtod(p, &end);
            if (end == p || *end || errno || !isfinite(x))
                return sf_fail(err, SF_EINPUT, "%s:%d: column %s: not a finite number ('%s')",
                               t->path, lineno, nm, p);
            row[c] = x;
        }
        if (!tab) {
            if (c + 1 < t->ncol)
                return sf_fail(err, SF_EINPUT, "%s:%d: %d fields, the header has %d", t->path,
                               lineno, c + 1, t->ncol);
            break;
        }
        p = tab + 1;
    }
    *branch = (int)row[cb];
    return SF_OK;
}

/* Read branch 1 of DIR/branch.tsv, up to its first reversal of p. */
static int table_read(run_table *t, const char *dir, sf_error *err)
{
    memset(t, 0, sizeof *t);
    snprintf(t->path, sizeof t->path, "%s/branch.tsv", dir);
    FILE *f = fopen(t->path, "r");
    if (!f) return sf_fail(err, SF_EIO, "%s: cannot read: %s (is %s the output of `smoothfold run`?)",
                           t->path, strerror(errno), dir);
    char line[65536];
    int lineno = 0, rc = SF_OK, dir_sign = 0, done = 0;
    double *row = NULL;
    while (!rc && !done && fgets(line, sizeof line, f)) {
        lineno++;
        if (line[0] == '#' || line[0] == '\n') continue;
        if (!t->name) {
            rc = parse_header(t, line, err);
            if (!rc && !(row = malloc(sizeof(double) * (size_t)t->ncol)))
                rc = sf_fail(err, SF_ENOMEM, "out of memory");
            continue;
        }
        int br = 0;
        if ((rc = parse_row(t, line, lineno, &br, row, err))) break;
        if (br != 1) break;
        if (t->n > 0) {
            double dp = row[t->cp] - t->v[(size_t)(t->n - 1) * t->ncol + t->cp];
            int sg = dp > 0 ? 1 : dp < 0 ? -1 : 0;
            if (sg == 0) continue;
            if (dir_sign == 0) dir_sign = sg;
            else if (sg != dir_sign) { done = 1; break; }
        }
        if (t->n == t->cap) {
            t->cap = t->cap ? 2 * t->cap : 64;
            double *nv = realloc(t->v, sizeof(double) * (size_t)t->cap * t->ncol);
            if (!nv) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); break; }
            t->v = nv;
        }
        memcpy(t->v + (size_t)t->n * t->ncol, row, sizeof(double) * t->ncol);
        t->n++;
    }
    free(row);
    fclose(f);
    if (!rc && !t->name) rc = sf_fail(err, SF_EINPUT, "%s: no header row", t->path);
    if (!rc && t->n < 2)
        rc = sf_fail(err, SF_EINPUT, "%s: fewer than two points on branch 1", t->path);
    return rc;
}

/* B's column c interpolated at parameter p; 0 when p is outside B. */
static int interp(const run_table *b, int c, double p, double *out)
{
    const double *v = b->v;
    int w = b->ncol, cp = b->cp;
    for (int i = 0; i + 1 < b->n; i++) {
        double p0 = v[(size_t)i * w + cp], p1 = v[(size_t)(i + 1) * w + cp];
        if ((p - p0) * (p - p1) <= 0) {
            double a = p1 == p0 ? 0.0 : (p - p0) / (p1 - p0);
            *out = (1 - a) * v[(size_t)i * w + c] + a * v[(size_t)(i + 1) * w + c];
            return 1;
        }
    }
    return 0;
}

/* The comparison table into f; worst[0], worst[1]: the largest probe [m]
 * and fold angle [rad] differences (-1 when there is none). */
static int compare_tables(const run_table *a, const run_table *b, const sf_options *o,
                          FILE *f, double worst_out[2], sf_error *err)
{
    int na = 0, nb = 0;
    for (int c = 0; c < a->ncol; c++)
        na += !strncmp(a->name[c], "probe", 5) || !strncmp(a->name[c], "theta", 5);
    for (int c = 0; c < b->ncol; c++)
        nb += !strncmp(b->name[c], "probe", 5) || !strncmp(b->name[c], "theta", 5);
    if (na != nb)
        return sf_fail(err, SF_EINPUT, "%s and %s: not the same sheet (%d and %d probe and "
                       "fold angle columns)", a->path, b->path, na, nb);
    fprintf(f, "# smoothfold compare: %s against %s (branch 1, B interpolated in p)\n", a->path, b->path);
    fprintf(f, "column\tmax_abs_diff\tat_p\tmax_abs_A\trelative\tpoints\n");
    int worst_c = -1, above = 0, wk[2] = {-1, -1};
    double worst = -1, wv[2] = {-1, -1};   /* per kind: probes [m], angles [rad] */
    long used_total = 0;
    for (int c = 0; c < a->ncol; c++) {
        const char *nm = a->name[c];
        if (strncmp(nm, "probe", 5) && strncmp(nm, "theta", 5)) continue;
        int cb = col_index(b, nm);
        if (cb < 0)
            return sf_fail(err, SF_EINPUT, "%s: no column %s (in %s): not the same sheet",
                           b->path, nm, a->path);
        double dmax = 0, at = NAN, amax = 0;
        int used = 0;
        for (int i = 0; i < a->n; i++) {
            double p = a->v[(size_t)i * a->ncol + a->cp], vb;
            if (!interp(b, cb, p, &vb)) continue;
            double va = a->v[(size_t)i * a->ncol + c], d = fabs(va - vb);
            amax = fmax(amax, fabs(va));
            if (d > dmax || used == 0) { dmax = d; at = p; }
            used++;
        }
        if (!used)
            return sf_fail(err, SF_EINPUT, "%s and %s: no point of A within the p range of B",
                           a->path, b->path);
        used_total = used;
        fprintf(f, "%s\t%.6g\t%.6g\t%.6g\t", nm, dmax, at, amax);
        if (amax > 0) fprintf(f, "%.3g", dmax / amax); else fprintf(f, "-");
        fprintf(f, "\t%d\n", used);
        int kind = nm[0] == 't';
        if (dmax > wv[kind]) { wv[kind] = dmax; wk[kind] = c; }
        if (o->have_tol && dmax > o->tol && (worst_c < 0 || dmax > worst)) { worst = dmax; worst_c = c; }
        if (o->have_tol && dmax > o->tol) above++;
    }
    for (int k = 0; k < 2; k++)
        if (wk[k] >= 0)
            fprintf(f, "# largest %s difference: %s %.6g %s over %ld matched points\n",
                   k ? "fold angle" : "probe", a->name[wk[k]], wv[k], k ? "rad" : "m", used_total);
    worst_out[0] = wv[0];
    worst_out[1] = wv[1];
    if (above)
        return sf_fail(err, SF_EDIFFER, "compare: %d column%s differ by more than --tol=%g "
                       "(largest: %s, %.6g)", above, above == 1 ? "" : "s", o->tol,
                       a->name[worst_c], worst);
    return SF_OK;
}

int sf_cmd_compare(const char *dir_a, const char *dir_b, const sf_options *o, sf_error *err)
{
    run_table a, b;
    memset(&b, 0, sizeof b);
    int rc = table_read(&a, dir_a, err);
    if (!rc) rc = table_read(&b, dir_b, err);
    double worst[2];
    if (!rc) rc = compare_tables(&a, &b, o, stdout, worst, err);
    table_free(&a);
    table_free(&b);
    return rc;
}

/* ---- analysis.convergence: the same run at K+1 ------------------------- */

typedef struct conv_ctx {
    const run_table *a, *b;
    const sf_options *o;
    double worst[2];
    sf_error *err;
} conv_ctx;

static int fill_conv(void *vc, void *f)
{
    conv_ctx *c = vc;
    int rc = compare_tables(c->a, c->b, c->o, f, c->worst, c->err);
    return rc ? rc : (ferror((FILE *)f) ? SF_EIO : SF_OK);
}

int sf_cli_convergence(const sf_options *o, sf_error *err)
{
    char path[1100], sub[1100];
    snprintf(path, sizeof path, "%s/branch.tsv", o->output);
    if (access(path, F_OK) != 0) return SF_OK;   /* not an equilibrium path */
    snprintf(path, sizeof path, "%s/study.cfg", o->output);
    sf_study s;
    sf_error serr;
    sf_error_clear(&serr);
    if (sf_study_load(path, 0, NULL, &s, &serr)) return SF_OK;
    int on = 0;
    sf_study_bool(&s, "analysis.convergence", 0, &on, NULL);
    int n = s.nfolds - s.nfacets, rc = SF_OK;   /* facet hinges keep K = 0 */
    const char **sets = on ? calloc((size_t)(o->nset + n + 7), sizeof *sets) : NULL;
    char **own = on ? calloc((size_t)n + 1, sizeof *own) : NULL;
    if (on && (!sets || !own)) rc = sf_fail(err, SF_ENOMEM, "out of memory");
    int ns = 0;
    for (int i = 0; !rc && on && i < o->nset; i++) sets[ns++] = o->sets[i];
    for (int i = 0; !rc && on && i < n; i++) {
        if (s.folds[i].modes + 1 > SF_STUDY_MAX_MODES) {
            rc = sf_fail(err, SF_EINPUT, "%s: analysis.convergence: fold %d has K = %d, the largest; "
                         "no K+1 run", s.path, i + 1, s.folds[i].modes);
            break;
        }
        own[i] = malloc(64);
        if (!own[i]) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); break; }
        snprintf(own[i], 64, "folds[%d].modes=%d", i, s.folds[i].modes + 1);
        sets[ns++] = own[i];
    }
    /* the keys that "auto" resolved by the size of the sheet (run_equilibrium.c):
     * the K+1 sheet is larger, and is run with the same choices */
    static const char *const pinned[3] = {"solver.formulation", "analysis.flat_start",
                                          "analysis.step_norm"};
    char pin[3][96];
    for (int i = 0; !rc && on && i < 3; i++) {
        const char *v;
        if (sf_study_string(&s, pinned[i], "auto", &v, NULL) == SF_OK && strcmp(v, "auto") != 0 &&
            strlen(v) < 32) {
            snprintf(pin[i], sizeof pin[i], "%s=\"%s\"", pinned[i], v);
            sets[ns++] = pin[i];
        }
    }
    int kmin = 1 << 30, kmax = 0;
    for (int i = 0; i < n; i++) {
        if (s.folds[i].modes < kmin) kmin = s.folds[i].modes;
        if (s.folds[i].modes > kmax) kmax = s.folds[i].modes;
    }
    sf_study_free(&s);
    if (!on || rc) {
        for (int i = 0; own && i < n; i++) free(own[i]);
        free(own);
        free(sets);
        return rc;
    }
    sets[ns++] = "analysis.convergence=false";
    sets[ns++] = "output.shapes=0";
    sets[ns++] = "output.plots=false";
    sf_options o2 = *o;
    snprintf(sub, sizeof sub, "%s/kplus1", o->output);
    o2.output = sub;
    o2.sets = sets;
    o2.nset = ns;
    o2.quiet = 1;
    o2.plot = 0;
    o2.have_tol = 0;
    rc = sf_cmd_run(&o2, err);
    if (rc == SF_ETOLERANCE) {   /* the reference check is the main run's business */
        sf_error_clear(err);
        rc = SF_OK;
    }
    if (rc) sf_error_prefix(err, "analysis.convergence: the run with K+1 shape modes");
    run_table a, b;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    if (!rc) rc = table_read(&a, o->output, err);
    if (!rc) rc = table_read(&b, sub, err);
    conv_ctx c = {&a, &b, &o2, {-1, -1}, err};
    snprintf(path, sizeof path, "%s/convergence.tsv", o->output);
    if (!rc) rc = sf_write_atomic(path, fill_conv, &c, err);
    if (!rc && !o->quiet) {
        printf("convergence (K = %d", kmin);
        if (kmax != kmin) printf("..%d", kmax);
        printf(" against K+1): largest probe difference %.3g m, fold angle %.3g rad (%s)\n",
               c.worst[0], c.worst[1], path);
    }
    table_free(&a);
    table_free(&b);
    for (int i = 0; i < n; i++) free(own[i]);
    free(own);
    free(sets);
    return rc;
}
