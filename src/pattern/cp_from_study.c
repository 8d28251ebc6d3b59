/* cp_from_study.c - a study's crease pattern as FOLD sees it (cpattern.h):
 * the study's vertices with their names, its folds in study order, then
 * the outline edges of the topology (with the vertices it inserted), the
 * facet edges (F), and the crease-pattern faces (not with facet edges: the
 * rigid faces do not split at them, FOLD's faces would). */
#include "cpattern.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "study.h"
#include "topology.h"

/* mountain/valley of fold i: its assignment, else the sign of its rest
 * angle at actuation 1 (its group's, else its own); *angle in degrees */
static char fold_sign(const sf_study *s, int i, double *angle, sf_error *err)
{
    const sf_fold_def *f = &s->folds[i];
    double r = f->group >= 0 ? s->groups[f->group].rest_angle : f->rest_angle;
    char key[64];
    snprintf(key, sizeof key, "folds[%d].assignment", i);
    const char *a = "";
    if (sf_study_has(s, key) && sf_study_string(s, key, "", &a, err)) return 0;
    *angle = r != 0 ? r * 180 / M_PI : NAN;
    if (a[0] == 'M' || a[0] == 'V') return a[0];
    return r < 0 ? 'M' : r > 0 ? 'V' : 'U';
}

int sf_cp_from_study(const sf_study *s, const sf_topology *t, sf_cpattern *cp,
                     sf_error *err)
{
    sf_cp_init(cp);
    snprintf(cp->title, sizeof cp->title, "%s", s->name);
    const char *desc = NULL;
    if (sf_study_has(s, "description") && sf_study_string(s, "description", "", &desc, err) == SF_OK)
        snprintf(cp->description, sizeof cp->description, "%s", desc);
    sf_error_clear(err);
    for (int v = 0; v < s->nvertices; v++)
        if (sf_cp_add_vertex(cp, s->vertices[v].x[0], s->vertices[v].x[1], s->vertices[v].name) < 0)
            goto oom;
    for (int i = 0; i < s->nfolds; i++) {
        double ang = NAN;
        char a = fold_sign(s, i, &ang, err);
        if (!a) { sf_cp_free(cp); return err->code; }
        int e = sf_cp_add_edge(cp, s->folds[i].a, s->folds[i].b, a, ang);
        if (e < 0) goto oom;
        snprintf(cp->e[e].name, SF_NAME_MAX, "%s", s->folds[i].name);
    }
    for (int k = 0; k < t->nboundary; k++)
        if (sf_cp_add_edge(cp, t->boundary[k], t->boundary[(k + 1) % t->nboundary], 'B', NAN) < 0)
            goto oom;
    for (int k = 0; k < s->nfacets; k++)
        if (sf_cp_add_edge(cp, s->facets[k][0], s->facets[k][1], 'F', 0.0) < 0) goto oom;
    if (s->nfacets) return SF_OK;   /* the topology's faces ignore the facet edges */
    int total = 0;
    for (int f = 0; f < t->nfaces; f++) total += t->faces[f].nverts;
    cp->face_start = malloc((size_t)(t->nfaces + 1) * sizeof *cp->face_start);
    cp->face_verts = malloc((size_t)(total + 1) * sizeof *cp->face_verts);
    if (!cp->face_start || !cp->face_verts) goto oom;
    int k = 0;
    for (int f = 0; f < t->nfaces; f++) {
        cp->face_start[f] = k;
        for (int j = 0; j < t->faces[f].nverts; j++) cp->face_verts[k++] = t->faces[f].verts[j];
    }
    cp->face_start[t->nfaces] = k;
    cp->nf = t->nfaces;
    return SF_OK;
oom:
    sf_cp_free(cp);
    return sf_fail(err, SF_ENOMEM, "out of memory");
}
