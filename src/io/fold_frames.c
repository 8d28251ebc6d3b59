/* fold_frames.c - the folded forms of a run as FOLD frames (fold.h). */
#include "fold.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kinematics.h"

int sf_foldrec_init(sf_foldrec *r, const sf_model *m, sf_error *err)
{
    memset(r, 0, sizeof *r);
    r->m = m;
    if (sf_cp_from_study(m->study, m->topo, &r->cp, err)) return err->code;
    const sf_topology *t = m->topo;
    int nv = r->cp.nv, total = 0;
    for (int f = 0; f < t->nfaces; f++) total += t->faces[f].nverts;
    r->vstart = calloc((size_t)nv + 1, sizeof *r->vstart);
    r->vface = malloc((size_t)(total + 1) * sizeof *r->vface);
    sf_kin *k = calloc(1, sizeof *k);
    r->kin = k;
    if (!r->vstart || !r->vface || !k || sf_kin_alloc(m, k)) {
        sf_foldrec_free(r);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int f = 0; f < t->nfaces; f++)
        for (int j = 0; j < t->faces[f].nverts; j++) r->vstart[t->faces[f].verts[j] + 1]++;
    for (int v = 0; v < nv; v++) r->vstart[v + 1] += r->vstart[v];
    int *fill = calloc((size_t)nv + 1, sizeof *fill);
    if (!fill) { sf_foldrec_free(r); return sf_fail(err, SF_ENOMEM, "out of memory"); }
    for (int f = 0; f < t->nfaces; f++)
        for (int j = 0; j < t->faces[f].nverts; j++) {
            int v = t->faces[f].verts[j];
            r->vface[r->vstart[v] + fill[v]++] = f;
        }
    free(fill);
    return SF_OK;
}

int sf_foldrec_add(sf_foldrec *r, const double *y, double p, double load,
                   int stable, int branch, sf_error *err)
{
    const sf_model *m = r->m;
    int nv = r->cp.nv, ne = r->cp.ne;
    if (r->nframes == r->cap) {
        int cap = r->cap ? 2 * r->cap : 16;
        double (*x)[3] = realloc(r->x, (size_t)cap * (size_t)nv * sizeof *x);
        if (x) r->x = x;
        double *a = realloc(r->angle, (size_t)cap * (size_t)ne * sizeof *a);
        if (a) r->angle = a;
        sf_fold_frame *fr = realloc(r->fr, (size_t)cap * sizeof *fr);
        if (fr) r->fr = fr;
        if (!x || !a || !fr) return sf_fail(err, SF_ENOMEM, "out of memory");
        r->cap = cap;
    }
    sf_kin *k = r->kin;
    sf_kin_eval(m, y, 0, k);
    double (*x)[3] = r->x + (size_t)r->nframes * (size_t)nv;
    double *ang = r->angle + (size_t)r->nframes * (size_t)ne;
    for (int v = 0; v < nv; v++) {
        int n = r->vstart[v + 1] - r->vstart[v];
        x[v][0] = x[v][1] = x[v][2] = 0;
        if (n == 0) {   /* a vertex on no face (unused by the pattern): where it lies */
            x[v][0] = m->study->vertices[v].x[0];
            x[v][1] = m->study->vertices[v].x[1];
            continue;
        }
        for (int j = r->vstart[v]; j < r->vstart[v + 1]; j++) {
            sf_mpoint pt;
            memset(&pt, 0, sizeof pt);
            pt.X[0] = m->study->vertices[v].x[0];
            pt.X[1] = m->study->vertices[v].x[1];
            pt.face = r->vface[j];
            pt.fold = -1;
            double xi[3];
            sf_point_eval(m, k, &pt, xi, NULL);
            for (int d = 0; d < 3; d++) x[v][d] += xi[d] / n;
        }
    }
    for (int e = 0; e < ne; e++)
        ang[e] = e < m->nfolds ? y[m->qoff[e]] * 180 / M_PI : 0.0;
    sf_fold_frame *f = &r->fr[r->nframes++];
    f->x = (const double (*)[3])x;
    f->angle = ang;
    f->p = p;
    f->load = load;
    f->stable = stable;
    f->branch = branch;
    return SF_OK;
}

int sf_foldrec_write(const sf_foldrec *r, const char *path, sf_error *err)
{
    /* the frames point into arrays that may have moved while growing */
    for (int k = 0; k < r->nframes; k++) {
        r->fr[k].x = (const double (*)[3])(r->x + (size_t)k * (size_t)r->cp.nv);
        r->fr[k].angle = r->angle + (size_t)k * (size_t)r->cp.ne;
    }
    return sf_fold_write(&r->cp, "smoothfold run", r->nframes, r->fr, path, err);
}

void sf_foldrec_free(sf_foldrec *r)
{
    sf_cp_free(&r->cp);
    free(r->x);
    free(r->angle);
    free(r->fr);
    free(r->vface);
    free(r->vstart);
    if (r->kin) { sf_kin_free(r->kin); free(r->kin); }
    memset(r, 0, sizeof *r);
}
