/* energy.h - total potential energy Pi = U - W of a scene (MODEL.md 5):
 * fold bending with rest curvature (actuation), dead point loads, gravity
 * on faces and fold bands, and the paper's penalty when the study asks for
 * it.  Only the effects the scene declares are assembled; a scene without
 * gravity never computes masses.
 *
 * The parameters enter through sf_params: a factor per load stage and a
 * rest angle per fold, each with its derivative in the continuation
 * parameter p, so that dF/dp is exact.
 */
#ifndef SF_ENERGY_H
#define SF_ENERGY_H

#include "kinematics.h"
#include "sf_error.h"

typedef struct sf_params {
    double *stage;      /* [nstages] load factor of each stage */
    double *dstage;     /* d stage / dp */
    double *rest;       /* [nfolds] rest angle theta0 */
    double *drest;      /* d rest / dp */
} sf_params;

typedef struct sf_energy {
    const sf_model *m;
    int nstages;
    double *stiff;          /* per fold D L / w [J] */
    sf_mpoint *loadpt;      /* per point load */
    int gravity;
    double *face_mass;      /* [nfaces] */
    sf_mpoint *face_pt;     /* centroid of each face body */
    double *fold_mass;      /* [nfolds] */
    double *fold_ref;       /* [nfolds][3] reference centroid of the band */
    int penalty;
    double lR, ld;
} sf_energy;

int sf_energy_init(sf_energy *e, const sf_model *m, sf_error *err);
void sf_energy_free(sf_energy *e);

int sf_params_alloc(const sf_energy *e, sf_params *p);
void sf_params_free(sf_params *p);

/* Pi at the kinematic state k; adds the gradient to grad, the Hessian to
 * H (nq x nq, leading dimension ld) and dgrad/dp to gp, each when not
 * NULL.  Returns Pi.  k must hold the derivative order needed. */
double sf_energy_eval(const sf_energy *e, const sf_kin *k, const sf_params *p,
                      double *grad, double *H, int ld, double *gp);

/* Bending energy alone (for reports). */
double sf_energy_bending(const sf_energy *e, const double *q, const sf_params *p);

#endif
