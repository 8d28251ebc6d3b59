/* svg_read.c - the crease pattern of an SVG drawing in Origami Simulator's
 * convention (foldread.h, docs/reference/svg-format.md).
 *
 * libxml2 parses the XML (no network, no entity substitution, no DTD
 * loading); this file walks the element tree: the straight segments of
 * line, polyline, polygon, rect and path elements (svg_path.c), each
 * mapped through its transforms, classed by its stroke colour
 *   black boundary (B), red mountain (M), blue valley (V), yellow facet
 *   (F), magenta unassigned (U), green cut (refused), and grey flat (F, as
 *   Rabbit Ear and flat-folder draw flat creases),
 * with fold angle +-180 degrees x opacity x stroke-opacity for M and V;
 * Rabbit Ear's data-assignment and data-foldAngle attributes, where an
 * element or its group has them, take the colour's place.
 * Colours (names, #rgb, #rrggbb, rgb(), rgba(), hsl(), hsla(); the alpha
 * counts as opacity) come from the style attribute, the presentation attribute or a
 * <style> sheet's rules (selectors tag, .class, #id, tag.class, *),
 * inherited from the ancestors.  The segments are then made planar
 * (sf_cp_planarize) with the merge tolerance. */
#include "foldread.h"

#include <libxml/parser.h>
#include <libxml/tree.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "svg_impl.h"

typedef struct css_rule {
    int kind;            /* 0 '*', 1 tag, 2 class, 3 id, 4 tag.class */
    char name[64], cls[64];
    char *decls;         /* "prop: value; ..." */
    int order;
} css_rule;

typedef struct sv {
    const char *path;
    const sf_import_opts *o;
    sf_cpattern *cp;
    sf_import_info *info;
    sf_error *err;
    css_rule *rules;
    int nrules;
    int nseg[6];          /* per kind: B M V F U C */
    int unknown;          /* elements with a stroke outside the convention */
    char colours[200];    /* the first few of those */
    int hidden;
    /* the element being read */
    svg_xf xf;
    char assign;
    double angle;
} sv;

#define BADS(...) (sf_fail(r->err, SF_EINPUT, __VA_ARGS__), r->err->code)

static const char *attr(xmlNode *n, const char *name)
{
    for (xmlAttr *a = n->properties; a; a = a->next)
        if (strcmp((const char *)a->name, name) == 0 && a->children && a->children->content)
            return (const char *)a->children->content;
    return NULL;
}

static const char *tag(xmlNode *n) { return (const char *)n->name; }

/* an element of SVG (or of no namespace), not of an editor's own */
static int is_svg_el(xmlNode *n)
{
    return n->type == XML_ELEMENT_NODE &&
           (!n->ns || !n->ns->href || strcmp((const char *)n->ns->href, "http://www.w3.org/2000/svg") == 0);
}

/* ---- style ----------------------------------------------------------------- */

/* the value of prop in a declaration list "a: b; c: d", into out */
static int decl_value(const char *decls, const char *prop, char *out, size_t n)
{
    size_t pl = strlen(prop);
    const char *s = decls;
    int found = 0;
    while (s && *s) {
        while (*s == ' ' || *s == '\t' || *s == '\n' || *s == '\r' || *s == ';') s++;
        const char *colon = strchr(s, ':'), *semi = strchr(s, ';');
        if (!colon || (semi && semi < colon)) { s = semi; continue; }
        const char *ke = colon;
        while (ke > s && (ke[-1] == ' ' || ke[-1] == '\t')) ke--;
        if ((size_t)(ke - s) == pl && strncasecmp(s, prop, pl) == 0) {
            const char *v = colon + 1, *ve = semi ? semi : v + strlen(v);
            while (v < ve && (*v == ' ' || *v == '\t' || *v == '\n')) v++;
            while (ve > v && (ve[-1] == ' ' || ve[-1] == '\t' || ve[-1] == '\n' || ve[-1] == '\r')) ve--;
            size_t l = (size_t)(ve - v);
            if (l >= n) l = n - 1;
            memcpy(out, v, l);
            out[l] = '\0';
            const char *imp = strstr(out, "!important");
            if (imp) {
                char *e = out + (imp - out);
                while (e > out && e[-1] == ' ') e--;
                *e = '\0';
            }
            found = 1;   /* the last declaration wins */
        }
        s = semi;
    }
    return found;
}

static int has_class(xmlNode *n, const char *cls)
{
    const char *c = attr(n, "class");
    size_t l = strlen(cls);
    while (c && *c) {
        while (*c == ' ' || *c == '\t') c++;
        const char *e = c;
        while (*e && *e != ' ' && *e != '\t') e++;
        if ((size_t)(e - c) == l && strncmp(c, cls, l) == 0) return 1;
        c = e;
    }
    return 0;
}

static int rule_matches(const css_rule *ru, xmlNode *n)
{
    const char *id;
    switch (ru->kind) {
    case 0: return 1;
    case 1: return strcmp(ru->name, tag(n)) == 0;
    case 2: return has_class(n, ru->name);
    case 3: id = attr(n, "id"); return id && strcmp(id, ru->name) == 0;
    default: return strcmp(ru->name, tag(n)) == 0 && has_class(n, ru->cls);
    }
}

static int specificity(int kind) { return kind == 3 ? 100 : kind == 4 ? 11 : kind == 2 ? 10 : kind == 1 ? 1 : 0; }

/* prop set on node n itself by CSS: its style attribute, then the
 * style-sheet rule of highest specificity (the last of equals) */
static int css_value(const sv *r, xmlNode *n, const char *prop, char *out, size_t len)
{
    const char *st = attr(n, "style");
    if (st && decl_value(st, prop, out, len)) return 1;
    int best = -1, bo = -1;
    for (int i = 0; i < r->nrules; i++) {
        const css_rule *ru = &r->rules[i];
        char tmp[512];
        if (!rule_matches(ru, n) || !decl_value(ru->decls, prop, tmp, sizeof tmp)) continue;
        int sp = specificity(ru->kind);
        if (sp > best || (sp == best && ru->order > bo)) {
            best = sp;
            bo = ru->order;
            snprintf(out, len, "%s", tmp);
        }
    }
    return best >= 0;
}

/* prop set on node n itself: CSS, then the presentation attribute */
static int own_value(const sv *r, xmlNode *n, const char *prop, char *out, size_t len)
{
    if (css_value(r, n, prop, out, len)) return 1;
    const char *a = attr(n, prop);
    if (a) {
        while (*a == ' ') a++;
        snprintf(out, len, "%s", a);
        return 1;
    }
    return 0;
}

/* an inherited property: the nearest ancestor that sets it ("inherit" goes on) */
static int inherited(const sv *r, xmlNode *n, const char *prop, char *out, size_t len)
{
    for (; n && n->type == XML_ELEMENT_NODE; n = n->parent)
        if (own_value(r, n, prop, out, len) && strcmp(out, "inherit") != 0) return 1;
    return 0;
}

static double number_or(const char *s, double dflt)
{
    double x;
    const char *p = s;
    while (*p == ' ') p++;
    if (svg_number(&p, &x)) return dflt;
    if (*p == '%') x /= 100;
    return x;
}

static int hex(char c) { return c >= '0' && c <= '9' ? c - '0' : (c | 32) >= 'a' && (c | 32) <= 'f' ? (c | 32) - 'a' + 10 : -1; }

/* the convention's class of a colour: 'B','M','V','F','U','C', 0 for none,
 * '?' for another colour */
/* hue (degrees), saturation and lightness (0..1) to 0..255 */
static void hsl_rgb(double h, double sat, double l, int rgb[3])
{
    double c = (1 - fabs(2 * l - 1)) * sat, hp = fmod(fmod(h, 360) + 360, 360) / 60;
    double x = c * (1 - fabs(fmod(hp, 2) - 1)), m = l - c / 2, r = 0, g = 0, b = 0;
    if (hp < 1) { r = c; g = x; } else if (hp < 2) { r = x; g = c; } else if (hp < 3) { g = c; b = x; }
    else if (hp < 4) { g = x; b = c; } else if (hp < 5) { r = x; b = c; } else { r = c; b = x; }
    rgb[0] = (int)lround(255 * (r + m));
    rgb[1] = (int)lround(255 * (g + m));
    rgb[2] = (int)lround(255 * (b + m));
}

static char colour_class(const char *c, double *alpha)
{
    *alpha = 1;
    char s[64];
    size_t k = 0;
    for (; *c && k + 1 < sizeof s; c++)
        if (*c != ' ' && *c != '\t') s[k++] = (char)(*c | ((*c >= 'A' && *c <= 'Z') ? 32 : 0));
    s[k] = '\0';
    if (!s[0] || strcmp(s, "none") == 0 || strcmp(s, "transparent") == 0) return 0;
    static const struct { const char *n; char c; } names[] = {
        {"black", 'B'}, {"red", 'M'}, {"blue", 'V'}, {"yellow", 'F'}, {"magenta", 'U'}, {"fuchsia", 'U'},
        {"green", 'C'}, {"lime", 'C'},
        /* Rabbit Ear's and flat-folder's flat creases: greys */
        {"gray", 'F'}, {"grey", 'F'}, {"lightgray", 'F'}, {"lightgrey", 'F'}, {"darkgray", 'F'},
        {"darkgrey", 'F'}, {"dimgray", 'F'}, {"dimgrey", 'F'}, {"silver", 'F'}, {"gainsboro", 'F'},
    };
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strcmp(s, names[i].n) == 0) return names[i].c;
    int rgb[3] = {-1, -1, -1};
    if (s[0] == '#' && (k == 4 || k == 7)) {
        for (int i = 0; i < 3; i++) {
            int h1 = k == 4 ? hex(s[1 + i]) : hex(s[1 + 2 * i]), h2 = k == 4 ? h1 : hex(s[2 + 2 * i]);
            if (h1 < 0 || h2 < 0) return '?';
            rgb[i] = 16 * h1 + h2;
        }
    } else if (strncmp(s, "rgb(", 4) == 0 || strncmp(s, "rgba(", 5) == 0 ||
               strncmp(s, "hsl(", 4) == 0 || strncmp(s, "hsla(", 5) == 0) {
        int hsl = s[0] == 'h', a = s[3] == 'a';
        const char *p = s + (a ? 5 : 4);
        double v[4] = {0, 0, 0, 1};
        for (int i = 0; i < 3 + a; i++) {
            if (svg_number(&p, &v[i])) return '?';
            if (*p == '%') { v[i] = i == 3 ? v[i] / 100 : hsl ? v[i] / 100 : v[i] * 2.55; p++; }
            if (*p == ',') p++;
        }
        if (*p != ')') return '?';
        if (hsl) hsl_rgb(v[0], v[1], v[2], rgb);
        else for (int i = 0; i < 3; i++) rgb[i] = (int)lround(v[i]);
        *alpha = fmin(1, fmax(0, v[3]));
    } else return '?';
    static const struct { int r, g, b; char c; } cols[] = {
        {0, 0, 0, 'B'}, {255, 0, 0, 'M'}, {0, 0, 255, 'V'}, {255, 255, 0, 'F'}, {255, 0, 255, 'U'}, {0, 255, 0, 'C'},
    };
    for (size_t i = 0; i < sizeof cols / sizeof cols[0]; i++)
        if (rgb[0] == cols[i].r && rgb[1] == cols[i].g && rgb[2] == cols[i].b) return cols[i].c;
    if (rgb[0] == rgb[1] && rgb[1] == rgb[2] && rgb[0] > 0 && rgb[0] < 255) return 'F';   /* a grey */
    return '?';
}

/* ---- style sheets ---------------------------------------------------------- */

static void free_rules(sv *r)
{
    for (int i = 0; i < r->nrules; i++) free(r->rules[i].decls);
    free(r->rules);
}

static int add_rule(sv *r, const char *sel, size_t sl, const char *decl, size_t dl)
{
    while (sl && (*sel == ' ' || *sel == '\n' || *sel == '\t' || *sel == '\r')) { sel++; sl--; }
    while (sl && (sel[sl - 1] == ' ' || sel[sl - 1] == '\n' || sel[sl - 1] == '\t' || sel[sl - 1] == '\r')) sl--;
    if (!sl || sl >= 64) return SF_OK;
    for (size_t i = 0; i < sl; i++)   /* compound selectors are not read */
        if (strchr(" >+~:[", sel[i])) return SF_OK;
    css_rule ru;
    memset(&ru, 0, sizeof ru);
    const char *dot = memchr(sel, '.', sl);
    if (sl == 1 && sel[0] == '*') ru.kind = 0;
    else if (sel[0] == '#') { ru.kind = 3; memcpy(ru.name, sel + 1, sl - 1); }
    else if (sel[0] == '.') { ru.kind = 2; memcpy(ru.name, sel + 1, sl - 1); }
    else if (dot) { ru.kind = 4; memcpy(ru.name, sel, (size_t)(dot - sel)); memcpy(ru.cls, dot + 1, sl - (size_t)(dot - sel) - 1); }
    else { ru.kind = 1; memcpy(ru.name, sel, sl); }
    ru.decls = malloc(dl + 1);
    css_rule *nr = realloc(r->rules, (size_t)(r->nrules + 1) * sizeof *nr);
    if (!ru.decls || !nr) { free(ru.decls); if (nr) r->rules = nr; return SF_ENOMEM; }
    r->rules = nr;
    memcpy(ru.decls, decl, dl);
    ru.decls[dl] = '\0';
    ru.order = r->nrules;
    r->rules[r->nrules++] = ru;
    return SF_OK;
}

/* the rules of one <style> text: "sel, sel { decls } ..." (comments and
 * at-rules skipped) */
static int read_sheet(sv *r, const char *t)
{
    while (t && *t) {
        if (t[0] == '/' && t[1] == '*') { const char *e = strstr(t + 2, "*/"); t = e ? e + 2 : NULL; continue; }
        if (*t == '@') { const char *e = strpbrk(t, ";{"); if (e && *e == '{') e = strchr(e, '}'); t = e ? e + 1 : NULL; continue; }
        const char *ob = strchr(t, '{');
        if (!ob) break;
        const char *cb = strchr(ob, '}');
        if (!cb) break;
        const char *s = t;
        while (s < ob) {
            const char *comma = memchr(s, ',', (size_t)(ob - s));
            const char *se = comma ? comma : ob;
            if (add_rule(r, s, (size_t)(se - s), ob + 1, (size_t)(cb - ob - 1))) return SF_ENOMEM;
            s = se + 1;
        }
        t = cb + 1;
    }
    return SF_OK;
}

static int collect_sheets(sv *r, xmlNode *n)
{
    for (; n; n = n->next) {
        if (n->type != XML_ELEMENT_NODE) continue;
        if (is_svg_el(n) && strcmp(tag(n), "style") == 0) {
            xmlChar *t = xmlNodeGetContent(n);
            int rc = t ? read_sheet(r, (const char *)t) : SF_OK;
            xmlFree(t);
            if (rc) return rc;
        } else if (collect_sheets(r, n->children)) return SF_ENOMEM;
    }
    return SF_OK;
}

/* ---- segments --------------------------------------------------------------- */

static int add_seg(void *ctx, double x0, double y0, double x1, double y1)
{
    sv *r = ctx;
    double p[2], q[2];
    svg_xf_apply(&r->xf, x0, y0, &p[0], &p[1]);
    svg_xf_apply(&r->xf, x1, y1, &q[0], &q[1]);
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(q[0]) || !isfinite(q[1])) return 1;
    int a = sf_cp_add_vertex(r->cp, p[0], p[1], NULL), b = sf_cp_add_vertex(r->cp, q[0], q[1], NULL);
    if (a < 0 || b < 0 || sf_cp_add_edge(r->cp, a, b, r->assign, r->angle) < 0) return 2;
    r->nseg[strchr("BMVFUC", r->assign) - "BMVFUC"]++;
    return 0;
}

static const char *el_name(xmlNode *n, char *buf, size_t len)
{
    const char *id = attr(n, "id");
    if (id) snprintf(buf, len, "<%s id=\"%.40s\">", tag(n), id);
    else snprintf(buf, len, "<%s>", tag(n));
    return buf;
}

static double attr_num(sv *r, xmlNode *n, const char *name, int *bad)
{
    const char *a = attr(n, name);
    if (!a) return 0;
    double x, m;
    if (svg_length(a, &x, &m)) { *bad = 1; return 0; }
    (void)r;
    return x;
}

/* the segments of one shape element; 0, or an error */
static int read_shape(sv *r, xmlNode *n, const char *t)
{
    char why[160] = "", nm[80], curve = 0;
    int rc = 0, bad = 0;
    long line = (long)xmlGetLineNo(n);
    if (strcmp(t, "line") == 0) {
        double v[4] = {attr_num(r, n, "x1", &bad), attr_num(r, n, "y1", &bad), attr_num(r, n, "x2", &bad),
                       attr_num(r, n, "y2", &bad)};
        if (bad) snprintf(why, sizeof why, "x1, y1, x2, y2: not numbers");
        else rc = add_seg(r, v[0], v[1], v[2], v[3]) ? -2 : 0;
        if (bad) rc = -1;
    } else if (strcmp(t, "rect") == 0) {
        double x = attr_num(r, n, "x", &bad), y = attr_num(r, n, "y", &bad);
        double w = attr_num(r, n, "width", &bad), h = attr_num(r, n, "height", &bad);
        double rx = attr_num(r, n, "rx", &bad), ry = attr_num(r, n, "ry", &bad);
        if (bad || !(w > 0) || !(h > 0)) { rc = -1; snprintf(why, sizeof why, "x, y, width, height: not numbers, or not positive"); }
        else if (rx > 0 || ry > 0) { rc = 1; curve = 'r'; }
        else if (add_seg(r, x, y, x + w, y) || add_seg(r, x + w, y, x + w, y + h) ||
                 add_seg(r, x + w, y + h, x, y + h) || add_seg(r, x, y + h, x, y)) rc = -2;
    } else if (strcmp(t, "polyline") == 0 || strcmp(t, "polygon") == 0) {
        const char *p = attr(n, "points");
        rc = p ? svg_parse_points(p, t[4] == 'g', add_seg, r, why, sizeof why) : 0;
    } else if (strcmp(t, "path") == 0) {
        const char *d = attr(n, "d");
        rc = d ? svg_parse_path(d, add_seg, r, &curve, why, sizeof why) : 0;
    } else {   /* circle, ellipse */
        rc = 1;
        curve = 'o';
    }
    if (rc == 1)
        return BADS("%s:%ld: %s: %s: smoothfold reads straight segments only (line, polyline, polygon, "
                    "rect, path with M, L, H, V, Z); replace the curve by straight segments", r->path, line,
                    el_name(n, nm, sizeof nm),
                    curve == 'o' ? "a curved shape" : curve == 'r' ? "rounded corners (rx, ry)" :
                    (snprintf(why, sizeof why, "curved segment '%c'", curve), why));
    if (rc == -1) return BADS("%s:%ld: %s: %s", r->path, line, el_name(n, nm, sizeof nm), why);
    if (rc == -2) return sf_fail(r->err, SF_ENOMEM, "out of memory (or a non-finite point) in %s", el_name(n, nm, sizeof nm));
    return SF_OK;
}

static int skipped_container(const char *t)
{
    static const char *const skip[] = {"defs", "symbol", "clipPath", "mask", "pattern", "marker", "metadata",
                                       "title", "desc", "style", "script", "text", "foreignObject", "linearGradient",
                                       "radialGradient", "filter"};
    for (size_t i = 0; i < sizeof skip / sizeof skip[0]; i++)
        if (strcmp(t, skip[i]) == 0) return 1;
    return 0;
}

static int walk(sv *r, xmlNode *n, const svg_xf *parent, double opacity)
{
    for (; n; n = n->next) {
        if (!is_svg_el(n)) continue;
        const char *t = tag(n);
        if (skipped_container(t)) continue;
        char v[128], nm[80];
        if (own_value(r, n, "display", v, sizeof v) && strcmp(v, "none") == 0) { r->hidden++; continue; }
        svg_xf xf = *parent;
        /* a CSS transform property overrides the attribute (CSS angles
         * and lengths carry units: deg, rad, turn, px) */
        char css_tr[512], why[160];
        const char *tr = css_value(r, n, "transform", css_tr, sizeof css_tr) ? css_tr : attr(n, "transform");
        if (tr && strcmp(tr, "none") == 0) tr = NULL;
        if (tr && svg_parse_transform(tr, &xf, why, sizeof why))
            return BADS("%s:%ld: %s: transform: %s", r->path, (long)xmlGetLineNo(n), el_name(n, nm, sizeof nm), why);
        double op = opacity * (own_value(r, n, "opacity", v, sizeof v) ? number_or(v, 1) : 1);
        int shape = !strcmp(t, "line") || !strcmp(t, "rect") || !strcmp(t, "polyline") || !strcmp(t, "polygon") ||
                    !strcmp(t, "path") || !strcmp(t, "circle") || !strcmp(t, "ellipse");
        if (shape) {
            double alpha = 1, dangle = NAN;
            char c = 0;
            /* Rabbit Ear's attributes, where given, say it outright */
            const char *da = NULL, *dfa = NULL;
            for (xmlNode *u = n; u && u->type == XML_ELEMENT_NODE && !da; u = u->parent) da = attr(u, "data-assignment");
            for (xmlNode *u = n; u && u->type == XML_ELEMENT_NODE && !dfa; u = u->parent) dfa = attr(u, "data-foldAngle");
            if (da) {
                char a = (char)(da[0] & ~32);
                if (a == 'J')
                    return BADS("%s:%ld: %s: data-assignment \"%s\" (join): a smoothfold sheet is one piece, without joins",
                                r->path, (long)xmlGetLineNo(n), el_name(n, nm, sizeof nm), da);
                if (!strchr("BMVFUC", a) || !a || da[1])
                    return BADS("%s:%ld: %s: data-assignment \"%s\": unknown (FOLD's B, M, V, F, U, C, J)",
                                r->path, (long)xmlGetLineNo(n), el_name(n, nm, sizeof nm), da);
                c = a;
                if (dfa) dangle = number_or(dfa, NAN);
            } else if (inherited(r, n, "stroke", v, sizeof v)) c = colour_class(v, &alpha);
            if (c && inherited(r, n, "visibility", v, sizeof v) && strcmp(v, "visible") != 0) { r->hidden++; c = 0; }
            if (c == '?') {
                inherited(r, n, "stroke", v, sizeof v);
                if (r->unknown++ < 6 && strlen(r->colours) + strlen(v) + 3 < sizeof r->colours && !strstr(r->colours, v))
                    snprintf(r->colours + strlen(r->colours), sizeof r->colours - strlen(r->colours), "%s%s",
                             r->colours[0] ? ", " : "", v);
                continue;
            }
            if (!c) continue;
            if (c == 'C')
                return BADS("%s:%ld: %s: a cut (a green line, or data-assignment C): a smoothfold sheet is one piece, without cuts",
                            r->path, (long)xmlGetLineNo(n), el_name(n, nm, sizeof nm));
            double so = inherited(r, n, "stroke-opacity", v, sizeof v) ? number_or(v, 1) : 1;
            double frac = fmin(1, fmax(0, op * so * alpha));
            r->xf = xf;
            r->assign = c;
            r->angle = c == 'M' ? -180 * frac : c == 'V' ? 180 * frac : c == 'F' ? 0 : NAN;
            if (da) {   /* data-foldAngle in FOLD's degrees, sign from the assignment */
                r->angle = c == 'F' ? 0 : (c == 'M' || c == 'V') && isfinite(dangle) ? (c == 'M' ? -1 : 1) * fabs(dangle) : NAN;
                if (r->angle == 0 && c != 'F') r->angle = NAN;
            }
            int rc = read_shape(r, n, t);
            if (rc) return rc;
            continue;
        }
        if (n->children) {
            int rc = walk(r, n->children, &xf, op);
            if (rc) return rc;
        }
    }
    return SF_OK;
}

/* metres per user unit from the root's width and viewBox; 0 without a
 * physical unit */
static double user_unit(xmlNode *root)
{
    const char *w = attr(root, "width"), *vb = attr(root, "viewBox");
    double x, m;
    if (!w || svg_length(w, &x, &m) || !(m > 0) || !(x > 0)) return 0;
    if (!vb) return 0.0254 / 96;   /* a physical width without a viewBox: user units are px */
    double v[4];
    const char *p = vb;
    for (int i = 0; i < 4; i++) {
        while (*p == ' ' || *p == ',' || *p == '\t' || *p == '\n') p++;
        if (svg_number(&p, &v[i])) return 0;
    }
    return v[2] > 0 ? x * m / v[2] : 0;
}

int sf_svg_read(const char *path, const sf_import_opts *o, sf_cpattern *cp,
                double *unit_m, sf_import_info *info, sf_error *err)
{
    sf_cp_init(cp);
    *unit_m = 0;
    xmlParserCtxtPtr ctx = xmlNewParserCtxt();
    if (!ctx) return sf_fail(err, SF_ENOMEM, "out of memory");
    xmlDocPtr doc = xmlCtxtReadFile(ctx, path, NULL, XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
    if (!doc) {
        xmlErrorPtr e = xmlCtxtGetLastError(ctx);
        int rc;
        if (e && e->domain == XML_FROM_IO)
            rc = sf_fail(err, SF_EIO, "%s: cannot read: %s", path, e->message ? e->message : "I/O error");
        else if (e && e->message) {
            char m[400];
            snprintf(m, sizeof m, "%s", e->message);
            size_t l = strlen(m);
            while (l && (m[l - 1] == '\n' || m[l - 1] == ' ')) m[--l] = '\0';
            rc = sf_fail(err, SF_EINPUT, "%s:%d: malformed XML: %s", path, e->line, m);
        } else rc = sf_fail(err, SF_EINPUT, "%s: not an XML file", path);
        xmlFreeParserCtxt(ctx);
        return rc;
    }
    xmlNode *root = xmlDocGetRootElement(doc);
    sv r;
    memset(&r, 0, sizeof r);
    r.path = path; r.o = o; r.cp = cp; r.info = info; r.err = err;
    int rc = SF_OK;
    if (!root || strcmp(tag(root), "svg") != 0)
        rc = sf_fail(err, SF_EINPUT, "%s: the root element is <%s>, not <svg>", path, root ? tag(root) : "none");
    if (!rc && collect_sheets(&r, root)) rc = sf_fail(err, SF_ENOMEM, "out of memory");
    if (!rc) {
        svg_xf id;
        svg_xf_identity(&id);
        rc = walk(&r, root, &id, 1.0);
    }
    if (!rc) {
        *unit_m = user_unit(root);
        const char *title = NULL;
        for (xmlNode *c = root->children; c && !title; c = c->next)
            if (is_svg_el(c) && strcmp(tag(c), "title") == 0 && c->children && c->children->content)
                title = (const char *)c->children->content;
        if (title) snprintf(cp->title, sizeof cp->title, "%s", title);
    }
    free_rules(&r);
    xmlFreeDoc(doc);
    xmlFreeParserCtxt(ctx);
    if (!rc && r.nseg[0] == 0)
        rc = sf_fail(err, SF_EINPUT, "%s: no black (boundary) line: Origami Simulator's convention draws the "
                     "outline black, mountains red, valleys blue, facets yellow%s%s%s", path,
                     r.unknown ? " (found strokes: " : "", r.colours, r.unknown ? ")" : "");
    if (!rc && r.unknown)
        sf_import_note(info, "%d element%s with other stroke colours (%s) ignored: the convention's are black, red, "
                       "blue, yellow, magenta, green", r.unknown, r.unknown == 1 ? "" : "s", r.colours);
    if (!rc && r.hidden) sf_import_note(info, "%d hidden element%s ignored", r.hidden, r.hidden == 1 ? "" : "s");
    if (!rc) {
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int i = 0; i < cp->nv; i++)
            for (int k = 0; k < 2; k++) { lo[k] = fmin(lo[k], cp->v[i].x[k]); hi[k] = fmax(hi[k], cp->v[i].x[k]); }
        double span = fmax(hi[0] - lo[0], hi[1] - lo[1]);
        int segs = cp->ne;
        rc = sf_cp_planarize(cp, o->merge * span, path, err);
        if (!rc)
            sf_import_note(info, "%d segments (%d boundary, %d mountain, %d valley, %d facet, %d unassigned): "
                           "ends within %.3g merged, crossings split: %d edges, %d vertices",
                           segs, r.nseg[0], r.nseg[1], r.nseg[2], r.nseg[3], r.nseg[4], o->merge * span,
                           cp->ne, cp->nv);
    }
    if (rc) sf_cp_free(cp);
    return rc;
}
