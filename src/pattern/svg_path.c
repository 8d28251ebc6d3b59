/* svg_path.c - SVG path data, point lists, transform lists, numbers and
 * lengths (svg_impl.h), after the grammar of SVG 1.1, chapters 7 and 8. */
#include "svg_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int is_ws(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f'; }
static int is_digit(char c) { return c >= '0' && c <= '9'; }

static void skip_ws(const char **s) { while (is_ws(**s)) (*s)++; }

/* white space and at most one comma */
static void skip_sep(const char **s)
{
    skip_ws(s);
    if (**s == ',') { (*s)++; skip_ws(s); }
}

int svg_number(const char **s, double *x)
{
    const char *p = *s, *q = p;
    if (*q == '+' || *q == '-') q++;
    int digits = 0;
    while (is_digit(*q)) { q++; digits++; }
    if (*q == '.') {
        q++;
        while (is_digit(*q)) { q++; digits++; }
    }
    if (!digits) return -1;
    if (*q == 'e' || *q == 'E') {   /* an exponent only when digits follow */
        const char *r = q + 1;
        if (*r == '+' || *r == '-') r++;
        if (is_digit(*r)) {
            while (is_digit(*r)) r++;
            q = r;
        }
    }
    char buf[64];
    size_t n = (size_t)(q - p);
    if (n >= sizeof buf) return -1;
    memcpy(buf, p, n);
    buf[n] = '\0';
    *x = strtod(buf, NULL);
    if (!isfinite(*x)) return -1;
    *s = q;
    return 0;
}

int svg_length(const char *s, double *x, double *metres)
{
    skip_ws(&s);
    if (svg_number(&s, x)) return -1;
    static const struct { const char *u; double m; } tab[] = {
        {"mm", 1e-3}, {"cm", 1e-2}, {"in", 0.0254}, {"pt", 0.0254 / 72}, {"pc", 0.0254 / 6},
        {"px", 0}, {"%", 0}, {"em", 0}, {"ex", 0}, {"", 0},
    };
    const char *u = s;
    while (*u && !is_ws(*u)) u++;
    size_t n = (size_t)(u - s);
    for (size_t i = 0; i < sizeof tab / sizeof tab[0]; i++)
        if (strlen(tab[i].u) == n && strncmp(s, tab[i].u, n) == 0) {
            *metres = tab[i].m;
            skip_ws(&u);
            return *u ? -1 : 0;
        }
    return -1;
}

/* ---- transforms ---------------------------------------------------------- */

void svg_xf_identity(svg_xf *t) { *t = (svg_xf){1, 0, 0, 1, 0, 0}; }

void svg_xf_mul(svg_xf *t, const svg_xf *s)
{
    svg_xf r = {
        t->a * s->a + t->c * s->b, t->b * s->a + t->d * s->b,
        t->a * s->c + t->c * s->d, t->b * s->c + t->d * s->d,
        t->a * s->e + t->c * s->f + t->e, t->b * s->e + t->d * s->f + t->f,
    };
    *t = r;
}

void svg_xf_apply(const svg_xf *t, double x, double y, double *ox, double *oy)
{
    *ox = t->a * x + t->c * y + t->e;
    *oy = t->b * x + t->d * y + t->f;
}

int svg_parse_transform(const char *s, svg_xf *t, char *why, size_t nwhy)
{
    static const struct { const char *name; int min, max; } fns[] = {
        {"matrix", 6, 6}, {"translate", 1, 2}, {"scale", 1, 2},
        {"rotate", 1, 3}, {"skewX", 1, 1}, {"skewY", 1, 1},
    };
    for (;;) {
        skip_ws(&s);
        while (*s == ',') { s++; skip_ws(&s); }
        if (!*s) return 0;
        int k = -1;
        size_t len = 0;
        for (size_t i = 0; i < sizeof fns / sizeof fns[0]; i++) {
            size_t l = strlen(fns[i].name);
            if (strncmp(s, fns[i].name, l) == 0) { k = (int)i; len = l; break; }
        }
        if (k < 0) { snprintf(why, nwhy, "unknown transform at '%.20s'", s); return -1; }
        s += len;
        skip_ws(&s);
        if (*s != '(') { snprintf(why, nwhy, "'(' expected after %s", fns[k].name); return -1; }
        s++;
        double v[6];
        int n = 0;
        skip_ws(&s);
        while (*s != ')') {
            if (n == 6 || svg_number(&s, &v[n])) {
                snprintf(why, nwhy, "%s: bad argument list", fns[k].name);
                return -1;
            }
            /* CSS writes units: angles in deg (the attribute's), rad or
             * turn, lengths in px (user units) */
            int angle = k >= 3 && !(k == 3 && n > 0);
            if (angle && strncmp(s, "deg", 3) == 0) s += 3;
            else if (angle && strncmp(s, "rad", 3) == 0) { s += 3; v[n] *= 180 / M_PI; }
            else if (angle && strncmp(s, "turn", 4) == 0) { s += 4; v[n] *= 360; }
            else if (!angle && k != 0 && k != 2 && strncmp(s, "px", 2) == 0) s += 2;
            else if (((*s | 32) >= 'a' && (*s | 32) <= 'z') || *s == '%') {
                snprintf(why, nwhy, "%s: unit '%.6s' not read (deg, rad, turn, px)", fns[k].name, s);
                return -1;
            }
            n++;
            skip_sep(&s);
        }
        s++;
        if (n < fns[k].min || n > fns[k].max || (k == 3 && n == 2)) {
            snprintf(why, nwhy, "%s: %d arguments", fns[k].name, n);
            return -1;
        }
        svg_xf m;
        svg_xf_identity(&m);
        double r;
        switch (k) {
        case 0: m = (svg_xf){v[0], v[1], v[2], v[3], v[4], v[5]}; break;
        case 1: m.e = v[0]; m.f = n > 1 ? v[1] : 0; break;
        case 2: m.a = v[0]; m.d = n > 1 ? v[1] : v[0]; break;
        case 3:
            r = v[0] * M_PI / 180;
            if (n == 3) {   /* about (cx, cy): translate, rotate, translate back */
                svg_xf tr = {1, 0, 0, 1, v[1], v[2]};
                svg_xf_mul(t, &tr);
            }
            m = (svg_xf){cos(r), sin(r), -sin(r), cos(r), 0, 0};
            if (n == 3) {
                svg_xf_mul(t, &m);
                m = (svg_xf){1, 0, 0, 1, -v[1], -v[2]};
            }
            break;
        case 4: m.c = tan(v[0] * M_PI / 180); break;
        case 5: m.b = tan(v[0] * M_PI / 180); break;
        }
        svg_xf_mul(t, &m);
    }
}

/* ---- path data ----------------------------------------------------------- */

static int coords(const char **s, int n, double *v)
{
    for (int i = 0; i < n; i++) {
        if (i) skip_sep(s);
        if (svg_number(s, &v[i])) return -1;
    }
    return 0;
}

int svg_parse_path(const char *d, svg_seg_fn fn, void *ctx, char *curve, char *why, size_t nwhy)
{
    const char *s = d;
    double cx = 0, cy = 0, sx = 0, sy = 0;   /* current point, subpath start */
    char cmd = 0;
    int have = 0;
    skip_ws(&s);
    while (*s) {
        char c = *s;
        if (strchr("MmLlHhVvZz", c)) { cmd = c; s++; skip_ws(&s); }
        else if (strchr("CcSsQqTtAa", c)) { *curve = c; return 1; }
        else if (!cmd || cmd == 'Z' || cmd == 'z' || !(c == '-' || c == '+' || c == '.' || is_digit(c))) {
            snprintf(why, nwhy, "path data: unexpected '%c' at offset %d", c, (int)(s - d));
            return -1;
        }
        if (cmd == 'Z' || cmd == 'z') {
            if (have && (cx != sx || cy != sy) && fn(ctx, cx, cy, sx, sy)) return -2;
            cx = sx; cy = sy;
            skip_sep(&s);
            continue;
        }
        if (!have && cmd != 'M' && cmd != 'm') {
            snprintf(why, nwhy, "path data: must start with a moveto (M or m)");
            return -1;
        }
        double v[2];
        int n = (cmd == 'H' || cmd == 'h' || cmd == 'V' || cmd == 'v') ? 1 : 2;
        if (coords(&s, n, v)) {
            snprintf(why, nwhy, "path data: '%c' needs %d number%s at offset %d", cmd, n, n > 1 ? "s" : "", (int)(s - d));
            return -1;
        }
        double nx = cx, ny = cy;
        switch (cmd) {
        case 'M': case 'L': nx = v[0]; ny = v[1]; break;
        case 'm': case 'l': nx = (have ? cx : 0) + v[0]; ny = (have ? cy : 0) + v[1]; break;
        case 'H': nx = v[0]; break;
        case 'h': nx = cx + v[0]; break;
        case 'V': ny = v[0]; break;
        case 'v': ny = cy + v[0]; break;
        }
        if (cmd == 'M' || cmd == 'm') {
            sx = nx; sy = ny;
            cmd = cmd == 'M' ? 'L' : 'l';   /* further pairs are lineto */
        } else if (fn(ctx, cx, cy, nx, ny)) return -2;
        cx = nx; cy = ny;
        have = 1;
        skip_sep(&s);
    }
    return 0;
}

int svg_parse_points(const char *s, int closed, svg_seg_fn fn, void *ctx, char *why, size_t nwhy)
{
    double x0 = 0, y0 = 0, px = 0, py = 0;
    int n = 0;
    skip_ws(&s);
    while (*s) {
        double v[2];
        if (coords(&s, 2, v)) { snprintf(why, nwhy, "points: a coordinate pair expected at '%.20s'", s); return -1; }
        if (n == 0) { x0 = v[0]; y0 = v[1]; }
        else if (fn(ctx, px, py, v[0], v[1])) return -2;
        px = v[0]; py = v[1];
        n++;
        skip_sep(&s);
    }
    if (closed && n > 2 && fn(ctx, px, py, x0, y0)) return -2;
    return 0;
}
