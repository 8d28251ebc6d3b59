/* cmd_fold.c - smoothfold import (a FOLD or SVG crease pattern as a study,
 * or as FOLD) and smoothfold export (a study's crease pattern as FOLD).
 * import prints what it read on stdout, its size first. */
#include "commands.h"

#include <math.h>
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

/* "200 x 150 mm" */
static void size_text(const sf_import_info *info, char *buf, size_t n)
{
    double w = 1e3 * info->width, h = 1e3 * info->height;
    if (fmax(w, h) >= 10000) snprintf(buf, n, "%.4g x %.4g m", w / 1e3, h / 1e3);
    else snprintf(buf, n, "%.4g x %.4g mm", w, h);
}

/* Bands that fit at no width: where two points of the file nearly
 * coincide (an edge shorter than 1e-3 of the sheet), merging them is what
 * to try */
static void near_points_hint(const sf_cpattern *cp, const sf_import_opts *io, const char *format, sf_error *err)
{
    double lmin = INFINITY;
    for (int e = 0; e < cp->ne; e++)
        lmin = fmin(lmin, hypot(cp->v[cp->e[e].b].x[0] - cp->v[cp->e[e].a].x[0],
                                cp->v[cp->e[e].b].x[1] - cp->v[cp->e[e].a].x[1]));
    double r = lmin / sf_cp_size(cp);
    if (!(r < 1e-3)) return;
    size_t l = strlen(err->msg);
    if (strcmp(format, "FOLD") == 0 && !io->planarize)
        snprintf(err->msg + l, sizeof err->msg - l, "; its shortest edge is %.2g of the sheet across (points that nearly "
                 "coincide): --planarize merges vertices within %g of it", r, io->merge);
    else if (r < io->merge * 2)
        snprintf(err->msg + l, sizeof err->msg - l, "; its shortest edge is %.2g of the sheet across (points that nearly "
                 "coincide): --merge=%g merges ends farther apart", r, 2 * io->merge);
}

int sf_cmd_import(int argc, char **argv, const char *cmdline, const char *output,
                  const sf_import_opts *io, struct sf_cp_study_opts *so, int nset,
                  const char **sets, sf_error *err)
{
    const char *in = argv[argc - 1];
    sf_cpattern cp;
    sf_import_info info;
    if (sf_import_read(in, io, &cp, &info, err)) return err->code;
    size_t olen = strlen(output);
    int to_fold = olen >= 5 && strcmp(output + olen - 5, ".fold") == 0;
    if (!to_fold) {   /* a study: folds that cannot turn with rigid faces are left out */
        char what[200];
        int nfold0 = 0, nd = sf_cp_drop_dangling(&cp, so->include_flat, what, sizeof what, err);
        if (nd < 0) { sf_cp_free(&cp); return err->code; }
        for (int e = 0; e < cp.ne; e++)
            nfold0 += cp.e[e].assign != 'B' && (cp.e[e].assign != 'F' || so->include_flat);
        if (nd > 0 && nfold0 == 0) {
            sf_cp_free(&cp);
            return sf_fail(err, SF_EINPUT, "%s: no fold separates two faces: the %d fold%s end%s inside a face "
                           "(%s), where rigid faces keep %s flat", in, nd, nd > 1 ? "s" : "", nd > 1 ? "" : "s",
                           what, nd > 1 ? "them" : "it");
        }
        if (nd > 0)
            sf_import_note(&info, "%d fold%s left out: %s inside a face, where rigid faces keep %s flat (%s)", nd,
                           nd > 1 ? "s" : "", nd > 1 ? "they end" : "it ends", nd > 1 ? "them" : "it", what);
    }
    char name[64], hdr[2600], size[64];
    study_name(&cp, in, name, sizeof name);
    size_text(&info, size, sizeof size);
    int nm = 0, nv = 0, nu = 0, nf = 0;
    for (int e = 0; e < cp.ne; e++) {
        char a = cp.e[e].assign;
        nm += a == 'M'; nv += a == 'V'; nu += a == 'U'; nf += a == 'F';
    }
    int rc;
    size_t l = (size_t)snprintf(hdr, sizeof hdr,
             "%s - imported from the %s file %s%s.\n\nImported by: %s\n"
             "Size: %s (%s).\nEdges: %d mountain, %d valley, %d unassigned, %d facet (F)%s.",
             name, info.format, in, io->frame >= 0 ? " (the frame asked for)" : "", cmdline, size, info.scale,
             nm, nv, nu, nf, nf && so->include_flat ? " (--include-flat: the facet edges are folds)" : "");
    for (int k = 0; k < info.nnotes && l < sizeof hdr; k++)
        l += (size_t)snprintf(hdr + l, sizeof hdr - l, "\n%s.", info.notes[k]);
    if (l < sizeof hdr) snprintf(hdr + l, sizeof hdr - l, "\n(docs/guides/importing-patterns.md, docs/reference/svg-format.md)");
    if (to_fold) {
        if (nset) { sf_cp_free(&cp); return sf_fail(err, SF_EINPUT, "import: --set applies to a study (-o S.cfg), not to FOLD output"); }
        if (!cp.title[0]) snprintf(cp.title, sizeof cp.title, "%s", name);
        rc = sf_fold_write_pattern(&cp, output, err);
    } else {
        so->name = name;
        so->header = hdr;
        rc = sf_cp_write_study(&cp, so, output, nset, sets, err);
        if (rc && strstr(err->msg, "did not fit either")) near_points_hint(&cp, io, info.format, err);
    }
    if (!rc) {
        /* what was read, the size first */
        printf("%s: %s crease pattern, %s (%s)\n", in, info.format, size, info.scale);
        for (int k = 0; k < info.nnotes; k++) printf("%s: %s\n", in, info.notes[k]);
        printf("%s: %d mountain, %d valley, %d unassigned, %d facet edges -> %s\n", in, nm, nv, nu, nf, output);
    }
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
