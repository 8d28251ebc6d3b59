/* import.c - a crease pattern from a FOLD or SVG file, in metres
 * (foldread.h): the reader chosen, the size taken (the file's unit,
 * --unit, --size, or the default sheet of SF_IMPORT_DEFAULT_SIZE across),
 * the pattern made planar where asked, and checked. */
#include "foldread.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

void sf_import_opts_default(sf_import_opts *o)
{
    memset(o, 0, sizeof *o);
    o->frame = -1;
    o->angle_sign = SF_SIGN_FOLD;
    o->merge = 3e-3;
}

void sf_import_note(sf_import_info *info, const char *fmt, ...)
{
    if (!info || info->nnotes >= SF_IMPORT_NOTES) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(info->notes[info->nnotes++], sizeof info->notes[0], fmt, ap);
    va_end(ap);
}

double sf_unit_metres(const char *u)
{
    static const struct { const char *n; double s; } tab[] = {
        {"m", 1}, {"cm", 1e-2}, {"mm", 1e-3}, {"um", 1e-6}, {"nm", 1e-9},
        {"in", 0.0254}, {"pt", 0.0254 / 72}, {"px", 0.0254 / 96},
    };
    for (size_t i = 0; i < sizeof tab / sizeof tab[0]; i++)
        if (strcmp(u, tab[i].n) == 0) return tab[i].s;
    return 0;
}

static int is_svg(const char *path)
{
    size_t n = strlen(path);
    if (n >= 4 && strcasecmp(path + n - 4, ".svg") == 0) return 1;
    if (n >= 5 && strcasecmp(path + n - 5, ".fold") == 0) return 0;
    FILE *f = fopen(path, "rb");
    if (!f) return 0;   /* the FOLD reader says it cannot read */
    int c;
    while ((c = fgetc(f)) != EOF && (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == 0xef || c == 0xbb || c == 0xbf))
        ;
    fclose(f);
    return c == '<';
}

static void bbox(const sf_cpattern *cp, double lo[2], double hi[2])
{
    lo[0] = lo[1] = INFINITY;
    hi[0] = hi[1] = -INFINITY;
    for (int i = 0; i < cp->nv; i++)
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], cp->v[i].x[k]);
            hi[k] = fmax(hi[k], cp->v[i].x[k]);
        }
}

int sf_import_read(const char *path, const sf_import_opts *o, sf_cpattern *cp,
                   sf_import_info *info, sf_error *err)
{
    sf_import_info dummy;
    if (!info) info = &dummy;
    memset(info, 0, sizeof *info);
    double unit_m = 0;
    int svg = is_svg(path);
    info->format = svg ? "SVG" : "FOLD";
    int rc = svg ? sf_svg_read(path, o, cp, &unit_m, info, err) : sf_fold_read(path, o, cp, &unit_m, info, err);
    if (rc) return rc;
    double lo[2], hi[2];
    bbox(cp, lo, hi);
    double span = cp->nv ? fmax(hi[0] - lo[0], hi[1] - lo[1]) : 0;
    if (!(span > 0) || !isfinite(span)) {
        int nv = cp->nv;
        sf_cp_free(cp);
        return nv ? sf_fail(err, SF_EINPUT, "%s: the pattern has no finite extent (%d vertices)", path, nv)
                  : sf_fail(err, SF_EINPUT, "%s: no lines", path);
    }
    if (!svg && o->planarize) {
        char w[1100];
        snprintf(w, sizeof w, "%s", path);
        int before = cp->ne;
        rc = sf_cp_planarize(cp, o->merge * span, w, err);
        if (rc) { sf_cp_free(cp); return rc; }
        sf_import_note(info, "--planarize: vertices within %g merged, crossings split: %d edges became %d",
                       o->merge * span, before, cp->ne);
    }
    {   /* several sheets in one file: the one asked for */
        char note[240];
        rc = sf_cp_pick_piece(cp, o->piece, path, note, sizeof note, err);
        if (rc) { sf_cp_free(cp); return rc; }
        if (note[0]) {
            sf_import_note(info, "%s", note);
            bbox(cp, lo, hi);
            span = fmax(hi[0] - lo[0], hi[1] - lo[1]);
        }
    }
    /* the size */
    double s;
    if (o->size > 0) {
        s = o->size / span;
        snprintf(info->scale, sizeof info->scale, "scaled to %g mm across (--size)", 1e3 * o->size);
    } else if (o->unit) {
        s = sf_unit_metres(o->unit);
        if (!(s > 0)) {
            sf_cp_free(cp);
            return sf_fail(err, SF_EINPUT, "--unit %s: unknown unit (m, cm, mm, um, nm, in, pt, px)", o->unit);
        }
        snprintf(info->scale, sizeof info->scale, "coordinates in %s (--unit)", o->unit);
    } else if (unit_m > 0) {
        s = unit_m;
        snprintf(info->scale, sizeof info->scale, "the file's unit");
    } else {
        s = SF_IMPORT_DEFAULT_SIZE / span;
        snprintf(info->scale, sizeof info->scale,
                 "no physical unit in the file: scaled to %g mm across; --size or --unit to change",
                 1e3 * SF_IMPORT_DEFAULT_SIZE);
    }
    cp->unit = s;
    info->width = s * (hi[0] - lo[0]);
    info->height = s * (hi[1] - lo[1]);
    rc = sf_cp_check(cp, path, err);
    if (rc && (strstr(err->msg, "crosses") || strstr(err->msg, "same point as") || strstr(err->msg, "zero length") ||
               strstr(err->msg, "lies inside the edge") || strstr(err->msg, "duplicate of"))) {
        size_t l = strlen(err->msg);
        if (svg || o->planarize)
            snprintf(err->msg + l, sizeof err->msg - l, "; --merge=%g merges ends farther apart", 2 * o->merge);
        else
            snprintf(err->msg + l, sizeof err->msg - l, "; --planarize merges close vertices and splits crossing edges");
    }
    if (rc) sf_cp_free(cp);
    return rc;
}
