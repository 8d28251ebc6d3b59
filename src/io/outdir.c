/* outdir.c - the output directory of a run (outdir.h). */
#include "outdir.h"

#include <dirent.h>
#include <errno.h>
#include <fnmatch.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "outbuf.h"
#include "vtk.h"

#define MARKER ".smoothfold"

/* Names smoothfold writes at the top of DIR (fnmatch patterns). */
static const char *const own_top[] = {
    MARKER, "branch.tsv", "special.tsv", "stats.csv", "study.cfg", "reactions.tsv",
    "trajectory.tsv", "compare*.tsv", "convergence.tsv", "folded.fold", "shapes.pvd", "shapes_branch*.pvd",
    "stability.png", "stability.pdf", "eigenvalues.png", "eigenvalues.pdf", "angles.png",
    "angles.pdf", "trajectory.png", "trajectory.pdf", "boundary.tsv", "boundary.png",
    "boundary.pdf", "*.tmp",
};
/* ... and in DIR/shapes/ */
static const char *const own_shapes[] = {"shape_*.vtp", "*.tmp"};

static int matches(const char *name, const char *const *pat, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (fnmatch(pat[i], name, 0) == 0) return 1;
    return 0;
}

/* Walk dir (and dir/shapes): count own and other entries; remove the own
 * ones when doit.  Returns SF_OK or an SF_EIO error. */
static int scan(const char *dir, int doit, int *own, int *other, char *first_other,
                size_t nfo, sf_error *err)
{
    DIR *d = opendir(dir);
    if (!d) return sf_fail(err, SF_EIO, "%s: cannot read directory: %s", dir, strerror(errno));
    struct dirent *e;
    int rc = SF_OK;
    char path[2048];
    while (!rc && (e = readdir(d))) {
        const char *nm = e->d_name;
        if (!strcmp(nm, ".") || !strcmp(nm, "..")) continue;
        snprintf(path, sizeof path, "%s/%s", dir, nm);
        struct stat st;
        if (lstat(path, &st) != 0) continue;
        if (S_ISDIR(st.st_mode) && !strcmp(nm, "kplus1")) {
            /* the K+1 run of analysis.convergence: a run directory of its own */
            int o2 = 0, x2 = 0;
            char fo[256] = "";
            rc = scan(path, doit, &o2, &x2, fo, sizeof fo, err);
            *own += o2;
            *other += x2;
            if (x2 && !first_other[0]) snprintf(first_other, nfo, "kplus1/%s", fo);
            if (!rc && doit && !x2) rmdir(path);
        } else if (S_ISDIR(st.st_mode) && !strcmp(nm, "shapes")) {
            DIR *sd = opendir(path);
            if (!sd) { rc = sf_fail(err, SF_EIO, "%s: cannot read directory: %s", path, strerror(errno)); break; }
            struct dirent *se;
            char sp[2400];
            int others_here = 0;
            while (!rc && (se = readdir(sd))) {
                if (!strcmp(se->d_name, ".") || !strcmp(se->d_name, "..")) continue;
                snprintf(sp, sizeof sp, "%s/%s", path, se->d_name);
                if (matches(se->d_name, own_shapes, sizeof own_shapes / sizeof *own_shapes)) {
                    (*own)++;
                    if (doit && unlink(sp) != 0)
                        rc = sf_fail(err, SF_EIO, "%s: cannot remove: %s", sp, strerror(errno));
                } else {
                    (*other)++;
                    others_here++;
                    if (!first_other[0]) snprintf(first_other, nfo, "shapes/%s", se->d_name);
                }
            }
            closedir(sd);
            if (!rc && doit && !others_here) rmdir(path);
        } else if (S_ISREG(st.st_mode) && matches(nm, own_top, sizeof own_top / sizeof *own_top)) {
            (*own)++;
            if (doit && unlink(path) != 0)
                rc = sf_fail(err, SF_EIO, "%s: cannot remove: %s", path, strerror(errno));
        } else {
            (*other)++;
            if (!first_other[0]) snprintf(first_other, nfo, "%s", nm);
        }
    }
    closedir(d);
    return rc;
}

/* Written by smoothfold: the marker, or (results from before the marker)
 * a table whose first line is smoothfold's header. */
static int is_ours(const char *dir)
{
    const char *probe[] = {MARKER, "branch.tsv", "trajectory.tsv", "boundary.tsv"};
    char path[1100], line[64];
    for (size_t i = 0; i < sizeof probe / sizeof *probe; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, probe[i]);
        FILE *f = fopen(path, "r");
        if (!f) continue;
        int ok = i == 0 || (fgets(line, sizeof line, f) && !strncmp(line, "# smoothfold ", 13));
        fclose(f);
        if (ok) return 1;
    }
    return 0;
}

static int fill_marker(void *ctx, void *f)
{
    (void)ctx;
    fputs("This directory holds the results of `smoothfold run`.  The next run into it\n"
          "removes them first (branch.tsv, shapes/, plots, ...); other files are kept.\n",
          (FILE *)f);
    return ferror((FILE *)f) ? SF_EIO : SF_OK;
}

int sf_outdir_prepare(const char *dir, int force, int *removed, sf_error *err)
{
    *removed = 0;
    struct stat st;
    if (stat(dir, &st) == 0) {
        if (!S_ISDIR(st.st_mode))
            return sf_fail(err, SF_EIO, "%s: exists and is not a directory", dir);
        int own = 0, other = 0;
        char first[512] = "";
        if (scan(dir, 0, &own, &other, first, sizeof first, err)) return err->code;
        if (own + other > 0 && !is_ours(dir) && !force)
            return sf_fail(err, SF_EIO, "%s: directory is not empty and holds no smoothfold "
                           "results (e.g. '%s'); choose another -o DIR, or give --force to "
                           "write into it (its other files are kept)", dir, first);
        if (own > 0) {
            int o2 = 0, x2 = 0;
            first[0] = '\0';
            if (scan(dir, 1, &o2, &x2, first, sizeof first, err)) return err->code;
            *removed = o2;
        }
    } else if (sf_mkdir_p(dir, err)) {
        return err->code;
    }
    char marker[1100];
    snprintf(marker, sizeof marker, "%s/" MARKER, dir);
    return sf_write_atomic(marker, fill_marker, NULL, err);
}
