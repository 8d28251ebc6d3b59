/* pattern.h - the study in memory: crease pattern, materials, effects and
 * analysis plan, as read from a .cfg file (study.c) and used by every other
 * module.  Plain data, no behaviour.  SI units throughout.
 *
 * Numbering: vertices, folds, loads and probes are 0-based here, in study
 * order; user-facing output numbers folds and probes from 1.
 */
#ifndef SF_PATTERN_H
#define SF_PATTERN_H

#define SF_NAME_MAX 64
/* Gauss-Legendre points across a fold section (solver.quadrature): the
 * one range, checked by the study schema and by the section model */
#define SF_QUADRATURE_MIN 2
#define SF_QUADRATURE_MAX 64

typedef struct sf_material {
    char name[SF_NAME_MAX];
    double E;          /* Young's modulus [Pa] */
    double nu;         /* Poisson ratio, in (-1, 0.5) */
    double thickness;  /* [m] */
    double density;    /* [kg/m^3] */
} sf_material;

typedef struct sf_vertex {
    char name[SF_NAME_MAX];
    double x[2];       /* reference position [m] */
    int line;          /* line in the study file, 0 if unknown */
} sf_vertex;

typedef struct sf_fold_def {
    char name[SF_NAME_MAX];   /* "" unless the study names it */
    int a, b;                 /* end vertices: the fold runs a -> b */
    double width;             /* band width w [m] */
    double setback[2];        /* d^a, d^b [m] */
    int continuity;           /* 1 (G1) or 2 (G2) */
    int modes;                /* K >= 0 extra shape modes */
    int material;             /* index into sf_study.materials */
    int group;                /* actuation group index, -1 if none */
    double rest_angle;        /* theta0 when not actuated [rad] (default 0) */
    int facet;                /* 1: a facet hinge of a bending face (facets.c),
                                 added after the study's own folds */
    int line;
} sf_fold_def;

typedef struct sf_point_load {
    double at[2];       /* material point, reference coordinates [m] */
    double force[3];    /* dead force at full load [N] */
    int stage;          /* 1-based load stage */
    int line;
} sf_point_load;

typedef struct sf_probe {
    char name[SF_NAME_MAX];
    double at[2];
    int line;
} sf_probe;

typedef struct sf_group {
    char name[SF_NAME_MAX];   /* actuation group: folds whose rest angle is driven */
    double rest_angle;        /* theta0 at actuation parameter 1 [rad] */
    int line;
} sf_group;

typedef struct sf_support {
    double at[2];         /* material point */
    int dof[3];           /* 1 where the displacement component is prescribed */
    double value[3];      /* prescribed displacement at full factor [m] */
    int line;
} sf_support;

enum { SF_CONSTRAINTS_EXACT = 0, SF_CONSTRAINTS_PENALTY = 1 };

typedef struct sf_study {
    char name[SF_NAME_MAX];
    char path[1024];            /* file it came from */

    int nvertices;
    sf_vertex *vertices;
    int noutline;               /* outline polygon as vertex indices, as given */
    int *outline;

    int nfolds;
    sf_fold_def *folds;

    int nfacet_edges;           /* faces.facets: lines across faces that are no */
    int (*facet_edges)[2];      /* folds; vertex indices [from, to] (facets.c) */

    int nmaterials;
    sf_material *materials;
    int face_material;          /* index, -1 when no face material is given */
    /* bending faces (faces.bending, facets.c): each face split into rigid
     * triangles joined by facet hinges, folds[nfolds - nfacets ..] */
    int bending;
    double bending_coefficient; /* C_B of the hinge stiffness */
    double facet_width;         /* facet band width / shortest side of its face */
    int nfacets;
    int nraised;                /* fold ends whose setback the facets raised */

    double fixed_point[2];      /* a point inside the fixed face */
    int fixed_line;

    int nloads;
    sf_point_load *loads;
    int gravity_on;
    double gravity[3];          /* [m/s^2] */
    int gravity_stage;
    int nstages;                /* number of load stages (>= 1) */

    int ngroups;
    sf_group *groups;

    int nsupports;
    sf_support *supports;

    int nprobes;
    sf_probe *probes;

    /* solver */
    int constraints;            /* SF_CONSTRAINTS_* */
    double penalty_rotation;    /* lambda_R [J] */
    double penalty_translation; /* lambda_d [J/m^2] */
    int quadrature;             /* Gauss-Legendre points per fold section */
    double tolerance;           /* solver.tolerance: Newton tolerance (added by study.c) */

    /* output */
    int samples;                /* samples across a fold band in VTK output */
    int shapes;                 /* output.shapes: shapes written along a path (added by study.c) */

    /* analysis: everything else the analysis needs is read by its module
     * from the libconfig tree kept here (opaque to avoid the dependency). */
    char analysis_type[SF_NAME_MAX];
    void *cfg;                  /* config_t *, owned by the study */
} sf_study;

#endif
