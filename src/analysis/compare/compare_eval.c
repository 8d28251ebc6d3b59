/* compare_eval.c - the computed path at the abscissae of the reference
 * rows (compare_impl.h, sf_compare_eval): solved at fixed p when the
 * abscissa is p, else interpolated along the recorded branch pieces
 * (Lagrange, within monotone pieces); the error measures per column. */
#include "compare_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cont.h"
#include "outbuf.h"

/* The recorded points as a curve: consecutive exact duplicates dropped,
 * each point with its cumulative chord length t in (yscale * y, p) within
 * its block (a discrete arclength: every quantity is a smooth function of
 * t, also through limit points, where it is not a function of p). */
typedef struct curve {
    int n;
    int *pt;            /* point index of each curve node */
    double *t;          /* chord length from the block's first node */
} curve;

static int make_curve(const sf_compare *c, const sf_equil *eq, curve *cv)
{
    cv->n = 0;
    cv->pt = malloc(sizeof(int) * (size_t)(c->npts + 1));
    cv->t = malloc(sizeof(double) * (size_t)(c->npts + 1));
    if (!cv->pt || !cv->t) return SF_ENOMEM;
    for (int i = 0; i < c->npts; i++) {
        double t = 0.0;
        if (cv->n > 0 && c->pblock[cv->pt[cv->n - 1]] == c->pblock[i]) {
            int j = cv->pt[cv->n - 1];
            double d2 = 0.0;
            for (int k = 0; k < c->ny; k++) {
                double d = (c->py[(size_t)i * c->ny + k] - c->py[(size_t)j * c->ny + k]) * eq->yscale[k];
                d2 += d * d;
            }
            double dp = c->pv[(size_t)i * c->nq + Q_P] - c->pv[(size_t)j * c->nq + Q_P];
            d2 += dp * dp;
            if (d2 == 0.0) continue;            /* the same point again */
            t = cv->t[cv->n - 1] + sqrt(d2);
        }
        cv->pt[cv->n] = i;
        cv->t[cv->n] = t;
        cv->n++;
    }
    return SF_OK;
}

static double xval(const sf_compare *c, int i, int xq) { return c->pv[(size_t)i * c->nq + xq]; }

static int same_block(const sf_compare *c, const curve *cv, int a, int b)
{
    return a >= 0 && b >= 0 && a < cv->n && b < cv->n && c->pblock[cv->pt[a]] == c->pblock[cv->pt[b]];
}

typedef struct piece {
    int start, n;       /* into the node index array */
} piece;

/* Cut the curve into pieces strictly monotone in quantity xq: a new piece
 * starts at each new block and at each turning point of x (shared by the
 * two pieces).  Nodes where x does not move are left out of the pieces
 * (they stay on the curve for interpolation). */
static int make_pieces(const sf_compare *c, const curve *cv, int xq, int **idx_out, piece **pc_out,
                       int *npc)
{
    int *idx = malloc(sizeof(int) * (size_t)(2 * cv->n + 1));
    piece *pc = malloc(sizeof(piece) * (size_t)(cv->n + 1));
    if (!idx || !pc) { free(idx); free(pc); return SF_ENOMEM; }
    int ni = 0, np = 0, dir = 0;
    for (int a = 0; a < cv->n; a++) {
        double x = xval(c, cv->pt[a], xq);
        if (np == 0 || !same_block(c, cv, a, idx[ni - 1])) {
            pc[np].start = ni;
            pc[np].n = 0;
            np++;
            dir = 0;
        } else {
            double dx = x - xval(c, cv->pt[idx[ni - 1]], xq);
            if (dx == 0.0) continue;
            int d = dx > 0 ? 1 : -1;
            if (dir != 0 && d != dir) {
                int turn = idx[ni - 1];
                pc[np].start = ni;
                pc[np].n = 1;
                idx[ni++] = turn;
                np++;
            }
            dir = d;
        }
        idx[ni++] = a;
        pc[np - 1].n++;
    }
    *idx_out = idx;
    *pc_out = pc;
    *npc = np;
    return SF_OK;
}

/* Where x lies on a piece: the bracketing nodes (*a, *b) with x between
 * their abscissae (returns 1), or an exact node (*a = *b), or 0 when x is
 * outside the piece. */
static int locate(const sf_compare *c, const curve *cv, const int *idx, const piece *pc, int xq,
                  double x, double eps, int *a, int *b)
{
    const int *id = idx + pc->start;
    for (int k = 0; k < pc->n; k++)
        if (fabs(xval(c, cv->pt[id[k]], xq) - x) <= eps) { *a = *b = id[k]; return 1; }
    for (int k = 0; k + 1 < pc->n; k++) {
        double xa = xval(c, cv->pt[id[k]], xq), xb = xval(c, cv->pt[id[k + 1]], xq);
        if ((x - xa) * (x - xb) < 0.0) { *a = id[k]; *b = id[k + 1]; return 1; }
    }
    return 0;
}

/* Lagrange weights at t of the nodes nd[0..nn-1]. */
static void lagrange(const curve *cv, const int *nd, int nn, double t, double *w)
{
    for (int i = 0; i < nn; i++) {
        w[i] = 1.0;
        for (int j = 0; j < nn; j++)
            if (j != i) w[i] *= (t - cv->t[nd[j]]) / (cv->t[nd[i]] - cv->t[nd[j]]);
    }
}

/* Values of every quantity (vals) and the state (ys, may be NULL) at x
 * between curve nodes a < b: each is interpolated in the chord length t,
 * cubically through a-1, a, b, b+1 where those exist in the block (also
 * across a turning point: the curve is smooth in t there), and t is where
 * the interpolated abscissa equals x (bisection; the data bracket it). */
static void interp_at(const sf_compare *c, const curve *cv, int a, int b, int xq, double x,
                      double *vals, double *ys)
{
    if (a == b) {
        memcpy(vals, c->pv + (size_t)cv->pt[a] * c->nq, sizeof(double) * c->nq);
        if (ys) memcpy(ys, c->py + (size_t)cv->pt[a] * c->ny, sizeof(double) * c->ny);
        return;
    }
    if (a > b) { int t = a; a = b; b = t; }
    int nd[4], nn = 0;
    if (same_block(c, cv, a - 1, a)) nd[nn++] = a - 1;
    nd[nn++] = a;
    nd[nn++] = b;
    if (same_block(c, cv, b + 1, b)) nd[nn++] = b + 1;
    double w[4];
    double lo = cv->t[a], hi = cv->t[b];
    double flo = xval(c, cv->pt[a], xq) - x;
    for (int it = 0; it < 200 && hi - lo > 1e-15 * (fabs(hi) + 1e-300); it++) {
        double mid = 0.5 * (lo + hi), xm = 0.0;
        lagrange(cv, nd, nn, mid, w);
        for (int i = 0; i < nn; i++) xm += w[i] * xval(c, cv->pt[nd[i]], xq);
        if ((xm - x) * flo > 0.0) { lo = mid; flo = xm - x; }
        else hi = mid;
    }
    lagrange(cv, nd, nn, 0.5 * (lo + hi), w);
    for (int q = 0; q < c->nq; q++) {
        double v = 0.0;
        for (int i = 0; i < nn; i++) v += w[i] * c->pv[(size_t)cv->pt[nd[i]] * c->nq + q];
        vals[q] = v;
    }
    vals[xq] = x;
    if (ys)
        for (int k = 0; k < c->ny; k++) {
            double v = 0.0;
            for (int i = 0; i < nn; i++) v += w[i] * c->py[(size_t)cv->pt[nd[i]] * c->ny + k];
            ys[k] = v;
        }
}

int sf_compare_eval(sf_compare *c, sf_equil *eq, const sf_mpoint *probes,
                    struct cont_solver *cs, sf_error *err)
{
    if (!c) return SF_OK;
    double *vals = malloc(sizeof(double) * (size_t)c->nq * 2 + 1);
    double *best = vals ? vals + c->nq : NULL;
    double *y = malloc(sizeof(double) * (size_t)(c->ny + 1));
    double *guess = malloc(sizeof(double) * (size_t)(c->ny + 1));
    curve cv = {0, NULL, NULL};
    if (!vals || !y || !guess || make_curve(c, eq, &cv)) {
        free(vals); free(y); free(guess); free(cv.pt); free(cv.t);
        return sf_fail(err, SF_ENOMEM, "out of memory");
    }
    int rc = SF_OK;
    for (int ri = 0; ri < c->nref && !rc; ri++) {
        cmp_ref *r = &c->refs[ri];
        int *idx = NULL, npc = 0;
        piece *pc = NULL;
        if (make_pieces(c, &cv, r->xq, &idx, &pc, &npc)) { rc = sf_fail(err, SF_ENOMEM, "out of memory"); break; }
        double xlo = INFINITY, xhi = -INFINITY;
        for (int i = 0; i < c->npts; i++) {
            xlo = fmin(xlo, xval(c, i, r->xq));
            xhi = fmax(xhi, xval(c, i, r->xq));
        }
        double eps = c->npts ? 1e-10 * fmax(xhi - xlo, fmax(fabs(xlo), fabs(xhi))) : 0.0;
        int solvable = cs && r->solve && (r->xq == Q_P || (r->xq == Q_LOAD && eq->param == SF_PARAM_LOAD));
        int lastpc = 0;
        r->noutside = r->nsolved = r->ninterp = r->npoint = 0;
        for (int row = 0; row < r->nrow; row++) {
            const double *rv = r->v + (size_t)row * r->ncol;
            double x = r->xscale * rv[r->xcol];
            r->x[row] = x;
            /* the piece closest in value; on a tie (the path passes the
             * same state twice, or pieces meet at a turning point) the
             * first one at or after the previous row's piece */
            int bp = -1, ba = -1, bb = -1;
            double bscore = INFINITY;
            for (int jj = 0; jj < npc; jj++) {
                int j = (lastpc + jj) % npc;
                int na, nb;
                if (!locate(c, &cv, idx, &pc[j], r->xq, x, eps, &na, &nb)) continue;
                interp_at(c, &cv, na, nb, r->xq, x, vals, NULL);
                double score = 0.0;
                for (int cc = 0; cc < r->ncols; cc++) {
                    const cmp_col *col = &r->cols[cc];
                    double ref = col->scale * rv[col->ccol];
                    score += fabs(vals[col->q] - ref) / (col->refmax > 0 ? col->refmax : 1.0);
                }
                if (bp < 0 || score < bscore - 1e-12 * (1.0 + bscore)) {
                    bscore = score;
                    bp = j; ba = na; bb = nb;
                    memcpy(best, vals, sizeof(double) * c->nq);
                }
            }
            if (bp < 0) {
                r->method[row] = 'o';
                r->noutside++;
                continue;
            }
            lastpc = bp;
            char method = ba == bb ? 'p' : 'i';
            if (method == 'i' && solvable) {
                /* solve at exactly p = x from the interpolated state; accept
                 * it only if it stays next to that stretch of the path */
                interp_at(c, &cv, ba, bb, r->xq, x, vals, guess);
                double dab = 0.0;
                for (int i = 0; i < c->ny; i++)
                    dab = fmax(dab, fabs(c->py[(size_t)cv.pt[bb] * c->ny + i] -
                                         c->py[(size_t)cv.pt[ba] * c->ny + i]) * eq->yscale[i]);
                memcpy(y, guess, sizeof(double) * c->ny);
                if (cont_solve_fixed(cs, y, x) == CONT_OK) {
                    double dist = 0.0;
                    int finite = 1;
                    for (int i = 0; i < c->ny; i++) {
                        if (!isfinite(y[i])) finite = 0;
                        dist = fmax(dist, fabs(y[i] - guess[i]) * eq->yscale[i]);
                    }
                    if (finite && dist <= dab + 1e-8) {
                        cm_quantities(c, eq, probes, y, x, best);
                        method = 's';
                    }
                }
            }
            r->method[row] = method;
            if (method == 'p') r->npoint++;
            else if (method == 's') r->nsolved++;
            else r->ninterp++;
            for (int cc = 0; cc < r->ncols; cc++) r->cols[cc].comp[row] = best[r->cols[cc].q];
        }
        free(idx);
        free(pc);
        /* errors */
        for (int cc = 0; cc < r->ncols; cc++) {
            cmp_col *col = &r->cols[cc];
            double se = 0, sa = 0;
            int na = 0;
            col->npts = 0;
            col->emax = col->erms = col->eend = col->amax = col->arms = col->aend = 0;
            col->xmax = 0;
            for (int row = 0; row < r->nrow; row++) {
                if (r->method[row] == 'o') continue;
                double ref = col->scale * r->v[(size_t)row * r->ncol + col->ccol];
                /* finite numbers only reach compare*.tsv (outbuf.h) */
                if (sf_need_finite(err, col->comp[row], "computed %s for reference %s line %d (x = %.10g)",
                                   c->qname[col->q], r->name, r->line[row], r->x[row]) ||
                    sf_need_finite(err, ref, "value of reference %s column %s line %d", r->name, col->column,
                                   r->line[row])) {
                    rc = err->code;
                    break;
                }
                double d = fabs(col->comp[row] - ref);
                na++;
                sa += d * d;
                col->amax = fmax(col->amax, d);
                col->aend = d;
                double e;
                if (col->measure == M_ABSOLUTE) e = d;
                else if (col->measure == M_SCALED) e = d / col->refmax;
                else if (fabs(ref) > 1e-9 * col->refmax && ref != 0.0) e = d / fabs(ref);
                else continue;      /* relative error undefined at a zero reference */
                col->npts++;
                se += e * e;
                if (col->npts == 1 || e > col->emax) { col->emax = e; col->xmax = r->x[row]; }
                col->eend = e;
            }
            if (rc) break;
            col->arms = na ? sqrt(sa / na) : 0.0;
            col->erms = col->npts ? sqrt(se / col->npts) : 0.0;
            double v = col->norm == N_MAX ? col->emax : col->norm == N_RMS ? col->erms : col->eend;
            col->pass = !col->has_tol ? -1 : (col->npts > 0 && v <= col->tol) ? 1 : 0;
            const double ev[] = {col->emax, col->erms, col->eend, col->amax, col->arms, col->aend};
            static const char *const en[] = {"max", "rms", "end", "max_abs", "rms_abs", "end_abs"};
            for (int j = 0; j < 6 && !rc; j++)
                if (sf_need_finite(err, ev[j], "%s error of %s against reference %s column %s", en[j],
                                   c->qname[col->q], r->name, col->column))
                    rc = err->code;
            if (rc) break;
        }
        if (rc) break;
    }
    free(vals);
    free(y);
    free(guess);
    free(cv.pt);
    free(cv.t);
    return rc;
}
