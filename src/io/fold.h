/* fold.h - FOLD 1.1 files (https://github.com/edemaine/fold, JSON) written
 * with jansson: a crease pattern, and the folded forms of a run.
 *
 * Frame 0 (the file's top level) is the crease pattern: vertices_coords
 * 2-D in metres (frame_unit "m"), edges_vertices, edges_assignment (B, M,
 * V, F, U), edges_foldAngle in degrees when the pattern gives target
 * angles, and smoothfold:vertices_name / smoothfold:edges_name for the
 * study's names.  Each further frame (file_frames[k]) is one computed
 * state: frame_classes ["foldedForm"], frame_inherit true, frame_parent 0,
 * 3-D vertices_coords, edges_foldAngle in degrees (FOLD's sign: valley
 * positive, 0 on boundary edges), and smoothfold:p, smoothfold:load,
 * smoothfold:stable, smoothfold:branch.  docs/guides/importing-patterns.md. */
#ifndef SF_FOLD_H
#define SF_FOLD_H

#include "cpattern.h"
#include "sf_error.h"

typedef struct sf_fold_frame {
    const double (*x)[3];   /* cp->nv points [m] */
    const double *angle;    /* cp->ne fold angles [deg] */
    double p;               /* continuation parameter */
    double load;            /* load factor */
    int stable;             /* 1 stable, 0 unstable, -1 unknown */
    int branch;             /* 1-based branch number */
} sf_fold_frame;

/* The crease pattern alone. */
int sf_fold_write_pattern(const sf_cpattern *cp, const char *path, sf_error *err);
/* The crease pattern and nframes folded forms, written atomically. */
int sf_fold_write(const sf_cpattern *cp, const char *creator, int nframes,
                  const sf_fold_frame *frames, const char *path, sf_error *err);

/* ---- the folded forms of a run (fold_frames.c) ----------------------------
 * DIR/folded.fold: the study's crease pattern (sf_cp_from_study) and one
 * foldedForm frame per output shape.  A crease-pattern vertex is not a
 * material point of a smooth-fold sheet (the bands and the small polygon
 * around each vertex separate the faces): it is placed at the mean of its
 * images under the rigid motions of the faces around it.  The fold angle
 * of an edge is the smooth fold's total turning theta (degrees, valley
 * positive); 0 on boundary edges.  docs/guides/importing-patterns.md. */
struct sf_model;
typedef struct sf_foldrec {
    const struct sf_model *m;
    sf_cpattern cp;
    int nframes, cap;
    double (*x)[3];           /* nframes * cp.nv points */
    double *angle;            /* nframes * cp.ne angles [deg] */
    sf_fold_frame *fr;
    int *vface;               /* per vertex: one face per incidence, CSR */
    int *vstart;
    void *kin;                /* sf_kin, for the maps */
} sf_foldrec;

int sf_foldrec_init(sf_foldrec *r, const struct sf_model *m, sf_error *err);
/* One frame: the state y (fold coordinates first) at parameter p. */
int sf_foldrec_add(sf_foldrec *r, const double *y, double p, double load,
                   int stable, int branch, sf_error *err);
int sf_foldrec_write(const sf_foldrec *r, const char *path, sf_error *err);
void sf_foldrec_free(sf_foldrec *r);

#endif
