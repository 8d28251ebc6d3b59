/* flatdescend.c - from an unstable first point off the flat state to the
 * stable branches next to it (flatstart.h, sf_flat_descend).
 *
 * When none of the regular branches of the tangent cone is stable (the
 * 2x2 waterbomb tessellation driven on both groups: Morse index 1), the
 * stable branches leave the flat state where the start cannot go (the
 * cone's degenerate rays, whose multipliers grow like 1/(p - p0)).  At
 * the first point p1, a saddle of the energy on the constraint set, the
 * sheet does not stay: it moves along the direction of negative curvature
 * of the reduced Hessian H_c = Z^T HL Z (Z: the null space of the
 * constraint rows, as in stability.c), on either side, to an equilibrium
 * of lower energy at the same p1.  This file takes both sides with Newton
 * at fixed p1 from the saddle pushed along +-v (5% to 80% of its largest
 * coordinate), keeps the converged states that differ from the saddle
 * (1e-3 of that coordinate), lie below its energy and whose H_c is
 * positive definite (stable), and orders them by energy.  Pushes that
 * come back to the saddle are counted: on the 2x2 waterbomb tessellation
 * all do, the negative curvature being that of the linearised loop rows
 * only (docs/flatstart.md).  Two of equal
 * energy (a symmetric driving) are mirror images: the driving selects
 * neither, and the caller says so.  Dense LAPACK (dgesvd, dsyev): for the
 * small sheets where the dense cone start runs at all. */
#include "flatstart.h"

#include "cont.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, double *a,
                    const int *lda, double *s, double *u, const int *ldu, double *vt,
                    const int *ldvt, double *work, const int *lwork, int *info);
extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

#define RANK_TOL 1e-9     /* as stability.c: relative singular value of the rows */
#define SAME_STATE 1e-3   /* a result this close to the saddle (relative) is the saddle */
#define LOWER_RTOL 1e-9   /* a state below the saddle's energy by more than this (relative) */
#define TIE_RTOL 1e-7     /* equal energies: mirror images */

/* Lowest eigenpair of H_c at (y, p) (fold coordinates): *lmin, v (nq
 * values, max-norm 1), *morse.  0, or -1 (memory, LAPACK, non-finite). */
static int reduced_hessian(sf_equil *q, const double *y, double p, double *lmin, double *v,
                           int *morse, double *scut)
{
    int nq = q->nq, nc = q->ncon, info = 0, rc = -1;
    double *HL = malloc(sizeof(double) * ((size_t)nq * nq + 1));
    double *C = malloc(sizeof(double) * ((size_t)nc * nq + 1));
    double *A = malloc(sizeof(double) * ((size_t)nq * nc + 1));
    double *U = malloc(sizeof(double) * ((size_t)nq * nq + 1));
    double *S = malloc(sizeof(double) * ((size_t)nq + nc + 1));
    double *Hc = malloc(sizeof(double) * ((size_t)nq * nq + 1));
    double *ev = malloc(sizeof(double) * ((size_t)nq + 1));
    double *W = NULL;
    if (!HL || !C || !A || !U || !S || !Hc || !ev) goto done;
    if (sf_equil_kkt(q, y, p, HL, C)) goto done;
    /* C^T column-major (nq x nc), rows normalised */
    for (int r = 0; r < nc; r++) {
        double s = 0.0;
        for (int j = 0; j < nq; j++) s += C[(size_t)r * nq + j] * C[(size_t)r * nq + j];
        double f = s > 0.0 ? 1.0 / sqrt(s) : 0.0;
        for (int j = 0; j < nq; j++) A[(size_t)r * nq + j] = f * C[(size_t)r * nq + j];
    }
    int rank = 0;
    if (nc > 0) {
        int lw = -1, one = 1;
        double wq, dum;
        dgesvd_("A", "N", &nq, &nc, A, &nq, S, U, &nq, &dum, &one, &wq, &lw, &info);
        lw = (int)wq + 1;
        W = malloc(sizeof(double) * (size_t)lw);
        if (!W) goto done;
        dgesvd_("A", "N", &nq, &nc, A, &nq, S, U, &nq, &dum, &one, W, &lw, &info);
        free(W);
        W = NULL;
        if (info != 0) goto done;
        int mn = nq < nc ? nq : nc;
        for (int i = 0; i < mn; i++)
            if (S[i] > RANK_TOL * S[0] && S[0] > 0) rank++;
        if (scut && rank > 0) *scut = S[rank - 1] / S[0];
    } else {
        memset(U, 0, sizeof(double) * (size_t)nq * nq);
        for (int i = 0; i < nq; i++) U[(size_t)i * nq + i] = 1.0;
    }
    int d = nq - rank;
    const double *Z = U + (size_t)rank * nq;
    if (d == 0) goto done;
    /* Hc = Z^T HL Z (HL symmetric) */
    for (int a = 0; a < d; a++)
        for (int b = 0; b <= a; b++) {
            double s = 0.0;
            for (int i = 0; i < nq; i++) {
                double t = 0.0;
                for (int j = 0; j < nq; j++) t += HL[(size_t)i * nq + j] * Z[(size_t)b * nq + j];
                s += Z[(size_t)a * nq + i] * t;
            }
            Hc[(size_t)a * d + b] = Hc[(size_t)b * d + a] = s;
        }
    {
        int lw = -1;
        double wq;
        dsyev_("V", "U", &d, Hc, &d, ev, &wq, &lw, &info);
        lw = (int)wq + 1;
        W = malloc(sizeof(double) * (size_t)lw);
        if (!W) goto done;
        dsyev_("V", "U", &d, Hc, &d, ev, W, &lw, &info);
        if (info != 0) goto done;
    }
    *morse = 0;
    for (int i = 0; i < d; i++) *morse += ev[i] < 0.0;
    *lmin = ev[0];
    double vmax = 0.0;
    for (int i = 0; i < nq; i++) {
        double s = 0.0;
        for (int a = 0; a < d; a++) s += Z[(size_t)a * nq + i] * Hc[a];
        v[i] = s;
        vmax = fmax(vmax, fabs(s));
    }
    if (!(vmax > 0.0) || !isfinite(*lmin)) goto done;
    for (int i = 0; i < nq; i++) v[i] /= vmax;
    rc = 0;
done:
    free(HL); free(C); free(A); free(U); free(S); free(Hc); free(ev); free(W);
    return rc;
}

int sf_flat_descend(sf_equil *q, struct cont_solver *cs, double p1, const double *y,
                    sf_flat_descent *out)
{
    int nq = q->nq, n = q->n;
    memset(out, 0, sizeof *out);
    double *v = malloc(sizeof(double) * ((size_t)nq + 1));
    double *yt = malloc(sizeof(double) * ((size_t)n + 1));
    double *w = malloc(sizeof(double) * ((size_t)nq + 1));
    out->y = malloc(sizeof(double) * 2 * ((size_t)n + 1));
    if (!v || !yt || !w || !out->y) {
        free(v); free(yt); free(w);
        sf_flat_descent_free(out);
        return -1;
    }
    int morse = 0;
    double lmin = 0.0;
    if (reduced_hessian(q, y, p1, &lmin, v, &morse, &out->sv_cut) != 0 || morse == 0) {
        out->saddle_morse = morse;
        free(v); free(yt); free(w);
        return morse == 0 ? 0 : -1;
    }
    out->saddle_morse = morse;
    out->saddle_eig = lmin;
    double amp = 0.0, rr, rt;
    sf_equil_report(q, y, p1, &out->saddle_energy, &rr, &rt);
    for (int j = 0; j < nq; j++) amp = fmax(amp, fabs(y[j]));
    for (int side = 0; side < 2; side++) {
        double sg = side == 0 ? 1.0 : -1.0;
        for (double t = 0.05; t <= 1.0001; t *= 2.0) {
            memcpy(yt, y, sizeof(double) * (size_t)n);
            for (int j = 0; j < nq; j++) yt[j] += sg * t * amp * v[j];
            if (cont_solve_fixed(cs, yt, p1) != CONT_OK) continue;
            double dist = 0.0, e;
            for (int j = 0; j < nq; j++) dist = fmax(dist, fabs(yt[j] - y[j]));
            out->push = fmax(out->push, t * amp);
            sf_equil_report(q, yt, p1, &e, &rr, &rt);
            if (!(dist > SAME_STATE * amp) ||
                !(e < out->saddle_energy - LOWER_RTOL * fabs(out->saddle_energy))) {
                /* back at the saddle */
                out->returned++;
                out->back = fmax(out->back, dist);
                continue;
            }
            int mo = -1;
            double lm = 0.0;
            if (reduced_hessian(q, yt, p1, &lm, w, &mo, NULL) != 0 || mo != 0 || !(lm > 0.0)) continue;
            int k = out->nfound;
            memcpy(out->y + (size_t)k * n, yt, sizeof(double) * (size_t)n);
            out->energy[k] = e;
            out->eig[k] = lm;
            out->dist[k] = dist;
            out->nfound++;
            break;
        }
    }
    if (out->nfound == 2 && out->energy[1] < out->energy[0]) {
        /* lowest energy first */
        memcpy(yt, out->y, sizeof(double) * (size_t)n);
        memcpy(out->y, out->y + n, sizeof(double) * (size_t)n);
        memcpy(out->y + n, yt, sizeof(double) * (size_t)n);
        double t = out->energy[0]; out->energy[0] = out->energy[1]; out->energy[1] = t;
        t = out->eig[0]; out->eig[0] = out->eig[1]; out->eig[1] = t;
        t = out->dist[0]; out->dist[0] = out->dist[1]; out->dist[1] = t;
    }
    out->ties = out->nfound == 2 &&
                fabs(out->energy[1] - out->energy[0]) <= TIE_RTOL * fabs(out->energy[0]);
    free(v); free(yt); free(w);
    return 0;
}

void sf_flat_descent_free(sf_flat_descent *d)
{
    free(d->y);
    d->y = NULL;
}

/* (flatstart.h) */
int sf_flat_start_descend(sf_equil *q, struct cont_solver *cs, double p1, int dir, double tol,
                          double *y, int branch, sf_flatstart_info *info, sf_error *err)
{
    int n = q->n;
    double *ys = malloc(sizeof(double) * ((size_t)n + 1));
    cont_solver *ds = NULL;   /* the pushes' own solver: cs stays at its point */
    if (!ys || sf_equil_create_solver(q, &ds) != CONT_OK) {
        free(ys);
        if (ds) cont_free(ds);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    cont_set_newton(ds, tol, 12, 0);
    memcpy(ys, cont_get_point(cs)->y, sizeof(double) * (size_t)n);
    sf_flat_descent D;
    int rc = SF_OK;
    int fr = sf_flat_descend(q, ds, p1, ys, &D);
    cont_free(ds);
    if (fr != 0) {
        sf_flat_descent_free(&D);
        free(ys);
        return sf_fail(err, SF_ENOMEM, "%s: flat start: out of memory (or a LAPACK failure) "
                       "on the reduced Hessian", q->m->study->path);
    }
    int pick = branch > 0 ? branch : 1;
    size_t len = strlen(info->note);
    char *nt = info->note + len;
    size_t room = sizeof info->note - len;
    if (D.nfound == 0) {
        snprintf(nt, room, "; at p = %g its Morse index %d (eigenvalue %.3g) holds for the "
                 "linearised constraints only: %d pushes of up to %.2g rad along the unstable "
                 "direction came back to the state under Newton (within %.2g rad, no lower "
                 "energy), blocked beyond second order by constraint rows with gradients down "
                 "to %.2g of the largest; no stable state next to it", p1, D.saddle_morse,
                 D.saddle_eig, D.returned, D.push, D.back, D.sv_cut);
    } else if (pick > D.nfound) {
        rc = sf_fail(err, SF_EINPUT, "%s: solver.flat_branch = %d, but the flat state has %d "
                     "stable branch%s (1..%d, by energy)", q->m->study->path, pick, D.nfound,
                     D.nfound == 1 ? "" : "es", D.nfound);
    } else {
        const double *yb = D.y + (size_t)(pick - 1) * n;
        if (D.ties)
            snprintf(nt, room, "; at p = %g it is a saddle (Morse index %d, eigenvalue %.3g, "
                     "energy %.6g J): the sheet leaves it either way along its unstable "
                     "direction to 2 stable states of the same energy (%.6g J, fold angles "
                     "%.3g rad from the saddle; mirror images): the driving selects no single "
                     "stable branch; following stable branch %d of 2, solver.flat_branch = 1..2 "
                     "selects the other", p1, D.saddle_morse, D.saddle_eig, D.saddle_energy,
                     D.energy[0], D.dist[pick - 1], pick);
        else
            snprintf(nt, room, "; at p = %g it is a saddle (Morse index %d, eigenvalue %.3g, "
                     "energy %.6g J): following the stable state of %s energy (%.6g J, fold "
                     "angles %.3g rad from the saddle) next to it, along its unstable direction "
                     "(%d found)", p1, D.saddle_morse, D.saddle_eig, D.saddle_energy,
                     pick == 1 ? "lowest" : "higher", D.energy[pick - 1], D.dist[pick - 1],
                     D.nfound);
        if (cont_start(cs, yb, p1, dir) != CONT_OK)
            rc = sf_fail(err, SF_ENUMERIC, "%s: flat start: the stable state next to the "
                         "first point: %s", q->m->study->path, cont_errmsg(cs));
        else
            memcpy(y, yb, sizeof(double) * (size_t)n);
        info->descended = D.nfound;
        info->ties = D.ties ? 2 : 0;
        info->branches = D.nfound;
        info->chosen = pick;
    }
    sf_flat_descent_free(&D);
    free(ys);
    return rc;
}


