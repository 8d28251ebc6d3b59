/* cmd_fold.c - smoothfold import (a FOLD crease pattern as a study) and
 * smoothfold export (a study's crease pattern as FOLD). */
#include "commands.h"

#include <stdio.h>
#include <string.h>

#include "cpattern.h"
#include "fold.h"
#include "foldread.h"
#include "study.h"
#include "topology.h"

/* a study name from the FOLD title or the file name: [A-Za-z0-9_.-] */
static void study_name(const sf_cpattern *cp, const char *path, char *out, size_t n)
{
    const char *src = cp->title;
    char base[256];
    if (!src[0]) {
        const char *sl = strrchr(path, '/');
        snprintf(base, sizeof base, "%s", sl ? sl + 1 : path);
        char *dot = strrchr(base, '.');
        if (dot && dot != base) *dot = '\0';
        src = base;
    }
    size_t k = 0;
    for (; src[k] && k + 1 < n && k < 63; k++) {
        char c = src[k];
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                 c == '_' || c == '.' || c == '-';
        out[k] = ok ? c : '-';
    }
    out[k] = '\0';
    if (!k) snprintf(out, n, "imported");
}

int sf_cmd_import(int argc, char **argv, const char *cmdline, const char *output, const char *unit,
                  int frame, struct sf_cp_study_opts *so, int nset,
                  const char **sets, sf_error *err)
{
    const char *in = argv[argc - 1];
    sf_cpattern cp;
    char note[160];
    if (sf_fold_read(in, frame, unit, &cp, note, sizeof note, err)) return err->code;
    char name[64], hdr[900];
    study_name(&cp, in, name, sizeof name);
    int nm = 0, nv = 0, nu = 0, nf = 0;
    for (int e = 0; e < cp.ne; e++) {
        char a = cp.e[e].assign;
        nm += a == 'M'; nv += a == 'V'; nu += a == 'U'; nf += a == 'F';
    }
    snprintf(hdr, sizeof hdr,
             "%s - imported from the FOLD file %s%s.\n\nImported by: %s\n"
             "Unit: %s.  Edges: %d mountain, %d valley, %d unassigned, %d flat%s.\n"
             "(docs/guides/importing-patterns.md)", name, in, frame >= 0 ? " (the frame asked for)" : "", cmdline, note,
             nm, nv, nu, nf, nf && !so->include_flat ? " (flat edges dropped: --include-flat keeps them)" : "");
    so->name = name;
    so->header = hdr;
    int rc = sf_cp_write_study(&cp, so, output, nset, sets, err);
    sf_cp_free(&cp);
    return rc;
}

int sf_cmd_export(int argc, char **argv, const char *output, int nset,
                  const char **sets, sf_error *err)
{
    const char *in = argv[argc - 1];
    sf_study s;
    sf_topology t;
    memset(&t, 0, sizeof t);
    int rc = sf_study_load(in, nset, sets, &s, err);
    if (!rc) rc = sf_topology_build(&s, &t, err);
    sf_cpattern cp;
    sf_cp_init(&cp);
    if (!rc) rc = sf_cp_from_study(&s, &t, &cp, err);
    if (!rc) rc = sf_fold_write_pattern(&cp, output, err);
    sf_cp_free(&cp);
    sf_topology_free(&t);
    sf_study_free(&s);
    return rc;
}
