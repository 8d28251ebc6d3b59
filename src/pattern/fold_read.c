/* fold_read.c - the crease pattern of a FOLD file (foldread.h): the frame
 * chosen, its vertices laid into the x-y plane (fold_plane.c), its edges
 * with their assignments and angles in the sign convention asked for.
 * Coordinates stay in the file's units; import.c scales them. */
#include "foldread.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fold_plane.h"

typedef struct rd {
    const char *path;
    const sf_import_opts *o;
    json_t *root;
    json_t *frame;     /* the frame read */
    int index;         /* its number */
    sf_import_info *info;
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

/* a key of frame f, or of its parents when it inherits */
static json_t *get_in(json_t *root, json_t *f, const char *key)
{
    for (int depth = 0; f && depth < 64; depth++) {
        json_t *v = json_object_get(f, key);
        if (v) return v;
        if (!json_is_true(json_object_get(f, "frame_inherit"))) return NULL;
        json_t *par = json_object_get(f, "frame_parent");
        if (!json_is_integer(par)) return f == root ? NULL : root;
        f = frame_n(root, (int)json_integer_value(par));
    }
    return NULL;
}

static json_t *get(const rd *r, const char *key) { return get_in(r->root, r->frame, key); }

static int has_class(json_t *f, const char *cls)
{
    json_t *c = json_object_get(f, "frame_classes");
    size_t i;
    json_t *v;
    json_array_foreach(c, i, v)
        if (json_is_string(v) && strcmp(json_string_value(v), cls) == 0) return 1;
    return 0;
}

static const char *frame_name(int k, char *buf, size_t n)
{
    if (k == 0) snprintf(buf, n, "the top level (frame 0)");
    else snprintf(buf, n, "file_frames[%d] (frame %d)", k - 1, k);
    return buf;
}

/* the points of frame k, or NULL when they are not an array of numbers */
static int frame_points(json_t *root, int k, double (**x)[3], int *n)
{
    *x = NULL;
    *n = 0;
    json_t *f = frame_n(root, k);
    json_t *vc = json_is_object(f) ? get_in(root, f, "vertices_coords") : NULL;
    if (!json_is_array(vc)) return -1;
    size_t m = json_array_size(vc), i;
    double (*p)[3] = malloc((m + 1) * sizeof *p);
    if (!p) return -1;
    json_t *pt;
    json_array_foreach(vc, i, pt) {
        size_t d = json_is_array(pt) ? json_array_size(pt) : 0;
        if (d != 2 && d != 3) { free(p); return -1; }
        p[i][2] = 0;
        for (size_t c = 0; c < d; c++) {
            json_t *v = json_array_get(pt, c);
            if (!json_is_number(v) || !isfinite(json_number_value(v))) { free(p); return -1; }
            p[i][c] = json_number_value(v);
        }
    }
    *x = p;
    *n = (int)m;
    return 0;
}

static int frame_is_flat(json_t *root, int k)
{
    double (*x)[3];
    int n;
    if (frame_points(root, k, &x, &n)) return 0;
    sf_plane pl;
    int flat = n > 0 && sf_plane_fit(n, (const double (*)[3])x, NULL, NULL, 0, &pl) == 0 && pl.flat;
    free(x);
    return flat;
}

static int pick_frame(rd *r)
{
    int n = nframes(r->root), want = r->o->frame;
    char fn[64];
    if (want >= 0) {
        if (want >= n)
            return BAD("%s: --frame %d: the file has %d frame%s (0 is the top level, file_frames[k] is frame k + 1)",
                       r->path, want, n, n == 1 ? "" : "s");
        r->index = want;
    } else {
        r->index = -1;
        for (int k = 0; k < n && r->index < 0; k++)
            if (has_class(frame_n(r->root, k), "creasePattern")) r->index = k;
        for (int k = 0; k < n && r->index < 0; k++)   /* Origami Simulator: a flat "foldedForm" */
            if (frame_is_flat(r->root, k)) {
                r->index = k;
                sf_import_note(r->info, "no \"creasePattern\" frame: %s, a flat %s, read as the crease pattern",
                               frame_name(k, fn, sizeof fn),
                               has_class(frame_n(r->root, k), "foldedForm") ? "\"foldedForm\"" : "frame");
            }
        if (r->index < 0) r->index = 0;   /* its vertices say what is wrong */
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

/* the first flat frame other than k, as "--frame N reads ...", or "" */
static const char *flat_hint(const rd *r, char *buf, size_t n)
{
    buf[0] = '\0';
    int nf = nframes(r->root);
    for (int k = 0; k < nf; k++)
        if (k != r->index && frame_is_flat(r->root, k)) {
            char fn[64];
            snprintf(buf, n, "; %s lies flat: --frame %d reads it", frame_name(k, fn, sizeof fn), k);
            break;
        }
    if (!buf[0]) snprintf(buf, n, "; no frame of the file lies flat: unfold it in the design tool "
                          "(Origami Simulator: fold percent 0) and save it again");
    return buf;
}

static int read_vertices(rd *r, sf_cpattern *cp)
{
    char f[128], h[160];
    json_t *vc = get(r, "vertices_coords");
    if (!vc) return BAD("%s: missing required field %s", r->path, fld(r, f, sizeof f, "vertices_coords"));
    if (!json_is_array(vc)) return BAD("%s: %s: expected an array of points", r->path, fld(r, f, sizeof f, "vertices_coords"));
    size_t i, m = json_array_size(vc);
    double (*x)[3] = malloc((m + 1) * sizeof *x);
    if (!x) return sf_fail(r->err, SF_ENOMEM, "out of memory");
    json_t *p;
    int rc = SF_OK, three = 0;
    json_array_foreach(vc, i, p) {
        size_t d = json_is_array(p) ? json_array_size(p) : 0;
        if (d != 2 && d != 3) { rc = BAD("%s: %s[%zu]: expected [x, y] or [x, y, z]", r->path, fld(r, f, sizeof f, "vertices_coords"), i); break; }
        x[i][2] = 0;
        three |= d == 3;
        for (size_t k = 0; k < d && !rc; k++) {
            json_t *c = json_array_get(p, k);
            if (!json_is_number(c))
                rc = BAD("%s: %s[%zu][%zu]: not a number", r->path, fld(r, f, sizeof f, "vertices_coords"), i, k);
            else if (!isfinite(x[i][k] = json_number_value(c)))
                rc = BAD("%s: %s[%zu][%zu]: not finite", r->path, fld(r, f, sizeof f, "vertices_coords"), i, k);
        }
        if (rc) break;
    }
    if (!rc && three) {
        /* the faces' winding tells which side is up (FOLD: counter-clockwise) */
        json_t *fv = get(r, "faces_vertices");
        int nf = 0, *fs = NULL, *fvv = NULL;
        if (json_is_array(fv)) {
            size_t tot = 0, j;
            json_t *fc;
            json_array_foreach(fv, j, fc) tot += json_is_array(fc) ? json_array_size(fc) : 0;
            fs = malloc((json_array_size(fv) + 1) * sizeof *fs);
            fvv = malloc((tot + 1) * sizeof *fvv);
            if (fs && fvv) {
                int k = 0;
                json_array_foreach(fv, j, fc) {
                    fs[nf++] = k;
                    size_t q;
                    json_t *vi;
                    json_array_foreach(fc, q, vi)
                        if (json_is_integer(vi) && json_integer_value(vi) >= 0 && json_integer_value(vi) < (json_int_t)m)
                            fvv[k++] = (int)json_integer_value(vi);
                }
                fs[nf] = k;
            } else nf = 0;
        }
        sf_plane pl;
        if (sf_plane_fit((int)m, (const double (*)[3])x, fs, fvv, nf, &pl)) rc = sf_fail(r->err, SF_ENOMEM, "out of memory");
        free(fs);
        free(fvv);
        if (!rc && !pl.flat)
            rc = BAD("%s: %s[%d]: %.3g off the plane that fits the vertices best: this frame is folded, "
                     "smoothfold imports the flat crease pattern%s", r->path, fld(r, f, sizeof f, "vertices_coords"),
                     pl.worst, pl.dev, flat_hint(r, h, sizeof h));
        if (!rc) {
            for (size_t k = 0; k < m; k++) sf_plane_map(&pl, x[k], x[k]);
            if (!pl.is_xy) {
                static const char *const axis[3] = {"y-z", "x-z", "x-y"};
                int k = fabs(pl.n[0]) == 1 ? 0 : fabs(pl.n[1]) == 1 ? 1 : fabs(pl.n[2]) == 1 ? 2 : -1;
                char plane[96];
                if (k >= 0) snprintf(plane, sizeof plane, "the %s plane", axis[k]);
                else snprintf(plane, sizeof plane, "the plane with normal (%.4g, %.4g, %.4g)", pl.n[0], pl.n[1], pl.n[2]);
                sf_import_note(r->info, "the vertices lie in %s: turned into the x-y plane, seen from the side from "
                               "which %s", plane, pl.how);
            }
        }
    }
    for (size_t k = 0; !rc && k < m; k++)
        if (sf_cp_add_vertex(cp, x[k][0], x[k][1], NULL) < 0) rc = sf_fail(r->err, SF_ENOMEM, "out of memory");
    free(x);
    if (rc) return rc;
    json_t *nm = json_object_get(r->frame, "smoothfold:vertices_name");
    json_array_foreach(nm, i, p)
        if (i < (size_t)cp->nv && json_is_string(p))
            snprintf(cp->v[i].name, SF_NAME_MAX, "%s", json_string_value(p));
    return SF_OK;
}

/* the angles against the assignments: which --angle-sign reads them */
static const char *sign_hint(json_t *ea, json_t *fa)
{
    int fold_ok = 1, opp_ok = 1;
    size_t i;
    json_t *s;
    json_array_foreach(ea, i, s) {
        json_t *av = json_array_get(fa, i);
        if (!json_is_string(s) || !json_is_number(av)) continue;
        double a = json_number_value(av);
        char c = json_string_value(s)[0];
        if ((c == 'M' && a > 0) || (c == 'V' && a < 0)) fold_ok = 0;
        if ((c == 'M' && a < 0) || (c == 'V' && a > 0)) opp_ok = 0;
    }
    if (!fold_ok && opp_ok) return "this file's angles are mountain positive: --angle-sign=opposite reads it";
    return "this file's angles do not follow one sign convention (older Rabbit Ear files give magnitudes): "
           "--angle-sign=magnitude reads them with the assignment's sign";
}

/* one angle in FOLD 1.1's convention, or an error */
static int take_angle(rd *r, json_t *ea, json_t *fa, size_t i, char as, double *out)
{
    char f[128], g[128];
    json_t *av = fa ? json_array_get(fa, i) : NULL;
    *out = NAN;
    if (!av || json_is_null(av)) return SF_OK;
    if (!json_is_number(av) || !isfinite(json_number_value(av)))
        return BAD("%s: %s[%zu]: not a number", r->path, fld(r, f, sizeof f, "edges_foldAngle"), i);
    double ang = json_number_value(av);
    if (fabs(ang) > 180)
        return BAD("%s: %s[%zu]: %g degrees: beyond [-180, 180]", r->path, fld(r, f, sizeof f, "edges_foldAngle"), i, ang);
    if (r->o->angle_sign == SF_SIGN_OPPOSITE) ang = -ang;
    else if (r->o->angle_sign == SF_SIGN_MAGNITUDE && (as == 'M' || as == 'V'))
        ang = as == 'M' ? -fabs(ang) : fabs(ang);
    if ((as == 'M' && ang > 0) || (as == 'V' && ang < 0)) {
        if (r->o->angle_sign != SF_SIGN_FOLD)
            return BAD("%s: %s[%zu]: %g degrees on a %s edge (%s[%zu] = \"%c\") with --angle-sign=opposite: "
                       "--angle-sign=magnitude takes the assignment's sign", r->path,
                       fld(r, f, sizeof f, "edges_foldAngle"), i, -ang, as == 'M' ? "mountain" : "valley",
                       fld(r, g, sizeof g, "edges_assignment"), i, as);
        return BAD("%s: %s[%zu]: %g degrees on a %s edge (%s[%zu] = \"%c\"): FOLD 1.1's angles are "
                   "valley positive, mountain negative; %s", r->path, fld(r, f, sizeof f, "edges_foldAngle"),
                   i, ang, as == 'M' ? "mountain" : "valley", fld(r, g, sizeof g, "edges_assignment"), i, as,
                   sign_hint(ea, fa));
    }
    *out = ang;
    return SF_OK;
}

/* edges_assignment absent: B on the outer face, else the sign of the angle
 * (FOLD: valley positive), F at 0, U without one */
static int derive_assignments(rd *r, sf_cpattern *cp)
{
    char *outer = malloc((size_t)cp->ne + 1);
    if (!outer) return sf_fail(r->err, SF_ENOMEM, "out of memory");
    int rc = sf_cp_outer_edges(cp, outer, r->err), nb = 0, nmv = 0, nf = 0, nu = 0;
    for (int e = 0; !rc && e < cp->ne; e++) {
        sf_cp_edge *ed = &cp->e[e];
        if (outer[e]) { ed->assign = 'B'; ed->angle = NAN; nb++; }
        else if (isnan(ed->angle)) { ed->assign = 'U'; nu++; }
        else if (ed->angle == 0) { ed->assign = 'F'; nf++; }
        else { ed->assign = ed->angle > 0 ? 'V' : 'M'; nmv++; }
    }
    free(outer);
    if (!rc)
        sf_import_note(r->info, "no edges_assignment: derived, %d boundary (the outer face), %d mountain or valley "
                       "(the sign of edges_foldAngle), %d flat (angle 0), %d unassigned (no angle)", nb, nmv, nf, nu);
    return rc;
}

static int read_edges(rd *r, sf_cpattern *cp)
{
    char f[128];
    json_t *ev = get(r, "edges_vertices");
    if (!ev) return BAD("%s: missing required field %s", r->path, fld(r, f, sizeof f, "edges_vertices"));
    if (!json_is_array(ev)) return BAD("%s: %s: expected an array of [v1, v2]", r->path, fld(r, f, sizeof f, "edges_vertices"));
    json_t *ea = get(r, "edges_assignment"), *fa = get(r, "edges_foldAngle");
    if (ea && (!json_is_array(ea) || json_array_size(ea) != json_array_size(ev)))
        return BAD("%s: %s: expected an array of %zu strings, one per edge", r->path,
                   fld(r, f, sizeof f, "edges_assignment"), json_array_size(ev));
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
        char as = 'U';
        if (ea) {
            json_t *s = json_array_get(ea, i);
            const char *t = json_is_string(s) ? json_string_value(s) : "";
            if (strcmp(t, "C") == 0 || strcmp(t, "J") == 0)
                return BAD("%s: %s[%zu]: \"%s\" (%s) is not supported: a smoothfold sheet is one piece, "
                           "without cuts or joins", r->path, fld(r, f, sizeof f, "edges_assignment"), i, t,
                           t[0] == 'C' ? "cut" : "join");
            if (strlen(t) != 1 || !strchr("BMVFUbmvfu", t[0]))
                return BAD("%s: %s[%zu]: unknown assignment %s%s%s (FOLD: B, M, V, F, U)", r->path,
                           fld(r, f, sizeof f, "edges_assignment"), i, json_is_string(s) ? "\"" : "",
                           json_is_string(s) ? t : "(not a string)", json_is_string(s) ? "\"" : "");
            as = (char)(t[0] & ~32);   /* FOLD allows lower case */
        }
        double ang;
        int rc = take_angle(r, ea, fa, i, ea ? as : 'U', &ang);
        if (rc) return rc;
        if (sf_cp_add_edge(cp, (int)json_integer_value(a), (int)json_integer_value(b), as, ang) < 0)
            return sf_fail(r->err, SF_ENOMEM, "out of memory");
    }
    if (!ea) {
        int rc = derive_assignments(r, cp);
        if (rc) return rc;
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

static void read_texts(rd *r, sf_cpattern *cp)
{
    json_t *t = get(r, "frame_title");
    if (!json_is_string(t)) t = json_object_get(r->root, "file_title");
    if (json_is_string(t)) snprintf(cp->title, sizeof cp->title, "%s", json_string_value(t));
    json_t *d = get(r, "frame_description");
    if (!json_is_string(d)) d = json_object_get(r->root, "file_description");
    if (json_is_string(d)) {
        const char *s = json_string_value(d);
        size_t k = 0;
        for (; s[k] && k + 1 < sizeof cp->description; k++)
            cp->description[k] = (s[k] == '"' || s[k] == '\\' || s[k] == '\n') ? ' ' : s[k];
        cp->description[k] = '\0';
    }
}

int sf_fold_read(const char *path, const sf_import_opts *o, sf_cpattern *cp,
                 double *unit_m, sf_import_info *info, sf_error *err)
{
    sf_cp_init(cp);
    *unit_m = 0;
    json_error_t je;
    json_t *root = json_load_file(path, JSON_REJECT_DUPLICATES, &je);
    if (!root) {
        if (je.line < 0 || strstr(je.text, "unable to open"))
            return sf_fail(err, SF_EIO, "%s: cannot read: %s", path, je.text);
        return sf_fail(err, SF_EINPUT, "%s:%d:%d: malformed JSON: %s", path, je.line, je.column, je.text);
    }
    rd r = {path, o, root, NULL, 0, info, err};
    int rc = SF_OK;
    if (!json_is_object(root)) rc = sf_fail(err, SF_EINPUT, "%s: the top level is not a JSON object", path);
    if (!rc) rc = pick_frame(&r);
    if (!rc) rc = read_vertices(&r, cp);
    if (!rc) rc = read_edges(&r, cp);
    if (!rc && !o->planarize) rc = read_faces(&r, cp);
    if (!rc) {
        json_t *fu = get(&r, "frame_unit");
        const char *u = json_is_string(fu) ? json_string_value(fu) : "unit";
        if (strcmp(u, "unit") != 0 && !(*unit_m = sf_unit_metres(u)) && !o->unit && !(o->size > 0))
            rc = sf_fail(err, SF_EINPUT, "%s: frame_unit \"%s\": unknown unit (m, cm, mm, um, nm, in, pt; "
                         "--unit U or --size L reads the file)", path, u);
        read_texts(&r, cp);
    }
    json_decref(root);
    if (rc) sf_cp_free(cp);
    return rc;
}
