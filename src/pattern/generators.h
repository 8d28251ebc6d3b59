/* generators.h - crease patterns of the classic tessellations, from a few
 * parameters (docs/guides/patterns.md):
 *
 *   miura      Miura-ori: m x n cells of 2 x 2 parallelogram panels with
 *              straight sides a (along x) and zigzag sides b at the sector
 *              angle (degrees, 0 < angle < 90) to the x axis; target fold
 *              angles (edges_foldAngle) of its rigid folding motion
 *   yoshimura  Yoshimura (diamond) pattern: m diamonds of width a along x,
 *              n rows of height b; horizontal creases mountain, diagonals
 *              valley
 *   waterbomb  waterbomb tessellation: m x n waterbomb bases of a x b
 *              (two valley diagonals and a mountain midline each), every
 *              other row shifted by a/2, mountain lines between the rows
 *   twist      square twist: a sheet of side a, a central square of side b
 *              turned by angle (degrees, 0 < angle < 45), a pleat from
 *              each of its edges to the sheet's side; not rigidly foldable
 *   hypar      hyperbolic paraboloid: m rings of concentric squares in a
 *              sheet of side a, alternately mountain and valley, with the
 *              diagonals between the rings' corners; the centre one face
 *
 * Coordinates in metres, the sheet from (0, 0); assignments M and V by
 * FOLD's convention (valley positive).  Vertex names record the lattice
 * position (miura: "v<i>_<j>"). */
#ifndef SF_GENERATORS_H
#define SF_GENERATORS_H

#include "cpattern.h"

typedef struct sf_gen_opts {
    int m, n;          /* cells along x and y */
    double a, b;       /* panel (cell) sizes [m] */
    double angle;      /* miura: sector angle [deg]; twist: twist angle [deg] */
    double fold_angle; /* miura: target angle of the zigzag folds [deg] (> 0);
                          the straight folds get the rigid-folding partner
                          2 atan(cos(angle) tan(fold_angle / 2)) */
} sf_gen_opts;

/* Names of the generators, for messages: "miura, yoshimura, waterbomb, twist, hypar". */
const char *sf_gen_names(void);
/* Defaults of generator name; SF_EINPUT when there is no such generator. */
int sf_gen_defaults(const char *name, sf_gen_opts *o, sf_error *err);
/* Build the pattern (cp initialised here; free with sf_cp_free).  Checks
 * the parameters (cells >= 1, sizes > 0, the angle's range). */
int sf_generate(const char *name, const sf_gen_opts *o, sf_cpattern *cp,
                sf_error *err);

#endif
