/* svg_impl.h - private to the SVG reader (svg_read.c): the parsers of
 * SVG's small languages, written here because libxml2 parses the XML but
 * not attribute values (svg_path.c):
 *   path data (M L H V Z and their lower-case forms; curved commands are
 *   reported, not read), point lists (polyline, polygon), transform
 *   lists, numbers and lengths. */
#ifndef SF_SVG_IMPL_H
#define SF_SVG_IMPL_H

#include <stddef.h>

/* an affine map: x' = a x + c y + e, y' = b x + d y + f */
typedef struct svg_xf { double a, b, c, d, e, f; } svg_xf;

void svg_xf_identity(svg_xf *t);
/* t = t * s (s applied first) */
void svg_xf_mul(svg_xf *t, const svg_xf *s);
void svg_xf_apply(const svg_xf *t, double x, double y, double *ox, double *oy);

/* Parse a transform list and compose it onto *t.  Returns 0, or -1 with
 * a short reason in why. */
int svg_parse_transform(const char *s, svg_xf *t, char *why, size_t nwhy);

/* one straight segment (user coordinates, before the transform) */
typedef int (*svg_seg_fn)(void *ctx, double x0, double y0, double x1, double y1);

/* Path data: every straight segment to fn.  Returns 0; 1 with the command
 * letter in *curve for the first curved command (C S Q T A, either case);
 * -1 with a reason in why for bad syntax; fn's non-zero result stops it
 * and is returned as -2. */
int svg_parse_path(const char *d, svg_seg_fn fn, void *ctx, char *curve, char *why, size_t nwhy);

/* A point list "x1,y1 x2,y2 ...": the segments between consecutive points,
 * and back to the first when closed.  Returns 0, -1 (syntax, in why) or
 * -2 (fn stopped). */
int svg_parse_points(const char *s, int closed, svg_seg_fn fn, void *ctx, char *why, size_t nwhy);

/* One SVG number at *s (sign, digits, fraction, exponent; no inf, nan or
 * hex); advances *s.  Returns 0, or -1 when there is none. */
int svg_number(const char **s, double *x);

/* A length "12.5", "12.5px", "210mm": *x the number, *metres the size of
 * its unit in metres (0 for px, no unit, % and em: no physical size).
 * Returns 0, or -1. */
int svg_length(const char *s, double *x, double *metres);

#endif
