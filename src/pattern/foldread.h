/* foldread.h - crease patterns from the files the design tools write:
 * FOLD 1.x (JSON, read with jansson; fold_read.c, fold_plane.c) and SVG in
 * Origami Simulator's colour convention (XML, read with libxml2;
 * svg_read.c, svg_path.c), into an sf_cpattern (cpattern.h) scaled to
 * metres (import.c).  docs/guides/importing-patterns.md, docs/reference/svg-format.md.
 *
 * FOLD: vertices_coords (2-D, or 3-D lying in any plane: rotated into
 * x-y), edges_vertices, edges_assignment (B, M, V, F, U; C and J refused;
 * when absent: derived, B on the outer face, M/V/F from the angle signs),
 * edges_foldAngle (degrees; the sign convention of opts.angle_sign),
 * faces_vertices, frame_unit, frame_title, smoothfold:vertices_name /
 * smoothfold:edges_name, file_frames with frame_inherit/frame_parent.
 * The frame read is the one asked for, else the first whose
 * frame_classes has "creasePattern", else the first that lies flat
 * (Origami Simulator labels its flat pattern "foldedForm" and lays it in
 * the x-z plane).
 *
 * Errors are one line naming the file and the location (JSON line and
 * column, the field and index, the SVG element and line), and where an
 * option would read the file, that option:
 *   p.fold:3:17: malformed JSON: ...
 *   p.fold: edges_vertices[4]: vertex 12 does not exist (vertices_coords has 9)
 *   p.svg:14: <path id="c1">: curved segment 'C' ...
 */
#ifndef SF_FOLDREAD_H
#define SF_FOLDREAD_H

#include "cpattern.h"

/* the sheet's larger side when the file has no physical unit [m] */
#define SF_IMPORT_DEFAULT_SIZE 0.2

enum {
    SF_SIGN_FOLD = 0,       /* FOLD 1.1: valley positive, mountain negative */
    SF_SIGN_OPPOSITE = 1,   /* mountain positive, valley negative */
    SF_SIGN_MAGNITUDE = 2   /* unsigned: |angle| with the sign of the assignment */
};

typedef struct sf_import_opts {
    int frame;              /* FOLD frame to read; -1: chosen as above */
    const char *unit;       /* coordinate unit (m, cm, mm, um, nm, in, pt, px);
                               NULL: the file's */
    double size;            /* > 0: scaled so that the larger side of the
                               bounding box is size [m], whatever the unit */
    int angle_sign;         /* SF_SIGN_* */
    int planarize;          /* FOLD: merge close vertices and split crossing
                               edges as for SVG (sf_cp_planarize) */
    double merge;           /* merge tolerance, a fraction of the larger side
                               of the bounding box (SVG and planarize) */
    int piece;              /* a file of several sheets: the one to read
                               (1 the largest); 0: refused naming --piece */
} sf_import_opts;

void sf_import_opts_default(sf_import_opts *o);

#define SF_IMPORT_NOTES 6
typedef struct sf_import_info {
    const char *format;     /* "FOLD" or "SVG" */
    char scale[200];        /* how the size was chosen, one phrase */
    double width, height;   /* bounding box after scaling [m] */
    int nnotes;             /* what the reader did beyond a plain reading */
    char notes[SF_IMPORT_NOTES][240];
} sf_import_info;

/* Read path (FOLD or SVG, by its extension, else by its first character)
 * into cp, scaled to metres (cp->unit), checked (sf_cp_check).  On failure
 * cp is empty and err holds one line. */
int sf_import_read(const char *path, const sf_import_opts *o, sf_cpattern *cp,
                   sf_import_info *info, sf_error *err);

/* The readers behind it: coordinates in the file's units; *unit_m gets
 * metres per unit, or 0 when the file gives no physical unit. */
int sf_fold_read(const char *path, const sf_import_opts *o, sf_cpattern *cp,
                 double *unit_m, sf_import_info *info, sf_error *err);
int sf_svg_read(const char *path, const sf_import_opts *o, sf_cpattern *cp,
                double *unit_m, sf_import_info *info, sf_error *err);

/* Metres per unit of a unit name; 0 when unknown. */
double sf_unit_metres(const char *unit);

/* A note for the header and the import summary (printf style). */
void sf_import_note(sf_import_info *info, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

#endif
