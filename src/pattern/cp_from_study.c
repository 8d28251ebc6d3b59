/* cp_from_study.c - a study's crease pattern as FOLD sees it (cpattern.h):
 * the study's vertices with their names, its folds in study order, then
 * the outline edges of the topology (with the vertices it inserted), the
 * facet edges (F: faces.facets, or with faces.bending the facet hinges,
 * which are folds), and the crease-pattern faces (not with rigid faces and
 * facet edges: the rigid faces do not split at them, FOLD's faces would). */
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
    if (f->facet) { *angle = NAN; return 'F'; }   /* a bending face's facet hinge */
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
    /* a facet edge may end on a fold's centre line (import joins collinear
     * folds through such vertices): the fold is split there, so that the
     * FOLD graph stays planar; its first piece keeps edge number i, the
     * others follow the folds (and import joins them again) */
    int *cut = NULL, ncut = 0;
    double *cpar = NULL;
    if (s->nfacet_edges) {
        cut = malloc(sizeof *cut * (size_t)(2 * s->nfacet_edges + 1));
        cpar = malloc(sizeof *cpar * (size_t)(2 * s->nfacet_edges + 1));
        if (!cut || !cpar) { free(cut); free(cpar); goto oom; }
    }
    int *piece_a = NULL, *piece_b = NULL, *piece_f = NULL, npiece = 0, cappiece = 0;
    for (int i = 0; i < s->nfolds; i++) {
        double ang = NAN;
        char a = fold_sign(s, i, &ang, err);
        if (!a) { free(cut); free(cpar); free(piece_a); free(piece_b); free(piece_f); sf_cp_free(cp); return err->code; }
        const double *pa = s->vertices[s->folds[i].a].x, *pb = s->vertices[s->folds[i].b].x;
        double d[2] = {pb[0] - pa[0], pb[1] - pa[1]}, l2 = d[0] * d[0] + d[1] * d[1];
        ncut = 0;
        for (int k = 0; k < s->nfacet_edges; k++)
            for (int j = 0; j < 2; j++) {
                int v = s->facet_edges[k][j];
                if (v == s->folds[i].a || v == s->folds[i].b) continue;
                const double *q = s->vertices[v].x;
                double t = ((q[0] - pa[0]) * d[0] + (q[1] - pa[1]) * d[1]) / l2;
                double off = fabs((q[0] - pa[0]) * d[1] - (q[1] - pa[1]) * d[0]) / sqrt(l2);
                int dup = 0;
                for (int c = 0; c < ncut; c++) dup |= cut[c] == v;
                if (t > 1e-9 && t < 1 - 1e-9 && off <= 1e-9 * sqrt(l2) && !dup) {
                    int c = ncut++;   /* insertion by t */
                    while (c > 0 && cpar[c - 1] > t) { cpar[c] = cpar[c - 1]; cut[c] = cut[c - 1]; c--; }
                    cpar[c] = t;
                    cut[c] = v;
                }
            }
        int e = sf_cp_add_edge(cp, s->folds[i].a, ncut ? cut[0] : s->folds[i].b, a, ang);
        if (e < 0) { free(cut); free(cpar); free(piece_a); free(piece_b); free(piece_f); goto oom; }
        snprintf(cp->e[e].name, SF_NAME_MAX, "%s", s->folds[i].name);
        for (int c = 0; c < ncut; c++) {
            if (npiece == cappiece) {
                cappiece = cappiece ? 2 * cappiece : 64;
                int *na = realloc(piece_a, sizeof *na * (size_t)cappiece);
                if (na) piece_a = na;
                int *nb = realloc(piece_b, sizeof *nb * (size_t)cappiece);
                if (nb) piece_b = nb;
                int *nf = realloc(piece_f, sizeof *nf * (size_t)cappiece);
                if (nf) piece_f = nf;
                if (!na || !nb || !nf) { free(cut); free(cpar); free(piece_a); free(piece_b); free(piece_f); goto oom; }
            }
            piece_a[npiece] = cut[c];
            piece_b[npiece] = c + 1 < ncut ? cut[c + 1] : s->folds[i].b;
            piece_f[npiece++] = e;
        }
    }
    for (int k = 0; k < npiece; k++)
        if (sf_cp_add_edge(cp, piece_a[k], piece_b[k], cp->e[piece_f[k]].assign, cp->e[piece_f[k]].angle) < 0) {
            free(cut); free(cpar); free(piece_a); free(piece_b); free(piece_f);
            goto oom;
        }
    free(cut); free(cpar); free(piece_a); free(piece_b); free(piece_f);
    for (int k = 0; k < t->nboundary; k++) {
        /* outline edges split at facet ends on them, as the folds */
        int a = t->boundary[k], b = t->boundary[(k + 1) % t->nboundary];
        const double *pa = s->vertices[a].x, *pb = s->vertices[b].x;
        double d[2] = {pb[0] - pa[0], pb[1] - pa[1]}, l2 = d[0] * d[0] + d[1] * d[1];
        int prev = a;
        for (;;) {
            int next = b;
            double tbest = 1, tprev = ((s->vertices[prev].x[0] - pa[0]) * d[0] + (s->vertices[prev].x[1] - pa[1]) * d[1]) / l2;
            for (int f = 0; f < s->nfacet_edges; f++)
                for (int j = 0; j < 2; j++) {
                    const double *q = s->vertices[s->facet_edges[f][j]].x;
                    double tq = ((q[0] - pa[0]) * d[0] + (q[1] - pa[1]) * d[1]) / l2;
                    double off = fabs((q[0] - pa[0]) * d[1] - (q[1] - pa[1]) * d[0]) / sqrt(l2);
                    if (tq > tprev + 1e-9 && tq < tbest - 1e-9 && off <= 1e-9 * sqrt(l2)) { tbest = tq; next = s->facet_edges[f][j]; }
                }
            if (sf_cp_add_edge(cp, prev, next, 'B', NAN) < 0) goto oom;
            if (next == b) break;
            prev = next;
        }
    }
    if (s->nfacet_edges && !s->bending) {   /* bending faces: the facet hinges are the F edges */
        for (int k = 0; k < s->nfacet_edges; k++)
            if (sf_cp_add_edge(cp, s->facet_edges[k][0], s->facet_edges[k][1], 'F', 0.0) < 0) goto oom;
        return SF_OK;   /* the topology's rigid faces ignore the facet edges */
    }
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
