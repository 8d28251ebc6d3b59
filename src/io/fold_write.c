/* fold_write.c - FOLD files of crease patterns and folded forms (fold.h).
 * Values are built and serialised by jansson; the top-level keys are laid
 * out one per line for readable diffs. */
#include "fold.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "outbuf.h"
#include "vtk.h"

static const char *assign_str(char a)
{
    switch (a) {
    case 'B': return "B";
    case 'M': return "M";
    case 'V': return "V";
    case 'F': return "F";
    default: return "U";
    }
}

/* a real number as jansson writes it, with the fewest digits that read
 * back to the same double (0.4, not 0.40000000000000002) */
static void num(sf_outbuf *b, double x)
{
    json_t *v = json_real(x);
    char *s = NULL;
    for (int p = 1; v && p <= 17; p++) {
        free(s);
        s = json_dumps(v, JSON_ENCODE_ANY | JSON_REAL_PRECISION(p));
        if (!s || strtod(s, NULL) == x) break;
    }
    json_decref(v);
    if (!s) { b->oom = 1; return; }
    sf_outbuf_printf(b, "%s", s);
    free(s);
}

static void key(sf_outbuf *b, int *first, const char *indent, const char *k)
{
    sf_outbuf_printf(b, "%s%s\"%s\": ", *first ? "" : ",\n", indent, k);
    *first = 0;
}

/* one "key": value line, the value compact */
static void put(sf_outbuf *b, int *first, const char *indent, const char *k, json_t *val)
{
    if (!val) { b->oom = 1; return; }
    char *s = json_dumps(val, JSON_COMPACT | JSON_REAL_PRECISION(17) | JSON_ENCODE_ANY);
    json_decref(val);
    if (!s) { b->oom = 1; return; }
    key(b, first, indent, k);
    sf_outbuf_printf(b, "%s", s);
    free(s);
}

static void points(sf_outbuf *b, int *first, const char *indent, const char *k, int n,
                   const double *x, int dim)
{
    key(b, first, indent, k);
    sf_outbuf_printf(b, "[");
    for (int i = 0; i < n; i++) {
        sf_outbuf_printf(b, "%s[", i ? "," : "");
        for (int d = 0; d < dim; d++) {
            if (d) sf_outbuf_printf(b, ",");
            num(b, x[dim * i + d]);
        }
        sf_outbuf_printf(b, "]");
    }
    sf_outbuf_printf(b, "]");
}

static void reals(sf_outbuf *b, int *first, const char *indent, const char *k, int n,
                  const double *x)
{
    key(b, first, indent, k);
    sf_outbuf_printf(b, "[");
    for (int i = 0; i < n; i++) {
        if (i) sf_outbuf_printf(b, ",");
        num(b, x[i]);
    }
    sf_outbuf_printf(b, "]");
}

static void pattern_keys(sf_outbuf *b, int *first, const sf_cpattern *cp)
{
    double *xy = malloc((size_t)(cp->nv ? cp->nv : 1) * 2 * sizeof *xy);
    if (!xy) { b->oom = 1; return; }
    for (int i = 0; i < cp->nv; i++) {
        xy[2 * i] = cp->unit * cp->v[i].x[0];
        xy[2 * i + 1] = cp->unit * cp->v[i].x[1];
    }
    points(b, first, "  ", "vertices_coords", cp->nv, xy, 2);
    free(xy);
    json_t *ev = json_array(), *ea = json_array();
    int anyangle = 0, allangle = 1, anyname = 0;
    for (int i = 0; ev && ea && i < cp->ne; i++) {
        json_array_append_new(ev, json_pack("[ii]", cp->e[i].a, cp->e[i].b));
        json_array_append_new(ea, json_string(assign_str(cp->e[i].assign)));
        char a = cp->e[i].assign;
        if (a == 'M' || a == 'V') {
            if (isfinite(cp->e[i].angle)) anyangle = 1; else allangle = 0;
        }
        if (cp->e[i].name[0]) anyname = 1;
    }
    put(b, first, "  ", "edges_vertices", ev);
    put(b, first, "  ", "edges_assignment", ea);
    if (anyangle && allangle) {
        double *fa = malloc((size_t)(cp->ne + 1) * sizeof *fa);
        if (!fa) { b->oom = 1; return; }
        for (int i = 0; i < cp->ne; i++) fa[i] = isfinite(cp->e[i].angle) ? cp->e[i].angle : 0.0;
        reals(b, first, "  ", "edges_foldAngle", cp->ne, fa);
        free(fa);
    }
    if (cp->nf > 0) {
        json_t *fv = json_array();
        for (int f = 0; fv && f < cp->nf; f++) {
            json_t *p = json_array();
            for (int k = cp->face_start[f]; p && k < cp->face_start[f + 1]; k++)
                json_array_append_new(p, json_integer(cp->face_verts[k]));
            json_array_append_new(fv, p);
        }
        put(b, first, "  ", "faces_vertices", fv);
    }
    int anyv = 0;
    for (int i = 0; i < cp->nv; i++) if (cp->v[i].name[0]) anyv = 1;
    if (anyv) {
        json_t *vn = json_array();
        for (int i = 0; vn && i < cp->nv; i++) json_array_append_new(vn, json_string(cp->v[i].name));
        put(b, first, "  ", "smoothfold:vertices_name", vn);
    }
    if (anyname) {
        json_t *en = json_array();
        for (int i = 0; en && i < cp->ne; i++) json_array_append_new(en, json_string(cp->e[i].name));
        put(b, first, "  ", "smoothfold:edges_name", en);
    }
}

static void frame(sf_outbuf *b, const sf_cpattern *cp, const sf_fold_frame *fr)
{
    int first = 1;
    const char *in = "      ";
    sf_outbuf_printf(b, "    {\n");
    put(b, &first, in, "frame_classes", json_pack("[s]", "foldedForm"));
    put(b, &first, in, "frame_attributes", json_pack("[s]", "3D"));
    put(b, &first, in, "frame_parent", json_integer(0));
    put(b, &first, in, "frame_inherit", json_true());
    points(b, &first, in, "vertices_coords", cp->nv, &fr->x[0][0], 3);
    reals(b, &first, in, "edges_foldAngle", cp->ne, fr->angle);
    key(b, &first, in, "smoothfold:p");
    num(b, fr->p);
    key(b, &first, in, "smoothfold:load");
    num(b, fr->load);
    put(b, &first, in, "smoothfold:stable",
        fr->stable < 0 ? json_null() : json_boolean(fr->stable));
    put(b, &first, in, "smoothfold:branch", json_integer(fr->branch));
    sf_outbuf_printf(b, "\n    }");
}

int sf_fold_write(const sf_cpattern *cp, const char *creator, int nframes,
                  const sf_fold_frame *frames, const char *path, sf_error *err)
{
    for (int k = 0; k < nframes; k++) {
        for (int i = 0; i < cp->nv; i++)
            for (int d = 0; d < 3; d++)
                if (!isfinite(frames[k].x[i][d]))
                    return sf_fail(err, SF_ENUMERIC, "%s: frame %d: vertex %d is not finite", path, k + 1, i);
        for (int e = 0; e < cp->ne; e++)
            if (!isfinite(frames[k].angle[e]))
                return sf_fail(err, SF_ENUMERIC, "%s: frame %d: fold angle of edge %d is not finite", path, k + 1, e);
    }
    sf_outbuf b = {0};
    int first = 1;
    sf_outbuf_printf(&b, "{\n");
    key(&b, &first, "  ", "file_spec");
    num(&b, 1.1);
    put(&b, &first, "  ", "file_creator", json_string(creator ? creator : "smoothfold"));
    put(&b, &first, "  ", "file_classes", json_pack("[s]", "singleModel"));
    if (cp->title[0]) put(&b, &first, "  ", "frame_title", json_string(cp->title));
    if (cp->description[0]) put(&b, &first, "  ", "frame_description", json_string(cp->description));
    put(&b, &first, "  ", "frame_classes", json_pack("[s]", "creasePattern"));
    put(&b, &first, "  ", "frame_attributes", json_pack("[s]", "2D"));
    put(&b, &first, "  ", "frame_unit", json_string("m"));
    pattern_keys(&b, &first, cp);
    if (nframes > 0) {
        sf_outbuf_printf(&b, ",\n  \"file_frames\": [\n");
        for (int k = 0; k < nframes; k++) {
            frame(&b, cp, &frames[k]);
            sf_outbuf_printf(&b, "%s\n", k + 1 < nframes ? "," : "");
        }
        sf_outbuf_printf(&b, "  ]");
    }
    sf_outbuf_printf(&b, "\n}\n");
    int rc;
    if (b.oom) rc = sf_fail(err, SF_ENOMEM, "%s: out of memory", path);
    else rc = sf_write_atomic(path, sf_outbuf_fill, &b, err);
    sf_outbuf_free(&b);
    return rc;
}

int sf_fold_write_pattern(const sf_cpattern *cp, const char *path, sf_error *err)
{
    return sf_fold_write(cp, "smoothfold", 0, NULL, path, err);
}
