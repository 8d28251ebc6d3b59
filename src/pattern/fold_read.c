/* fold_read.c - the crease pattern of a FOLD file (foldread.h). */
#include "foldread.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct rd {
    const char *path;
    json_t *root;
    json_t *frame;     /* the frame read */
    int index;         /* its number */
    sf_error *err;
} rd;

#define BAD(...) (sf_fail(r->err, SF_EINPUT, __VA_ARGS__), r->err->code)

static json_t *frame_n(json_t *root, int k)
{
    if (k == 0) return root;
    json_t *ff = json_object_get(root, "file_frames");
    return json_is_array(ff) ? json_array_get(ff, (size_t)(k - 1)) : NULL;
}

static int nframes(json_t *root)
{
    json_t *ff = json_object_get(root, "file_frames");
    return 1 + (json_is_array(ff) ? (int)json_array_size(ff) : 0);
}

/* a key of the frame, or of its parents when it inherits */
static json_t *get(const rd *r, const char *key)
{
    json_t *f = r->frame;
    for (int depth = 0; f && depth < 64; depth++) {
        json_t *v = json_object_get(f, key);
        if (v) return v;
        if (!json_is_true(json_object_get(f, "frame_inherit"))) return NULL;
        json_t *par = json_object_get(f, "frame_parent");
        if (!json_is_integer(par)) return f == r->root ? NULL : r->root;
        f = frame_n(r->root, (int)json_integer_value(par));
    }
    return NULL;
}

static int has_class(json_t *f, const char *cls)
{
    json_t *c = json_object_get(f, "frame_classes");
    size_t i;
    json_t *v;
    json_array_foreach(c, i, v)
        if (json_is_string(v) && strcmp(json_string_value(v), cls) == 0) return 1;
    return 0;
}

static int pick_frame(rd *r, int want)
{
    int n = nframes(r->root);
    if (want >= 0) {
        if (want >= n)
            return BAD("%s: --frame %d: the file has %d frame%s (0 is the top level, file_frames[k] is frame k + 1)",
                       r->path, want, n, n == 1 ? "" : "s");
        r->index = want;
    } else {
        r->index = -1;
        for (int k = 0; k < n; k++)
            if (has_class(frame_n(r->root, k), "creasePattern")) { r->index = k; break; }
        if (r->index < 0 && has_class(r->root, "foldedForm"))
            return BAD("%s: frame_classes: no \"creasePattern\" frame, the top level is a \"foldedForm\" "
                       "(--frame N reads a frame as a crease pattern anyway)", r->path);
        if (r->index < 0) r->index = 0;
    }
    r->frame = frame_n(r->root, r->index);
    if (!json_is_object(r->frame))
        return BAD("%s: file_frames[%d]: not an object", r->path, r->index - 1);
    return SF_OK;
}

static const char *fld(const rd *r, char *buf, size_t n, const char *key)
{
    if (r->index == 0) snprintf(buf, n, "%s", key);
    else snprintf(buf, n, "file_frames[%d].%s", r->index - 1, key);
    return buf;
}

static int unit_scale(const char *u, double *s)
{
    static const struct { const char *n; double s; } tab[] = {
        {"m", 1}, {"cm", 1e-2}, {"mm", 1e-3}, {"um", 1e-6}, {"nm", 1e-9},
        {"in", 0.0254}, {"pt", 0.0254 / 72}, {"unit", 1},
    };
    for (size_t i = 0; i < sizeof tab / sizeof tab[0]; i++)
        if (strcmp(u, tab[i].n) == 0) { *s = tab[i].s; return 1; }
    return 0;
}

static int read_vertices(rd *r, sf_cpattern *cp)
{
    char f[128];
    json_t *vc = get(r, "vertices_coords");
    if (!vc) return BAD("%s: missing required field %s", r->path, fld(r, f, sizeof f, "vertices_coords"));
    if (!json_is_array(vc)) return BAD("%s: %s: expected an array of points", r->path, fld(r, f, sizeof f, "vertices_coords"));
    size_t i;
    json_t *p;
    json_array_foreach(vc, i, p) {
        size_t d = json_is_array(p) ? json_array_size(p) : 0;
        if (d != 2 && d != 3)
            return BAD("%s: %s[%zu]: expected [x, y] or [x, y, z]", r->path, fld(r, f, sizeof f, "vertices_coords"), i);
        double x[3] = {0, 0, 0};
        for (size_t k = 0; k < d; k++) {
            json_t *c = json_array_get(p, k);
            if (!json_is_number(c))
                return BAD("%s: %s[%zu][%zu]: not a number", r->path, fld(r, f, sizeof f, "vertices_coords"), i, k);
            x[k] = json_number_value(c);
            if (!isfinite(x[k]))
                return BAD("%s: %s[%zu][%zu]: not finite", r->path, fld(r, f, sizeof f, "vertices_coords"), i, k);
        }
        if (sf_cp_add_vertex(cp, x[0], x[1], NULL) < 0) return sf_fail(r->err, SF_ENOMEM, "out of memory");
        if (x[2] != 0)
            return BAD("%s: %s[%zu]: z = %g: a crease pattern lies flat (z = 0; this frame looks folded: "
                       "choose a creasePattern frame with --frame)", r->path,
                       fld(r, f, sizeof f, "vertices_coords"), i, x[2]);
    }
    json_t *nm = json_object_get(r->frame, "smoothfold:vertices_name");
    json_array_foreach(nm, i, p)
        if (i < (size_t)cp->nv && json_is_string(p))
            snprintf(cp->v[i].name, SF_NAME_MAX, "%s", json_string_value(p));
    return SF_OK;
}

static int read_edges(rd *r, sf_cpattern *cp)
{
    char f[128], g[128];
    json_t *ev = get(r, "edges_vertices");
    if (!ev) return BAD("%s: missing required field %s", r->path, fld(r, f, sizeof f, "edges_vertices"));
    if (!json_is_array(ev)) return BAD("%s: %s: expected an array of [v1, v2]", r->path, fld(r, f, sizeof f, "edges_vertices"));
    json_t *ea = get(r, "edges_assignment");
    if (!ea)
        return BAD("%s: missing field %s: needed for the outline (\"B\" edges) and the folds (\"M\", \"V\")",
                   r->path, fld(r, f, sizeof f, "edges_assignment"));
    if (!json_is_array(ea) || json_array_size(ea) != json_array_size(ev))
        return BAD("%s: %s: expected an array of %zu strings, one per edge", r->path,
                   fld(r, f, sizeof f, "edges_assignment"), json_array_size(ev));
    json_t *fa = get(r, "edges_foldAngle");
    if (fa && (!json_is_array(fa) || json_array_size(fa) != json_array_size(ev)))
        return BAD("%s: %s: expected an array of %zu numbers, one per edge", r->path,
                   fld(r, f, sizeof f, "edges_foldAngle"), json_array_size(ev));
    size_t i;
    json_t *e;
    json_array_foreach(ev, i, e) {
        json_t *a = json_array_get(e, 0), *b = json_array_get(e, 1);
        if (!json_is_array(e) || json_array_size(e) != 2 || !json_is_integer(a) || !json_is_integer(b))
            return BAD("%s: %s[%zu]: expected two vertex indices [v1, v2]", r->path, fld(r, f, sizeof f, "edges_vertices"), i);
        for (int k = 0; k < 2; k++) {
            json_int_t x = json_integer_value(k ? b : a);
            if (x < 0 || x >= cp->nv)
                return BAD("%s: %s[%zu]: vertex %lld does not exist (vertices_coords has %d)", r->path,
                           fld(r, f, sizeof f, "edges_vertices"), i, (long long)x, cp->nv);
        }
        json_t *s = json_array_get(ea, i);
        const char *as = json_is_string(s) ? json_string_value(s) : "";
        if (strcmp(as, "C") == 0 || strcmp(as, "J") == 0)
            return BAD("%s: %s[%zu]: \"%s\" (%s) is not supported: a smoothfold sheet is one piece, "
                       "without cuts or joins", r->path, fld(r, f, sizeof f, "edges_assignment"), i, as,
                       as[0] == 'C' ? "cut" : "join");
        if (strlen(as) != 1 || !strchr("BMVFU", as[0]))
            return BAD("%s: %s[%zu]: unknown assignment %s%s%s (FOLD: B, M, V, F, U)", r->path,
                       fld(r, f, sizeof f, "edges_assignment"), i, json_is_string(s) ? "\"" : "",
                       json_is_string(s) ? as : "(not a string)", json_is_string(s) ? "\"" : "");
        double ang = NAN;
        json_t *av = fa ? json_array_get(fa, i) : NULL;
        if (av && !json_is_null(av)) {
            if (!json_is_number(av) || !isfinite(json_number_value(av)))
                return BAD("%s: %s[%zu]: not a number", r->path, fld(r, f, sizeof f, "edges_foldAngle"), i);
            ang = json_number_value(av);
            if (fabs(ang) > 180)
                return BAD("%s: %s[%zu]: %g degrees: beyond [-180, 180]", r->path, fld(r, f, sizeof f, "edges_foldAngle"), i, ang);
            if ((as[0] == 'M' && ang > 0) || (as[0] == 'V' && ang < 0))
                return BAD("%s: %s[%zu]: %g degrees on a %s edge (%s[%zu] = \"%c\"): FOLD's angles are "
                           "valley positive, mountain negative", r->path, fld(r, f, sizeof f, "edges_foldAngle"),
                           i, ang, as[0] == 'M' ? "mountain" : "valley", fld(r, g, sizeof g, "edges_assignment"),
                           i, as[0]);
        }
        if (sf_cp_add_edge(cp, (int)json_integer_value(a), (int)json_integer_value(b), as[0], ang) < 0)
            return sf_fail(r->err, SF_ENOMEM, "out of memory");
    }
    json_t *nm = json_object_get(r->frame, "smoothfold:edges_name");
    json_array_foreach(nm, i, e)
        if (i < (size_t)cp->ne && json_is_string(e))
            snprintf(cp->e[i].name, SF_NAME_MAX, "%s", json_string_value(e));
    return SF_OK;
}

static int read_faces(rd *r, sf_cpattern *cp)
{
    char f[128];
    json_t *fv = get(r, "faces_vertices");
    if (!fv) return SF_OK;
    if (!json_is_array(fv)) return BAD("%s: %s: expected an array of vertex lists", r->path, fld(r, f, sizeof f, "faces_vertices"));
    size_t nf = json_array_size(fv), total = 0, i;
    json_t *face;
    json_array_foreach(fv, i, face) {
        if (!json_is_array(face))
            return BAD("%s: %s[%zu]: expected a list of vertex indices", r->path, fld(r, f, sizeof f, "faces_vertices"), i);
        total += json_array_size(face);
    }
    cp->face_start = malloc((nf + 1) * sizeof *cp->face_start);
    cp->face_verts = malloc((total + 1) * sizeof *cp->face_verts);
    if (!cp->face_start || !cp->face_verts) return sf_fail(r->err, SF_ENOMEM, "out of memory");
    int k = 0;
    json_array_foreach(fv, i, face) {
        cp->face_start[i] = k;
        size_t j;
        json_t *v;
        json_array_foreach(face, j, v) {
            if (!json_is_integer(v) || json_integer_value(v) < 0 || json_integer_value(v) >= cp->nv)
                return BAD("%s: %s[%zu][%zu]: not the index of a vertex (vertices_coords has %d)", r->path,
                           fld(r, f, sizeof f, "faces_vertices"), i, j, cp->nv);
            cp->face_verts[k++] = (int)json_integer_value(v);
        }
    }
    cp->face_start[nf] = k;
    cp->nf = (int)nf;
    return SF_OK;
}

int sf_fold_read(const char *path, int frame, const char *unit,
                 sf_cpattern *cp, char *unit_note, size_t nnote, sf_error *err)
{
    sf_cp_init(cp);
    json_error_t je;
    json_t *root = json_load_file(path, JSON_REJECT_DUPLICATES, &je);
    if (!root) {
        if (je.line < 0 || strstr(je.text, "unable to open"))
            return sf_fail(err, SF_EIO, "%s: cannot read: %s", path, je.text);
        return sf_fail(err, SF_EINPUT, "%s:%d:%d: malformed JSON: %s", path, je.line, je.column, je.text);
    }
    rd r = {path, root, NULL, 0, err};
    int rc = SF_OK;
    if (!json_is_object(root)) rc = sf_fail(err, SF_EINPUT, "%s: the top level is not a JSON object", path);
    if (!rc) rc = pick_frame(&r, frame);
    if (!rc) rc = read_vertices(&r, cp);
    if (!rc) rc = read_edges(&r, cp);
    if (!rc) rc = read_faces(&r, cp);
    if (!rc) {
        json_t *fu = get(&r, "frame_unit");
        const char *u = unit ? unit : json_is_string(fu) ? json_string_value(fu) : "unit";
        if (!unit_scale(u, &cp->unit))
            rc = unit ? sf_fail(err, SF_EINPUT, "--unit %s: unknown unit (m, cm, mm, um, nm, in, pt, unit)", u)
                      : sf_fail(err, SF_EINPUT, "%s: frame_unit \"%s\": unknown unit (m, cm, mm, um, nm, in, pt, "
                                "unit; or give --unit)", path, u);
        else if (unit_note)
            snprintf(unit_note, nnote, "%s%s", u,
                     strcmp(u, "unit") == 0 ? " (no physical unit in the file: read as metres; --unit to change)"
                     : unit ? " (--unit)" : " (frame_unit)");
        json_t *t = get(&r, "frame_title");
        if (!json_is_string(t)) t = json_object_get(root, "file_title");
        if (json_is_string(t)) snprintf(cp->title, sizeof cp->title, "%s", json_string_value(t));
        json_t *d = get(&r, "frame_description");
        if (!json_is_string(d)) d = json_object_get(root, "file_description");
        if (json_is_string(d)) {
            const char *s = json_string_value(d);
            size_t k = 0;
            for (; s[k] && k + 1 < sizeof cp->description; k++)
                cp->description[k] = (s[k] == '"' || s[k] == '\\' || s[k] == '\n') ? ' ' : s[k];
            cp->description[k] = '\0';
        }
    }
    if (!rc) rc = sf_cp_check(cp, path, err);
    json_decref(root);
    if (rc) sf_cp_free(cp);
    return rc;
}
