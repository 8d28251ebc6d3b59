/* dynamics_dae.c - the equations of motion of a trajectory (dynamics.h,
 * docs/guides/dynamics.md): lumped masses from the faces, inertia forces and
 * their Jacobian, kinetic energy, the constraint rows, and the DAE
 * residual and Jacobian IDA solves (sf_dyn_residual, sf_dyn_jacobian). */
#include "dynamics_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* --------------------------------------------------------------- masses */

static int add_mass(sf_dyn *d, int *cap, const sf_mpoint *pt, double mass)
{
    if (d->nmass == *cap) {
        int nc = *cap ? 2 * *cap : 64;
        sf_mpoint *np = realloc(d->mpt, sizeof(sf_mpoint) * (size_t)nc);
        if (!np) return SF_ENOMEM;
        d->mpt = np;
        double *nw = realloc(d->mw, sizeof(double) * (size_t)nc);
        if (!nw) return SF_ENOMEM;
        d->mw = nw;
        *cap = nc;
    }
    d->mpt[d->nmass] = *pt;
    d->mw[d->nmass] = mass;
    d->nmass++;
    return SF_OK;
}

/* Quadrature points carrying the mass of the moving faces and of the
 * fold bands (see dynamics.h). */
int dy_build_masses(sf_dyn *d, sf_error *err)
{
    const sf_model *m = d->m;
    const sf_study *s = m->study;
    const sf_topology *t = m->topo;
    int cap = 0;
    if (s->face_material >= 0) {
        const sf_material *fm = &s->materials[s->face_material];
        double rh = fm->density * fm->thickness;
        for (int f = 0; f < t->nfaces; f++) {
            if (f == t->root) continue;     /* it does not move */
            const sf_face *F = &t->faces[f];
            const sf_polygon *P = &F->body;
            const double *c = F->centroid;
            for (int i = 0; i < P->n; i++) {
                const double *a = P->p[i], *b = P->p[(i + 1) % P->n];
                double area = 0.5 * ((a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]));
                double mid[3][2] = {{0.5 * (c[0] + a[0]), 0.5 * (c[1] + a[1])},
                                    {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])},
                                    {0.5 * (b[0] + c[0]), 0.5 * (b[1] + c[1])}};
                for (int k = 0; k < 3; k++) {
                    sf_mpoint pt;
                    memset(&pt, 0, sizeof pt);
                    pt.X[0] = mid[k][0];
                    pt.X[1] = mid[k][1];
                    pt.face = f;
                    pt.fold = -1;
                    if (add_mass(d, &cap, &pt, rh * area / 3.0))
                        return sf_fail(err, SF_ENOMEM, "out of memory");
                }
            }
        }
    }
    /* fold bands: 4 Gauss points across, 2 along */
    static const double xs[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281,
                                 0.9305681557970263};
    static const double ws[4] = {0.1739274225687269, 0.3260725774312731, 0.3260725774312731,
                                 0.1739274225687269};
    static const double xt[2] = {0.2113248654051871, 0.7886751345948129};
    for (int i = 0; i < m->nfolds; i++) {
        const sf_fold_def *fd = &s->folds[i];
        const sf_fold_geom *g = &t->folds[i];
        const sf_material *mat = &s->materials[fd->material];
        double w = fd->width, L = g->L;
        double mass = mat->density * mat->thickness * w * L;
        for (int a = 0; a < 4; a++)
            for (int b = 0; b < 2; b++) {
                sf_mpoint pt;
                memset(&pt, 0, sizeof pt);
                pt.fold = i;
                pt.face = g->right;
                pt.s = w * xs[a];
                pt.tpos = fd->setback[0] + L * xt[b];
                for (int c = 0; c < 2; c++)
                    pt.X[c] = g->a[c] + pt.tpos * g->m[c] + (pt.s - 0.5 * w) * g->n[c];
                if (add_mass(d, &cap, &pt, mass * ws[a] * 0.5))
                    return sf_fail(err, SF_ENOMEM, "out of memory");
            }
    }
    return SF_OK;
}

/* Inertia terms at (q, v, a = v') with the kinematics of d->eq.k evaluated
 * at order 2: f += M a + h(q, v); when M is not NULL also M (nq x nq), Kq
 * (d f / d q without the third-derivative part of h) and Dv (d f / d v),
 * row-major, added.  Uses d->Hc (3 nq x nq) and d->work (3 nq + ...). */
static void inertia_eval(sf_dyn *d, const double *v, const double *a, double *f, double *M,
                         double *Kq, double *Dv)
{
    const sf_model *m = d->m;
    int nq = d->nq;
    size_t nn = (size_t)nq * nq;
    double *dx = d->work;                /* 3 nq */
    double *Hv = d->work + 3 * nq;       /* 3 nq: Hc v */
    double *Ha = d->work + 6 * nq;       /* 3 nq: Hc a */
    for (int p = 0; p < d->nmass; p++) {
        double x[3], w = d->mw[p];
        sf_point_eval(m, &d->eq.k, &d->mpt[p], x, dx);
        memset(d->Hc, 0, sizeof(double) * 3 * nn);
        for (int c = 0; c < 3; c++) {
            double e[3] = {0, 0, 0};
            e[c] = 1.0;
            sf_point_hess_add(m, &d->eq.k, &d->mpt[p], e, d->Hc + c * nn, nq);
        }
        double acc[3];
        for (int c = 0; c < 3; c++) {
            const double *H = d->Hc + c * nn;
            double s = 0.0, vHv = 0.0;
            for (int j = 0; j < nq; j++) s += dx[c * nq + j] * a[j];
            for (int j = 0; j < nq; j++) {
                double hv = 0.0, ha = 0.0;
                for (int l = 0; l < nq; l++) {
                    hv += H[(size_t)j * nq + l] * v[l];
                    ha += H[(size_t)j * nq + l] * a[l];
                }
                Hv[c * nq + j] = hv;
                Ha[c * nq + j] = ha;
                vHv += v[j] * hv;
            }
            acc[c] = s + vHv;
        }
        for (int j = 0; j < nq; j++)
            f[j] += w * (dx[j] * acc[0] + dx[nq + j] * acc[1] + dx[2 * nq + j] * acc[2]);
        if (!M) continue;
        for (int j = 0; j < nq; j++)
            for (int l = 0; l < nq; l++) {
                double mm = 0.0, kq = 0.0, dv = 0.0;
                for (int c = 0; c < 3; c++) {
                    double dj = dx[c * nq + j];
                    mm += dj * dx[c * nq + l];
                    kq += acc[c] * d->Hc[c * nn + (size_t)j * nq + l] + dj * Ha[c * nq + l];
                    dv += 2.0 * dj * Hv[c * nq + l];
                }
                M[(size_t)j * nq + l] += w * mm;
                Kq[(size_t)j * nq + l] += w * kq;
                Dv[(size_t)j * nq + l] += w * dv;
            }
    }
}

/* Kinetic energy (1/2) v^T M v at the kinematic state of d->eq.k (order >= 1). */
double dy_kinetic_energy(sf_dyn *d, const double *v)
{
    int nq = d->nq;
    double T = 0.0, x[3];
    for (int p = 0; p < d->nmass; p++) {
        sf_point_eval(d->m, &d->eq.k, &d->mpt[p], x, d->work);
        for (int c = 0; c < 3; c++) {
            double u = 0.0;
            for (int j = 0; j < nq; j++) u += d->work[c * nq + j] * v[j];
            T += 0.5 * d->mw[p] * u * u;
        }
    }
    return T;
}

/* Constraint Jacobian (every row, unscaled) into d->Jc after
 * sf_equil_residual has evaluated the kinematics at order >= 1. */
static void constraint_jacobian(sf_dyn *d)
{
    sf_equil *eq = &d->eq;
    int nq = d->nq;
    if (eq->nloop) memcpy(d->Jc, eq->J, sizeof(double) * (size_t)eq->nloop * nq);
    for (int r = 0; r < eq->nsup; r++) {
        double x[3];
        sf_point_eval(d->m, &eq->k, &eq->rowpt[r], x, d->work);
        memcpy(d->Jc + (size_t)(eq->nloop + r) * nq, d->work + eq->rowc[r] * nq,
               sizeof(double) * nq);
    }
}

/* d g_r / dt: only a prescribed displacement moves with time. */
static double row_rate(const sf_dyn *d, int r)
{
    const sf_equil *eq = &d->eq;
    if (eq->disp_row >= 0 && r == eq->nloop + eq->disp_row) return -d->pslope;
    return 0.0;
}

int sf_dyn_residual(sf_dyn *d, double t, const double *y, const double *yd, double *R)
{
    int nq = d->nq, nc = d->ncon, ne = d->eq.n;
    sf_dyn_set_time(d, t);
    for (int i = 0; i < d->n; i++)
        if (!isfinite(y[i]) || !isfinite(yd[i])) return 1;
    if (sf_equil_residual(y, d->p, d->F, &d->eq)) return 1;
    const double *v = d->inertia ? y + d->ov : yd;
    for (int j = 0; j < nq; j++) {
        double cv = 0.0;
        const double *Cj = d->C + (size_t)j * nq;
        for (int l = 0; l < nq; l++) cv += Cj[l] * v[l];
        R[j] = d->F[j] + cv;
    }
    int needJ = d->ic_mode || d->inertia;
    if (needJ) constraint_jacobian(d);
    for (int r = 0; r < nc; r++) {
        if (!d->ic_mode) {
            R[nq + r] = d->F[nq + r];
        } else {
            /* index-1 form: d g / dt = J q' + g_t */
            const double *Jr = d->Jc + (size_t)r * nq;
            double s = row_rate(d, r);
            for (int j = 0; j < nq; j++) s += Jr[j] * yd[j];
            R[nq + r] = s;
        }
    }
    if (d->inertia) {
        sf_kin_eval(d->m, y, 2, &d->eq.k);
        inertia_eval(d, v, yd + d->ov, R, NULL, NULL, NULL);
        const double *mu = y + d->om;
        const double *fs = d->eq.fscale + nq;
        for (int j = 0; j < nq; j++) {
            double s = 0.0;
            for (int r = 0; r < nc; r++) s += d->Jc[(size_t)r * nq + j] * fs[r] * mu[r];
            R[d->ov + j] = yd[j] - v[j] - s;
        }
        const double *w = d->ic_mode ? yd + d->ov : v;
        for (int r = 0; r < nc; r++) {
            const double *Jr = d->Jc + (size_t)r * nq;
            double s = 0.0;
            for (int j = 0; j < nq; j++) s += Jr[j] * w[j];
            R[d->om + r] = fs[r] * s;
        }
    }
    for (int i = 0; i < ne; i++) R[i] *= d->eq.fscale[i];
    for (int i = 0; i < d->n; i++)
        if (!isfinite(R[i])) return 1;
    return 0;
}

#define AEL(A, i, j) SM_ELEMENT_D(A, i, j)

int sf_dyn_jacobian(sf_dyn *d, double t, double cj, const double *y, const double *yd,
                    SUNMatrix A)
{
    int nq = d->nq, nc = d->ncon, ne = d->eq.n;
    if (d->ida) d->ida->ss = 20.0;    /* new Jacobian: no rate estimate yet */
    sf_dyn_set_time(d, t);
    SUNMatrix Aeq = d->inertia ? d->ida->Aeq : A;
    SUNMatZero(Aeq);
    if (sf_equil_jacobian(y, d->p, Aeq, d->Fp, &d->eq)) return 1;
    if (!d->inertia) {
        for (int j = 0; j < nq; j++)
            for (int l = 0; l < nq; l++) AEL(A, j, l) += cj * d->C[(size_t)j * nq + l];
        if (d->ic_mode)
            for (int r = 0; r < nc; r++)
                for (int j = 0; j < nq; j++) AEL(A, nq + r, j) *= cj;
    } else {
        SUNMatZero(A);
        size_t nn = (size_t)nq * nq;
        double *M = d->Hc + 3 * nn, *Kq = M + nn, *Dv = Kq + nn, *Hmu = Dv + nn;
        memset(M, 0, sizeof(double) * 4 * nn);
        /* first-order kinematics for the constraint rows, then order 2 */
        if (sf_equil_residual(y, d->p, d->F, &d->eq)) return 1;
        constraint_jacobian(d);
        sf_kin_eval(d->m, y, 2, &d->eq.k);
        double *f = d->F;   /* scratch for the inertial force */
        memset(f, 0, sizeof(double) * nq);
        const double *v = y + d->ov, *a = yd + d->ov, *mu = y + d->om;
        inertia_eval(d, v, a, f, M, Kq, Dv);
        /* sum_r (fs_r mu_r) d2 g_r */
        const sf_equil *eq = &d->eq;
        const double *fs = eq->fscale + nq;
        double *wl = d->work + 9 * nq;    /* nc weights */
        for (int r = 0; r < nc; r++) wl[r] = fs[r] * mu[r];
        if (eq->nloop) sf_constraints(d->m, &d->eq.k, d->Fp, NULL, wl, Hmu, nq);
        for (int r = 0; r < eq->nsup; r++) {
            double fr[3] = {0, 0, 0};
            fr[eq->rowc[r]] = wl[eq->nloop + r];
            sf_point_hess_add(d->m, &d->eq.k, &eq->rowpt[r], fr, Hmu, nq);
        }
        for (int j = 0; j < nq; j++) {
            for (int l = 0; l < nq; l++) {
                size_t jl = (size_t)j * nq + l;
                AEL(A, j, l) = AEL(Aeq, j, l) + Kq[jl];
                AEL(A, j, d->ov + l) = d->C[jl] + Dv[jl] + cj * M[jl];
                AEL(A, d->ov + j, l) = -Hmu[jl];
            }
            AEL(A, d->ov + j, j) += cj;
            AEL(A, d->ov + j, d->ov + j) = -1.0;
            for (int r = 0; r < nc; r++) {
                double Jrj = d->Jc[(size_t)r * nq + j];
                AEL(A, j, nq + r) = AEL(Aeq, j, nq + r);                    /* J^T */
                AEL(A, nq + r, j) = (d->ic_mode ? cj : 1.0) * AEL(Aeq, nq + r, j);
                AEL(A, d->ov + j, d->om + r) = -fs[r] * Jrj;
                AEL(A, d->om + r, d->ov + j) = (d->ic_mode ? cj : 1.0) * fs[r] * Jrj;
            }
        }
        for (int r = 0; r < nc; r++) {
            AEL(A, nq + r, nq + r) = AEL(Aeq, nq + r, nq + r);
            AEL(A, d->om + r, d->om + r) = -REG_EPS;
        }
    }
    for (int i = 0; i < ne; i++) {
        double s = d->eq.fscale[i];
        for (int j = 0; j < d->n; j++) AEL(A, i, j) *= s;
    }
    for (int i = 0; i < d->n; i++)
        for (int j = 0; j < d->n; j++)
            if (!isfinite(AEL(A, i, j))) return 1;
    return 0;
}
