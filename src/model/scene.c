/* scene.c - open and close a scene: study, topology, model; its probes. */
#include "scene.h"

#include <stdlib.h>
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

int sf_scene_locate_probes(const sf_scene *sc, sf_mpoint **probes, sf_error *err)
{
    const sf_study *s = &sc->study;
    *probes = calloc((size_t)s->nprobes + 1, sizeof(sf_mpoint));
    if (!*probes) return sf_fail(err, SF_ENOMEM, "out of memory");
    for (int i = 0; i < s->nprobes; i++)
        if (sf_model_locate(&sc->model, s->probes[i].at, &(*probes)[i], err)) {
            sf_error_prefix(err, "%s:%d: probe %d", s->path, s->probes[i].line, i + 1);
            return err->code;
        }
    return SF_OK;
}
