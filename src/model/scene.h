/* scene.h - a loaded study with its topology and kinematic model. */
#ifndef SF_SCENE_H
#define SF_SCENE_H

#include "kinematics.h"
#include "pattern.h"
#include "sf_error.h"
#include "topology.h"

typedef struct sf_scene {
    sf_study study;
    sf_topology topo;
    sf_model model;
    int have_study, have_topo, have_model;
} sf_scene;

/* Load, apply overrides, build topology and model.  On failure the scene
 * may be partly built: always sf_scene_close it. */
int sf_scene_open(sf_scene *sc, const char *path, int nset, const char **sets,
                  sf_error *err);
void sf_scene_close(sf_scene *sc);
/* The study's probes located on the model (calloc'ed array of nprobes,
 * freed by the caller); a probe outside the sheet fails with its line. */
int sf_scene_locate_probes(const sf_scene *sc, sf_mpoint **probes, sf_error *err);

#endif
