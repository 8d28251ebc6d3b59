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
 * smoothfold:stable, smoothfold:branch.  docs/fold-format.md. */
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

#endif
