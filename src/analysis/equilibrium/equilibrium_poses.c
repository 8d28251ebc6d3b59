/* equilibrium_poses.c - the equilibrium problem in face poses (see
 * equilibrium_poses.h): residual, CSC Jacobian with a pattern recorded
 * once, and the hooks equilibrium.c calls. */
#include "equilibrium_poses.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <sunmatrix/sunmatrix_sparse.h>

#include "cont.h"
#include "flatstart.h"
#include "poses.h"
#include "poses_rowsel.h"
#include "shape.h"
#include "study.h"

/* the generic state of the row selection and the QR's rank tolerance
 * (relative to the longest scaled row; docs/design/model.md) */
#define ROWSEL_SEED 20261123u
#define ROWSEL_RTOL 1e-9
#define ROWSEL_AMP 0.1

struct sf_peq {
    sf_poses P;
    sf_triplets T;
    int nx;
    /* the fold rows kept (poses_rowsel.h): kidx[6 N] = index among the
     * kept rows (multiplier nx + kidx) or -1 for a dropped row; frow[nloop]
     * = the fold row of each kept one */
    int *kidx, *frow, ndrop;
    int grank;            /* rank of the fold rows at the generic state (-1: not computed) */
    double *work, *dg, *Hl, *dx;
    int *col;
    /* the KKT blocks for sstab.h (sf_peq_kkt_csc): HL's lower triangle and
     * C, as CSC with int indices, and where each entry sits in T.val */
    int *hp, *hi, *cpc, *ci;
    long *hsrc, *csrc;
    double *hv, *cv;
};

/* ------------------------------------------------------------ assembly */

/* The local Hessian block z->Hl (nv x nv, over the columns z->col) into
 * the triplets. */
static void add_block(struct sf_peq *z, int nv)
{
    for (int a = 0; a < nv; a++)
        for (int b = 0; b < nv; b++) sf_trip_add(&z->T, z->col[a], z->col[b], z->Hl[a * nv + b]);
}

/* Constraint row `row` with gradient d over the columns z->col and
 * multiplier lam: lam d into F (J^T lambda), and with jac the row and its
 * transpose into the triplets. */
static void add_row(struct sf_peq *z, int row, int nv, const double *d, double lam, double *F, int jac)
{
    for (int j = 0; j < nv; j++) {
        int cj = z->col[j];
        if (cj < 0) continue;
        if (F) F[cj] += lam * d[j];
        if (jac) {
            sf_trip_add(&z->T, row, cj, d[j]);
            sf_trip_add(&z->T, cj, row, d[j]);
        }
    }
}

/* One energy term -f . (x - ref) of a point attached to face (and to the
 * band of fold when fold >= 0); gradient into F, df-gradient into Fp,
 * Hessian into the triplets when jac. */
static double point_term(sf_equil *q, const double *y, int face, int fold, int kind,
                         const double X[2], double tpos, double s, const double ref[3],
                         const double f[3], const double df[3], double *F, int jac, double *Fp)
{
    struct sf_peq *z = q->pz;
    int nv = sf_poses_point_vars(&z->P, face, fold, z->col);
    double x[3], mf[3] = {-f[0], -f[1], -f[2]};
    sf_poses_point(&z->P, y, face, fold, kind, X, tpos, s, x, z->dx, jac ? mf : NULL,
                   jac ? z->Hl : NULL, z->work);
    for (int j = 0; j < nv; j++) {
        int c = z->col[j];
        if (c < 0) continue;
        const double *d = z->dx;
        if (F) F[c] -= f[0] * d[j] + f[1] * d[nv + j] + f[2] * d[2 * nv + j];
        if (Fp) Fp[c] -= df[0] * d[j] + df[1] * d[nv + j] + df[2] * d[2 * nv + j];
    }
    if (jac) add_block(z, nv);
    return -(f[0] * (x[0] - ref[0]) + f[1] * (x[1] - ref[1]) + f[2] * (x[2] - ref[2]));
}

/* Residual F (n values, when not NULL); with jac, the Jacobian values into
 * the triplets (or their pattern while recording) and dF/dp into Fp.
 * Returns Pi.  The sequence of sf_trip_add calls depends on the study
 * only, never on values. */
static double assemble(sf_equil *q, const double *y, double p, double *F, int jac, double *Fp)
{
    struct sf_peq *z = q->pz;
    const sf_model *m = q->m;
    const sf_study *s = m->study;
    const sf_energy *e = &q->e;
    int nx = z->nx, n = q->n;
    const double *lam = y + nx;
    sf_equil_set_param(q, p);
    if (F) memset(F, 0, sizeof(double) * (size_t)n);
    if (Fp) memset(Fp, 0, sizeof(double) * (size_t)n);
    if (jac) sf_trip_zero(&z->T);
    double Pi = sf_energy_bending(e, y, &q->par);
    /* bending: (D L / w) G (q - q0) on each fold's own coordinates */
    for (int i = 0; i < m->nfolds; i++) {
        int qn = m->qn[i], off = m->qoff[i];
        const double *G = m->sec[i].gram;
        double c = e->stiff[i];
        for (int a = 0; a < qn; a++) {
            double v = 0.0;
            for (int b = 0; b < qn; b++) v += G[a * qn + b] * (y[off + b] - (b == 0 ? q->par.rest[i] : 0.0));
            if (F) F[off + a] += c * v;
            if (Fp) Fp[off + a] -= c * G[a * qn] * q->par.drest[i];
            if (jac)
                for (int b = 0; b < qn; b++) sf_trip_add(&z->T, off + a, off + b, c * G[a * qn + b]);
        }
    }
    /* point loads */
    for (int l = 0; l < s->nloads; l++) {
        int st = s->loads[l].stage - 1;
        if (st < 0 || st >= e->nstages) continue;
        double f[3], df[3];
        for (int c = 0; c < 3; c++) {
            f[c] = q->par.stage[st] * s->loads[l].force[c];
            df[c] = q->par.dstage[st] * s->loads[l].force[c];
        }
        const sf_mpoint *pt = &e->loadpt[l];
        double ref[3] = {pt->X[0], pt->X[1], 0.0};
        Pi += point_term(q, y, pt->face, pt->fold, SF_SEC_CHORD, pt->X, pt->tpos, pt->s, ref, f, df,
                         F, jac, Fp);
    }
    /* gravity: faces at their centroids, bands at theirs */
    if (e->gravity) {
        int st = s->gravity_stage - 1;
        double fac = (st >= 0 && st < e->nstages) ? q->par.stage[st] : 0.0;
        double dfac = (st >= 0 && st < e->nstages) ? q->par.dstage[st] : 0.0;
        for (int f = 0; f < m->nfaces; f++) {
            double F3[3], dF3[3];
            for (int c = 0; c < 3; c++) {
                F3[c] = fac * e->face_mass[f] * s->gravity[c];
                dF3[c] = dfac * e->face_mass[f] * s->gravity[c];
            }
            const sf_mpoint *pt = &e->face_pt[f];
            double ref[3] = {pt->X[0], pt->X[1], 0.0};
            Pi += point_term(q, y, f, -1, SF_SEC_CHORD, pt->X, 0.0, 0.0, ref, F3, dF3, F, jac, Fp);
        }
        for (int i = 0; i < m->nfolds; i++) {
            double F3[3], dF3[3];
            for (int c = 0; c < 3; c++) {
                F3[c] = fac * e->fold_mass[i] * s->gravity[c];
                dF3[c] = dfac * e->fold_mass[i] * s->gravity[c];
            }
            const sf_fold_geom *g = &m->topo->folds[i];
            const sf_fold_def *d = &s->folds[i];
            double tmid = 0.5 * (d->setback[0] + g->l - d->setback[1]);
            Pi += point_term(q, y, g->right, i, SF_SEC_CENTROID, NULL, tmid, 0.0,
                             e->fold_ref + 3 * i, F3, dF3, F, jac, Fp);
        }
    }
    /* fold rows: the kept ones of the 6 per fold */
    for (int i = 0; i < m->nfolds; i++) {
        int nv = sf_poses_fold_vars(&z->P, i, z->col);
        double g[6], li[6];
        for (int c = 0; c < 6; c++) li[c] = z->kidx[6 * i + c] >= 0 ? lam[z->kidx[6 * i + c]] : 0.0;
        sf_poses_fold_rows(&z->P, y, i, g, z->dg, jac ? li : NULL, jac ? z->Hl : NULL, z->work);
        for (int c = 0; c < 6; c++) {
            if (z->kidx[6 * i + c] < 0) continue;
            int row = nx + z->kidx[6 * i + c];
            if (F) F[row] = g[c];
            add_row(z, row, nv, z->dg + c * nv, li[c], F, jac);
        }
        if (jac) add_block(z, nv);
    }
    /* support and prescribed-displacement rows */
    for (int r = 0; r < q->nsup; r++) {
        const sf_mpoint *pt = &q->rowpt[r];
        int row = nx + q->nloop + r, c = q->rowc[r];
        int nv = sf_poses_point_vars(&z->P, pt->face, pt->fold, z->col);
        double x[3], w[3] = {0, 0, 0};
        w[c] = lam[q->nloop + r];
        sf_poses_mpoint(&z->P, y, pt, x, z->dx, jac ? w : NULL, jac ? z->Hl : NULL, z->work);
        double X = c < 2 ? pt->X[c] : 0.0;
        double target = r == q->disp_row ? p : q->rowval[r];
        if (F) F[row] = x[c] - X - target;
        add_row(z, row, nv, z->dx + c * nv, w[c], F, jac);
        if (jac) add_block(z, nv);
    }
    if (Fp && q->disp_row >= 0) Fp[nx + q->nloop + q->disp_row] = -1.0;
    if (jac) {
        double eps = sf_equil_reg_eps(q, y);   /* 1e-10 unless a flat start set reg_rel */
        for (int r = 0; r < q->ncon; r++)
            sf_trip_add(&z->T, nx + r, nx + r, -sf_equil_row_eps(q, eps, r) * q->yscale[nx + r] / q->fscale[nx + r]);
    }
    return Pi;
}

static int finite_all(const double *v, long n)
{
    for (long i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

/* ------------------------------------------------------------ set-up */

/* Newton scales as in the fold formulation (equilibrium.c), and for the
 * pose unknowns: rotation vectors O(1), positions ~ lref [m], their rows
 * a moment ~ kref and a force ~ kref / lref. */
static void poses_scales(sf_equil *q)
{
    int nq = q->m->nq, nx = q->pz->nx;
    for (int j = 0; j < nx; j++) {
        int pos = j >= nq && (j - nq) % 6 >= 3;
        q->yscale[j] = pos ? 1.0 / q->lref : 1.0;
        q->fscale[j] = pos ? q->lref / q->kref : 1.0 / q->kref;
    }
    for (int r = 0; r < q->ncon; r++) {
        int rot = r < q->nloop && q->pz->frow[r] % 6 < 3;
        q->yscale[nx + r] = rot ? 1.0 / q->kref : q->lref / q->kref;
        q->fscale[nx + r] = rot ? 1.0 : 1.0 / q->lref;
    }
}

/* The fold rows kept (poses_rowsel.h): all of them (solver.pose_rows =
 * "all", the default), or a maximal independent set at a generic state
 * ("independent": not valid from the flat state on every sheet, see
 * docs/design/model.md). */
static int select_rows(sf_equil *q, sf_error *err)
{
    struct sf_peq *z = q->pz;
    const sf_model *m = q->m;
    int nr = 6 * m->nfolds, nkeep = nr;
    const char *mode;
    if (sf_study_string(m->study, "solver.pose_rows", "all", &mode, err)) return err->code;
    z->kidx = malloc(sizeof(int) * ((size_t)nr + 1));
    z->frow = malloc(sizeof(int) * ((size_t)nr + 1));
    double *x = calloc((size_t)z->nx + 1, sizeof(double));
    int rc = SF_OK;
    if (!z->kidx || !z->frow || !x) rc = sf_fail(err, SF_ENOMEM, "out of memory");
    else {
        for (int r = 0; r < nr; r++) z->kidx[r] = 1;
        z->grank = -1;
        if (strcmp(mode, "independent") == 0) {
            rc = sf_rowsel_generic_state(&z->P, q->lref, ROWSEL_AMP, ROWSEL_SEED, x)
                     ? sf_fail(err, SF_ENOMEM, "out of memory")
                     : sf_rowsel_select(&z->P, x, q->lref, ROWSEL_RTOL, z->kidx, &nkeep, &z->grank,
                                  err);
        }
    }
    free(x);
    if (rc) return rc;
    int k = 0;
    for (int r = 0; r < nr; r++) {
        if (z->kidx[r]) z->frow[k] = r;
        z->kidx[r] = z->kidx[r] ? k++ : -1;
    }
    z->ndrop = nr - k;
    return SF_OK;
}

int sf_equil_use_poses(sf_equil *q, sf_error *err)
{
    const sf_model *m = q->m;
    if (!q->exact)
        return sf_fail(err, SF_EINPUT, "%s: solver.formulation = \"poses\" needs exact loop "
                       "closure (solver.constraints = \"exact\"); the paper's loop penalty exists "
                       "in the fold formulation only (solver.formulation = \"folds\")",
                       m->study->path);
    struct sf_peq *z = calloc(1, sizeof *z);
    if (!z) return sf_fail(err, SF_ENOMEM, "out of memory");
    q->pz = z;
    if (sf_poses_init(&z->P, m, err)) return err->code;
    z->nx = z->P.nx;
    int nv = z->P.maxnv;
    z->work = calloc(sf_poses_work_size(&z->P), sizeof(double));
    z->dg = calloc(6 * (size_t)nv, sizeof(double));
    z->Hl = calloc((size_t)nv * nv, sizeof(double));
    z->dx = calloc(3 * (size_t)nv, sizeof(double));
    z->col = calloc((size_t)nv, sizeof(int));
    q->nq = z->nx;
    if (select_rows(q, err)) return err->code;
    q->nloop = 6 * m->nfolds - z->ndrop;
    q->ncon = q->nloop + q->nsup;
    q->n = q->nq + q->ncon;
    free(q->yscale);
    free(q->fscale);
    q->yscale = calloc((size_t)q->n + 1, sizeof(double));
    q->fscale = calloc((size_t)q->n + 1, sizeof(double));
    double *y = calloc((size_t)q->n + 1, sizeof(double));
    if (!z->work || !z->dg || !z->Hl || !z->dx || !z->col || !q->yscale || !q->fscale || !y) {
        free(y);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    poses_scales(q);
    /* the pattern, once: the additions at the flat state */
    if (sf_equil_poses_lift(q, y)) {
        free(y);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    sf_trip_begin(&z->T, q->n);
    assemble(q, y, 0.0, NULL, 1, NULL);
    free(y);
    if (sf_trip_finish(&z->T)) return sf_fail(err, SF_ENOMEM, "out of memory");
    return SF_OK;
}

void sf_peq_free(sf_equil *q)
{
    struct sf_peq *z = q->pz;
    if (!z) return;
    sf_poses_free(&z->P);
    sf_trip_free(&z->T);
    free(z->work);
    free(z->dg);
    free(z->Hl);
    free(z->dx);
    free(z->col);
    free(z->kidx);
    free(z->frow);
    free(z->hp); free(z->hi); free(z->cpc); free(z->ci);
    free(z->hsrc); free(z->csrc); free(z->hv); free(z->cv);
    free(z);
    q->pz = NULL;
}

int sf_equil_poses_lift(sf_equil *q, double *y)
{
    struct sf_peq *z = q->pz;
    if (sf_poses_from_folds(&z->P, y, y)) return SF_ENOMEM;
    memset(y + z->nx, 0, sizeof(double) * (size_t)q->ncon);
    return SF_OK;
}

int sf_equil_poses_lift_dir(sf_equil *q, const double *y, const double *dy, double *dx)
{
    struct sf_peq *z = q->pz;
    if (sf_poses_from_folds_dir(&z->P, y, dy, dx)) return SF_ENOMEM;
    memset(dx + z->nx, 0, sizeof(double) * (size_t)q->ncon);
    return SF_OK;
}

long sf_equil_poses_nnz(const sf_equil *q) { return q->pz ? q->pz->T.nnz : 0; }

/* ------------------------------------------------------------ callbacks */

/* The stated limit of Rbar_f = I (docs/design/model.md): a face turns by
 * less than 2 pi from the flat sheet (exp is singular on |phi| = 2 pi);
 * a state beyond 1.9 pi is refused as a failed evaluation. */
static int rotations_ok(const sf_equil *q, const double *y)
{
    const struct sf_peq *z = q->pz;
    for (int k = 0; k < z->P.nfree; k++) {
        const double *v = y + z->P.nq + 6 * k;
        if (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > (1.9 * M_PI) * (1.9 * M_PI)) return 0;
    }
    return 1;
}

int sf_peq_residual(sf_equil *q, const double *y, double p, double *F)
{
    if (!finite_all(y, q->n) || !isfinite(p) || !rotations_ok(q, y)) return 1;
    q->nres++;
    assemble(q, y, p, F, 0, NULL);
    sf_equil_anchor_rows(q, y, F);
    return finite_all(F, q->n) ? 0 : 1;
}

int sf_peq_jacobian(sf_equil *q, const double *y, double p, SUNMatrix Jy, double *Fp)
{
    struct sf_peq *z = q->pz;
    if (!finite_all(y, q->n) || !isfinite(p) || !rotations_ok(q, y)) return 1;
    if (SUNMatGetID(Jy) != SUNMATRIX_SPARSE) return 1;
    q->njac++;
    assemble(q, y, p, NULL, 1, Fp);
    const sf_triplets *T = &z->T;
    if (!finite_all(T->val, T->nnz) || !finite_all(Fp, q->n)) return 1;
    if (SUNSparseMatrix_NNZ(Jy) < T->nnz && SUNSparseMatrix_Reallocate(Jy, T->nnz) != 0) return 1;
    sunindextype *cp = SUNSparseMatrix_IndexPointers(Jy), *ri = SUNSparseMatrix_IndexValues(Jy);
    sunrealtype *v = SUNSparseMatrix_Data(Jy);
    for (int j = 0; j <= q->n; j++) cp[j] = (sunindextype)T->colptr[j];
    for (long k = 0; k < T->nnz; k++) {
        ri[k] = T->rowind[k];
        v[k] = T->val[k];
    }
    return 0;
}

int sf_peq_kkt(sf_equil *q, const double *y, double p, double *HL, double *C)
{
    struct sf_peq *z = q->pz;
    int nx = z->nx;
    if (!finite_all(y, q->n) || !isfinite(p)) return 1;
    assemble(q, y, p, NULL, 1, NULL);
    memset(HL, 0, sizeof(double) * (size_t)nx * nx);
    memset(C, 0, sizeof(double) * (size_t)q->ncon * nx);
    const sf_triplets *T = &z->T;
    for (int j = 0; j < nx; j++)
        for (long k = T->colptr[j]; k < T->colptr[j + 1]; k++) {
            int i = T->rowind[k];
            if (i < nx) HL[(size_t)i * nx + j] = T->val[k];
            else C[(size_t)(i - nx) * nx + j] = T->val[k];
        }
    for (int i = 0; i < nx; i++)
        for (int j = 0; j < i; j++) {
            double v = 0.5 * (HL[(size_t)i * nx + j] + HL[(size_t)j * nx + i]);
            HL[(size_t)i * nx + j] = HL[(size_t)j * nx + i] = v;
        }
    return finite_all(HL, (long)nx * nx) && finite_all(C, (long)q->ncon * nx) ? 0 : 1;
}

int sf_peq_jacobian_csc(sf_equil *q, const double *y, double p, const long **colptr,
                        const int **rowind, const double **val, double *Fp)
{
    struct sf_peq *z = q->pz;
    if (!finite_all(y, q->n) || !isfinite(p)) return SF_ENUMERIC;
    assemble(q, y, p, NULL, 1, Fp);
    if (!finite_all(z->T.val, z->T.nnz) || !finite_all(Fp, q->n)) return SF_ENUMERIC;
    *colptr = z->T.colptr;
    *rowind = z->T.rowind;
    *val = z->T.val;
    return SF_OK;
}

/* The blocks' patterns, once, from the Jacobian's: HL = rows and columns
 * below nx (lower triangle), C = rows from nx, columns below nx. */
static int kkt_pattern(sf_equil *q)
{
    struct sf_peq *z = q->pz;
    const sf_triplets *T = &z->T;
    int nx = z->nx;
    long nh = 0, nc = 0;
    for (int j = 0; j < nx; j++)
        for (long k = T->colptr[j]; k < T->colptr[j + 1]; k++) {
            if (T->rowind[k] >= nx) nc++;
            else if (T->rowind[k] >= j) nh++;
        }
    z->hp = malloc(sizeof(int) * ((size_t)nx + 1));
    z->cpc = malloc(sizeof(int) * ((size_t)nx + 1));
    z->hi = malloc(sizeof(int) * ((size_t)nh + 1));
    z->ci = malloc(sizeof(int) * ((size_t)nc + 1));
    z->hsrc = malloc(sizeof(long) * ((size_t)nh + 1));
    z->csrc = malloc(sizeof(long) * ((size_t)nc + 1));
    z->hv = calloc((size_t)nh + 1, sizeof(double));
    z->cv = calloc((size_t)nc + 1, sizeof(double));
    if (!z->hp || !z->cpc || !z->hi || !z->ci || !z->hsrc || !z->csrc || !z->hv || !z->cv)
        return SF_ENOMEM;
    nh = nc = 0;
    for (int j = 0; j < nx; j++) {
        z->hp[j] = (int)nh;
        z->cpc[j] = (int)nc;
        for (long k = T->colptr[j]; k < T->colptr[j + 1]; k++) {
            int i = T->rowind[k];
            if (i >= nx) {
                z->ci[nc] = i - nx;
                z->csrc[nc++] = k;
            } else if (i >= j) {
                z->hi[nh] = i;
                z->hsrc[nh++] = k;
            }
        }
    }
    z->hp[nx] = (int)nh;
    z->cpc[nx] = (int)nc;
    return SF_OK;
}

int sf_peq_kkt_csc(sf_equil *q, const double *y, double p, sf_csc *HL, sf_csc *C)
{
    struct sf_peq *z = q->pz;
    int nx = z->nx;
    if (!finite_all(y, q->n) || !isfinite(p)) return SF_ENUMERIC;
    if (!z->hp && kkt_pattern(q)) return SF_ENOMEM;
    assemble(q, y, p, NULL, 1, NULL);
    for (int k = 0; k < z->hp[nx]; k++) z->hv[k] = z->T.val[z->hsrc[k]];
    for (int k = 0; k < z->cpc[nx]; k++) z->cv[k] = z->T.val[z->csrc[k]];
    if (!finite_all(z->hv, z->hp[nx]) || !finite_all(z->cv, z->cpc[nx])) return SF_ENUMERIC;
    *HL = (sf_csc){nx, nx, z->hp, z->hi, z->hv};
    *C = (sf_csc){q->ncon, nx, z->cpc, z->ci, z->cv};
    return SF_OK;
}

void sf_peq_report(sf_equil *q, const double *y, double p, double *Pi, double *res_rot,
                   double *res_tra)
{
    struct sf_peq *z = q->pz;
    const sf_model *m = q->m;
    /* the writers evaluate probes and shapes from the fold coordinates */
    sf_kin_eval(m, y, 0, &q->k);
    *Pi = assemble(q, y, p, NULL, 0, NULL);
    double rr = 0, rt = 0;
    for (int i = 0; i < m->nfolds; i++) {
        double g[6];
        sf_poses_fold_rows(&z->P, y, i, g, NULL, NULL, NULL, z->work);
        for (int c = 0; c < 6; c++) {
            if (c < 3) rr = fmax(rr, fabs(g[c]));
            else rt = fmax(rt, fabs(g[c]));
        }
    }
    *res_rot = rr;
    *res_tra = rt;
}

int sf_peq_fold_row(const sf_equil *q, int fold_row)
{
    return q->pz->kidx[fold_row];
}

int sf_peq_rows_dropped(const sf_equil *q) { return q->pz ? q->pz->ndrop : 0; }

int sf_peq_rows_rank(const sf_equil *q) { return q->pz ? q->pz->grank : -1; }

double sf_peq_dropped_residual(sf_equil *q, const double *y)
{
    struct sf_peq *z = q->pz;
    double worst = 0.0;
    if (!z || !z->ndrop) return 0.0;
    for (int i = 0; i < q->m->nfolds; i++) {
        int any = 0;
        for (int c = 0; c < 6; c++) any |= z->kidx[6 * i + c] < 0;
        if (!any) continue;
        double g[6];
        sf_poses_fold_rows(&z->P, y, i, g, NULL, NULL, NULL, z->work);
        for (int c = 0; c < 6; c++)
            if (z->kidx[6 * i + c] < 0) {
                /* scaled as Newton scales the kept rows (poses_scales) */
                double v = fabs(g[c]) * (c < 3 ? 1.0 : 1.0 / q->lref);
                worst = isfinite(v) ? fmax(worst, v) : INFINITY;
            }
    }
    return worst;
}

static int peq_jac_cb(const double *y, double p, SUNMatrix Jy, double *Fp, void *user)
{
    return sf_peq_jacobian(user, y, p, Jy, Fp);
}

static int peq_res_cb(const double *y, double p, double *F, void *user)
{
    return sf_peq_residual(user, y, p, F);
}

int sf_peq_create_solver(sf_equil *q, cont_solver **out)
{
    cont_problem prob;
    memset(&prob, 0, sizeof prob);
    prob.n = q->n;
    prob.residual = peq_res_cb;
    prob.jacobian = peq_jac_cb;
    prob.jac_matrix = CONT_MATRIX_SPARSE;
    prob.jac_nnz = q->pz->T.nnz;
    prob.yscale = q->yscale;
    prob.fscale = q->fscale;
    prob.anchor = sf_equil_anchor;
    /* the Jacobian is the KKT matrix [H A^T; A -eps D] of a potential
     * (bending, dead loads, gravity) with constraint rows and their
     * transposes, H assembled symmetric: the engine factorises its LDL^T
     * (and checks the symmetry, continuation/README.md) */
    prob.jac_symmetric = 1;
    prob.user = q;
    *out = NULL;
    int rc = cont_create(&prob, sf_equil_sparse_linsol(q), out);   /* MUMPS unless "klu" */
    if (rc == CONT_OK) {
        /* the arclength norm of the fold formulation: fold coordinates
         * and p (the poses follow from them) */
        double *w = calloc((size_t)q->n, sizeof(double));
        if (!w) return CONT_ENOMEM;
        for (int j = 0; j < q->m->nq; j++) w[j] = 1.0;
        rc = cont_set_weights(*out, w);
        free(w);
    }
    return rc;
}

/* ------------------------------------------------------------ flat start */

int sf_equil_poses_start_flat(sf_equil *q, cont_solver *cs, double p0, double p1, int dir,
                              double tol, double *y, sf_error *err)
{
    const sf_model *m = q->m;
    if (q->disp_row >= 0)
        return sf_fail(err, SF_EINPUT, "%s: a displacement parameter with exact loop constraints "
                       "cannot start at the flat state; start from p != 0", m->study->path);
    sf_equil f;
    if (sf_equil_init(&f, m, q->param, q->group, 0, 0, q->load, err)) return err->code;
    f.ramp_stage = q->ramp_stage;
    double *yf = calloc((size_t)f.n + 1, sizeof(double));
    if (!yf) {
        sf_equil_free(&f);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    sf_error lerr;
    sf_error_clear(&lerr);
    char why[SF_MSG_SIZE] = "";
    int ok = 0;
    /* the limit of the branch (flatstart.c), in fold coordinates */
    sf_flatstart_info fi;
    if (sf_equil_start_limit(&f, p0, p1, yf, &fi, &lerr) == SF_OK) {
        if (fi.degenerate) {   /* flatstart.h */
            q->reg_rel = SF_FLAT_REG_REL_POSES;
            q->reg_min = SF_FLAT_REG_MIN_POSES;
        }
        memset(y, 0, sizeof(double) * (size_t)q->n);
        memcpy(y, yf, sizeof(double) * (size_t)m->nq);
        sf_equil_poses_lift(q, y);
        ok = cont_start(cs, y, p1, dir) == CONT_OK;
        if (!ok) snprintf(why, sizeof why, "%s", cont_errmsg(cs));
    } else {
        snprintf(why, sizeof why, "%s", lerr.msg);
    }
    if (!ok && sf_equil_start_flat_solved(&f, p0, p1, dir, tol, yf, &lerr) == SF_OK) {
        /* the fold formulation's start, converged (its multipliers are of
         * no use here): from an exact equilibrium, Newton's first step
         * gives the poses' multipliers */
        memset(y, 0, sizeof(double) * (size_t)q->n);
        memcpy(y, yf, sizeof(double) * (size_t)m->nq);
        sf_equil_poses_lift(q, y);
        ok = cont_start(cs, y, p1, dir) == CONT_OK;
        if (!ok) snprintf(why + strlen(why), sizeof why - strlen(why),
                          "; from the converged fold start: %s", cont_errmsg(cs));
    }
    if (!ok) {
        /* the penalty homotopy as the fallback */
        sf_error_clear(&lerr);
        memset(yf, 0, sizeof(double) * (size_t)f.n);
        if (sf_equil_start_off_flat(&f, p1, tol, yf, &lerr)) {
            sf_fail(err, lerr.code, "%s: no equilibrium at p = %g off the flat state (limit "
                    "start: %s; penalty start: %s)", m->study->path, p1, why, lerr.msg);
        } else {
            memset(y, 0, sizeof(double) * (size_t)q->n);
            memcpy(y, yf, sizeof(double) * (size_t)m->nq);
            sf_equil_poses_lift(q, y);
            if (cont_start(cs, y, p1, dir) == CONT_OK) ok = 1;
            else
                sf_fail(err, SF_ENUMERIC, "%s: no equilibrium at p = %g off the flat state "
                        "(limit start: %s; from the penalty start: %s)", m->study->path, p1,
                        why, cont_errmsg(cs));
        }
    }
    free(yf);
    sf_equil_free(&f);
    return ok ? SF_OK : err->code;
}

/* (equilibrium_poses.h) The constraint force on the left face's pose
 * coordinates xi = (phi, xf) is Q = -(dg/dxi)^T lambda (F = grad Pi + J^T
 * lambda = 0: applied plus constraint forces vanish).  Virtual work
 * Q . dxi = F . dxf + M_o . domega with domega = T dphi, T's columns the
 * axial vectors of dR/dphi_a R^T: so F = Q_x, M_o = T^-T Q_phi (moment
 * about the face's reference point xf), moved to the origin. */
int sf_peq_fold_wrench(sf_equil *q, const double *y, int fold, double F[3], double M[3])
{
    struct sf_peq *z = q->pz;
    const sf_model *m = q->m;
    int qn = m->qn[fold], nv = qn + 12, l = m->topo->folds[fold].left;
    double g[6], lam[6];
    sf_poses_fold_rows(&z->P, y, fold, g, z->dg, NULL, NULL, z->work);
    for (int c = 0; c < 6; c++) {
        int k = z->kidx[6 * fold + c];
        lam[c] = k < 0 ? 0.0 : y[z->nx + k];
    }
    double Q[6];
    for (int a = 0; a < 6; a++) {
        Q[a] = 0.0;
        for (int c = 0; c < 6; c++) Q[a] -= lam[c] * z->dg[c * nv + qn + 6 + a];
    }
    double phi[3] = {0, 0, 0}, R[9], dR[3][9], xf[3];
    int k = z->P.pose_of[l];
    if (k >= 0) memcpy(phi, y + z->P.nq + 6 * k, sizeof phi);
    sf_rodrigues(phi, R, dR, NULL);
    sf_poses_face(&z->P, y, l, R, xf);
    /* T (row-major): column a = axial(dR_a R^T) */
    double T[9];
    for (int a = 0; a < 3; a++) {
        double W[9];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double s = 0.0;
                for (int t = 0; t < 3; t++) s += dR[a][3 * i + t] * R[3 * j + t];
                W[3 * i + j] = s;
            }
        T[0 * 3 + a] = 0.5 * (W[7] - W[5]);
        T[1 * 3 + a] = 0.5 * (W[2] - W[6]);
        T[2 * 3 + a] = 0.5 * (W[3] - W[1]);
    }
    /* solve T^T Mr = Q_phi (Cramer) */
    double A[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) A[3 * i + j] = T[3 * j + i];
    double det = A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
                 A[2] * (A[3] * A[7] - A[4] * A[6]);
    if (!(fabs(det) > 1e-300)) return SF_ENUMERIC;
    double Mr[3];
    for (int c = 0; c < 3; c++) {
        double B[9];
        memcpy(B, A, sizeof B);
        for (int i = 0; i < 3; i++) B[3 * i + c] = Q[i];
        Mr[c] = (B[0] * (B[4] * B[8] - B[5] * B[7]) - B[1] * (B[3] * B[8] - B[5] * B[6]) +
                 B[2] * (B[3] * B[7] - B[4] * B[6])) / det;
    }
    for (int i = 0; i < 3; i++) F[i] = Q[3 + i];
    M[0] = Mr[0] + xf[1] * F[2] - xf[2] * F[1];
    M[1] = Mr[1] + xf[2] * F[0] - xf[0] * F[2];
    M[2] = Mr[2] + xf[0] * F[1] - xf[1] * F[0];
    return finite_all(F, 3) && finite_all(M, 3) ? SF_OK : SF_ENUMERIC;
}
