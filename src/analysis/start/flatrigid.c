/* flatrigid.c - a rigid-origami motion of a crease pattern at the flat
 * state from the closed form of its degree-4 vertices (flatrigid.h); the
 * start of the sparse limit problem that finds the uniform Miura motion
 * where the first-order response leads elsewhere (flatlimit_sparse.c,
 * docs/flatstart.md). */
#include "flatrigid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The closed form per vertex, then the chain (flatrigid.h). */
int sf_flat_rigid_modes(const sf_model *m, const double *u, const double *b, double *x)
{
    const sf_topology *t = m->topo;
    int nv = t->nivertices, used = 0;
    double *rv = calloc((size_t)nv * 4 + 1, sizeof(double)), *al = calloc((size_t)nv + 1, sizeof(double));
    int *ok = calloc((size_t)nv + 1, sizeof(int)), *queue = malloc(sizeof(int) * ((size_t)nv + 1));
    char *set = calloc((size_t)m->nfolds + 1, 1);
    int *fv = malloc(sizeof(int) * (2 * (size_t)m->nfolds + 1));   /* the fold's interior vertices */
    if (!rv || !al || !ok || !queue || !set || !fv) goto out;
    for (int f = 0; f < 2 * m->nfolds; f++) fv[f] = -1;
    for (int v = 0; v < nv; v++)
        for (int k = 0; k < t->ivertices[v].degree; k++) {
            int f = t->ivertices[v].folds[k];
            fv[2 * f + (fv[2 * f] >= 0)] = v;
        }
    memset(x, 0, sizeof(double) * (size_t)m->nq);
    for (int v = 0; v < nv; v++) {
        const sf_ivertex *iv = &t->ivertices[v];
        if (iv->degree != 4) continue;
        double e[4][2], best = -1.0;
        for (int k = 0; k < 4; k++) {
            const sf_fold_geom *g = &t->folds[iv->folds[k]];
            e[k][0] = iv->sign[k] * g->m[0];
            e[k][1] = iv->sign[k] * g->m[1];
        }
        /* the plane sum rho_k e_k = 0: pivots (i, j), the largest det */
        int pi = 0, pj = 1;
        double dm = 0.0;
        for (int i = 0; i < 4; i++)
            for (int j = i + 1; j < 4; j++) {
                double d = fabs(e[i][0] * e[j][1] - e[i][1] * e[j][0]);
                if (d > dm) dm = d, pi = i, pj = j;
            }
        if (dm < 1e-6) continue;
        double nb[2][4];
        int fr[2], nfr = 0;
        for (int k = 0; k < 4; k++)
            if (k != pi && k != pj) fr[nfr++] = k;
        for (int b = 0; b < 2; b++) {   /* rho_fr[b] = 1: solve for the pivots */
            double rx = -e[fr[b]][0], ry = -e[fr[b]][1];
            double det = e[pi][0] * e[pj][1] - e[pi][1] * e[pj][0];
            memset(nb[b], 0, sizeof nb[b]);
            nb[b][fr[b]] = 1.0;
            nb[b][pi] = (rx * e[pj][1] - ry * e[pj][0]) / det;
            nb[b][pj] = (e[pi][0] * ry - e[pi][1] * rx) / det;
        }
        double Q[2][2] = {{0, 0}, {0, 0}};
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < 2; b++)
                for (int i = 0; i < 4; i++)
                    for (int j = i + 1; j < 4; j++) {
                        double c = e[i][0] * e[j][1] - e[i][1] * e[j][0];
                        Q[a][b] += 0.5 * c * (nb[a][i] * nb[b][j] + nb[b][i] * nb[a][j]);
                    }
        /* null lines of Q: eigenvalues l1 <= 0 <= l2, rays sqrt|l2| v1 +- sqrt|l1| v2 */
        double tr = 0.5 * (Q[0][0] + Q[1][1]), df = 0.5 * (Q[0][0] - Q[1][1]);
        double rad = sqrt(df * df + Q[0][1] * Q[0][1]), l1 = tr - rad, l2 = tr + rad;
        if (l1 > 0 || l2 < 0) continue;
        double th = 0.5 * atan2(2.0 * Q[0][1], Q[0][0] - Q[1][1]);   /* v2 = (cos, sin) */
        double v2[2] = {cos(th), sin(th)}, v1[2] = {-sin(th), cos(th)};
        for (int sg = -1; sg <= 1; sg += 2) {
            double ca = sqrt(fabs(l2)) * v1[0] + sg * sqrt(fabs(l1)) * v2[0];
            double cb = sqrt(fabs(l2)) * v1[1] + sg * sqrt(fabs(l1)) * v2[1];
            double r[4], nr = 0.0, dot = 0.0;
            for (int k = 0; k < 4; k++) {
                r[k] = ca * nb[0][k] + cb * nb[1][k];
                nr += r[k] * r[k];
                int o = m->qoff[iv->folds[k]];
                double uk = b[o] != 0.0 ? -b[o] : u[o];
                dot += ((uk > 0) - (uk < 0)) * r[k];
            }
            if (!(nr > 0)) continue;
            double sc = fabs(dot) / sqrt(nr);
            if (sc > best) {
                best = sc;
                for (int k = 0; k < 4; k++) rv[4 * v + k] = (dot < 0 ? -r[k] : r[k]) / sqrt(nr);
            }
        }
        ok[v] = best >= 0;
    }
    /* chain the vertices' modes breadth-first across shared folds, from
     * the vertex where u is largest; components not reached start anew */
    for (;;) {
        int seed = -1;
        double um = -1.0;
        for (int v = 0; v < nv; v++) {
            if (ok[v] != 1) continue;
            double a = 0.0;
            for (int k = 0; k < 4; k++) a += fabs(u[m->qoff[t->ivertices[v].folds[k]]]);
            if (a > um) um = a, seed = v;
        }
        if (seed < 0) break;
        int qh = 0, qt = 0;
        al[seed] = 1.0;
        ok[seed] = 2;
        queue[qt++] = seed;
        while (qh < qt) {
            int v = queue[qh++];
            const sf_ivertex *iv = &t->ivertices[v];
            used++;
            for (int k = 0; k < 4; k++) {
                int f = iv->folds[k];
                double val = al[v] * rv[4 * v + k];
                if (!set[f]) {
                    x[m->qoff[f]] = val;
                    set[f] = 1;
                }
                /* the vertex at the other end of fold f */
                for (int e = 0; e < 2; e++) {
                    int w = fv[2 * f + e];
                    if (w < 0 || ok[w] != 1) continue;
                    const sf_ivertex *iw = &t->ivertices[w];
                    for (int kk = 0; kk < 4; kk++)
                        if (iw->folds[kk] == f && fabs(rv[4 * w + kk]) > 1e-3) {
                            al[w] = x[m->qoff[f]] / rv[4 * w + kk];
                            ok[w] = 2;
                            queue[qt++] = w;
                            break;
                        }
                }
            }
        }
    }
    if (used) {
        double xm = 0.0, um = 0.0, dot = 0.0;
        for (int i = 0; i < m->nfolds; i++) {
            if (!set[i]) x[m->qoff[i]] = u[m->qoff[i]];
            xm = fmax(xm, fabs(x[m->qoff[i]]));
            um = fmax(um, fabs(u[m->qoff[i]]));
            dot += x[m->qoff[i]] * (b[m->qoff[i]] != 0.0 ? -b[m->qoff[i]] : u[m->qoff[i]]);
        }
        double sc = xm > 0 ? (dot < 0 ? -um : um) / xm : 0.0;
        for (int i = 0; i < m->nfolds; i++) x[m->qoff[i]] *= sc;
    }
out:
    free(rv);
    free(al);
    free(ok);
    free(queue);
    free(set);
    free(fv);
    return used;
}

