/* vtk.c - VTK XML PolyData and PVD writers. */
#include "vtk.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int sf_write_atomic(const char *path, int (*fill)(void *ctx, void *file),
                    void *ctx, sf_error *err)
{
    char tmp[1100];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    /* SIGINT and SIGTERM wait until the file is complete and renamed (or
     * removed): an interrupted run leaves complete files or none, never a
     * .tmp.  They are delivered, with their default action, on return. */
    sigset_t block, old;
    sigemptyset(&block);
    sigaddset(&block, SIGINT);
    sigaddset(&block, SIGTERM);
    sigaddset(&block, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &block, &old);
    int rc = SF_OK;
    FILE *f = fopen(tmp, "w");
    if (!f) {
        rc = sf_fail(err, SF_EIO, "%s: cannot write: %s", tmp, strerror(errno));
        goto out;
    }
    errno = 0;
    rc = fill(ctx, f);
    int e = rc ? errno : 0;            /* the reason of a failed write */
    if (fflush(f) != 0 && !rc) { rc = SF_EIO; e = errno; }
    if (fclose(f) != 0 && !rc) { rc = SF_EIO; e = errno; }
    if (rc != 0) {
        remove(tmp);
        if (rc == SF_EIO)
            rc = sf_fail(err, SF_EIO, "%s: write failed: %s", path,
                         e ? strerror(e) : "unknown error");
        else
            rc = sf_fail(err, rc, "%s: write failed%s", path, rc == SF_ENOMEM ? ": out of memory" : "");
        goto out;
    }
    if (rename(tmp, path) != 0) {
        e = errno;
        remove(tmp);
        rc = sf_fail(err, SF_EIO, "%s: cannot rename from %s: %s", path, tmp, strerror(e));
    }
out:
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    return rc;
}

typedef struct shape_ctx {
    const sf_model *m;
    const double *q;
    int samples;
    sf_kin k;
    int nfields;
    const char *const *fname;
    const double *fval;
    const char *path;
    sf_error *err;
} shape_ctx;

/* The shape's computed numbers finite, checked before they are written:
 * else SF_ENUMERIC naming the quantity (the .tmp file is then removed). */
static int shape_finite(shape_ctx *c, const double *X, const double *U, long npts)
{
    const sf_model *m = c->m;
    for (long j = 0; j < 3 * npts; j++)
        if (!isfinite(X[j]) || !isfinite(U[j]))
            return sf_fail(c->err, SF_ENUMERIC, "%s: non-finite %s of shape point %ld: not written", c->path,
                           isfinite(X[j]) ? "displacement" : "position", j / 3);
    for (int i = 0; i < m->nfolds; i++)
        for (int s = 0; s < c->samples; s++)
            if (!isfinite(sf_section_kappa(&m->sec[i], c->q + m->qoff[i], (s + 0.5) / c->samples)))
                return sf_fail(c->err, SF_ENUMERIC, "%s: non-finite curvature of fold %d at sample %d: "
                               "not written", c->path, i + 1, s);
    return SF_OK;
}

static int fill_shape(void *vctx, void *vf)
{
    shape_ctx *c = vctx;
    FILE *f = vf;
    const sf_model *m = c->m;
    const sf_topology *t = m->topo;
    int ns = c->samples;
    /* count points and cells */
    long npts = 0, ncells = 0;
    for (int i = 0; i < t->nfaces; i++)
        if (t->faces[i].body.n >= 3) { npts += t->faces[i].body.n; ncells++; }
    npts += (long)m->nfolds * 2 * (ns + 1);
    ncells += (long)m->nfolds * ns;
    fprintf(f, "<?xml version=\"1.0\"?>\n");
    fprintf(f, "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\">\n");
    fprintf(f, "<PolyData>\n");
    if (c->nfields > 0) {
        fprintf(f, "<FieldData>\n");
        for (int i = 0; i < c->nfields; i++)
            fprintf(f, "<DataArray type=\"Float64\" Name=\"%s\" NumberOfTuples=\"1\" "
                       "format=\"ascii\">%.12g</DataArray>\n", c->fname[i], c->fval[i]);
        fprintf(f, "</FieldData>\n");
    }
    fprintf(f, "<Piece NumberOfPoints=\"%ld\" NumberOfVerts=\"0\" "
               "NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"%ld\">\n",
            npts, ncells);
    /* points and displacements: faces first, then bands */
    double *X = malloc(sizeof(double) * 3 * (size_t)(npts + 1));
    double *U = malloc(sizeof(double) * 3 * (size_t)(npts + 1));
    if (!X || !U) { free(X); free(U); return SF_ENOMEM; }
    long p = 0;
    for (int i = 0; i < t->nfaces; i++) {
        const sf_polygon *b = &t->faces[i].body;
        if (b->n < 3) continue;
        for (int j = 0; j < b->n; j++, p++) {
            double r[3] = {b->p[j][0], b->p[j][1], 0.0};
            sf_affine_apply(c->k.X + 12 * i, r, X + 3 * p);
            for (int e = 0; e < 3; e++) U[3 * p + e] = X[3 * p + e] - r[e];
        }
    }
    for (int i = 0; i < m->nfolds; i++) {
        const sf_fold_geom *g = &t->folds[i];
        const sf_fold_def *d = &m->study->folds[i];
        double w = m->sec[i].w;
        for (int end = 0; end < 2; end++) {
            double tpos = end == 0 ? d->setback[0] : g->l - d->setback[1];
            for (int s = 0; s <= ns; s++, p++) {
                sf_mpoint mp = {{0, 0}, g->right, i, w * s / ns, tpos};
                for (int e = 0; e < 2; e++)
                    mp.X[e] = g->a[e] + tpos * g->m[e] + (w * s / ns - 0.5 * w) * g->n[e];
                sf_point_eval(m, &c->k, &mp, X + 3 * p, NULL);
                U[3 * p] = X[3 * p] - mp.X[0];
                U[3 * p + 1] = X[3 * p + 1] - mp.X[1];
                U[3 * p + 2] = X[3 * p + 2];
            }
        }
    }
    if (shape_finite(c, X, U, npts)) {
        free(X);
        free(U);
        return SF_ENUMERIC;
    }
    fprintf(f, "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for (long j = 0; j < npts; j++) fprintf(f, "%.10g %.10g %.10g\n", X[3 * j], X[3 * j + 1], X[3 * j + 2]);
    fprintf(f, "</DataArray>\n</Points>\n");
    fprintf(f, "<PointData Vectors=\"displacement\">\n<DataArray type=\"Float64\" "
               "Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for (long j = 0; j < npts; j++)
        fprintf(f, "%.10g %.10g %.10g\n", U[3 * j], U[3 * j + 1], U[3 * j + 2]);
    fprintf(f, "</DataArray>\n</PointData>\n");
    free(X);
    free(U);
    /* cell data */
    fprintf(f, "<CellData Scalars=\"fold_angle\">\n");
    fprintf(f, "<DataArray type=\"Int32\" Name=\"part\" format=\"ascii\">\n");
    for (int i = 0; i < t->nfaces; i++)
        if (t->faces[i].body.n >= 3) fprintf(f, "0\n");
    for (long j = 0; j < (long)m->nfolds * ns; j++) fprintf(f, "1\n");
    fprintf(f, "</DataArray>\n<DataArray type=\"Int32\" Name=\"index\" format=\"ascii\">\n");
    for (int i = 0; i < t->nfaces; i++)
        if (t->faces[i].body.n >= 3) fprintf(f, "%d\n", i + 1);
    for (int i = 0; i < m->nfolds; i++)
        for (int s = 0; s < ns; s++) fprintf(f, "%d\n", i + 1);
    fprintf(f, "</DataArray>\n<DataArray type=\"Float64\" Name=\"fold_angle\" format=\"ascii\">\n");
    for (int i = 0; i < t->nfaces; i++)
        if (t->faces[i].body.n >= 3) fprintf(f, "0\n");
    for (int i = 0; i < m->nfolds; i++)
        for (int s = 0; s < ns; s++) fprintf(f, "%.10g\n", c->q[m->qoff[i]]);
    fprintf(f, "</DataArray>\n<DataArray type=\"Float64\" Name=\"curvature\" format=\"ascii\">\n");
    for (int i = 0; i < t->nfaces; i++)
        if (t->faces[i].body.n >= 3) fprintf(f, "0\n");
    for (int i = 0; i < m->nfolds; i++)
        for (int s = 0; s < ns; s++)
            fprintf(f, "%.10g\n", sf_section_kappa(&m->sec[i], c->q + m->qoff[i], (s + 0.5) / ns));
    fprintf(f, "</DataArray>\n</CellData>\n");
    /* polygons */
    fprintf(f, "<Polys>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    p = 0;
    for (int i = 0; i < t->nfaces; i++) {
        int n = t->faces[i].body.n;
        if (n < 3) continue;
        for (int j = 0; j < n; j++) fprintf(f, "%ld ", p + j);
        fprintf(f, "\n");
        p += n;
    }
    for (int i = 0; i < m->nfolds; i++) {
        long base0 = p, base1 = p + ns + 1;
        for (int s = 0; s < ns; s++)
            fprintf(f, "%ld %ld %ld %ld\n", base0 + s, base1 + s, base1 + s + 1, base0 + s + 1);
        p += 2 * (ns + 1);
    }
    fprintf(f, "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    long off = 0;
    for (int i = 0; i < t->nfaces; i++)
        if (t->faces[i].body.n >= 3) {
            off += t->faces[i].body.n;
            fprintf(f, "%ld\n", off);
        }
    for (long j = 0; j < (long)m->nfolds * ns; j++) {
        off += 4;
        fprintf(f, "%ld\n", off);
    }
    fprintf(f, "</DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n");
    return ferror(f) ? SF_EIO : SF_OK;
}

int sf_vtk_write_shape(const sf_model *m, const double *q, int samples,
                       const char *path, sf_error *err)
{
    return sf_vtk_write_shape_fields(m, q, samples, path, 0, NULL, NULL, err);
}

int sf_vtk_write_shape_fields(const sf_model *m, const double *q, int samples,
                              const char *path, int nfields, const char *const *names,
                              const double *values, sf_error *err)
{
    shape_ctx c = {m, q, samples < 1 ? 1 : samples, {0}, nfields, names, values, path, err};
    for (int i = 0; i < nfields; i++)
        if (!isfinite(values[i]))
            return sf_fail(err, SF_ENUMERIC, "%s: field %s is not finite", path, names[i]);
    /* ParaView chooses its reader by the extension: write only what the
     * name says */
    const char *dot = strrchr(path, '.'), *sl = strrchr(path, '/');
    if (!dot || (sl && dot < sl) || strcmp(dot, ".vtp") != 0)
        return sf_fail(err, SF_EINPUT, "%s: unsupported extension '%s' (smoothfold writes VTK XML "
                       "PolyData; supported: .vtp)", path, dot && !(sl && dot < sl) ? dot : "");
    for (int j = 0; j < m->nq; j++)
        if (!isfinite(q[j]))
            return sf_fail(err, SF_ENUMERIC, "%s: state has a non-finite coordinate %d", path, j + 1);
    if (sf_kin_alloc(m, &c.k)) return sf_fail(err, SF_ENOMEM, "out of memory");
    sf_kin_eval(m, q, 0, &c.k);
    int rc = sf_write_atomic(path, fill_shape, &c, err);
    sf_kin_free(&c.k);
    return rc;
}

void sf_pvd_init(sf_pvd *p, const char *path)
{
    memset(p, 0, sizeof *p);
    snprintf(p->path, sizeof p->path, "%s", path);
}

int sf_pvd_add(sf_pvd *p, double time, const char *file, sf_error *err)
{
    if (!isfinite(time))
        return sf_fail(err, SF_ENUMERIC, "%s: non-finite time (%g) of %s: not written", p->path, time, file);
    if (p->n == p->cap) {
        int cap = p->cap ? 2 * p->cap : 16;
        double *t = realloc(p->time, sizeof(double) * cap);
        if (!t) return sf_fail(err, SF_ENOMEM, "out of memory");
        p->time = t;
        char **fl = realloc(p->file, sizeof(char *) * cap);
        if (!fl) return sf_fail(err, SF_ENOMEM, "out of memory");
        p->file = fl;
        p->cap = cap;
    }
    p->file[p->n] = strdup(file);
    if (!p->file[p->n]) return sf_fail(err, SF_ENOMEM, "out of memory");
    p->time[p->n++] = time;
    return SF_OK;
}

static int fill_pvd(void *ctx, void *vf)
{
    const sf_pvd *p = ctx;
    FILE *f = vf;
    fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n");
    for (int i = 0; i < p->n; i++)
        fprintf(f, "<DataSet timestep=\"%.10g\" part=\"0\" file=\"%s\"/>\n", p->time[i], p->file[i]);
    fprintf(f, "</Collection>\n</VTKFile>\n");
    return ferror(f) ? SF_EIO : SF_OK;
}

int sf_pvd_write(const sf_pvd *p, sf_error *err)
{
    return sf_write_atomic(p->path, fill_pvd, (void *)p, err);
}

void sf_pvd_free(sf_pvd *p)
{
    for (int i = 0; i < p->n; i++) free(p->file[i]);
    free(p->file);
    free(p->time);
    memset(p, 0, sizeof *p);
}
