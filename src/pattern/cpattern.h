/* cpattern.h - a crease pattern as FOLD sees it: 2-D vertices, straight
 * edges with an assignment (B boundary, M mountain, V valley, F flat,
 * U unassigned) and an optional target fold angle, optional faces.
 *
 * The common ground of the tessellation generators (generators.h), the FOLD
 * reader and writer (fold.h) and the study writer (sf_cp_write_study):
 *
 *   generator or FOLD file --> sf_cpattern --> commented study .cfg
 *   study (+ topology)      --> sf_cpattern --> FOLD file
 *
 * Sign convention (FOLD's, and the study's: docs/reference/study-keys.md): a
 * valley fold has a positive fold angle, a mountain fold a negative one.
 * Angles here are in degrees, as in FOLD's edges_foldAngle.
 */
#ifndef SF_CPATTERN_H
#define SF_CPATTERN_H

#include <stdio.h>

#include "pattern.h"
#include "sf_error.h"

typedef struct sf_cp_vertex {
    double x[2];
    char name[SF_NAME_MAX];   /* "" when unnamed */
} sf_cp_vertex;

typedef struct sf_cp_edge {
    int a, b;                 /* vertex indices */
    char assign;              /* 'B', 'M', 'V', 'F' or 'U' */
    double angle;             /* target fold angle [deg], valley positive;
                                 NAN when not given */
    char name[SF_NAME_MAX];   /* "" when unnamed */
} sf_cp_edge;

typedef struct sf_cpattern {
    int nv, vcap;
    sf_cp_vertex *v;
    int ne, ecap;
    sf_cp_edge *e;
    int nf;                   /* optional faces (0 when not given) */
    int *face_start;          /* nf + 1 offsets into face_verts */
    int *face_verts;
    double unit;              /* metres per coordinate unit (1 for SI) */
    char title[128];          /* study name to use, or "" */
    char description[256];    /* one line, or "" */
} sf_cpattern;

void sf_cp_init(sf_cpattern *cp);
void sf_cp_free(sf_cpattern *cp);

/* Append a vertex; returns its index, or -1 when out of memory. */
int sf_cp_add_vertex(sf_cpattern *cp, double x, double y, const char *name);
/* The vertex at (x, y) within tol, added when there is none: for lattice
 * generators.  Returns its index, or -1 when out of memory. */
int sf_cp_vertex_at(sf_cpattern *cp, double x, double y, double tol);
/* Append an edge; returns its index, or -1 when out of memory. */
int sf_cp_add_edge(sf_cpattern *cp, int a, int b, char assign, double angle_deg);

/* The larger side of the bounding box (1 when it has none). */
double sf_cp_size(const sf_cpattern *cp);

/* Check the pattern as a planar straight-line graph: edges refer to
 * existing, distinct vertices; no zero-length, duplicate or overlapping
 * edges; no two edges crossing away from a shared vertex; no vertex inside
 * an edge; the boundary edges form one closed loop (sf_cp_outline); faces,
 * when given, refer to existing vertices and tile the outline (their areas
 * add up to its area).  Messages name the FOLD field and 0-based index,
 * "edges_vertices[3]: ...", prefixed by where (a file name) when not NULL. */
int sf_cp_check(const sf_cpattern *cp, const char *where, sf_error *err);

/* The boundary (B) edges walked into one loop, counter-clockwise:
 * *out (malloc'd, caller frees) gets the vertex indices, *n their number. */
int sf_cp_outline(const sf_cpattern *cp, int **out, int *n, const char *where,
                  sf_error *err);

/* Drawn line work made planar (cp_clean.c): vertices within tol merged,
 * edges split where they cross or where a vertex lies on them, zero-length
 * edges dropped, duplicates merged (a line over the outline is the
 * outline, a fold over a facet or unassigned line is the fold, a mountain
 * over a valley is an error).  Faces are dropped. */
int sf_cp_planarize(sf_cpattern *cp, double tol, const char *where, sf_error *err);

/* Folds that end inside a face, removed from cp (cp_dangling.c): the M, V
 * and U edges (and F with flat_too) peeled from their free ends inwards,
 * a free end being a vertex with no other fold or outline edge.  With
 * rigid faces such a fold cannot turn, so the study without it has the
 * same states.  Returns how many were removed (then cp's faces are
 * dropped), a negative code on failure; what (when not NULL) gets the
 * first three as "(x, y)-(x, y) mm". */
int sf_cp_drop_dangling(sf_cpattern *cp, int flat_too, char *what, size_t nwhat, sf_error *err);

/* A file that draws several sheets (cp_pieces.c): its boundary loops, a
 * loop inside no other being a sheet, numbered by area (1 the largest).
 * piece = N >= 1 keeps sheet N, its outline and the lines inside it (cp's
 * vertices renumbered, faces dropped; note, when not NULL, says so);
 * piece = 0 fails naming --piece when there are several sheets.  A hole
 * (a loop inside the sheet kept) fails either way.  Outlines that are not
 * loops are left to sf_cp_check. */
int sf_cp_pick_piece(sf_cpattern *cp, int piece, const char *where, char *note, size_t nnote, sf_error *err);

/* outer[e] = 1 for the edges on the outer face of the pattern's graph (the
 * loop walked around it from its leftmost vertex), else 0. */
int sf_cp_outer_edges(const sf_cpattern *cp, char *outer, sf_error *err);

/* Setbacks that keep the bands of the folds (edges with half-width
 * width[e]/2 > 0; edges with width[e] = 0 take part as lines only, e.g.
 * the boundary; edges with width[e] < 0 not at all) from overlapping near every vertex: for two neighbouring
 * rays at a vertex with sector alpha < pi the bands' facing edge lines meet
 * at distances (h2 + h1 cos alpha)/sin alpha and (h1 + h2 cos alpha)/sin alpha
 * from the vertex; each band starts margin times farther, and at least
 * min_frac * its width from the vertex.  At a boundary vertex the sector
 * outside the sheet is skipped (outline: the loop of sf_cp_outline).
 * sb[e][0] is the setback at edge e's vertex a, sb[e][1] at b. */
void sf_cp_setbacks(const sf_cpattern *cp, const double *width,
                    const int *outline, int noutline, double margin,
                    double min_frac, double (*sb)[2]);

/* The crease pattern of a study (cp_from_study.c): its vertices (names
 * kept), its folds in study order as edges 0..nfolds-1 (M or V from
 * folds[].assignment, else from the sign of the rest angle at actuation 1,
 * else U; that angle in degrees), then the outline edges (B) of the
 * topology, and the topology's faces. */
struct sf_topology;
int sf_cp_from_study(const sf_study *s, const struct sf_topology *t,
                     sf_cpattern *cp, sf_error *err);

/* ---- writing a study ---------------------------------------------------- */

typedef struct sf_cp_study_opts {
    const char *name;         /* study name (else cp->title, else "pattern") */
    const char *header;       /* comment lines at the top ('\n'-separated), or NULL */
    double width;             /* band width [m]; <= 0: 0.1 x the shortest fold */
    int setback_given;        /* 1: no setbacks written (defaults.setback set by the caller) */
    int fixed_given;          /* 1: fixed_face below, else the body of the
                                 face nearest the sheet's centroid */
    double fixed[2];
    int include_flat;         /* F edges become folds too (else they are
                                 written as facet edges, key facets) */
    double fold_angle;        /* actuation rest angle magnitude [rad] where the
                                 pattern gives none (> 0) */
    double fold_percent;      /* analysis.end = fold_percent / 100 (Origami
                                 Simulator's fold percent); <= 0: 100 */
    int modes;                /* defaults.modes (1: degree-4 vertices lock with 0);
                                 < 0: the smallest K >= 1 whose fold
                                 coordinates match the loop rows (import) */
    int gravity;              /* add gravity (stage 1) */
    double load;              /* point load [N] downwards at the probe (0: none) */
    const char *drive;        /* actuation group driven by p (analysis.group), NULL: all */
    int bending;              /* faces.bending = true, with E and nu in the face
                                 material (twist, hypar) */
} sf_cp_study_opts;

void sf_cp_study_opts_default(sf_cp_study_opts *o);

/* Write cp as a commented, ready-to-run study .cfg to path (through a
 * temporary file, renamed at the end), then load it with the nset --set
 * overrides and build its topology: on any failure nothing is left at path
 * and err holds one line.  The fixed face is chosen on a first pass through
 * the topology.  With overrides the merged study is written instead (its
 * values, with the header comment).  When the automatic width (o->width
 * <= 0) gives bands that do not fit the faces, it is halved up to four
 * times; the message of the first failure is kept when none fits. */
int sf_cp_write_study(const sf_cpattern *cp, const sf_cp_study_opts *o,
                      const char *path, int nset, const char *const *sets,
                      sf_error *err);

/* Shortest text of x that reads back exactly and that libconfig reads as a
 * real number (always with '.' or an exponent). */
void sf_cp_real(char *buf, size_t n, double x);

#endif
