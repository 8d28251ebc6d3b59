/* flatcone_impl.h - what flatcone.c and flatcone_rays.c share: the
 * reduced problem's helpers and tolerances (internal to the two files). */
#ifndef SF_FLATCONE_IMPL_H
#define SF_FLATCONE_IMPL_H

#include "flatcone.h"

#define CONE_TOL 1e-13    /* |x^T Q x| / 2 on a cone point (x^T A x = 1) */
#define CONE_MAXIT 60
#define SAME_TOL 1e-3     /* two solutions are one when closer (A norm, relative): a flat valley of the energy converges to ~1e-6 only */
#define ASCENT_MAXIT 400  /* projected-gradient steps of the work on the cone */
#define ASCENT_TOL 1e-6   /* projected gradient (A norm, relative) of a stationary ray */
#define ASCENT_STALL_ITS 10     /* with a stable branch already found, an ascent ends */
#define ASCENT_STALL_GAIN 1e-9  /* at a corner when its last ASCENT_STALL_ITS steps raised
                                 * the work by less than this (relative): on square4 they
                                 * gained ~1e-11 each for all ASCENT_MAXIT steps */
#define ASCENT_STARTS 24  /* random starts of the ascent on the cone */

typedef sf_cone_red red;

/* flatcone.c */
int sf_fc_lstsq(int m, int n, double *a, double *b);
double sf_fc_maxabs(const double *v, int n);
void sf_fc_matvec(int k, const double *M, const double *x, double *y);
double sf_fc_dot(int k, const double *a, const double *b);
void sf_fc_cone_eval(const red *R, const double *x, double *h, double *Jh, double *tmp);
void sf_fc_anormalise(const red *R, double *x, double *tmp);
int sf_fc_red_newton(const red *R, double *v, double *F, double *Jm, double *d, double *vt,
                     double *tmp);
double sf_fc_rnd(unsigned long long *st);
int sf_fc_add_sol(const red *R, const double *v, double a0, double *sols, double *en, int ns,
                  int nmax, int *ncone, double *d, double *tmp);

/* flatcone_rays.c: ASCENT_STARTS pseudo-random rays raised along the cone
 * (solutions into sols/en/ns, degenerate rays into c); the caller's rays
 * (nq values each).  stall_ends: an ascent that gains almost nothing ends
 * (ASCENT_STALL_*).  0, or -1 when out of memory. */
int sf_fc_cone_search(const red *R, double a0, double *sols, double *en, int *ns, int nmax,
                      sf_cone *c, double *v, double *F, double *Jm, double *d, double *vt,
                      unsigned long long *st, int stall_ends);
int sf_fc_rays_add(const sf_limit *L, const red *R, const double *rays, int nrays, double a0,
                   double *sols, double *en, int *ns, int nmax, sf_cone *c, double *v, double *F,
                   double *Jm, double *d, double *vt, double *tmp);

/* Keep the ray x (unit A norm, w = b . x < 0) as a degenerate one of c
 * unless it is there already (flatcone_rays.c). */
void sf_fc_deg_add(const red *R, const double *x, double w, sf_cone *c);
#endif
