/* plot.c - `smoothfold plot DIR`: the gnuplot scripts of plots/ on a run
 * directory, told what the columns mean.
 *
 * The scripts read DIR/branch.tsv (or trajectory.tsv); what the table does
 * not say - the study's name, what p is per load stage, probe, fold and
 * group names, which folds to draw - comes from DIR/study.cfg (the merged
 * study the run wrote) and is passed as gnuplot variables (-e sf_... =
 * "..."), so the scripts also run by hand without them.
 */
#include <errno.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include "commands.h"
#include "outbuf.h"
#include "study.h"

#include <libconfig.h>

#ifndef SF_SRCDIR
#define SF_SRCDIR "."
#endif

extern char **environ;

/* gnuplot [-e VARS] -c SCRIPT DIR */
static int run_gnuplot(const char *script, const char *dir, const char *vars, sf_error *err)
{
    char *av[7];
    int n = 0;
    av[n++] = "gnuplot";
    if (vars && vars[0]) {
        av[n++] = "-e";
        av[n++] = (char *)vars;
    }
    av[n++] = "-c";
    av[n++] = (char *)script;
    av[n++] = (char *)dir;
    av[n] = NULL;
    pid_t pid;
    int rc = posix_spawnp(&pid, "gnuplot", NULL, NULL, av, environ);
    if (rc != 0)
        return sf_fail(err, SF_EIO, "plot: cannot run gnuplot (%s); install it with "
                       "apt-get install gnuplot-nox", strerror(rc));
    int status;
    if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return sf_fail(err, SF_EIO, "plot: gnuplot failed on %s", script);
    return SF_OK;
}

/* Run plots/NAME for each name of scripts on dir. */
static int run_scripts(const char *dir, const char *const *scripts, int n, const char *vars,
                       sf_error *err)
{
    char pdir[1024], script[1200];
    struct stat st;
    const char *env = getenv("SMOOTHFOLD_PLOTS");
    snprintf(pdir, sizeof pdir, "%s", env && env[0] ? env : SF_SRCDIR "/plots");
    for (int i = 0; i < n; i++) {
        snprintf(script, sizeof script, "%s/%s", pdir, scripts[i]);
        if (stat(script, &st) != 0)
            return sf_fail(err, SF_EIO, "plot: %s not found (set SMOOTHFOLD_PLOTS to the plots/ "
                           "directory)", script);
        if (run_gnuplot(script, dir, vars, err)) return err->code;
    }
    return SF_OK;
}

/* What p is, per load stage: "load factor p (stage 1, p in [0, 1]: 2 loads,
 * 5 N)", for the axis label. */
static void describe_p(const sf_study *s, sf_outbuf *b)
{
    const char *param = "load";
    sf_study_string(s, "analysis.parameter", "load", &param, NULL);
    if (strcmp(param, "actuation") == 0) {
        sf_outbuf_printf(b, "actuation factor p (rest angle = p x that of the group");
        if (s->ngroups == 1) sf_outbuf_printf(b, " %s, %.4g rad", s->groups[0].name,
                                              s->groups[0].rest_angle);
        sf_outbuf_printf(b, ")");
        return;
    }
    if (strcmp(param, "displacement") == 0) {
        sf_outbuf_printf(b, "prescribed displacement p [m]");
        return;
    }
    sf_outbuf_printf(b, "load factor p");
    for (int k = 1; k <= s->nstages; k++) {
        int n = 0;
        double f = 0;
        for (int i = 0; i < s->nloads; i++)
            if (s->loads[i].stage == k) {
                n++;
                f += sqrt(s->loads[i].force[0] * s->loads[i].force[0] +
                          s->loads[i].force[1] * s->loads[i].force[1] +
                          s->loads[i].force[2] * s->loads[i].force[2]);
            }
        int grav = s->gravity_on && s->gravity_stage == k;
        sf_outbuf_printf(b, "%s", k == 1 ? " (" : "; ");
        if (s->nstages > 1) sf_outbuf_printf(b, "stage %d, p in [%d, %d]: ", k, k - 1, k);
        else sf_outbuf_printf(b, "1 = ");
        if (n == 1) sf_outbuf_printf(b, "%.4g N", f);
        else if (n > 1) sf_outbuf_printf(b, "%d loads, %.4g N in all", n, f);
        if (grav) sf_outbuf_printf(b, "%sgravity", n ? " + " : "");
        if (!n && !grav) sf_outbuf_printf(b, "no load");
    }
    sf_outbuf_printf(b, ")");
}

/* Which folds angles.gp draws: a list of fold names, group names, numbers
 * from 1, or "all" (comma or space separated); "" draws the default. */
static int select_folds(const sf_study *s, const char *sel, sf_outbuf *b, sf_error *err)
{
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", sel);
    int any = 0;
    for (char *tok = strtok(buf, ", "); tok; tok = strtok(NULL, ", ")) {
        if (strcmp(tok, "all") == 0) {
            for (int i = 0; i < s->nfolds; i++) sf_outbuf_printf(b, " %d", i + 1);
            any = 1;
            continue;
        }
        int f = sf_study_fold_index(s, tok), g = sf_study_group_index(s, tok);
        char *end;
        long k = strtol(tok, &end, 10);
        if (f >= 0) sf_outbuf_printf(b, " %d", f + 1);
        else if (g >= 0) {
            for (int i = 0; i < s->nfolds; i++)
                if (s->folds[i].group == g) sf_outbuf_printf(b, " %d", i + 1);
        } else if (!*end && k >= 1 && k <= s->nfolds) sf_outbuf_printf(b, " %ld", k);
        else
            return sf_fail(err, SF_EINPUT, "plot: --folds: '%s' is no fold name, group name or "
                           "fold number 1..%d of %s", tok, s->nfolds, s->name);
        any = 1;
    }
    if (!any) return sf_fail(err, SF_EINPUT, "plot: --folds: empty selection");
    return SF_OK;
}

/* gnuplot variables from DIR/study.cfg; "" when it cannot be read (the
 * scripts then fall back to column names). */
static int plot_vars(const char *dir, const char *folds, sf_outbuf *v, sf_error *err)
{
    char path[1100];
    snprintf(path, sizeof path, "%s/study.cfg", dir);
    sf_study s;
    sf_error serr;
    sf_error_clear(&serr);
    if (sf_study_load(path, 0, NULL, &s, &serr)) {
        if (folds) return sf_fail(err, SF_EINPUT, "plot: --folds needs %s: %s", path, serr.msg);
        return SF_OK;
    }
    sf_outbuf_printf(v, "sf_title = \"%s\"; sf_plabel = \"", s.name);
    describe_p(&s, v);
    sf_outbuf_printf(v, "\"; sf_probes = \"");
    for (int i = 0; i < s.nprobes; i++) sf_outbuf_printf(v, "%s%s", i ? " " : "", s.probes[i].name);
    sf_outbuf_printf(v, "\"; sf_folds = \"");
    for (int i = 0; i < s.nfolds; i++) {
        if (s.folds[i].name[0]) sf_outbuf_printf(v, "%s%s", i ? " " : "", s.folds[i].name);
        else sf_outbuf_printf(v, "%sfold%d", i ? " " : "", i + 1);
    }
    sf_outbuf_printf(v, "\"; sf_fgroup = \"");
    for (int i = 0; i < s.nfolds; i++) sf_outbuf_printf(v, "%s%d", i ? " " : "", s.folds[i].group + 1);
    sf_outbuf_printf(v, "\"; sf_groups = \"");
    for (int i = 0; i < s.ngroups; i++) sf_outbuf_printf(v, "%s%s", i ? " " : "", s.groups[i].name);
    sf_outbuf_printf(v, "\";");
    int rc = SF_OK;
    char fromstudy[4096] = "";
    if (!folds && sf_study_count(&s, "output.plot_folds") > 0) {
        /* the study's selection, as a --folds list */
        int n = sf_study_count(&s, "output.plot_folds");
        config_setting_t *a = config_lookup((const config_t *)s.cfg, "output.plot_folds");
        for (int i = 0; a && i < n; i++) {
            const char *w = config_setting_get_string_elem(a, i);
            size_t l = strlen(fromstudy);
            snprintf(fromstudy + l, sizeof fromstudy - l, "%s%s", i ? "," : "", w ? w : "");
        }
        folds = fromstudy;
    }
    if (folds) {
        sf_outbuf_printf(v, " sf_select = \"");
        rc = select_folds(&s, folds, v, err);
        sf_outbuf_printf(v, "\";");
    }
    sf_study_free(&s);
    if (!rc && v->oom) rc = sf_fail(err, SF_ENOMEM, "out of memory");
    return rc;
}

int sf_cli_run_plots(const sf_options *o, sf_error *err)
{
    char path[1100];
    snprintf(path, sizeof path, "%s/branch.tsv", o->output);
    struct stat st;
    if (stat(path, &st) != 0) return SF_OK;   /* a dynamics run draws its own */
    int want = o->plot;
    if (want < 0) {   /* the merged study the run wrote: output.plots */
        sf_study s;
        sf_error serr;
        sf_error_clear(&serr);
        snprintf(path, sizeof path, "%s/study.cfg", o->output);
        want = 0;
        if (sf_study_load(path, 0, NULL, &s, &serr) == SF_OK) {
            /* the schema's default (true) is a dynamics default: an
             * equilibrium study draws only when it says so */
            if (sf_study_has(&s, "output.plots")) sf_study_bool(&s, "output.plots", 0, &want, NULL);
            sf_study_free(&s);
        }
    }
    if (!want) return SF_OK;
    return sf_cmd_plot(o->output, o->folds, err);
}

int sf_plot_trajectory(const char *dir, sf_error *err)
{
    const char *scripts[] = {"trajectory.gp"};
    return run_scripts(dir, scripts, 1, NULL, err);
}

int sf_cmd_plot(const char *dir, const char *folds, sf_error *err)
{
    char branch[1200], traj[1200], bnd[1200];
    struct stat st;
    snprintf(bnd, sizeof bnd, "%s/boundary.tsv", dir);
    if (stat(bnd, &st) == 0) {
        /* a two-parameter stability diagram (analysis.type = "boundary") */
        const char *scripts[] = {"boundary.gp"};
        if (run_scripts(dir, scripts, 1, NULL, err)) return err->code;
        printf("wrote %s/boundary.png, boundary.pdf\n", dir);
        return SF_OK;
    }
    snprintf(branch, sizeof branch, "%s/branch.tsv", dir);
    snprintf(traj, sizeof traj, "%s/trajectory.tsv", dir);
    int have_branch = stat(branch, &st) == 0, have_traj = stat(traj, &st) == 0;
    char sweep[1200];
    snprintf(sweep, sizeof sweep, "%s/sweep.tsv", dir);
    if (!have_branch && !have_traj && stat(sweep, &st) == 0) {
        const char *scripts[] = {"sweep.gp"};   /* a sweep directory (docs/guides/sweeps.md) */
        if (run_scripts(dir, scripts, 1, NULL, err)) return err->code;
        printf("wrote %s/sweep.png, sweep.pdf\n", dir);
        return SF_OK;
    }
    if (!have_branch && !have_traj)
        return sf_fail(err, SF_EIO, "plot: %s: no such file (run `smoothfold run STUDY.cfg -o %s` "
                       "first)", branch, dir);
    if (have_branch) {
        sf_outbuf vars = {0};
        int rc = plot_vars(dir, folds, &vars, err);
        const char *scripts[] = {"stability.gp", "eigenvalues.gp", "angles.gp"};
        if (!rc) rc = run_scripts(dir, scripts, 3, vars.s ? vars.s : "", err);
        sf_outbuf_free(&vars);
        if (rc) return rc;
        printf("wrote in %s:", dir);
        const char *outs[] = {"stability", "eigenvalues", "angles"};
        for (size_t i = 0; i < sizeof outs / sizeof *outs; i++) {
            char f[1200];
            snprintf(f, sizeof f, "%s/%s.png", dir, outs[i]);
            if (stat(f, &st) == 0) printf(" %s.png|pdf", outs[i]);
        }
        printf("\n");
    }
    if (have_traj) {
        if (sf_plot_trajectory(dir, err)) return err->code;
        printf("wrote %s/trajectory.png, trajectory.pdf\n", dir);
    }
    return SF_OK;
}
