/* scene.c - open and close a scene: study, topology, model. */
#include "scene.h"

#include <string.h>

#include "study.h"

int sf_scene_open(sf_scene *sc, const char *path, int nset, const char **sets,
                  sf_error *err)
{
    memset(sc, 0, sizeof *sc);
    if (sf_study_load(path, nset, (const char *const *)sets, &sc->study, err)) return err->code;
    sc->have_study = 1;
    if (sf_topology_build(&sc->study, &sc->topo, err)) return err->code;
    sc->have_topo = 1;
    if (sf_model_init(&sc->model, &sc->study, &sc->topo, err)) return err->code;
    sc->have_model = 1;
    return SF_OK;
}

void sf_scene_close(sf_scene *sc)
{
    if (sc->have_model) sf_model_free(&sc->model);
    if (sc->have_topo) sf_topology_free(&sc->topo);
    if (sc->have_study) sf_study_free(&sc->study);
    memset(sc, 0, sizeof *sc);
}
