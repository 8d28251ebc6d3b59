/* kinematics.c - folding maps and their derivatives (MODEL.md sections 3-4).
 *
 * Derivatives of products of folding maps use spatial twists.  For a chain
 * L = T_1^s1 T_2^s2 ... T_n^sn (s = +1 or -1), with prefix P_k (product of
 * the first k-1 factors), local twist Xi = dT T^-1 and second-order map
 * Xi2 = d2T T^-1 of each factor:
 *   dL/dq      = S L,              S = s Ad(B) Xi,
 *   d2L/dqa dqb = S_a S_b L         (a in an earlier factor than b),
 *   d2L/dqj dqk = B M B^-1 L        (j, k of the same factor),
 * where B = P_k for s = +1 and B = P_k T^-1 for s = -1 (in both cases the
 * map of the factor's right face), M = Xi2 for s = +1 and
 * M = Xi_j Xi_k + Xi_k Xi_j - Xi2 for s = -1 (from d2(T^-1)).
 * Face maps are chains along the face tree from the root; vertex loops are
 * chains around the vertex, starting from the identity.
 */
#include "kinematics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void cross(const double a[3], const double b[3], double c[3])
{
    double t0 = a[1] * b[2] - a[2] * b[1];
    double t1 = a[2] * b[0] - a[0] * b[2];
    double t2 = a[0] * b[1] - a[1] * b[0];
    c[0] = t0; c[1] = t1; c[2] = t2;
}

/* The 3x4 matrix of a twist (omega, v): [omega]x | v. */
static void twist_matrix(const double xi[6], double M[12])
{
    const double *w = xi;
    M[0] = 0.0;   M[1] = -w[2]; M[2] = w[1];  M[3] = xi[3];
    M[4] = w[2];  M[5] = 0.0;   M[6] = -w[0]; M[7] = xi[4];
    M[8] = -w[1]; M[9] = w[0];  M[10] = 0.0;  M[11] = xi[5];
}

/* Product of two "derivative" maps (bottom row 0 0 0 0): C = A B. */
static void dmap_mul(const double A[12], const double B[12], double C[12])
{
    double T[12];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++) {
            double v = 0.0;
            for (int k = 0; k < 3; k++) v += A[r * 4 + k] * B[k * 4 + c];
            T[r * 4 + c] = v;
        }
    memcpy(C, T, sizeof T);
}

/* Derivative map D times an affine map A (bottom row 0 0 0 1). */
static void dmap_mul_affine(const double D[12], const double A[12], double C[12])
{
    double T[12];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++) {
            double v = c == 3 ? D[r * 4 + 3] : 0.0;
            for (int k = 0; k < 3; k++) v += D[r * 4 + k] * A[k * 4 + c];
            T[r * 4 + c] = v;
        }
    memcpy(C, T, sizeof T);
}

/* B M B^-1 for a derivative map M and a rigid map B. */
static void conjugate(const double B[12], const double M[12], double C[12])
{
    double Bi[12], T[12];
    sf_affine_inv(B, Bi);
    dmap_mul_affine(M, Bi, T);    /* M B^-1 */
    /* B (M B^-1): linear part of B on the derivative map, no translation of B */
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++) {
            double v = 0.0;
            for (int k = 0; k < 3; k++) v += B[r * 4 + k] * T[k * 4 + c];
            C[r * 4 + c] = v;
        }
}

/* Ad(B) of a twist. */
static void adjoint(const double B[12], const double xi[6], double out[6])
{
    double w[3], v[3], t[3] = {B[3], B[7], B[11]};
    for (int r = 0; r < 3; r++) {
        w[r] = B[r * 4] * xi[0] + B[r * 4 + 1] * xi[1] + B[r * 4 + 2] * xi[2];
        v[r] = B[r * 4] * xi[3] + B[r * 4 + 1] * xi[4] + B[r * 4 + 2] * xi[5];
    }
    double txw[3];
    cross(t, w, txw);
    for (int r = 0; r < 3; r++) {
        out[r] = w[r];
        out[3 + r] = v[r] + txw[r];
    }
}

/* ---------------------------------------------------------------- model */

int sf_model_init(sf_model *m, const sf_study *s, const sf_topology *t,
                  sf_error *err)
{
    memset(m, 0, sizeof *m);
    m->study = s;
    m->topo = t;
    m->nfolds = s->nfolds;
    m->nfaces = t->nfaces;
    m->qoff = calloc((size_t)m->nfolds + 1, sizeof(int));
    m->qn = calloc((size_t)m->nfolds + 1, sizeof(int));
    m->sec = calloc((size_t)m->nfolds + 1, sizeof(sf_section));
    m->pathlen = calloc((size_t)m->nfaces + 1, sizeof(int));
    m->path = calloc((size_t)m->nfaces + 1, sizeof(int *));
    m->pathsign = calloc((size_t)m->nfaces + 1, sizeof(int *));
    if (!m->qoff || !m->qn || !m->sec || !m->pathlen || !m->path || !m->pathsign) {
        sf_model_free(m);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    int nquad = s->quadrature > 0 ? s->quadrature : 24;
    for (int i = 0; i < m->nfolds; i++) {
        const sf_fold_def *f = &s->folds[i];
        m->qoff[i] = m->nq;
        m->qn[i] = f->modes + 1;
        m->nq += m->qn[i];
        if (m->qn[i] > m->maxqn) m->maxqn = m->qn[i];
        if (sf_section_init(&m->sec[i], f->width, f->continuity, f->modes, nquad, err)) {
            sf_error_prefix(err, "%s:%d: fold %d", s->path, f->line, i + 1);
            sf_model_free(m);
            return err ? err->code : SF_EINPUT;
        }
    }
    for (int f = 0; f < m->nfaces; f++) {
        int n = t->faces[f].depth;
        m->pathlen[f] = n;
        m->path[f] = calloc((size_t)n + 1, sizeof(int));
        m->pathsign[f] = calloc((size_t)n + 1, sizeof(int));
        if (!m->path[f] || !m->pathsign[f]) {
            sf_model_free(m);
            return sf_fail(err, SF_ENOMEM, "out of memory");
        }
        int g = f;
        for (int k = n - 1; k >= 0; k--) {
            int fold = t->faces[g].parent_fold;
            m->path[f][k] = fold;
            /* stepping from the parent onto g: +1 when g is the left face */
            m->pathsign[f][k] = t->folds[fold].left == g ? +1 : -1;
            g = t->faces[g].parent;
        }
    }
    m->ncon = 6 * t->nivertices;
    return SF_OK;
}

void sf_model_free(sf_model *m)
{
    if (m->sec)
        for (int i = 0; i < m->nfolds; i++) sf_section_free(&m->sec[i]);
    if (m->path)
        for (int f = 0; f < m->nfaces; f++) free(m->path[f]);
    if (m->pathsign)
        for (int f = 0; f < m->nfaces; f++) free(m->pathsign[f]);
    free(m->qoff);
    free(m->qn);
    free(m->sec);
    free(m->pathlen);
    free(m->path);
    free(m->pathsign);
    memset(m, 0, sizeof *m);
}

int sf_kin_alloc(const sf_model *m, sf_kin *k)
{
    memset(k, 0, sizeof *k);
    size_t nf = (size_t)m->nfolds + 1, mq = (size_t)m->maxqn + 1;
    k->q = calloc((size_t)m->nq + 1, sizeof(double));
    k->T = calloc(nf * 12, sizeof(double));
    k->chord = calloc(nf * 2, sizeof(double));
    k->xi = calloc(((size_t)m->nq + 1) * 6, sizeof(double));
    k->xi2 = calloc(nf * mq * mq * 12, sizeof(double));
    k->X = calloc(((size_t)m->nfaces + 1) * 12, sizeof(double));
    if (!k->q || !k->T || !k->chord || !k->xi || !k->xi2 || !k->X) {
        sf_kin_free(k);
        return SF_ENOMEM;
    }
    return SF_OK;
}

void sf_kin_free(sf_kin *k)
{
    free(k->q);
    free(k->T);
    free(k->chord);
    free(k->xi);
    free(k->xi2);
    free(k->X);
    memset(k, 0, sizeof *k);
}

#define XI2(m, k, i, j, l) ((k)->xi2 + ((((size_t)(i) * ((m)->maxqn + 1) + (j)) * ((m)->maxqn + 1)) + (l)) * 12)

/* Local folding map of fold i and its derivative maps. */
static void fold_local(const sf_model *m, int i, const double *qi, int order,
                       sf_kin *k)
{
    const sf_fold_geom *g = &m->topo->folds[i];
    const sf_section *sec = &m->sec[i];
    int nq = sec->nq;
    double w = sec->w;
    double mm[3] = {g->m[0], g->m[1], 0.0};
    double nn[3] = {g->n[0], g->n[1], 0.0};
    double e3[3] = {0.0, 0.0, 1.0};
    double pR[3] = {g->a[0] - 0.5 * w * nn[0], g->a[1] - 0.5 * w * nn[1], 0.0};
    double pL[3] = {g->a[0] + 0.5 * w * nn[0], g->a[1] + 0.5 * w * nn[1], 0.0};
    double c[2], dc[2 * 65], d2c[2 * 65 * 65];
    sf_section_integral(sec, SF_SEC_CHORD, qi, c, order >= 1 ? dc : NULL,
                        order >= 2 ? d2c : NULL);
    k->chord[2 * i] = c[0];
    k->chord[2 * i + 1] = c[1];
    double R[9];
    sf_rotation(mm, qi[0], R);
    k->fold_evals++;
    double *T = k->T + 12 * i;
    double RpL[3];
    for (int r = 0; r < 3; r++) {
        RpL[r] = R[3 * r] * pL[0] + R[3 * r + 1] * pL[1] + R[3 * r + 2] * pL[2];
        for (int cc = 0; cc < 3; cc++) T[4 * r + cc] = R[3 * r + cc];
        T[4 * r + 3] = pR[r] + c[0] * nn[r] + c[1] * e3[r] - RpL[r];
    }
    if (order < 1) return;
    double t[3] = {T[3], T[7], T[11]};
    /* [m]x R pL and [m]x^2 R pL */
    double mRpL[3], mmRpL[3], mt[3], mmt[3];
    cross(mm, RpL, mRpL);
    cross(mm, mRpL, mmRpL);
    cross(mm, t, mt);
    cross(mm, mt, mmt);
    int off = m->qoff[i];
    for (int j = 0; j < nq; j++) {
        double *xi = k->xi + 6 * (off + j);
        double dt[3];
        for (int r = 0; r < 3; r++) dt[r] = dc[j] * nn[r] + dc[nq + j] * e3[r];
        if (j == 0) {
            for (int r = 0; r < 3; r++) {
                xi[r] = mm[r];
                xi[3 + r] = dt[r] - mRpL[r] - mt[r];
            }
        } else {
            for (int r = 0; r < 3; r++) {
                xi[r] = 0.0;
                xi[3 + r] = dt[r];
            }
        }
    }
    if (order < 2) return;
    /* [m]x^2 as a matrix */
    double M2[9];
    for (int cc = 0; cc < 3; cc++) {
        double e[3] = {0, 0, 0}, a1[3], a2[3];
        e[cc] = 1.0;
        cross(mm, e, a1);
        cross(mm, a1, a2);
        for (int r = 0; r < 3; r++) M2[3 * r + cc] = a2[r];
    }
    for (int j = 0; j < nq; j++)
        for (int l = 0; l < nq; l++) {
            double *X2 = XI2(m, k, i, j, l);
            double t2[3];
            for (int r = 0; r < 3; r++)
                t2[r] = d2c[j * nq + l] * nn[r] + d2c[(nq + j) * nq + l] * e3[r];
            memset(X2, 0, sizeof(double) * 12);
            if (j == 0 && l == 0) {
                /* linear part [m]^2, translation t'' - [m]^2 t with
                 * t'' = c'' - [m]^2 R pL */
                for (int r = 0; r < 3; r++) {
                    for (int cc = 0; cc < 3; cc++) X2[4 * r + cc] = M2[3 * r + cc];
                    X2[4 * r + 3] = t2[r] - mmRpL[r] - mmt[r];
                }
            } else {
                for (int r = 0; r < 3; r++) X2[4 * r + 3] = t2[r];
            }
        }
}

void sf_kin_eval(const sf_model *m, const double *q, int order, sf_kin *k)
{
    const sf_topology *t = m->topo;
    k->order = order;
    memcpy(k->q, q, sizeof(double) * m->nq);
    for (int i = 0; i < m->nfolds; i++)
        fold_local(m, i, q + m->qoff[i], order, k);
    /* face maps along the tree */
    for (int n = 0; n < t->nfaces; n++) {
        int f = t->order[n];
        double *X = k->X + 12 * f;
        if (t->faces[f].parent < 0) {
            sf_affine_identity(X);
            continue;
        }
        int p = t->faces[f].parent, fold = t->faces[f].parent_fold;
        const double *T = k->T + 12 * fold;
        if (t->folds[fold].left == f) {
            sf_affine_mul(k->X + 12 * p, T, X);
        } else {
            double Ti[12];
            sf_affine_inv(T, Ti);
            sf_affine_mul(k->X + 12 * p, Ti, X);
        }
    }
}

void sf_kin_eval_folds(const sf_model *m, const double *q, int order, int nf, const int *folds,
                       sf_kin *k)
{
    k->order = order;
    for (int a = 0; a < nf; a++) {
        int i = folds[a], off = m->qoff[i];
        memcpy(k->q + off, q + off, sizeof(double) * (size_t)m->qn[i]);
        fold_local(m, i, q + off, order, k);
    }
}

/* ---------------------------------------------------------------- chains */

/* Derivative data of a chain of crossings: coordinates (global indices),
 * signed spatial twists, and the factor each coordinate belongs to. */
typedef struct chain {
    int n;           /* coordinates */
    int *coord;      /* global q index */
    int *factor;     /* factor index (position along the chain) */
    int *fold;       /* fold of the factor */
    int *local;      /* coordinate index within its fold */
    int *sig;        /* sign of the factor */
    double *S;       /* [n][6] signed spatial twists */
    double *Q;       /* [n][n][12] same-factor second-order maps (others unused) */
    double L[12];    /* the product */
} chain;

static int chain_alloc(chain *c, int n)
{
    memset(c, 0, sizeof *c);
    c->coord = malloc(sizeof(int) * (n + 1));
    c->factor = malloc(sizeof(int) * (n + 1));
    c->fold = malloc(sizeof(int) * (n + 1));
    c->local = malloc(sizeof(int) * (n + 1));
    c->sig = malloc(sizeof(int) * (n + 1));
    c->S = malloc(sizeof(double) * 6 * (n + 1));
    c->Q = malloc(sizeof(double) * 12 * (size_t)(n + 1) * (n + 1));
    if (!c->coord || !c->factor || !c->fold || !c->local || !c->sig || !c->S || !c->Q)
        return SF_ENOMEM;
    return SF_OK;
}

static void chain_free(chain *c)
{
    free(c->coord); free(c->factor); free(c->fold); free(c->local);
    free(c->sig); free(c->S); free(c->Q);
    memset(c, 0, sizeof *c);
}

/* A chain from the identity through the given crossings, local frame. */
static int chain_build(const sf_model *m, const sf_kin *k, int nf,
                       const int *folds, const int *sig, int order, chain *c)
{
    int n = 0;
    for (int a = 0; a < nf; a++) n += m->qn[folds[a]];
    if (chain_alloc(c, n)) { chain_free(c); return SF_ENOMEM; }
    c->n = n;
    double P[12];
    sf_affine_identity(P);
    int idx = 0;
    for (int a = 0; a < nf; a++) {
        int i = folds[a], nq = m->qn[i], off = m->qoff[i];
        const double *T = k->T + 12 * i;
        double Ti[12], Pn[12];
        if (sig[a] > 0) {
            sf_affine_mul(P, T, Pn);
        } else {
            sf_affine_inv(T, Ti);
            sf_affine_mul(P, Ti, Pn);
        }
        const double *B = sig[a] > 0 ? P : Pn;
        for (int j = 0; j < nq; j++) {
            int r = idx + j;
            c->coord[r] = off + j;
            c->factor[r] = a;
            c->fold[r] = i;
            c->local[r] = j;
            c->sig[r] = sig[a];
            if (order >= 1) {
                adjoint(B, k->xi + 6 * (off + j), c->S + 6 * r);
                for (int e = 0; e < 6; e++) c->S[6 * r + e] *= sig[a];
            }
        }
        if (order >= 2)
            for (int j = 0; j < nq; j++)
                for (int l = 0; l < nq; l++) {
                    double M[12];
                    const double *X2 = XI2(m, k, i, j, l);
                    if (sig[a] > 0) {
                        memcpy(M, X2, sizeof M);
                    } else {
                        double Xj[12], Xl[12], A1[12], A2[12];
                        twist_matrix(k->xi + 6 * (off + j), Xj);
                        twist_matrix(k->xi + 6 * (off + l), Xl);
                        dmap_mul(Xj, Xl, A1);
                        dmap_mul(Xl, Xj, A2);
                        for (int e = 0; e < 12; e++) M[e] = A1[e] + A2[e] - X2[e];
                    }
                    conjugate(B, M, c->Q + 12 * ((size_t)(idx + j) * n + idx + l));
                }
        memcpy(P, Pn, sizeof P);
        idx += nq;
    }
    memcpy(c->L, P, sizeof P);
    return SF_OK;
}

/* First derivative of the chain product: dL = S L. */
static void chain_d1(const chain *c, int r, double D[12])
{
    double Sm[12];
    twist_matrix(c->S + 6 * r, Sm);
    dmap_mul_affine(Sm, c->L, D);
}

/* Second derivative d2L / dq_r dq_s. */
static void chain_d2(const chain *c, int r, int s, double D[12])
{
    if (c->factor[r] == c->factor[s]) {
        dmap_mul_affine(c->Q + 12 * ((size_t)r * c->n + s), c->L, D);
        return;
    }
    if (c->factor[r] > c->factor[s]) { int t = r; r = s; s = t; }
    double Sa[12], Sb[12], SbL[12];
    twist_matrix(c->S + 6 * r, Sa);
    twist_matrix(c->S + 6 * s, Sb);
    dmap_mul_affine(Sb, c->L, SbL);
    dmap_mul(Sa, SbL, D);
}

/* Add sum_e W[e] d2L[e] to H for all coordinate pairs. */
static void chain_hess_add(const chain *c, const double W[12], double *H, int ld)
{
    for (int r = 0; r < c->n; r++)
        for (int s = 0; s <= r; s++) {
            double D[12], v = 0.0;
            chain_d2(c, r, s, D);
            for (int e = 0; e < 12; e++) v += W[e] * D[e];
            H[(size_t)c->coord[r] * ld + c->coord[s]] += v;
            if (r != s) H[(size_t)c->coord[s] * ld + c->coord[r]] += v;
        }
}

/* The chain of the tree path of face f. */
static int face_chain(const sf_model *m, const sf_kin *k, int f, int order, chain *c)
{
    return chain_build(m, k, m->pathlen[f], m->path[f], m->pathsign[f], order, c);
}

/* ---------------------------------------------------------------- points */

int sf_model_locate(const sf_model *m, const double X[2], sf_mpoint *p,
                    sf_error *err)
{
    memset(p, 0, sizeof *p);
    p->X[0] = X[0];
    p->X[1] = X[1];
    p->fold = -1;
    double tpos, upos;
    int b = sf_topology_locate_band(m->topo, X, &tpos, &upos);
    if (b >= 0) {
        p->fold = b;
        p->tpos = tpos;
        p->s = upos + 0.5 * m->sec[b].w;
        if (p->s < 0.0) p->s = 0.0;
        if (p->s > m->sec[b].w) p->s = m->sec[b].w;
        p->face = m->topo->folds[b].right;
        return SF_OK;
    }
    p->face = sf_topology_locate_face(m->topo, X);
    if (p->face < 0)
        return sf_fail(err, SF_EINPUT, "point (%g, %g) is outside the sheet", X[0], X[1]);
    return SF_OK;
}

/* Reference position of a band point in its right face's frame, and its
 * derivatives in the fold's own coordinates (3 x nq, 3 x nq x nq). */
static void band_local(const sf_model *m, const sf_kin *k, int fold, int kind,
                       double tpos, double s, double y[3], double *dy, double *d2y)
{
    const sf_fold_geom *g = &m->topo->folds[fold];
    const sf_section *sec = &m->sec[fold];
    int nq = sec->nq;
    const double *qi = k->q + m->qoff[fold];
    double r[2], dr[2 * 65], d2r[2 * 65 * 65];
    if (kind == SF_SEC_CENTROID)
        sf_section_integral(sec, SF_SEC_CENTROID, qi, r, dy ? dr : NULL, d2y ? d2r : NULL);
    else
        sf_section_point(sec, qi, s, r, dy ? dr : NULL, d2y ? d2r : NULL);
    double n3[3] = {g->n[0], g->n[1], 0.0};
    for (int c = 0; c < 2; c++)
        y[c] = g->a[c] + tpos * g->m[c] - 0.5 * sec->w * g->n[c] + r[0] * g->n[c];
    y[2] = r[1];
    if (dy)
        for (int j = 0; j < nq; j++) {
            dy[j] = dr[j] * n3[0];
            dy[nq + j] = dr[j] * n3[1];
            dy[2 * nq + j] = dr[nq + j];
        }
    if (d2y)
        for (int j = 0; j < nq; j++)
            for (int l = 0; l < nq; l++) {
                d2y[(0 * nq + j) * nq + l] = d2r[j * nq + l] * n3[0];
                d2y[(1 * nq + j) * nq + l] = d2r[j * nq + l] * n3[1];
                d2y[(2 * nq + j) * nq + l] = d2r[(nq + j) * nq + l];
            }
}

/* Position, gradient and f-weighted Hessian of a point attached either to a
 * face (fold < 0, reference position Xr) or to fold band `fold` (kind and
 * tpos/s as in band_local). */
static void attached_point(const sf_model *m, const sf_kin *k, int face, int fold,
                           int kind, const double Xr[2], double tpos, double s,
                           double x[3], double *dx, const double *f, double *H, int ld)
{
    int order = H ? 2 : dx ? 1 : 0;
    int nq = m->nq;
    chain c;
    if (face_chain(m, k, face, order, &c)) { chain_free(&c); return; }
    double y[3], dy[3 * 65], d2y[3 * 65 * 65];
    int nqi = fold >= 0 ? m->qn[fold] : 0;
    if (fold >= 0)
        band_local(m, k, fold, kind, tpos, s, y, order >= 1 ? dy : NULL,
                   order >= 2 ? d2y : NULL);
    else {
        y[0] = Xr[0]; y[1] = Xr[1]; y[2] = 0.0;
    }
    sf_affine_apply(c.L, y, x);
    const double *RL = c.L;
    if (dx) {
        memset(dx, 0, sizeof(double) * 3 * nq);
        for (int r = 0; r < c.n; r++) {
            double wx[3];
            const double *S = c.S + 6 * r;
            cross(S, x, wx);
            for (int e = 0; e < 3; e++) dx[e * nq + c.coord[r]] += wx[e] + S[3 + e];
        }
        for (int j = 0; j < nqi; j++) {
            int col = m->qoff[fold] + j;
            for (int e = 0; e < 3; e++)
                dx[e * nq + col] += RL[4 * e] * dy[j] + RL[4 * e + 1] * dy[nqi + j] +
                                    RL[4 * e + 2] * dy[2 * nqi + j];
        }
    }
    if (H && f) {
        /* path x path */
        double W[12];
        for (int e = 0; e < 3; e++) {
            W[4 * e] = f[e] * y[0];
            W[4 * e + 1] = f[e] * y[1];
            W[4 * e + 2] = f[e] * y[2];
            W[4 * e + 3] = f[e];
        }
        chain_hess_add(&c, W, H, ld);
        if (fold >= 0) {
            /* own x own: R d2y; own x path: S_a (R dy_j) (rotation part) */
            for (int j = 0; j < nqi; j++) {
                double v[3];
                for (int e = 0; e < 3; e++)
                    v[e] = RL[4 * e] * dy[j] + RL[4 * e + 1] * dy[nqi + j] +
                           RL[4 * e + 2] * dy[2 * nqi + j];
                int cj = m->qoff[fold] + j;
                for (int l = 0; l < nqi; l++) {
                    double val = 0.0;
                    for (int e = 0; e < 3; e++)
                        val += f[e] * (RL[4 * e] * d2y[(0 * nqi + j) * nqi + l] +
                                       RL[4 * e + 1] * d2y[(1 * nqi + j) * nqi + l] +
                                       RL[4 * e + 2] * d2y[(2 * nqi + j) * nqi + l]);
                    H[(size_t)cj * ld + m->qoff[fold] + l] += val;
                }
                for (int r = 0; r < c.n; r++) {
                    double wv[3];
                    cross(c.S + 6 * r, v, wv);
                    double val = f[0] * wv[0] + f[1] * wv[1] + f[2] * wv[2];
                    H[(size_t)cj * ld + c.coord[r]] += val;
                    H[(size_t)c.coord[r] * ld + cj] += val;
                }
            }
        }
    }
    chain_free(&c);
}

void sf_point_eval(const sf_model *m, const sf_kin *k, const sf_mpoint *p,
                   double x[3], double *dx)
{
    attached_point(m, k, p->face, p->fold, SF_SEC_CHORD, p->X, p->tpos, p->s, x,
                   dx, NULL, NULL, 0);
}

void sf_point_hess_add(const sf_model *m, const sf_kin *k, const sf_mpoint *p,
                       const double f[3], double *H, int ld)
{
    double x[3];
    attached_point(m, k, p->face, p->fold, SF_SEC_CHORD, p->X, p->tpos, p->s, x,
                   NULL, f, H, ld);
}

void sf_fold_centroid(const sf_model *m, const sf_kin *k, int fold, double x[3],
                      double *dx, const double *f, double *H, int ld)
{
    const sf_fold_geom *g = &m->topo->folds[fold];
    const sf_fold_def *d = &m->study->folds[fold];
    double tmid = 0.5 * (d->setback[0] + g->l - d->setback[1]);
    attached_point(m, k, g->right, fold, SF_SEC_CENTROID, NULL, tmid, 0.0, x, dx,
                   f, H, ld);
}

/* ---------------------------------------------------------------- loops */

static int loop_chain(const sf_model *m, const sf_kin *k, int v, int order, chain *c)
{
    const sf_ivertex *iv = &m->topo->ivertices[v];
    return chain_build(m, k, iv->degree, iv->folds, iv->sign, order, c);
}

/* The loop product measured about the vertex o (origin moved to o):
 * translation t + (R - I) o; for a derivative map (deriv = 1) dt + dR o. */
static void about_vertex(const double L[12], const double o[2], int deriv, double out[12])
{
    memcpy(out, L, sizeof(double) * 12);
    for (int r = 0; r < 3; r++) {
        out[4 * r + 3] += L[4 * r] * o[0] + L[4 * r + 1] * o[1];
        if (!deriv && r < 2) out[4 * r + 3] -= o[r];
    }
}

/* Weights on the entries of L equivalent to weights W on the entries of
 * about_vertex(L): the translation weights also act on R times o. */
static void weights_about_vertex(const double W[12], const double o[2], double Wl[12])
{
    memcpy(Wl, W, sizeof(double) * 12);
    for (int r = 0; r < 3; r++) {
        Wl[4 * r] += W[4 * r + 3] * o[0];
        Wl[4 * r + 1] += W[4 * r + 3] * o[1];
    }
}

/* Constraint values of a loop product: axial vector of (R - R^T)/2, then t. */
static void loop_g(const double L[12], double g[6])
{
    g[0] = 0.5 * (L[9] - L[6]);  /* R32 - R23 */
    g[1] = 0.5 * (L[2] - L[8]);  /* R13 - R31 */
    g[2] = 0.5 * (L[4] - L[1]);  /* R21 - R12 */
    g[3] = L[3];
    g[4] = L[7];
    g[5] = L[11];
}

/* Weights W (on entries of L) with sum_e W[e] L[e] = lambda . g. */
static void loop_weights(const double lam[6], double W[12])
{
    memset(W, 0, sizeof(double) * 12);
    W[9] += 0.5 * lam[0]; W[6] -= 0.5 * lam[0];
    W[2] += 0.5 * lam[1]; W[8] -= 0.5 * lam[1];
    W[4] += 0.5 * lam[2]; W[1] -= 0.5 * lam[2];
    W[3] = lam[3]; W[7] = lam[4]; W[11] = lam[5];
}

void sf_constraints(const sf_model *m, const sf_kin *k, double *g, double *J,
                    const double *lambda, double *H, int ld)
{
    int nq = m->nq;
    if (J) memset(J, 0, sizeof(double) * (size_t)m->ncon * nq);
    for (int v = 0; v < m->topo->nivertices; v++) {
        int order = (lambda && H) ? 2 : J ? 1 : 0;
        chain c;
        if (loop_chain(m, k, v, order, &c)) { chain_free(&c); continue; }
        const double *o = m->study->vertices[m->topo->ivertices[v].vertex].x;
        double Lv[12];
        about_vertex(c.L, o, 0, Lv);
        if (g) loop_g(Lv, g + 6 * v);
        if (J)
            for (int r = 0; r < c.n; r++) {
                double D[12], Dv[12], dg[6];
                chain_d1(&c, r, D);
                about_vertex(D, o, 1, Dv);
                loop_g(Dv, dg);
                for (int e = 0; e < 6; e++) J[(size_t)(6 * v + e) * nq + c.coord[r]] += dg[e];
            }
        if (lambda && H) {
            double W[12], Wl[12];
            loop_weights(lambda + 6 * v, W);
            weights_about_vertex(W, o, Wl);
            chain_hess_add(&c, Wl, H, ld);
        }
        chain_free(&c);
    }
}

int sf_constraints_vertex(const sf_model *m, const sf_kin *k, int v, double g[6], int *cols,
                          int *ncols, double *J, const double *lambda, double *H)
{
    int order = (lambda && H) ? 2 : J ? 1 : 0;
    chain c;
    if (loop_chain(m, k, v, order, &c)) {
        chain_free(&c);
        return SF_ENOMEM;
    }
    /* distinct columns, in chain order; pos[r] = local column of coordinate r */
    int nc = 0, pos[64];
    if (c.n > 64) {
        chain_free(&c);
        return SF_ENOMEM;
    }
    for (int r = 0; r < c.n; r++) {
        int j = 0;
        while (j < nc && cols[j] != c.coord[r]) j++;
        if (j == nc) cols[nc++] = c.coord[r];
        pos[r] = j;
    }
    *ncols = nc;
    const double *o = m->study->vertices[m->topo->ivertices[v].vertex].x;
    double Lv[12];
    about_vertex(c.L, o, 0, Lv);
    if (g) loop_g(Lv, g);
    if (J) {
        memset(J, 0, sizeof(double) * 6 * (size_t)nc);
        for (int r = 0; r < c.n; r++) {
            double D[12], Dv[12], dg[6];
            chain_d1(&c, r, D);
            about_vertex(D, o, 1, Dv);
            loop_g(Dv, dg);
            for (int e = 0; e < 6; e++) J[(size_t)e * nc + pos[r]] += dg[e];
        }
    }
    if (lambda && H) {
        double W[12], Wl[12];
        loop_weights(lambda, W);
        weights_about_vertex(W, o, Wl);
        for (int r = 0; r < c.n; r++)
            for (int s2 = 0; s2 <= r; s2++) {
                double D[12], val = 0.0;
                chain_d2(&c, r, s2, D);
                for (int e = 0; e < 12; e++) val += Wl[e] * D[e];
                H[(size_t)pos[r] * nc + pos[s2]] += val;
                if (r != s2) H[(size_t)pos[s2] * nc + pos[r]] += val;
            }
    }
    chain_free(&c);
    return SF_OK;
}

double sf_penalty(const sf_model *m, const sf_kin *k, double lR, double ld,
                  double *grad, double *H, int ldh)
{
    double E = 0.0;
    /* entries R23, R31, R12 and the translation */
    static const int rot[3] = {6, 8, 1};
    static const int tra[3] = {3, 7, 11};
    for (int v = 0; v < m->topo->nivertices; v++) {
        int order = H ? 2 : grad ? 1 : 0;
        chain c;
        if (loop_chain(m, k, v, order, &c)) { chain_free(&c); continue; }
        const double *o = m->study->vertices[m->topo->ivertices[v].vertex].x;
        double Lv[12];
        about_vertex(c.L, o, 0, Lv);
        double W[12] = {0};
        for (int e = 0; e < 3; e++) {
            E += 0.5 * lR * Lv[rot[e]] * Lv[rot[e]] + 0.5 * ld * Lv[tra[e]] * Lv[tra[e]];
            W[rot[e]] = lR * Lv[rot[e]];
            W[tra[e]] = ld * Lv[tra[e]];
        }
        if (grad || H) {
            double *D = malloc(sizeof(double) * 12 * (c.n + 1));
            if (!D) { chain_free(&c); continue; }
            for (int r = 0; r < c.n; r++) {
                double Dr[12];
                chain_d1(&c, r, Dr);
                about_vertex(Dr, o, 1, D + 12 * r);
            }
            if (grad)
                for (int r = 0; r < c.n; r++) {
                    double val = 0.0;
                    for (int e = 0; e < 12; e++) val += W[e] * D[12 * r + e];
                    grad[c.coord[r]] += val;
                }
            if (H) {
                for (int r = 0; r < c.n; r++)
                    for (int s = 0; s < c.n; s++) {
                        double val = 0.0;
                        for (int e = 0; e < 3; e++)
                            val += lR * D[12 * r + rot[e]] * D[12 * s + rot[e]] +
                                   ld * D[12 * r + tra[e]] * D[12 * s + tra[e]];
                        H[(size_t)c.coord[r] * ldh + c.coord[s]] += val;
                    }
                double Wl[12];
                weights_about_vertex(W, o, Wl);
                chain_hess_add(&c, Wl, H, ldh);
            }
            free(D);
        }
        chain_free(&c);
    }
    return E;
}
