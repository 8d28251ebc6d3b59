/* energy.c - potential energy terms and their derivatives. */
#include "energy.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int sf_energy_init(sf_energy *e, const sf_model *m, sf_error *err)
{
    memset(e, 0, sizeof *e);
    const sf_study *s = m->study;
    e->m = m;
    e->nstages = s->nstages > 0 ? s->nstages : 1;
    e->stiff = calloc((size_t)m->nfolds + 1, sizeof(double));
    e->loadpt = calloc((size_t)s->nloads + 1, sizeof(sf_mpoint));
    if (!e->stiff || !e->loadpt) {
        sf_energy_free(e);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    for (int i = 0; i < m->nfolds; i++) {
        const sf_fold_def *f = &s->folds[i];
        const sf_material *mat = &s->materials[f->material];
        double D = mat->E * pow(mat->thickness, 3) / (12.0 * (1.0 - mat->nu * mat->nu));
        e->stiff[i] = D * m->topo->folds[i].L / f->width;
    }
    for (int l = 0; l < s->nloads; l++)
        if (sf_model_locate(m, s->loads[l].at, &e->loadpt[l], err)) {
            sf_error_prefix(err, "%s:%d: load %d", s->path, s->loads[l].line, l + 1);
            sf_energy_free(e);
            return err->code;
        }
    if (s->gravity_on) {
        e->gravity = 1;
        if (s->face_material < 0) {
            sf_energy_free(e);
            return sf_fail(err, SF_EINPUT, "%s: gravity needs a face material (faces.material)",
                           s->path);
        }
        const sf_material *fm = &s->materials[s->face_material];
        e->face_mass = calloc((size_t)m->nfaces + 1, sizeof(double));
        e->face_pt = calloc((size_t)m->nfaces + 1, sizeof(sf_mpoint));
        e->fold_mass = calloc((size_t)m->nfolds + 1, sizeof(double));
        e->fold_ref = calloc(3 * ((size_t)m->nfolds + 1), sizeof(double));
        if (!e->face_mass || !e->face_pt || !e->fold_mass || !e->fold_ref) {
            sf_energy_free(e);
            return sf_fail(err, SF_ENOMEM, "out of memory");
        }
        for (int f = 0; f < m->nfaces; f++) {
            const sf_face *F = &m->topo->faces[f];
            e->face_mass[f] = fm->density * fm->thickness * F->area;
            e->face_pt[f].X[0] = F->centroid[0];
            e->face_pt[f].X[1] = F->centroid[1];
            e->face_pt[f].face = f;
            e->face_pt[f].fold = -1;
        }
        sf_kin k;
        if (sf_kin_alloc(m, &k)) {
            sf_energy_free(e);
            return sf_fail(err, SF_ENOMEM, "out of memory");
        }
        double *q0 = calloc((size_t)m->nq + 1, sizeof(double));
        if (!q0) {
            sf_kin_free(&k);
            sf_energy_free(e);
            return sf_fail(err, SF_ENOMEM, "out of memory");
        }
        sf_kin_eval(m, q0, 0, &k);
        for (int i = 0; i < m->nfolds; i++) {
            const sf_fold_def *fd = &s->folds[i];
            const sf_material *mat = &s->materials[fd->material];
            e->fold_mass[i] = mat->density * mat->thickness * fd->width * m->topo->folds[i].L;
            sf_fold_centroid(m, &k, i, e->fold_ref + 3 * i, NULL, NULL, NULL, 0);
        }
        free(q0);
        sf_kin_free(&k);
    }
    if (s->constraints == SF_CONSTRAINTS_PENALTY) {
        e->penalty = 1;
        e->lR = s->penalty_rotation;
        e->ld = s->penalty_translation;
    }
    return SF_OK;
}

void sf_energy_free(sf_energy *e)
{
    free(e->stiff);
    free(e->loadpt);
    free(e->face_mass);
    free(e->face_pt);
    free(e->fold_mass);
    free(e->fold_ref);
    memset(e, 0, sizeof *e);
}

int sf_params_alloc(const sf_energy *e, sf_params *p)
{
    memset(p, 0, sizeof *p);
    size_t ns = (size_t)e->nstages + 1, nf = (size_t)e->m->nfolds + 1;
    p->stage = calloc(ns, sizeof(double));
    p->dstage = calloc(ns, sizeof(double));
    p->rest = calloc(nf, sizeof(double));
    p->drest = calloc(nf, sizeof(double));
    if (!p->stage || !p->dstage || !p->rest || !p->drest) {
        sf_params_free(p);
        return SF_ENOMEM;
    }
    return SF_OK;
}

void sf_params_free(sf_params *p)
{
    free(p->stage);
    free(p->dstage);
    free(p->rest);
    free(p->drest);
    memset(p, 0, sizeof *p);
}

double sf_energy_bending(const sf_energy *e, const double *q, const sf_params *p)
{
    const sf_model *m = e->m;
    double U = 0.0;
    for (int i = 0; i < m->nfolds; i++) {
        int nq = m->qn[i], off = m->qoff[i];
        const double *G = m->sec[i].gram;
        double d[65];
        for (int j = 0; j < nq; j++) d[j] = q[off + j];
        d[0] -= p->rest[i];
        double s = 0.0;
        for (int a = 0; a < nq; a++)
            for (int b = 0; b < nq; b++) s += d[a] * G[a * nq + b] * d[b];
        U += 0.5 * e->stiff[i] * s;
    }
    return U;
}

/* A dead load f at a material point: adds -f.u to Pi. */
static double dead_load(const sf_model *m, const sf_kin *k, const sf_mpoint *pt,
                        const double f[3], const double df[3], double *grad, double *H,
                        int ld, double *gp)
{
    int nq = m->nq;
    double x[3];
    double *dx = (grad || gp) ? malloc(sizeof(double) * 3 * (size_t)nq) : NULL;
    sf_point_eval(m, k, pt, x, dx);
    double u[3] = {x[0] - pt->X[0], x[1] - pt->X[1], x[2]};
    if (dx) {
        for (int j = 0; j < nq; j++) {
            double a = f[0] * dx[j] + f[1] * dx[nq + j] + f[2] * dx[2 * nq + j];
            if (grad) grad[j] -= a;
            if (gp) gp[j] -= df[0] * dx[j] + df[1] * dx[nq + j] + df[2] * dx[2 * nq + j];
        }
        free(dx);
    }
    if (H) {
        double mf[3] = {-f[0], -f[1], -f[2]};
        sf_point_hess_add(m, k, pt, mf, H, ld);
    }
    return -(f[0] * u[0] + f[1] * u[1] + f[2] * u[2]);
}

double sf_energy_eval(const sf_energy *e, const sf_kin *k, const sf_params *p,
                      double *grad, double *H, int ld, double *gp)
{
    const sf_model *m = e->m;
    const sf_study *s = m->study;
    const double *q = k->q;
    double Pi = sf_energy_bending(e, q, p);
    /* bending: (D L / w) G (q - q0), q0 = (theta0, 0, ...) */
    for (int i = 0; i < m->nfolds; i++) {
        int nq = m->qn[i], off = m->qoff[i];
        const double *G = m->sec[i].gram;
        double c = e->stiff[i];
        for (int a = 0; a < nq; a++) {
            double v = 0.0;
            for (int b = 0; b < nq; b++) v += G[a * nq + b] * (q[off + b] - (b == 0 ? p->rest[i] : 0.0));
            if (grad) grad[off + a] += c * v;
            if (gp) gp[off + a] -= c * G[a * nq] * p->drest[i];
            if (H)
                for (int b = 0; b < nq; b++) H[(size_t)(off + a) * ld + off + b] += c * G[a * nq + b];
        }
    }
    /* point loads */
    for (int l = 0; l < s->nloads; l++) {
        int st = s->loads[l].stage - 1;
        if (st < 0 || st >= e->nstages) continue;
        double fac = p->stage[st], dfac = p->dstage[st];
        if (fac == 0.0 && dfac == 0.0) continue;
        double f[3], df[3];
        for (int c = 0; c < 3; c++) {
            f[c] = fac * s->loads[l].force[c];
            df[c] = dfac * s->loads[l].force[c];
        }
        Pi += dead_load(m, k, &e->loadpt[l], f, df, grad, H, ld, gp);
    }
    /* gravity */
    if (e->gravity) {
        int st = s->gravity_stage - 1;
        double fac = (st >= 0 && st < e->nstages) ? p->stage[st] : 0.0;
        double dfac = (st >= 0 && st < e->nstages) ? p->dstage[st] : 0.0;
        if (fac != 0.0 || dfac != 0.0) {
            for (int f = 0; f < m->nfaces; f++) {
                double F[3], dF[3];
                for (int c = 0; c < 3; c++) {
                    F[c] = fac * e->face_mass[f] * s->gravity[c];
                    dF[c] = dfac * e->face_mass[f] * s->gravity[c];
                }
                Pi += dead_load(m, k, &e->face_pt[f], F, dF, grad, H, ld, gp);
            }
            int nq = m->nq;
            double *dx = (grad || gp) ? malloc(sizeof(double) * 3 * (size_t)nq) : NULL;
            for (int i = 0; i < m->nfolds; i++) {
                double F[3], dF[3], x[3];
                for (int c = 0; c < 3; c++) {
                    F[c] = fac * e->fold_mass[i] * s->gravity[c];
                    dF[c] = dfac * e->fold_mass[i] * s->gravity[c];
                }
                double mF[3] = {-F[0], -F[1], -F[2]};
                sf_fold_centroid(m, k, i, x, dx, H ? mF : NULL, H, ld);
                for (int c = 0; c < 3; c++) Pi -= F[c] * (x[c] - e->fold_ref[3 * i + c]);
                if (dx)
                    for (int j = 0; j < nq; j++) {
                        double a = 0, b = 0;
                        for (int c = 0; c < 3; c++) {
                            a += F[c] * dx[c * nq + j];
                            b += dF[c] * dx[c * nq + j];
                        }
                        if (grad) grad[j] -= a;
                        if (gp) gp[j] -= b;
                    }
            }
            free(dx);
        }
    }
    if (e->penalty) Pi += sf_penalty(m, k, e->lR, e->ld, grad, H, ld);
    return Pi;
}
