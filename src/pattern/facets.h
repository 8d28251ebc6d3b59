/* facets.h - bending faces (faces.bending): the faces of a study split
 * into rigid triangles joined by facet hinges, appended to the study as
 * folds (facets.c, docs/guides/bending-faces.md). */
#ifndef SF_FACETS_H
#define SF_FACETS_H

#include "pattern.h"
#include "sf_error.h"

/* faces.facets read into s->facet_edges (checked: two vertex names, not
 * one fold's ends), bending or not.  With s->bending on (and no facets
 * yet): triangulate every face (the
 * given faces.facets first, then ear clipping by shortest diagonal) and
 * append one fold per facet edge (facet = 1, K = 0, rest angle 0, no
 * group, a material of its own whose plate stiffness gives the hinge the
 * stiffness sf_facet_stiffness).  Called by sf_study_load. */
int sf_study_add_facets(sf_study *s, sf_error *err);

/* Rotational stiffness of a facet hinge of length l [m] in a plate of
 * modulus E, Poisson ratio nu, thickness t (Filipov et al., IJSS 2017):
 * cb (l / t)^(1/3) E t^3 / (12 (1 - nu^2))  [N m / rad]. */
double sf_facet_stiffness(double E, double nu, double t, double l, double cb);

#endif
