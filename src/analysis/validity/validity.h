/* validity.h - is a computed shape physically possible?  Two checks of a
 * state q (docs/reference/output-files.md, "Physical validity"):
 *
 *  - folds beyond +-180 degrees: |theta_i| > pi (by more than
 *    SF_VALIDITY_ANGLE_TOL), the fold turned past flat onto itself;
 *  - parts of the sheet through each other: the faces and fold bands as
 *    placed in space (the triangles of the VTK shape: each face body
 *    triangulated, each band `samples` planar strips across its width,
 *    two triangles each) tested pairwise for crossings.  A crossing is a
 *    penetration when the two material points that occupy one place lie
 *    farther apart in the flat sheet than the contact distance delta
 *    (tritri.h: the material separation); neighbours that meet along
 *    their common fold band edge, or at a common corner, share material
 *    there (separation 0) and are not flagged.  Around an interior vertex
 *    the model leaves a small polygon of the sheet out (MODEL.md 1); the
 *    parts that border it meet there in ways the model does not resolve,
 *    so a crossing whose two material points both lie within that
 *    vertex's region (the disc about the vertex through the band corners
 *    nearest it) is contact, not penetration; so is one at the set-back
 *    end of a band at a vertex on the outline (the disc about that vertex
 *    through the band's two corners there).
 *
 * delta is a tenth of the narrowest fold band: material points closer
 * than that cannot meet through folding (faces are rigid and a band
 * curves over its whole width), only through the loop gaps of the
 * penalty method or the polygonal bands.
 *
 * Cost: the parts' bounding boxes in an R-tree (libspatialindex,
 * quadratic split, built anew for each state: O(n log n) in the parts),
 * each part's box queried for the boxes it overlaps, triangle pairs of
 * overlapping parts tested where their own boxes overlap
 * (bench/validity-cost.sh: 0.09 s on 16 x 16 Miura cells, 3008 parts;
 * the library's insertions and queries take about half of it). */
#ifndef SF_VALIDITY_H
#define SF_VALIDITY_H

#include "kinematics.h"
#include "sf_error.h"

#define SF_VALIDITY_ANGLE_TOL 1e-9   /* rad: a fold at pi to rounding is flat, not beyond */

typedef struct sf_validity_report {
    int nbeyond;          /* folds with |theta| > pi */
    int beyond_fold;      /* the one of them farthest beyond (-1: none) */
    double beyond_angle;  /* its angle [rad] */
    long ncross;          /* pairs of parts (faces, bands) through each other */
    int cross_part[2];    /* the pair with the largest separation: part ids
                             (sf_validity_part_name), -1 when none */
    double cross_sep;     /* its material separation [m] */
    double cross_at[3];   /* where in space */
    long part_pairs;      /* pairs of parts whose boxes overlap (work) */
    long tri_tests;       /* triangle pairs tested (work) */
} sf_validity_report;

typedef struct sf_validity sf_validity;

/* Prepare the checks of states of m: the triangles, their reference
 * coordinates, the vertex regions.  samples: strips across each band (as
 * output.samples for the VTK shapes).  SF_ENOMEM. */
int sf_validity_create(const sf_model *m, int samples, sf_validity **out, sf_error *err);
void sf_validity_free(sf_validity *v);

/* Check the state q (m->nq fold coordinates).  brute = 1 tests every pair
 * of parts instead of those the tree finds (for tests: the same answer).
 * SF_OK, SF_ENOMEM, SF_ENUMERIC (a non-finite position, or the spatial
 * index failed, with its message). */
int sf_validity_check(sf_validity *v, const double *q, int brute, sf_validity_report *rep,
                      sf_error *err);

/* The contact distance delta [m] (above). */
double sf_validity_delta(const sf_validity *v);
/* Triangles in all (faces and bands). */
long sf_validity_ntriangles(const sf_validity *v);

/* "face 3 (c1 f1a f1b c4)" or "band of fold 7 (v2->v5)" for a part id. */
void sf_validity_part_name(const sf_validity *v, int part, char *buf, size_t size);

#endif
